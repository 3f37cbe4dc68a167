//! Every frame of a RIB file (`FrameBegin n` … `FrameEnd`): each renders
//! with its own options on top of those before it, exactly as the same
//! scene given alone; textures made between frames serve the later ones;
//! `--frame` selects, `-o out.####.png` numbers the images; bad frame
//! structure is an error with its line; a failed frame stops the later
//! ones unless `--keep-going`, and the exit status says so. Renders are
//! tiny `--cpu` ones.

mod common;
mod files;

use std::path::Path;
use std::process::Command;

use files::TempDir;
use reyes::rib::{RibFrames, RibOptions, RibScene};

/// The options before the first frame.
const BEFORE: &str = "PixelSamples 1 1\nPixelFilter \"box\" 1 1\nShadingRate 4\n";

/// Frame 1: a perspective red sphere, 2 x 2 samples, the camera moved.
const FRAME_1: &str = "Format 32 24 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" 50\n\
Display \"one.png\" \"file\" \"rgba\"\nTranslate 0.3 0 0\nWorldBegin\nTranslate 0 0 5\n\
Color 1 0 0\nSphere 1 -1 1 360\nWorldEnd\n";

/// Frame 2: another size, camera and colour; the samples and the
/// projection are the file's (orthographic), not frame 1's.
const FRAME_2: &str = "Format 20 30 1\nDisplay \"two.png\" \"file\" \"rgba\"\n\
Translate 0 -0.4 0\nWorldBegin\nTranslate 0 0 5\nColor 0 0.5 1\nSphere 1 -1 1 360\nWorldEnd\n";

/// `reyes ARGS` run in `dir`: (success, stdout, stderr).
fn reyes(dir: &TempDir, args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(dir.path(""))
        .args(args)
        .output()
        .expect("reyes runs");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn each_frame_renders_as_the_same_scene_alone() {
    let dir = TempDir::new("frames-alone");
    let both =
        format!("{BEFORE}FrameBegin 1\n{FRAME_1}FrameEnd\nFrameBegin 2\n{FRAME_2}FrameEnd\n");
    std::fs::write(dir.path("both.rib"), both).unwrap();
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "both.rib"]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("wrote one.png (32x24, 4 spp)")
            && stdout.contains("wrote two.png (20x30, 1 spp)"),
        "{stdout}"
    );
    for (frame, image) in [(FRAME_1, "one.png"), (FRAME_2, "two.png")] {
        let alone = format!("alone-{image}.rib");
        std::fs::write(dir.path(&alone), format!("{BEFORE}{frame}")).unwrap();
        let out = format!("alone-{image}");
        let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", &alone, "-o", &out]);
        assert!(ok, "{stderr}");
        assert!(
            bytes(&dir.path(image)) == bytes(&dir.path(&out)),
            "{image} differs from its scene rendered alone"
        );
    }
    // The frames differ (size, camera, colour).
    assert!(bytes(&dir.path("one.png")) != bytes(&dir.path("two.png")));
}

