//! The `reyes` command line's outputs (issue 19, D13, D15, D16): paths are
//! checked before rendering, files are replaced all or nothing, the
//! extension chooses the format, and a frame that lost its patches says so.
//! Every render here is a tiny `--cpu` one.

mod files;

mod common;

use std::fs;
use std::path::Path;
use std::process::Command;

use files::{TempDir, run_cli, run_command, symlink};
use reyes::color::{linear_to_srgb8, srgb_to_linear};
use reyes::quantize::Encoding;
use reyes::stats::RenderStats;

/// A path as the command line takes it.
fn path_str(path: &Path) -> &str {
    path.to_str().expect("temp paths are UTF-8")
}

/// The arguments of a tiny CPU render of the teapot.
const TINY: [&str; 6] = ["--cpu", "--width", "32", "--height", "24", "--spp"];

/// Runs `reyes render` (tiny, on the CPU) with `extra` arguments in `dir`.
fn render_in(dir: &Path, extra: &[&str]) -> (bool, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command
        .current_dir(dir)
        .arg("render")
        .args(TINY)
        .arg("1")
        .args(extra);
    run_command(command)
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    common::dir_names(dir)
}

#[test]
fn one_file_named_twice_is_refused_before_rendering() {
    let temp = TempDir::new("out-same");
    let dir = temp.path("");
    for stats in ["same.png", "./same.png", "sub/../same.png"] {
        let (ok, stderr) = render_in(&dir, &["-o", "same.png", "--stats-json", stats]);
        assert!(!ok, "{stats}: {stderr}");
        assert!(stderr.contains("both name"), "{stats}: {stderr}");
        assert!(names(&dir).is_empty(), "{stats}: wrote {:?}", names(&dir));
    }
    // Through a link, an old image survives the refusal.
    fs::write(dir.join("same.png"), b"old").unwrap();
    if symlink(Path::new("same.png"), &dir.join("link.json")) {
        let (ok, stderr) = render_in(&dir, &["-o", "same.png", "--stats-json", "link.json"]);
        assert!(!ok && stderr.contains("both name"), "{stderr}");
        assert_eq!(fs::read(dir.join("same.png")).unwrap(), b"old");
    }
}

#[test]
fn a_failing_stats_json_leaves_no_image() {
    let temp = TempDir::new("out-stats-fail");
    let image = temp.path("r.png");
    // A parent that is a file: no directory can be made there.
    fs::write(temp.path("file"), b"").unwrap();
    let below_a_file = temp.path("file/x.json");
    let mut refused = vec![path_str(&below_a_file).to_owned()];
    if Path::new("/proc/self").exists() {
        refused.push("/proc/x.json".to_owned());
    } else {
        println!("NOTICE: no /proc; checking only a parent that is a file");
    }
    for stats in &refused {
        let (ok, stderr) = render_in(
            temp.path("").as_path(),
            &["-o", path_str(&image), "--stats-json", stats],
        );
        assert!(!ok, "{stats}: {stderr}");
        assert!(stderr.contains(Path::new(stats).parent().unwrap().to_str().unwrap()));
        assert!(!image.exists(), "{stats}: the image was written");
    }
}

#[test]
fn unknown_image_formats_are_refused_without_a_file() {
    let temp = TempDir::new("out-formats");
    for name in ["r.jpg", "r", "sub/r.tiff"] {
        let (ok, stderr) = render_in(&temp.path(""), &["-o", name]);
        assert!(!ok, "{name}");
        assert!(
            stderr.contains(name) && stderr.contains(".png") && stderr.contains(".exr"),
            "{name}: {stderr}"
        );
        assert!(names(&temp.path("")).is_empty(), "{name}: wrote a file");
    }
    let (ok, stderr) = render_in(&temp.path(""), &["-o", "upper.PNG"]);
    assert!(ok, "{stderr}");
    assert!(image::open(temp.path("upper.PNG")).is_ok());
}

#[test]
fn the_exr_holds_the_floats_the_png_encodes() {
    let temp = TempDir::new("out-exr");
    let (ok, stderr) = render_in(&temp.path(""), &["-o", "r.png"]);
    assert!(ok, "{stderr}");
    let (ok, stderr) = render_in(&temp.path(""), &["-o", "r.Exr"]);
    assert!(ok, "{stderr}");
    let png = image::open(temp.path("r.png")).unwrap().to_rgba8();
    let exr = image::open(temp.path("r.Exr")).unwrap();
    let exr = exr.as_rgba32f().expect("the EXR holds Rgba32F");
    assert_eq!(exr.dimensions(), (32, 24));
    // The PNG is the default encoding (RenderMan's exposure and
    // quantization, with its dither) of the EXR's floats, and each code is
    // within one of the float's nearest sRGB code.
    assert!(
        Encoding::default().encode(exr, [0, 0]) == png,
        "the PNG is not the encoding of the EXR"
    );
    let mut lit = 0;
    let mut between_codes = 0;
    for (x, y, pixel) in png.enumerate_pixels() {
        let float = exr.get_pixel(x, y);
        for c in 0..3 {
            let nearest = linear_to_srgb8(float[c]);
            assert!(
                pixel[c].abs_diff(nearest) <= 1,
                "{x},{y}: {float:?} vs {pixel:?}"
            );
            let decoded = srgb_to_linear(f32::from(pixel[c]) / 255.0);
            between_codes += usize::from((float[c] - decoded).abs() > 1e-6);
        }
        assert_eq!(float[3], 1.0);
        lit += usize::from(pixel[0] > 100);
    }
    assert!(lit > 0, "the teapot is in the frame");
    // The floats are not the 8-bit image decoded.
    assert!(
        between_codes > 32 * 24,
        "{between_codes} channels off the codes"
    );
}

