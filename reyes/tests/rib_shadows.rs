//! Shadows in RIB: depth frames (`Display ... "z"`), `MakeShadow` between
//! frames, and the shadowed standard lights reading the maps. The golden
//! scene `tests/data/rib_shadows/shadows.rib` renders two depth frames from
//! two spotlights, makes their maps and renders a beauty frame with two
//! `shadowspot` lights; its hand-written TOML twin `shadows.toml` reads
//! the same maps. Everything is rendered by the binary with `--cpu`, in a
//! temporary directory (the RIB's names are relative to the current
//! directory). Unbalanced `FrameBegin`/`FrameEnd` is tested in
//! `rib_frames.rs` and `rib_structure.rs`.

mod files;

use std::path::Path;
use std::process::Command;

use files::TempDir;
use glam::Vec3;
use image::RgbImage;
use reyes::prepare::PreparedScene;
use reyes::rib::FrameRequest;
use reyes::scene::{Light, LightKind, LightShadow, Scene, ShadowMaps};
use reyes::shadow::ShadowFilter;

/// The golden scene's files.
const SCENE_FILES: [&str; 5] = [
    "shadows.rib",
    "geometry.rib",
    "shadows.toml",
    "square.bpt",
    "bump.bpt",
];

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

/// A temporary directory holding the golden scene.
fn scene_dir(name: &str) -> TempDir {
    let dir = TempDir::new(name);
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rib_shadows");
    for file in SCENE_FILES {
        std::fs::copy(data.join(file), dir.path(file)).unwrap();
    }
    dir
}

fn rgb(path: &Path) -> RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// The twin's text without its lights' shadows.
fn unshadowed(toml: &str) -> String {
    toml.lines()
        .filter(|l| {
            !["shadow_map", "samples", "blur", "bias"]
                .iter()
                .any(|k| l.starts_with(k))
        })
        .map(|l| format!("{l}\n"))
        .collect()
}

/// The pixel (column, row) where the twin's camera sees the world point `p`.
fn pixel_of(dir: &TempDir, toml: &str, p: Vec3) -> (u32, u32) {
    let scene = Scene::load(dir.path(toml)).unwrap();
    let camera = PreparedScene::load(&scene).unwrap().camera;
    let clip = camera.to_clip(p);
    let (x, y) = (clip.x / clip.w, clip.y / clip.w);
    let column = (x + 1.0) * 0.5 * camera.width as f32;
    let row = (1.0 - y) * 0.5 * camera.height as f32;
    (column as u32, row as u32)
}

/// The largest channel difference between two pixels.
fn diff(a: &RgbImage, b: &RgbImage, (x, y): (u32, u32)) -> i32 {
    let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
    (0..3)
        .map(|c| i32::from(q[c]) - i32::from(p[c]))
        .max_by_key(|d| d.abs())
        .unwrap()
}