#[test]
fn a_texture_made_between_frames_serves_the_next_one() {
    let dir = TempDir::new("frames-texture");
    // Frame 1 draws the picture that the texture made after it names;
    // frame 2 maps it on a square facing the camera.
    let square = "WorldBegin\nTranslate 0 0 3\nSurface \"paintedplastic\" \"texturename\" \"made.tx\" \"Ks\" 0\n\
Patch \"bilinear\" \"P\" [-1 -1 0  1 -1 0  -1 1 0  1 1 0]\nWorldEnd\n";
    let frame_2 = format!(
        "Format 16 16 1\nDisplay \"two.png\" \"file\" \"rgba\"\nLightSource \"ambientlight\" 1 \"intensity\" 1\n{square}"
    );
    let text = format!(
        "{BEFORE}FrameBegin 1\n{FRAME_1}FrameEnd\n\
MakeTexture \"one.png\" \"made.tx\" \"clamp\" \"clamp\" \"box\" 1 1\n\
FrameBegin 2\n{frame_2}FrameEnd\n"
    );
    std::fs::write(dir.path("pass.rib"), text).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "pass.rib"]);
    assert!(ok, "{stderr}");
    // The same frame alone, with the picture frame 1 wrote.
    let alone = format!(
        "{BEFORE}MakeTexture \"one.png\" \"made.tx\" \"clamp\" \"clamp\" \"box\" 1 1\n{frame_2}"
    );
    std::fs::write(dir.path("alone.rib"), alone).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "alone.rib", "-o", "alone.png"]);
    assert!(ok, "{stderr}");
    assert!(bytes(&dir.path("two.png")) == bytes(&dir.path("alone.png")));
    // The texture shows: the square is red where the sphere was, black
    // around it.
    let image = image::open(dir.path("two.png")).unwrap().to_rgba8();
    let red = image
        .pixels()
        .filter(|p| p.0[0] > 100 && p.0[2] < 50)
        .count();
    let dark = image.pixels().filter(|p| p.0[0] < 20).count();
    assert!(red > 10 && dark > 10, "red {red}, dark {dark}");

    // A frame must not write the texture it reads.
    let text = format!(
        "{BEFORE}MakeTexture \"tex.png\" \"made.tx\" \"clamp\" \"clamp\" \"box\" 1 1\n\
FrameBegin 1\n{FRAME_1}FrameEnd\nFrameBegin 2\n{}FrameEnd\n",
        frame_2.replace("two.png", "tex.png")
    );
    std::fs::copy(dir.path("one.png"), dir.path("tex.png")).unwrap();
    std::fs::write(dir.path("self.rib"), text).unwrap();
    let before = bytes(&dir.path("tex.png"));
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "self.rib", "--frame", "2"]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("frame 2: the image of frame 2 tex.png is the input texture"),
        "{stderr}"
    );
    assert!(before == bytes(&dir.path("tex.png")), "the texture is kept");
}

/// Three frames of one tiny scene, 16 x 12, `Display "f<n>.png"`; frame
/// `bad` has a field of view the renderer refuses.
fn three_frames(bad: Option<u32>) -> String {
    let mut text = String::from(BEFORE);
    for n in [1, 2, 12] {
        let fov = if Some(n) == bad { 190 } else { 40 };
        text.push_str(&format!(
            "FrameBegin {n}\nFormat 16 12 1\nProjection \"perspective\" \"fov\" {fov}\n\
Display \"f{n}.png\" \"file\" \"rgba\"\nWorldBegin\nTranslate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n"
        ));
    }
    text
}

#[test]
fn frames_are_selected_and_numbered_by_the_pattern() {
    let dir = TempDir::new("frames-select");
    std::fs::write(dir.path("three.rib"), three_frames(None)).unwrap();
    // A plain -o names one image: several frames need the pattern.
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "three.rib", "-o", "out.png"]);
    assert!(
        !ok && stderr.contains("-o out.####.png") && stderr.contains("--frame N"),
        "{stderr}"
    );
    assert!(!dir.path("out.png").exists());
    // A frame the file lacks: the error lists its frames.
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "three.rib", "--frame", "2,5..7"]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("--frame 2,5..7: three.rib has no frame 5..7; its frames are 1, 2, 12"),
        "{stderr}"
    );
    // One frame: a plain -o.
    let (ok, stdout, stderr) = reyes(
        &dir,
        &[
            "render",
            "--cpu",
            "three.rib",
            "--frame",
            "12",
            "-o",
            "only.png",
        ],
    );
    assert!(ok && stdout.contains("wrote only.png"), "{stderr}");
    assert!(!dir.path("f1.png").exists() && !dir.path("f12.png").exists());
    // A range and the pattern, for the image and the statistics.
    let (ok, stdout, stderr) = reyes(
        &dir,
        &[
            "render",
            "--cpu",
            "three.rib",
            "--frame",
            "2..12",
            "-o",
            "seq/img.###.png",
            "--stats-json",
            "seq/stats.#.json",
            "--stats",
        ],
    );
    assert!(ok, "{stderr}");
    assert_eq!(
        common::dir_names(&dir.path("seq")),
        [
            "img.002.png",
            "img.012.png",
            "stats.12.json",
            "stats.2.json"
        ]
    );
    assert!(
        stdout.contains("statistics of frame 2") && stdout.contains("statistics of frame 12"),
        "{stdout}"
    );
    assert!(!stdout.contains("statistics of frame 1\n"), "{stdout}");
    let json = std::fs::read_to_string(dir.path("seq/stats.12.json")).unwrap();
    assert!(json.contains("\"input_patches\": 8"), "{json}");
    // Without -o, every frame's Display file.
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "three.rib"]);
    assert!(ok, "{stderr}");
    for name in ["f1.png", "f2.png", "f12.png"] {
        assert!(dir.path(name).exists(), "{name}");
    }
    // A file without frames takes no --frame and no pattern.
    std::fs::write(dir.path("plain.rib"), format!("{BEFORE}{FRAME_2}")).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "plain.rib", "--frame", "1"]);
    assert!(!ok && stderr.contains("has no FrameBegin"), "{stderr}");
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "plain.rib", "-o", "p.##.png"]);
    assert!(!ok && stderr.contains("no FrameBegin"), "{stderr}");
}

