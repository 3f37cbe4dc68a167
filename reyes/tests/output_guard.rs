//! The output guard of every command (issue 42, item 1): no output of
//! `render`, `convert` or `view` may replace a file the run reads, by name,
//! through `..`, through a symbolic link or as a hard link; extensions must
//! name the format written; `convert` replaces its files all or nothing.
//! Every refusal exits non-zero, names the file, and leaves every input
//! byte-identical. Renders are tiny `--cpu` ones; `view` is refused before
//! any window opens, so no GPU or display is needed.

mod files;

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use files::{TempDir, run_command, symlink};

/// A RIB scene of one sphere in front of the camera.
const SPHERE_RIB: &str = "Projection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\n";

/// A tiny CPU frame.
const TINY: [&str; 7] = ["--cpu", "--width", "32", "--height", "24", "--spp", "1"];

/// Runs `reyes ARGS` in `dir`; (success, stderr).
fn reyes_in(dir: &Path, args: &[&str]) -> (bool, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command.current_dir(dir).args(args);
    run_command(command)
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    common::dir_names(dir)
}

/// The contents of `files` (relative to `dir`), to compare after a run.
fn snapshot(dir: &Path, files: &[&str]) -> Vec<(String, Vec<u8>)> {
    files
        .iter()
        .map(|name| ((*name).to_owned(), fs::read(dir.join(name)).unwrap()))
        .collect()
}

/// Asserts that a run was refused with a message containing every one of
/// `words`, and that the files of `before` are unchanged.
fn assert_refused(
    what: &str,
    (ok, stderr): (bool, String),
    words: &[&str],
    dir: &Path,
    before: &[(String, Vec<u8>)],
) {
    assert!(!ok, "{what}: not refused: {stderr}");
    for word in words {
        assert!(stderr.contains(word), "{what}: {word:?} not in {stderr:?}");
    }
    for (name, bytes) in before {
        assert_eq!(
            &fs::read(dir.join(name)).unwrap(),
            bytes,
            "{what}: {name} changed"
        );
    }
}

/// An 8-bit grey 4 x 4 PNG (a height map), encoded by the image crate.
fn height_map_png() -> Vec<u8> {
    let map = image::GrayImage::from_fn(4, 4, |x, y| image::Luma([(40 * (x + y)) as u8]));
    let mut bytes = Vec::new();
    map.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    bytes
}

#[test]
fn convert_refuses_to_replace_its_rib() {
    let temp = TempDir::new("guard-convert-self");
    let dir = temp.path("");
    fs::write(dir.join("in.rib"), SPHERE_RIB).unwrap();
    let before = snapshot(&dir, &["in.rib"]);
    let outcome = reyes_in(&dir, &["convert", "in.rib", "-o", "in.rib"]);
    assert_refused(
        "-o in.rib",
        outcome,
        &["in.rib", "input RIB scene"],
        &dir,
        &before,
    );
    assert_eq!(names(&dir), ["in.rib"], "something was written");
}

#[test]
fn convert_refuses_a_model_name_that_is_its_rib() {
    let temp = TempDir::new("guard-convert-bpt");
    let dir = temp.path("");
    // The converter's first model would be scene-0.bpt: the RIB itself.
    fs::write(dir.join("scene-0.bpt"), SPHERE_RIB).unwrap();
    let before = snapshot(&dir, &["scene-0.bpt"]);
    let outcome = reyes_in(&dir, &["convert", "scene-0.bpt", "-o", "scene.toml"]);
    assert_refused(
        "scene-0.bpt -o scene.toml",
        outcome,
        &["scene-0.bpt", "input RIB scene"],
        &dir,
        &before,
    );
    assert_eq!(names(&dir), ["scene-0.bpt"], "something was written");
}

#[test]
fn convert_refuses_to_replace_an_archive() {
    let temp = TempDir::new("guard-convert-archive");
    let dir = temp.path("");
    fs::create_dir(dir.join("o")).unwrap();
    for archive in ["part.rib", "part.toml"] {
        let main = format!(
            "Projection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 5\nReadArchive \"{archive}\"\nWorldEnd\n"
        );
        fs::write(dir.join("o/main.rib"), main).unwrap();
        fs::write(dir.join("o").join(archive), "Sphere 1 -1 1 360\n").unwrap();
        let files = ["o/main.rib".to_owned(), format!("o/{archive}")];
        let before = snapshot(&dir, &files.iter().map(String::as_str).collect::<Vec<_>>());
        let output = format!("o/{archive}");
        let outcome = reyes_in(&dir, &["convert", "o/main.rib", "-o", &output]);
        // A `.rib` TOML is refused for its extension before the RIB is read;
        // a `.toml` archive as the input it is.
        let reason = if archive.ends_with(".rib") {
            "name it *.toml"
        } else {
            "input RIB archive"
        };
        assert_refused(&output, outcome, &[&output, reason], &dir, &before);
        assert!(
            !dir.join("o/part-0.bpt").exists(),
            "{archive}: a model was written"
        );
        fs::remove_file(dir.join("o").join(archive)).unwrap();
    }
}