#[test]
fn depth_frames_make_the_maps_the_shadowed_spotlights_of_the_last_frame_read() {
    let dir = scene_dir("rib-shadows-golden");
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "shadows.rib"]);
    assert!(ok, "{stderr}");
    for line in [
        "wrote spot1.z (256x256, 1 spp)",
        "wrote shadow map spot1.shad (256x256, from spot1.z)",
        "wrote shadow map spot2.shad (256x256, from spot2.z)",
        "wrote shadows.png (160x120, 4 spp)",
    ] {
        assert!(stdout.contains(line), "{line:?} missing:\n{stdout}");
    }
    // In order: each map after its depth frame, both before the picture.
    let at = |s: &str| stdout.find(s).unwrap();
    assert!(at("wrote spot1.z") < at("spot1.shad") && at("spot2.shad") < at("wrote shadows.png"));
    assert!(!stderr.contains("warning"), "{stderr}");

    // The twin, with the same maps and without shadows.
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "shadows.toml", "-o", "twin.png"]);
    assert!(ok, "{stderr}");
    let plain = unshadowed(&std::fs::read_to_string(dir.path("shadows.toml")).unwrap());
    std::fs::write(dir.path("plain.toml"), plain).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "plain.toml", "-o", "plain.png"]);
    assert!(ok, "{stderr}");
    let (rib, twin, plain) = (
        rgb(&dir.path("shadows.png")),
        rgb(&dir.path("twin.png")),
        rgb(&dir.path("plain.png")),
    );

    // The RIB and its twin agree.
    let pixels = rib.width() * rib.height();
    let mut within = 0;
    let mut largest = 0;
    for y in 0..rib.height() {
        for x in 0..rib.width() {
            let d = diff(&rib, &twin, (x, y)).abs();
            largest = largest.max(d);
            within += u32::from(d <= 2);
        }
    }
    assert!(
        f64::from(within) >= 0.99 * f64::from(pixels) && largest <= 8,
        "{within} of {pixels} pixels within 2/255, largest difference {largest}"
    );

    // Ground points in the floating square's shadow from each spotlight
    // (the square at z = 1.2 projected from the light onto z = 0, where
    // the camera sees the ground), and one both light.
    let spot2_shadow = pixel_of(&dir, "plain.toml", Vec3::new(-0.05, 0.32, 0.0));
    let spot1_shadow = pixel_of(&dir, "plain.toml", Vec3::new(-2.0, 0.2, 0.0));
    let lit = pixel_of(&dir, "plain.toml", Vec3::new(1.2, 0.8, 0.0));
    for (what, pixel) in [("spot2", spot2_shadow), ("spot1", spot1_shadow)] {
        let darker = diff(&rib, &plain, pixel);
        assert!(
            darker >= 20,
            "{what}'s shadow at {pixel:?}: only {darker}/255 darker than unshadowed"
        );
    }
    let d = diff(&rib, &plain, lit);
    assert!(d.abs() <= 2, "the lit ground at {lit:?} differs by {d}/255");

    // Frame 3 alone runs the one request before it (spot2's), not the
    // one before frame 2 (spot1's): its map is read as it is on disk.
    std::fs::remove_file(dir.path("spot1.shad")).unwrap();
    std::fs::remove_file(dir.path("spot2.shad")).unwrap();
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "shadows.rib", "--frame", "3"]);
    assert!(
        !ok && stdout.contains("wrote shadow map spot2.shad"),
        "{stdout}"
    );
    assert!(!dir.path("spot1.shad").exists());
    assert!(
        stderr.contains("shadows.rib:53: lights[2] (spot light): shadow map spot1.shad"),
        "{stderr}"
    );
}

/// A one-frame beauty scene lit by a `shadowspot` reading `map`, after
/// `before` (requests before the frame).
fn beauty(before: &str, map: &str) -> String {
    format!(
        "{before}FrameBegin 1\nFormat 16 12 1\nPixelSamples 1 1\nDisplay \"beauty.png\" \"file\" \"rgba\"\n\
WorldBegin\nLightSource \"shadowspot\" 1 \"from\" [0 0 0] \"to\" [0 0 1] \"string shadowname\" [\"{map}\"]\n\
Translate 0 0 3\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n"
    )
}

#[test]
fn make_shadow_of_a_picture_that_is_no_depth_image_names_the_file_and_line() {
    let dir = TempDir::new("rib-shadows-wrong-kind");
    // An RGB EXR and a PNG, as a beauty frame writes them.
    let frame = "FrameBegin 1\nFormat 8 8 1\nDisplay \"rgb.exr\" \"file\" \"rgba\"\nWorldBegin\n\
Translate 0 0 3\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n";
    let frame_png = frame
        .replace("rgb.exr", "rgb.png")
        .replace("FrameBegin 1", "FrameBegin 2");
    for (picture, line) in [("rgb.exr", 17), ("rgb.png", 18)] {
        let rib = format!(
            "{frame}{frame_png}MakeShadow \"rgb.exr\" \"a.shad\"\nMakeShadow \"rgb.png\" \"b.shad\"\n"
        );
        let rib = if picture == "rgb.png" {
            rib.replace("MakeShadow \"rgb.exr\" \"a.shad\"\n", "\n")
        } else {
            rib
        };
        std::fs::write(dir.path("scene.rib"), rib).unwrap();
        let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "scene.rib"]);
        assert!(!ok, "{stderr}");
        assert!(
            stderr.contains(&format!("scene.rib:{line}: MakeShadow \"{picture}\"")),
            "{stderr}"
        );
        assert!(stderr.contains("request failed"), "{stderr}");
        if picture == "rgb.exr" {
            assert!(
                stderr.contains("not a depth image with its camera"),
                "{stderr}"
            );
            // The failure stops the request after it.
            assert!(
                stderr.contains("not run: scene.rib:18: MakeShadow"),
                "{stderr}"
            );
        } else {
            assert!(
                stderr.contains("cannot read it as a depth image"),
                "{stderr}"
            );
        }
        assert!(!dir.path("a.shad").exists() && !dir.path("b.shad").exists());
    }
}