#[test]
fn a_failed_frame_stops_the_later_ones_unless_keep_going() {
    let dir = TempDir::new("frames-fail");
    std::fs::write(dir.path("bad.rib"), three_frames(Some(2))).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "bad.rib"]);
    assert!(!ok, "the exit status says a frame failed: {stderr}");
    assert!(
        stderr.contains("error: frame 2: ") && stderr.contains("fov 190"),
        "{stderr}"
    );
    assert!(
        stderr.contains("1 of 3 frames failed: frame 2; not rendered: frame 12"),
        "{stderr}"
    );
    assert!(dir.path("f1.png").exists() && !dir.path("f12.png").exists());
    std::fs::remove_file(dir.path("f1.png")).unwrap();

    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "bad.rib", "--keep-going"]);
    assert!(!ok, "{stderr}");
    assert!(stderr.contains("1 of 3 frames failed: frame 2"), "{stderr}");
    assert!(!stderr.contains("not rendered"), "{stderr}");
    assert!(dir.path("f1.png").exists() && dir.path("f12.png").exists());
    assert!(!dir.path("f2.png").exists());
}

/// The error of RIB `text` and its (line, column).
fn error(text: &str) -> (String, Option<(usize, usize)>) {
    let e = RibFrames::from_text_with(text, "bad.rib", RibOptions::default())
        .expect_err("the RIB is refused");
    (e.to_string(), e.position())
}

#[test]
fn bad_frame_structure_is_an_error_with_its_line() {
    let world = "WorldBegin\nWorldEnd\n";
    let cases = [
        (
            format!("FrameBegin 1\n{world}FrameBegin 2\n{world}FrameEnd\nFrameEnd\n"),
            4,
            "FrameBegin: inside the FrameBegin of line 1: frames do not nest",
        ),
        (
            format!("FrameBegin 1\n{world}FrameEnd\nFrameEnd\n"),
            5,
            "FrameEnd: without its FrameBegin",
        ),
        (
            format!("FrameBegin 1\n{world}"),
            1,
            "FrameBegin is never closed",
        ),
        (
            format!("FrameBegin 1\n{world}FrameEnd\n{world}"),
            5,
            "WorldBegin: outside FrameBegin/FrameEnd, after the frames that begin at line 1",
        ),
        (
            format!("{world}FrameBegin 1\n{world}FrameEnd\n"),
            3,
            "FrameBegin: after the world block of line 1, which is outside any frame",
        ),
        (
            "WorldBegin\nFrameBegin 1\nFrameEnd\nWorldEnd\n".to_owned(),
            2,
            "FrameBegin: inside the WorldBegin of line 1",
        ),
        (
            format!("FrameBegin 1.5\n{world}FrameEnd\n"),
            1,
            "not a whole number",
        ),
    ];
    for (text, line, message) in cases {
        let (got, position) = error(&text);
        assert!(got.contains(message), "{text}: {got}");
        assert_eq!(position.map(|p| p.0), Some(line), "{text}: {got}");
    }
}

#[test]
fn options_inside_a_frame_end_with_it() {
    let text = "Format 10 10 1\nFrameBegin 1\nFormat 30 20 1\nDisplay \"a.png\" \"file\" \"rgba\"\nWorldBegin\nWorldEnd\nFrameEnd\n\
Display \"base.png\" \"file\" \"rgba\"\nFrameBegin 2\nWorldBegin\nWorldEnd\nFrameEnd\n";
    let frames = RibFrames::from_text_with(text, "f.rib", RibOptions::default()).unwrap();
    let scenes: Vec<&RibScene> = frames
        .frames
        .iter()
        .map(|f| f.scene.as_ref().unwrap())
        .collect();
    assert_eq!(frames.list(), "1, 2");
    assert_eq!(
        (
            scenes[0].scene.resolution.width,
            scenes[0].scene.resolution.height
        ),
        (30, 20)
    );
    assert_eq!(
        (
            scenes[1].scene.resolution.width,
            scenes[1].scene.resolution.height
        ),
        (10, 10)
    );
    assert_eq!(scenes[0].display.as_deref(), Some("a.png"));
    assert_eq!(scenes[1].display.as_deref(), Some("base.png"));
    // Read as one scene: the first frame, with a warning that says so.
    let first = RibScene::from_text(text, "f.rib").unwrap();
    assert_eq!(first.scene.resolution.width, 30);
    assert!(
        first
            .warnings
            .iter()
            .any(|w| w.message.contains("the file has 2 frames (1, 2)")),
        "{:?}",
        first.warnings
    );
}