#[test]
fn convert_refuses_other_extensions_devices_and_directories() {
    let temp = TempDir::new("guard-convert-names");
    let dir = temp.path("");
    fs::write(dir.join("in.rib"), SPHERE_RIB).unwrap();
    fs::create_dir(dir.join("d.toml")).unwrap();
    let before = snapshot(&dir, &["in.rib"]);
    for (output, words) in [
        ("scene.png", &["scene.png", "name it *.toml"][..]),
        ("scene", &["scene", "name it *.toml"]),
        ("scene.toml/", &["scene.toml/", "names no file"]),
        ("d.toml", &["d.toml", "not a regular file"]),
    ] {
        let outcome = reyes_in(&dir, &["convert", "in.rib", "-o", output]);
        assert_refused(output, outcome, words, &dir, &before);
        assert_eq!(names(&dir), ["d.toml", "in.rib"], "{output}: wrote a file");
    }
    if Path::new("/dev/null").exists() {
        let stray = Path::new("/dev/null-0.bpt");
        let existed = stray.exists();
        let outcome = reyes_in(&dir, &["convert", "in.rib", "-o", "/dev/null"]);
        assert_refused(
            "/dev/null",
            outcome,
            &["/dev/null", "not a regular file"],
            &dir,
            &before,
        );
        assert!(existed || !stray.exists(), "/dev/null-0.bpt was created");
    } else {
        println!("NOTICE: no /dev/null; skipping the device check");
    }
}

/// Whether `sh` can set a file-size limit; prints a notice if not.
fn has_ulimit() -> bool {
    let works = Command::new("sh")
        .args(["-c", "ulimit -f 2"])
        .status()
        .is_ok_and(|s| s.success());
    if !works {
        println!("NOTICE: no sh with ulimit -f; skipping the size-limit check");
    }
    works
}

#[test]
fn a_failed_convert_keeps_the_previous_files() {
    let temp = TempDir::new("guard-convert-limit");
    let dir = temp.path("");
    fs::write(dir.join("in.rib"), SPHERE_RIB).unwrap();
    let (ok, stderr) = reyes_in(&dir, &["convert", "in.rib", "-o", "s.toml"]);
    assert!(ok, "{stderr}");
    assert_eq!(names(&dir), ["in.rib", "s-0.bpt", "s.toml"]);
    // A second conversion with the same names replaces both, leaving nothing else.
    let (ok, stderr) = reyes_in(&dir, &["convert", "in.rib", "-o", "s.toml"]);
    assert!(ok, "{stderr}");
    assert_eq!(names(&dir), ["in.rib", "s-0.bpt", "s.toml"]);
    if !has_ulimit() {
        return;
    }
    let before = snapshot(&dir, &["in.rib", "s-0.bpt", "s.toml"]);
    // The sphere's model is about 8 KiB, past a 1 KiB limit. SIGXFSZ is
    // left at its default here: reyes itself must ignore it.
    let mut command = Command::new("sh");
    command
        .args([
            "-c",
            "ulimit -f 2 || exit 99; exec \"$0\" convert in.rib -o s.toml",
            env!("CARGO_BIN_EXE_reyes"),
        ])
        .current_dir(&dir);
    let outcome = run_command(command);
    assert_refused("ulimit -f 2", outcome, &["s-0.bpt"], &dir, &before);
    assert_eq!(
        names(&dir),
        ["in.rib", "s-0.bpt", "s.toml"],
        "a temporary file is left"
    );
}

#[test]
fn render_refuses_a_name_that_ends_in_a_separator() {
    let temp = TempDir::new("guard-render-slash");
    let dir = temp.path("");
    for output in ["out.png/", "out.png/.", "sub/.."] {
        let mut args = vec!["render", "-o", output];
        args.extend(TINY);
        let (ok, stderr) = reyes_in(&dir, &args);
        assert!(
            !ok && stderr.contains("names no file"),
            "{output}: {stderr}"
        );
        assert!(names(&dir).is_empty(), "{output}: wrote {:?}", names(&dir));
    }
}