#[test]
fn a_failed_make_shadow_stops_the_later_frames_unless_keep_going() {
    let dir = TempDir::new("rib-shadows-stop");
    let rib = beauty("MakeShadow \"missing.z\" \"a.shad\"\n", "a.shad");
    std::fs::write(dir.path("scene.rib"), &rib).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "scene.rib"]);
    assert!(
        !ok && stderr.contains("scene.rib:1: MakeShadow"),
        "{stderr}"
    );
    assert!(stderr.contains("not rendered: frame 1"), "{stderr}");
    assert!(!dir.path("beauty.png").exists());
    // With --keep-going the frame renders, and fails on its missing map.
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "--keep-going", "scene.rib"]);
    assert!(!ok, "{stderr}");
    assert!(stderr.contains("1 of 1 frames failed: frame 1"), "{stderr}");
    assert!(
        stderr.contains("1 request failed: scene.rib:1: MakeShadow"),
        "{stderr}"
    );
}

#[test]
fn a_missing_shadow_map_names_the_light_and_path_and_is_unshadowed_with_lenient() {
    let dir = TempDir::new("rib-shadows-missing-map");
    std::fs::write(dir.path("scene.rib"), beauty("", "nowhere.shad")).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "scene.rib"]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("scene.rib:6: lights[0] (spot light): shadow map nowhere.shad"),
        "{stderr}"
    );
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "--lenient", "scene.rib"]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains(
            "warning: scene.rib:6: lights[0] (spot light): shadow map nowhere.shad is missing"
        ) && stderr.contains("renders the light unshadowed"),
        "{stderr}"
    );
    assert!(stdout.contains("wrote beauty.png"), "{stdout}");
    // Unshadowed: as the same scene with a plain spotlight.
    let lenient = rgb(&dir.path("beauty.png"));
    let plain = beauty("", "").replace("shadowspot", "spotlight");
    std::fs::write(dir.path("plain.rib"), plain).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "plain.rib", "-o", "plain.png"]);
    assert!(ok, "{stderr}");
    assert_eq!(lenient, rgb(&dir.path("plain.png")));
}

#[test]
fn make_shadow_after_the_last_frame_runs_and_convert_keeps_the_maps_space() {
    let dir = scene_dir("rib-shadows-after");
    let rib = std::fs::read_to_string(dir.path("shadows.rib")).unwrap();
    // Only the first depth frame, its MakeShadow after it, the last request.
    let first = &rib[..rib.find("FrameBegin 2").unwrap()];
    std::fs::write(dir.path("depth.rib"), first).unwrap();
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "depth.rib"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("wrote shadow map spot1.shad"), "{stdout}");
    let map = reyes::shadow::read_shadow_map(&dir.path("spot1.shad")).unwrap();
    assert_eq!((map.width, map.height), (256, 256));
    let (ok, _, stderr) = reyes(&dir, &["convert", "depth.rib", "-o", "depth.toml"]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("MakeShadow is not run (not converted)"),
        "{stderr}"
    );
    // The beauty frame's shadowed lights keep their maps, and the TOML
    // scene the space they were rendered in (the RIB's world; the scene is
    // in the frame's camera space): it renders the RIB's picture.
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "shadows.rib"]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = reyes(
        &dir,
        &["convert", "shadows.rib", "--frame", "3", "-o", "b.toml"],
    );
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("world space"), "{stderr}");
    let toml = std::fs::read_to_string(dir.path("b.toml")).unwrap();
    assert!(toml.contains("shadow_map = \"spot1.shad\""), "{toml}");
    assert!(toml.contains("shadow_map_space = ["), "{toml}");
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "b.toml", "-o", "b.png"]);
    assert!(ok, "{stderr}");
    let (rib, converted) = (rgb(&dir.path("shadows.png")), rgb(&dir.path("b.png")));
    let differing = |a: &RgbImage, b: &RgbImage| {
        let mut count = 0;
        for y in 0..a.height() {
            for x in 0..a.width() {
                count += u32::from(diff(a, b, (x, y)).abs() > 2);
            }
        }
        count
    };
    let pixels = rib.width() * rib.height();
    let apart = differing(&rib, &converted);
    assert!(
        apart * 100 <= pixels,
        "{apart} of {pixels} pixels differ by more than 2/255"
    );
    // Without the maps' space the shadows fall elsewhere.
    let lost: String = toml
        .lines()
        .filter(|l| !l.starts_with("shadow_map_space"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path("lost.toml"), lost).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "lost.toml", "-o", "lost.png"]);
    assert!(ok, "{stderr}");
    let misplaced = differing(&rib, &rgb(&dir.path("lost.png")));
    eprintln!(
        "converted: {apart} of {pixels} pixels differ by more than 2/255; without the space {misplaced}"
    );
    assert!(
        misplaced * 20 > pixels,
        "only {misplaced} of {pixels} pixels move without the space"
    );
}

