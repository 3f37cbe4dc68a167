//! The sampling flags of `reyes render`, on the CPU reference: the
//! Interleave tile and permutations and the flat-shading short form.

mod files;

use files::{TempDir, run_cli};

/// Renders the default teapot small with the CPU reference and `extra`
/// flags into `dir/name`; returns the PNG's bytes.
fn render(dir: &TempDir, name: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.path(name);
    let out_str = out.to_str().expect("temp paths are UTF-8");
    let mut args = vec![
        "render", "--cpu", "--width", "48", "--height", "36", "-o", out_str,
    ];
    args.extend_from_slice(extra);
    let (ok, stderr) = run_cli(&args);
    assert!(ok, "reyes render {extra:?} failed: {stderr}");
    std::fs::read(&out).expect("the PNG was written")
}

#[test]
fn flat_shading_is_constant_shading_interpolation() {
    let dir = TempDir::new("cli-flat-shading");
    let flat = render(
        &dir,
        "flat.png",
        &["--flat-shading", "--shading-rate", "16"],
    );
    let constant = render(
        &dir,
        "constant.png",
        &[
            "--shading-interpolation",
            "constant",
            "--shading-rate",
            "16",
        ],
    );
    let smooth = render(&dir, "smooth.png", &["--shading-rate", "16"]);
    assert!(
        flat == constant,
        "--flat-shading renders what constant does"
    );
    assert!(flat != smooth, "and not what smooth shading does");
}

#[test]
fn the_interleave_tile_flag_takes_2_3_or_4() {
    let dir = TempDir::new("cli-interleave-tile");
    for tile in ["2", "3", "4"] {
        render(
            &dir,
            &format!("k{tile}.png"),
            &[
                "--sampling",
                "interleave",
                "--spin",
                "20",
                "--interleave-tile",
                tile,
            ],
        );
    }
    let out = dir.path("k5.png");
    let (ok, stderr) = run_cli(&[
        "render",
        "--cpu",
        "--interleave-tile",
        "5",
        "-o",
        out.to_str().expect("temp paths are UTF-8"),
    ]);
    assert!(!ok);
    assert!(stderr.contains("--interleave-tile"), "{stderr}");
    let (ok, stderr) = run_cli(&[
        "render",
        "--flat-shading",
        "--shading-interpolation",
        "smooth",
    ]);
    assert!(!ok);
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}

#[test]
fn the_interleave_permutations_flag_takes_1_to_256() {
    let dir = TempDir::new("cli-interleave-permutations");
    let flags = |p: &'static str| {
        [
            "--sampling",
            "interleave",
            "--spin",
            "20",
            "--interleave-permutations",
            p,
        ]
    };
    let one = render(&dir, "p1.png", &flags("1"));
    let many = render(&dir, "p64.png", &flags("64"));
    let default = render(&dir, "default.png", &flags("64")[..4]);
    assert!(one != many, "one permutation renders another image");
    assert!(many == default, "64 is the default");
    render(&dir, "p256.png", &flags("256"));
    for bad in ["0", "257"] {
        let out = dir.path("bad.png");
        let (ok, stderr) = run_cli(&[
            "render",
            "--cpu",
            "--interleave-permutations",
            bad,
            "-o",
            out.to_str().expect("temp paths are UTF-8"),
        ]);
        assert!(!ok);
        assert!(stderr.contains("--interleave-permutations"), "{stderr}");
    }
}