/// A directory with a scene reading every kind of input: `scene.toml`
/// names `model.bpt` (displaced by `hm.png`), and `main.rib` reads
/// `part.png` (a RIB archive despite its name).
fn inputs_dir(name: &str) -> TempDir {
    let temp = TempDir::new(name);
    let dir = temp.path("");
    let teapot = reyes::load::bpt::write(&reyes::model::Model::teapot());
    fs::write(dir.join("model.bpt"), teapot).unwrap();
    fs::write(dir.join("hm.png"), height_map_png()).unwrap();
    fs::write(
        dir.join("scene.toml"),
        "[[objects]]\nmodel = \"model.bpt\"\n\n[objects.displacement]\nsource = \"hm.png\"\nscale = 0.05\n",
    )
    .unwrap();
    fs::write(
        dir.join("main.rib"),
        "Projection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 5\nReadArchive \"part.png\"\nWorldEnd\n",
    )
    .unwrap();
    fs::write(dir.join("part.png"), "Sphere 1 -1 1 360\n").unwrap();
    temp
}

/// The spellings of `input` (in `dir`) to try as an output: its name,
/// a path through `..`, a symbolic link and a hard link (the links named
/// `soft-<n>.<extension>` and `hard-<n>.<extension>`, made here).
fn spellings(dir: &Path, input: &str, n: usize, extension: &str) -> Vec<(String, &'static str)> {
    let mut spelled = vec![
        (input.to_owned(), "name"),
        (format!("missing/../{input}"), ".."),
    ];
    let soft = format!("soft-{n}.{extension}");
    if symlink(Path::new(input), &dir.join(&soft)) {
        spelled.push((soft, "symbolic link"));
    }
    let hard = format!("hard-{n}.{extension}");
    fs::hard_link(dir.join(input), dir.join(&hard)).unwrap();
    spelled.push((hard, "hard link"));
    spelled
}

/// The files of [`inputs_dir`].
const INPUTS: [&str; 5] = ["scene.toml", "model.bpt", "hm.png", "main.rib", "part.png"];

/// Every spelling of each of `inputs` (file, label) as the output of the
/// command `run` makes is refused, and every input survives. The links
/// carry `extension`, one the output accepts, so their refusal is the
/// input's (`input <label>`); an input's own name may be refused for its
/// extension first, which protects it as well.
fn try_every_input(
    dir: &Path,
    command: &str,
    inputs: &[(&str, &str)],
    extension: &str,
    run: impl Fn(&str) -> Vec<String>,
) {
    let before = snapshot(dir, &INPUTS);
    for (n, (input, label)) in inputs.iter().enumerate() {
        for (output, how) in spellings(dir, input, n, extension) {
            let args = run(&output);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let what = format!("{command}: {input} by {how} ({output})");
            let (ok, stderr) = reyes_in(dir, &args);
            let input_words = format!("input {label}");
            let for_the_extension = !output.ends_with(&format!(".{extension}"))
                && (stderr.contains("unknown image format")
                    || stderr.contains("extension does not match"));
            let words: &[&str] = if for_the_extension {
                &[&output]
            } else {
                &[&output, &input_words]
            };
            assert_refused(&what, (ok, stderr.clone()), words, dir, &before);
        }
    }
    // No image, statistics or screenshot was written; the links go.
    let mut written = Vec::new();
    for name in names(dir) {
        if name.starts_with("soft-") || name.starts_with("hard-") {
            fs::remove_file(dir.join(name)).unwrap();
        } else if !INPUTS.contains(&name.as_str()) {
            written.push(name);
        }
    }
    assert!(written.is_empty(), "{command}: wrote {written:?}");
}

/// `args` as owned strings.
fn owned(args: &[&str]) -> Vec<String> {
    args.iter().map(|a| (*a).to_owned()).collect()
}

#[test]
fn render_refuses_every_input_as_any_output() {
    let temp = inputs_dir("guard-render-inputs");
    let dir = temp.path("");
    let toml_inputs = [
        ("scene.toml", "scene"),
        ("model.bpt", "model"),
        ("hm.png", "height map"),
    ];
    try_every_input(&dir, "render -o", &toml_inputs, "png", |output| {
        let mut args = owned(&["render", "scene.toml", "-o", output]);
        args.extend(owned(&TINY));
        args
    });
    try_every_input(
        &dir,
        "render --stats-json",
        &toml_inputs,
        "json",
        |output| {
            let mut args = owned(&[
                "render",
                "scene.toml",
                "-o",
                "r.png",
                "--stats-json",
                output,
            ]);
            args.extend(owned(&TINY));
            args
        },
    );
    try_every_input(&dir, "render --trace", &toml_inputs, "json", |output| {
        let mut args = owned(&["render", "scene.toml", "-o", "r.png", "--trace", output]);
        args.extend(owned(&TINY));
        args
    });
    let rib_inputs = [("main.rib", "scene"), ("part.png", "RIB archive")];
    try_every_input(&dir, "render main.rib -o", &rib_inputs, "png", |output| {
        let mut args = owned(&["render", "main.rib", "-o", output]);
        args.extend(owned(&TINY));
        args
    });
    try_every_input(
        &dir,
        "render main.rib --stats-json",
        &rib_inputs,
        "json",
        |output| {
            let mut args = owned(&["render", "main.rib", "-o", "r.png", "--stats-json", output]);
            args.extend(owned(&TINY));
            args
        },
    );
}