/// The one frame of RIB `world` (requests inside `WorldBegin`), read from
/// text; its warnings joined.
fn lights_of(world: &str) -> (Vec<reyes::scene::Light>, String) {
    let text =
        format!("Format 16 16 1\nWorldBegin\n{world}Polygon \"P\" [0 0 5 1 0 5 0 1 5]\nWorldEnd\n");
    let rib =
        reyes::rib::RibScene::from_text(&text, "l.rib").unwrap_or_else(|e| panic!("{e}\n{text}"));
    let warnings: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    (rib.scene.lights, warnings.join("\n"))
}

fn maps(light: &reyes::scene::Light) -> Vec<String> {
    match &light.shadow.as_ref().expect("a shadow").maps {
        ShadowMaps::Files(files) => files.iter().map(|f| f.display().to_string()).collect(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn shadowed_lights_are_the_plain_lights_with_their_maps_and_filter() {
    let spot = "\"from\" [1 2 3] \"to\" [0 0 5] \"coneangle\" [0.5] \"intensity\" [7]";
    let (plain, _) = lights_of(&format!("LightSource \"spotlight\" 1 {spot}\n"));
    let (shadowed, warnings) = lights_of(&format!(
        "LightSource \"shadowspot\" 1 {spot} \"string shadowname\" \"a.shad\" \"float samples\" [4] \"float width\" [2] \"float blur\" [0.1] \"float bias\" [0.05]\n"
    ));
    assert_eq!(warnings, "");
    let shadow = shadowed[0].shadow.clone().expect("a shadow");
    assert_eq!(
        shadow,
        LightShadow {
            maps: ShadowMaps::Files(vec!["a.shad".into()]),
            filter: ShadowFilter {
                samples: 4,
                width: 2.0,
                blur: 0.1,
                bias: 0.05,
            },
        }
    );
    assert_eq!(
        Light {
            shadow: None,
            ..shadowed[0].clone()
        },
        plain[0]
    );

    // shadowdistant: distantlight's direction; the filter's defaults.
    let distant = "\"from\" [0 1 0] \"to\" [0 0 1]";
    let (plain, _) = lights_of(&format!("LightSource \"distantlight\" 1 {distant}\n"));
    let (shadowed, _) = lights_of(&format!(
        "LightSource \"shadowdistant\" 1 {distant} \"string shadowname\" [\"d.shad\"]\n"
    ));
    assert_eq!(shadowed[0].kind, LightKind::Distant);
    assert_eq!(shadowed[0].direction, plain[0].direction);
    assert_eq!(maps(&shadowed[0]), ["d.shad"]);
    assert_eq!(
        shadowed[0].shadow.as_ref().unwrap().filter,
        ShadowFilter::default()
    );

    // shadowpoint: the faces given, in the order px nx py ny pz nz.
    let (shadowed, warnings) = lights_of(
        "LightSource \"shadowpoint\" 1 \"from\" [0 0 1] \"string sfnz\" \"nz.shad\" \"string sfny\" \"\" \"string sfpx\" \"px.shad\"\n",
    );
    assert_eq!(warnings, "");
    assert_eq!(shadowed[0].kind, LightKind::Point);
    assert_eq!(maps(&shadowed[0]), ["px.shad", "nz.shad"]);
}

#[test]
fn an_empty_shadowname_is_no_shadow_and_bad_filters_warn() {
    let (lights, warnings) =
        lights_of("LightSource \"shadowspot\" 1 \"string shadowname\" [\"\"]\n");
    assert_eq!(
        (lights[0].kind, lights[0].shadow.is_none()),
        (LightKind::Spot, true)
    );
    assert_eq!(warnings, "");
    let (lights, warnings) = lights_of("LightSource \"shadowpoint\" 1 \"from\" [0 0 1]\n");
    assert!(lights[0].shadow.is_none());
    assert!(
        warnings.contains("l.rib:3: shadowpoint names no shadow map"),
        "{warnings}"
    );
    let (lights, warnings) = lights_of(
        "LightSource \"shadowspot\" 1 \"string shadowname\" \"a.shad\" \"float swidth\" [2] \"float twidth\" [3] \"float samples\" [0] \"float blur\" [-1]\n",
    );
    let filter = lights[0].shadow.as_ref().unwrap().filter;
    assert_eq!((filter.width, filter.samples, filter.blur), (3.0, 1, 0.0));
    for expected in [
        "swidth 2 and twidth 3",
        "shadow samples 0; using 1",
        "shadow blur -1",
    ] {
        assert!(warnings.contains(expected), "{expected:?}: {warnings}");
    }
}

#[test]
fn make_shadow_is_handed_over_with_the_frame_after_it() {
    let frame = |n: u32, inside: &str| {
        format!("FrameBegin {n}\n{inside}WorldBegin\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n")
    };
    let text = format!(
        "MakeShadow \"a.z\" \"a.shad\"\n{}MakeShadow \"b.z\" \"b.shad\"\n{}MakeShadow \"c.z\" \"c.shad\"\n",
        frame(1, "MakeShadow \"in.z\" \"in.shad\"\n"),
        frame(2, "")
    );
    let frames = reyes::rib::RibFrames::from_text_with(&text, "f.rib", Default::default()).unwrap();
    let names = |requests: &[FrameRequest]| -> Vec<(String, usize)> {
        requests
            .iter()
            .map(|r| (r.output().display().to_string(), r.origin().1))
            .collect()
    };
    assert_eq!(
        names(&frames.frames[0].requests_before),
        [("a.shad".to_owned(), 1), ("in.shad".to_owned(), 3)]
    );
    assert_eq!(
        names(&frames.frames[1].requests_before),
        [("b.shad".to_owned(), 8)]
    );
    assert_eq!(names(&frames.requests_after), [("c.shad".to_owned(), 14)]);
    // Read as one scene, none runs: each warns.
    let scene = reyes::rib::RibScene::from_text(&text, "f.rib").unwrap();
    let not_run = scene
        .warnings
        .iter()
        .filter(|w| w.message.starts_with("MakeShadow is not run"))
        .count();
    assert_eq!(not_run, 4);
}

#[test]
fn a_frame_maps_the_files_world_into_its_own() {
    // The camera 5 in front of the world's origin and 1 to its right:
    // RenderMan's world point (1, 0, 0) is at the camera's origin, x
    // mirrored into the renderer's world. A depth frame writes a map, so
    // it keeps the space; the same frame in colour keeps none (it reads and
    // writes no map).
    let frame = "Format 16 16 1\nTranslate -1 0 5\nWorldBegin\nSphere 1 -1 1 360\nWorldEnd\n";
    let colour = reyes::rib::RibScene::from_text(frame, "w.rib").unwrap();
    assert_eq!(colour.scene.shadow_map_space, None);
    let text = format!("Display \"w.z\" \"zfile\" \"z\"\n{frame}");
    let rib = reyes::rib::RibScene::from_text(&text, "w.rib").unwrap();
    let to_world = rib
        .scene
        .shadow_map_space
        .expect("a RIB frame's maps' space");
    assert_eq!(
        to_world.transform_point3(Vec3::new(1.0, 0.0, 0.0)),
        Vec3::new(0.0, 0.0, 5.0)
    );
    assert_eq!(
        to_world.transform_point3(Vec3::new(2.0, 0.0, 0.0)),
        Vec3::new(-1.0, 0.0, 5.0)
    );
}

#[test]
fn a_shadowdistant_reads_an_orthographic_depth_frame_from_above() {
    let dir = scene_dir("rib-shadows-distant");
    let golden = std::fs::read_to_string(dir.path("shadows.rib")).unwrap();
    // The golden beauty frame's camera, lit by one light from straight above.
    let beauty = &golden[golden.find("FrameBegin 3").unwrap()
        ..golden.find("  WorldBegin\n    LightSource").unwrap()];
    let rib = |light: &str, image: &str| {
        let beauty = beauty.replace("shadows.png", image);
        format!(
            "Clipping 0.1 100\nFrameBegin 1\nFormat 256 256 1\nPixelSamples 1 1\n\
Projection \"orthographic\"\nScreenWindow -3 3 -3 3\nDisplay \"sun.z\" \"zfile\" \"z\"\n\
Hider \"hidden\" \"depthfilter\" \"midpoint\"\nTransform [1 0 0 0 0 1 0 0 0 0 -1 0 0 0 10 1]\n\
WorldBegin\nReadArchive \"geometry.rib\"\nWorldEnd\nFrameEnd\nMakeShadow \"sun.z\" \"sun.shad\"\n\
{beauty}  WorldBegin\nLightSource {light} 1 \"from\" [0 0 1] \"to\" [0 0 0] \"string shadowname\" \"sun.shad\"\n\
ReadArchive \"geometry.rib\"\nWorldEnd\nFrameEnd\n"
        )
    };
    std::fs::write(dir.path("sun.rib"), rib("\"shadowdistant\"", "sun.png")).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "sun.rib"]);
    assert!(ok, "{stderr}");
    std::fs::write(dir.path("plain.rib"), rib("\"distantlight\"", "plain.png")).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "plain.rib"]);
    assert!(ok, "{stderr}");
    let (shadowed, plain) = (rgb(&dir.path("sun.png")), rgb(&dir.path("plain.png")));
    let twin = unshadowed(&std::fs::read_to_string(dir.path("shadows.toml")).unwrap());
    std::fs::write(dir.path("plain.toml"), twin).unwrap();
    // Straight below the floating square (x in [-1.6, -0.4], y in
    // [-0.6, 0.6]), where the camera sees the ground past it; and the
    // open ground.
    let below = pixel_of(&dir, "plain.toml", Vec3::new(-1.0, -0.3, 0.0));
    let open = pixel_of(&dir, "plain.toml", Vec3::new(1.5, 1.5, 0.0));
    let darker = diff(&shadowed, &plain, below);
    assert!(
        darker >= 20,
        "below the square at {below:?}: {darker}/255 darker"
    );
    let d = diff(&shadowed, &plain, open);
    assert!(
        d.abs() <= 2,
        "the open ground at {open:?} differs by {d}/255"
    );
}