#[test]
fn convert_takes_one_frame() {
    let dir = TempDir::new("frames-convert");
    std::fs::write(dir.path("three.rib"), three_frames(None)).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["convert", "three.rib", "-o", "s.toml"]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains(
            "three.rib has 3 frames (1, 2, 12): a TOML scene holds one; choose it with --frame N"
        ),
        "{stderr}"
    );
    assert!(!dir.path("s.toml").exists());
    let (ok, stdout, stderr) = reyes(
        &dir,
        &["convert", "three.rib", "-o", "s.toml", "--frame", "12"],
    );
    assert!(
        ok && stdout.contains("converting frame 12 of three.rib"),
        "{stdout}{stderr}"
    );
    let toml = std::fs::read_to_string(dir.path("s.toml")).unwrap();
    assert!(toml.contains("width = 16"), "{toml}");
    let (ok, _, stderr) = reyes(
        &dir,
        &["convert", "three.rib", "-o", "s.toml", "--frame", "3"],
    );
    assert!(
        !ok && stderr.contains("its frames are 1, 2, 12"),
        "{stderr}"
    );
}

#[test]
fn each_frame_has_the_whole_patch_budget() {
    // A frame's sphere is 8 patches; three frames make 24, which one
    // budget for the whole file refused at the second frame. Frames are
    // rendered one at a time, each with the budget to itself.
    let dir = TempDir::new("frames-budget");
    std::fs::write(dir.path("three.rib"), three_frames(None)).unwrap();
    let (ok, stdout, stderr) = reyes(
        &dir,
        &["render", "--cpu", "--max-patches", "8", "three.rib"],
    );
    assert!(ok, "{stderr}");
    for n in [1, 2, 12] {
        assert!(stdout.contains(&format!("wrote f{n}.png")), "{stdout}");
    }
    // One frame over the budget is still refused, naming the request.
    let (ok, _, stderr) = reyes(
        &dir,
        &["render", "--cpu", "--max-patches", "7", "three.rib"],
    );
    assert!(!ok && stderr.contains("over the budget of 7"), "{stderr}");
}

#[test]
fn a_stream_gives_the_frames_that_load_gives() {
    let dir = TempDir::new("frames-stream");
    let path = dir.path("three.rib");
    std::fs::write(&path, three_frames(Some(2))).unwrap();
    let loaded = RibFrames::load(&path).unwrap();
    let mut stream = RibFrames::stream(&path, RibOptions::default());
    let streamed: Vec<_> = stream.by_ref().collect();
    let end = stream.finish().unwrap();
    assert_eq!(end.sources, loaded.sources);
    assert_eq!(streamed.len(), loaded.frames.len());
    for (a, b) in streamed.iter().zip(&loaded.frames) {
        assert_eq!((a.number, a.line), (b.number, b.line));
        match (&a.scene, &b.scene) {
            (Ok(a), Ok(b)) => {
                assert_eq!((&a.display, a.models.len()), (&b.display, b.models.len()))
            }
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
            _ => panic!("frame {:?}: one failed, the other not", a.number),
        }
    }
    // A stream dropped after its first frame stops its reader.
    let mut stream = RibFrames::stream(&path, RibOptions::default());
    assert!(stream.next().is_some());
    drop(stream);
    // An error in the text ends the stream; finish returns it.
    std::fs::write(
        &path,
        format!("{}FrameBegin 9\nWorldBegin\n", three_frames(None)),
    )
    .unwrap();
    let mut stream = RibFrames::stream(&path, RibOptions::default());
    assert_eq!(stream.by_ref().count(), 3);
    assert!(stream.finish().is_err());
}