#[test]
fn view_refuses_every_input_before_opening_a_window() {
    let temp = inputs_dir("guard-view-inputs");
    let dir = temp.path("");
    let inputs = [
        ("scene.toml", "scene"),
        ("model.bpt", "model"),
        ("hm.png", "height map"),
    ];
    for flag in ["--screenshot", "-o"] {
        try_every_input(&dir, &format!("view {flag}"), &inputs, "png", |output| {
            owned(&["view", "scene.toml", "--frames", "1", flag, output])
        });
    }
    try_every_input(&dir, "view --log-json", &inputs, "json", |output| {
        owned(&["view", "scene.toml", "--frames", "1", "--log-json", output])
    });
}

#[test]
fn convert_refuses_every_input_as_its_scene() {
    let temp = inputs_dir("guard-convert-inputs");
    let dir = temp.path("");
    // main.rib reads part.png; here also an archive named like a TOML.
    fs::write(
        dir.join("main.rib"),
        "Projection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 5\nReadArchive \"part.png\"\nReadArchive \"scene.toml\"\nWorldEnd\n",
    )
    .unwrap();
    fs::write(dir.join("scene.toml"), "Sphere 2 -2 2 360\n").unwrap();
    let inputs = [
        ("main.rib", "RIB scene"),
        ("part.png", "RIB archive"),
        ("scene.toml", "RIB archive"),
    ];
    try_every_input(&dir, "convert -o", &inputs, "toml", |output| {
        owned(&["convert", "main.rib", "-o", output])
    });
}

#[test]
fn view_refuses_an_image_name_of_another_format() {
    let temp = inputs_dir("guard-view-jpg");
    let dir = temp.path("");
    let before = snapshot(&dir, &["scene.toml"]);
    for flag in ["--screenshot", "-o"] {
        let outcome = reyes_in(
            &dir,
            &["view", "scene.toml", "--frames", "1", flag, "shot.jpg"],
        );
        assert_refused(flag, outcome, &["shot.jpg", ".png", ".exr"], &dir, &before);
        assert!(!dir.join("shot.jpg").exists());
    }
}

#[test]
fn json_outputs_refuse_the_extensions_of_other_formats() {
    let temp = TempDir::new("guard-json");
    let dir = temp.path("");
    for output in ["s.png", "s.toml", "s.bpt"] {
        let mut args = vec!["render", "-o", "r.png", "--stats-json", output];
        args.extend(TINY);
        let (ok, stderr) = reyes_in(&dir, &args);
        assert!(
            !ok && stderr.contains(output) && stderr.contains("*.json"),
            "{stderr}"
        );
        assert!(names(&dir).is_empty(), "{output}: wrote {:?}", names(&dir));
    }
    let paths: Vec<PathBuf> = ["s.json", "s.txt"].iter().map(|n| dir.join(n)).collect();
    for path in &paths {
        let mut args = vec![
            "render",
            "-o",
            "r.png",
            "--stats-json",
            path.to_str().unwrap(),
        ];
        args.extend(TINY);
        let (ok, stderr) = reyes_in(&dir, &args);
        assert!(ok, "{stderr}");
        assert!(path.exists());
    }
}

/// A scene's surface shader and the texture its parameters name are inputs
/// too: `render -o` refuses the texture by every spelling, and both
/// survive.
#[test]
fn render_refuses_the_texture_its_shader_reads() {
    let temp = inputs_dir("guard-render-shader-inputs");
    let dir = temp.path("");
    fs::write(
        dir.join("paint.wgsl"),
        "struct Parameters { map: TextureId }\n\
         fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {\n\
             return SurfaceOutput(ctx.Cs * texture(ctx, params.map, ctx.s, ctx.t).rgb, ctx.Os);\n\
         }\n",
    )
    .unwrap();
    fs::write(
        dir.join("shaded.toml"),
        "[[objects]]\nmodel = \"model.bpt\"\n\n[objects.surface]\nshader = \"wgsl\"\nfile = \"paint.wgsl\"\nparameters = { map = \"hm.png\" }\n",
    )
    .unwrap();
    let before = snapshot(&dir, &["paint.wgsl", "hm.png", "shaded.toml"]);
    for (n, (output, how)) in spellings(&dir, "hm.png", 9, "png").into_iter().enumerate() {
        let mut args = owned(&["render", "shaded.toml", "-o", &output]);
        args.extend(owned(&TINY));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (ok, stderr) = reyes_in(&dir, &args);
        assert_refused(
            &format!("texture by {how} ({n})"),
            (ok, stderr),
            &[&output, "input texture"],
            &dir,
            &before,
        );
    }
}