/// A depth frame of a sphere seen from the spotlight of [`beauty`], to `map`.
fn depth_frame(map: &str) -> String {
    format!(
        "FrameBegin 0\nFormat 16 16 1\nPixelSamples 1 1\nProjection \"perspective\" \"fov\" [90]\n\
Display \"{map}\" \"zfile\" \"z\"\nWorldBegin\nTranslate 0 0 3\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n"
    )
}

#[test]
fn a_display_that_would_replace_a_made_map_is_refused_before_any_work() {
    let dir = TempDir::new("rib-shadows-display-over-map");
    let rib = depth_frame("d.z")
        + &beauty("MakeShadow \"d.z\" \"m.exr\"\n", "m.exr").replace("beauty.png", "m.exr");
    std::fs::write(dir.path("scene.rib"), &rib).unwrap();
    let (ok, _, stderr) = reyes(&dir, &["render", "--cpu", "scene.rib"]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("shadow map made by scene.rib:11: MakeShadow"),
        "{stderr}"
    );
    assert!(!dir.path("d.z").exists(), "nothing is rendered");
}

#[test]
fn a_map_remade_between_frames_is_no_conflict() {
    let dir = TempDir::new("rib-shadows-remade-map");
    let make = "MakeShadow \"d.z\" \"m.shad\"\n";
    let rib = depth_frame("d.z") + make + make + &beauty("", "m.shad");
    std::fs::write(dir.path("scene.rib"), &rib).unwrap();
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "scene.rib"]);
    assert!(ok, "{stderr}");
    assert_eq!(
        stdout.matches("wrote shadow map m.shad").count(),
        2,
        "{stdout}"
    );
    assert!(dir.path("beauty.png").exists());
}

#[test]
fn a_map_made_by_the_file_is_found_when_rendering_from_another_directory() {
    // The RIB lies in scenes/, the render runs in its parent: Display and
    // MakeShadow write there (the current directory), and the light's
    // shadowname, relative to the current directory too, reads the map
    // MakeShadow wrote, not scenes/m.shad.
    let dir = TempDir::new("rib-shadows-other-directory");
    std::fs::create_dir_all(dir.path("scenes")).unwrap();
    let rib = depth_frame("d.z") + &beauty("MakeShadow \"d.z\" \"m.shad\"\n", "m.shad");
    std::fs::write(dir.path("scenes/scene.rib"), &rib).unwrap();
    let (ok, stdout, stderr) = reyes(&dir, &["render", "--cpu", "scenes/scene.rib"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("wrote shadow map m.shad"), "{stdout}");
    assert!(dir.path("m.shad").exists() && dir.path("beauty.png").exists());
    assert!(!dir.path("scenes/m.shad").exists());
    assert!(
        !stderr.contains("shadow map"),
        "no map is missing: {stderr}"
    );
}