#[test]
fn both_outputs_create_their_directories() {
    let temp = TempDir::new("out-dirs");
    let (ok, stderr) = render_in(
        &temp.path(""),
        &["-o", "img/r.png", "--stats-json", "deep/er/s.json"],
    );
    assert!(ok, "{stderr}");
    assert!(image::open(temp.path("img/r.png")).is_ok());
    let json = fs::read_to_string(temp.path("deep/er/s.json")).unwrap();
    let stats: RenderStats = serde_json::from_str(&json).unwrap();
    assert_eq!(stats.input_patches, 32);
    // Nothing else: no temporary or probe file.
    assert_eq!(names(&temp.path("img")), ["r.png"]);
    assert_eq!(names(&temp.path("deep/er")), ["s.json"]);
}

#[test]
fn a_full_disk_leaves_the_old_file() {
    let temp = TempDir::new("out-full");
    let image = temp.path("r.exr");
    fs::write(&image, b"old").unwrap();
    // A 1 KiB file-size limit (SIGXFSZ ignored, so writes fail with EFBIG)
    // stands in for a full disk: the 32 x 24 float EXR needs 12 KiB.
    let script = format!(
        "trap '' XFSZ; ulimit -f 2 || exit 99; exec \"$0\" render {} 1 -o \"$1\"",
        TINY.join(" ")
    );
    let mut command = Command::new("sh");
    command
        .args(["-c", &script, env!("CARGO_BIN_EXE_reyes"), path_str(&image)])
        .current_dir(temp.path(""));
    if Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 2")
        .status()
        .is_ok_and(|s| s.success())
    {
        let (ok, stderr) = run_command(command);
        assert!(!ok, "the write succeeded despite the limit: {stderr}");
        assert!(stderr.contains("r.exr"), "{stderr}");
        assert_eq!(
            fs::read(&image).unwrap(),
            b"old",
            "the old file was replaced"
        );
        assert_eq!(names(&temp.path("")), ["r.exr"], "a temporary file is left");
    } else {
        println!("NOTICE: no sh with ulimit -f; skipping the size-limit check");
    }
    // A device is no output: refused before rendering, left as it is.
    if Path::new("/dev/full").exists() {
        let png = temp.path("r.png");
        let (ok, stderr) = run_cli(&[
            "render",
            "--cpu",
            "-o",
            path_str(&png),
            "--stats-json",
            "/dev/full",
        ]);
        assert!(!ok && stderr.contains("not a regular file"), "{stderr}");
        assert!(!png.exists());
        assert!(!fs::metadata("/dev/full").unwrap().is_file());
    } else {
        println!("NOTICE: no /dev/full; skipping the device check");
    }
}

/// Renders `scene` on the CPU at `width` x `height`, 1 spp, into `dir`.
fn render_sized(dir: &Path, scene: &Path, width: &str, height: &str) -> (bool, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command.current_dir(dir).arg("render").arg(scene).args([
        "--cpu", "--width", width, "--height", height, "--spp", "1", "-o", "r.png",
    ]);
    run_command(command)
}

#[test]
fn depth_guard_drops_are_reported() {
    let temp = TempDir::new("out-depth");
    let scene = temp.path("scene.toml");
    fs::write(
        &scene,
        "max_split_depth = 0\n\n[[objects]]\nmodel = \"teapot\"\n",
    )
    .unwrap();
    // At 160 x 120 every teapot patch needs a split: all are dropped.
    let (ok, stderr) = render_sized(&temp.path(""), &scene, "160", "120");
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("warning: the depth guard dropped all 32 patch piece(s)")
            && stderr.contains("raise the scene key `max_split_depth` (now 0"),
        "{stderr}"
    );
    assert!(
        stderr.contains("warning: the frame covered no sample"),
        "{stderr}"
    );
    // At 64 x 48 some patches are small enough to dice unsplit.
    let (ok, stderr) = render_sized(&temp.path(""), &scene, "64", "48");
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("warning: the depth guard dropped ")
            && stderr.contains("parts of the surface may be missing")
            && !stderr.contains("covered no sample"),
        "{stderr}"
    );
    // The default depth drops nothing and warns of nothing.
    fs::write(&scene, "[[objects]]\nmodel = \"teapot\"\n").unwrap();
    let (ok, stderr) = render_sized(&temp.path(""), &scene, "160", "120");
    assert!(ok && !stderr.contains("warning:"), "{stderr}");
}

#[test]
fn an_empty_frame_is_reported() {
    let temp = TempDir::new("out-empty");
    let scene = temp.path("away.toml");
    // The camera looks away from the teapot.
    fs::write(
        &scene,
        "[camera]\neye = [0.0, -12.0, 2.0]\ntarget = [0.0, -24.0, 2.0]\n\n[[objects]]\nmodel = \"teapot\"\n",
    )
    .unwrap();
    let (ok, stderr) = render_in(&temp.path(""), &[path_str(&scene), "-o", "r.png"]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("warning: the frame covered no sample although the scene has 1 object(s)")
            && stderr.contains("culled"),
        "{stderr}"
    );
}

#[test]
fn the_scene_is_no_output() {
    let temp = TempDir::new("out-input");
    let scene = temp.path("scene.toml");
    let text = "[[objects]]\nmodel = \"teapot\"\n";
    fs::write(&scene, text).unwrap();
    let (ok, stderr) = render_in(
        &temp.path(""),
        &[
            path_str(&scene),
            "-o",
            "r.png",
            "--stats-json",
            "scene.toml",
        ],
    );
    assert!(!ok && stderr.contains("input scene"), "{stderr}");
    assert_eq!(fs::read_to_string(&scene).unwrap(), text);
    assert!(!temp.path("r.png").exists());
}
