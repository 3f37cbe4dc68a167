//! The command line reports what it would otherwise do silently (issue 42,
//! item 3): an empty scene renders the background with a warning; a
//! truncated RIB is an error unless `--lenient`; options the chosen
//! renderer ignores are refused. Renders are tiny `--cpu` ones.

mod files;

use std::path::Path;

use files::{TempDir, run_cli};

/// A tiny CPU frame.
const TINY: [&str; 7] = ["--cpu", "--width", "16", "--height", "12", "--spp", "1"];

fn path_str(path: &Path) -> &str {
    path.to_str().expect("temp paths are UTF-8")
}

/// `reyes render SCENE TINY -o OUT [extra]`: (success, stderr, whether OUT
/// exists).
fn render(dir: &TempDir, scene: &str, extra: &[&str]) -> (bool, String, bool) {
    let out = dir.path("out.png");
    let _ = std::fs::remove_file(&out);
    let scene = dir.path(scene);
    let mut args = vec!["render", path_str(&scene)];
    args.extend(TINY);
    args.extend(["-o", path_str(&out)]);
    args.extend(extra);
    let (ok, stderr) = run_cli(&args);
    (ok, stderr, out.exists())
}

#[test]
fn empty_scenes_warn_and_render_the_background() {
    let dir = TempDir::new("cli-empty");
    for (name, text) in [
        ("empty.toml", ""),
        ("no-objects.toml", "objects = []\n"),
        ("background.toml", "background = [0.2, 0.3, 0.4]\n"),
        ("empty.rib", "Format 16 12 1\nWorldBegin\nWorldEnd\n"),
    ] {
        std::fs::write(dir.path(name), text).unwrap();
        let (ok, stderr, written) = render(&dir, name, &[]);
        assert!(ok && written, "{name}: {stderr}");
        assert!(
            stderr.contains(&format!(
                "warning: {}: the scene has no objects: the image is the background",
                path_str(&dir.path(name))
            )),
            "{name}: {stderr}"
        );
    }
}

#[test]
fn a_truncated_rib_is_an_error_unless_lenient() {
    let dir = TempDir::new("cli-truncated");
    std::fs::write(
        dir.path("cut.rib"),
        "Format 16 12 1\nFrameBegin 1\nWorldBegin\nAttributeBegin\nTranslate 0 0 5\nSphere 1 -1 1 360\n",
    )
    .unwrap();
    let (ok, stderr, written) = render(&dir, "cut.rib", &[]);
    assert!(!ok && !written, "{stderr}");
    assert!(
        stderr.contains("cut.rib:4:1: AttributeBegin is never closed")
            && stderr.contains("AttributeEnd")
            && stderr.contains("--lenient"),
        "{stderr}"
    );
    let (ok, stderr, written) = render(&dir, "cut.rib", &["--lenient"]);
    assert!(ok && written, "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("cut.rib:3: WorldBegin is never closed"),
        "{stderr}"
    );
    // `convert` reads the same way.
    let toml = dir.path("cut.toml");
    let (ok, stderr) = run_cli(&[
        "convert",
        path_str(&dir.path("cut.rib")),
        "-o",
        path_str(&toml),
    ]);
    assert!(!ok && !toml.exists(), "{stderr}");
    assert!(
        stderr.contains("AttributeBegin is never closed"),
        "{stderr}"
    );
    let (ok, stderr) = run_cli(&[
        "convert",
        path_str(&dir.path("cut.rib")),
        "-o",
        path_str(&toml),
        "--lenient",
    ]);
    assert!(ok && toml.exists(), "{stderr}");
}

#[test]
fn sides_out_of_range_is_an_error() {
    let dir = TempDir::new("cli-sides");
    std::fs::write(dir.path("s.rib"), "WorldBegin\nSides 3\nWorldEnd\n").unwrap();
    let (ok, stderr, written) = render(&dir, "s.rib", &[]);
    assert!(!ok && !written, "{stderr}");
    assert!(
        stderr.contains("s.rib:2:1: Sides: 3 is out of range: must be 1 or 2"),
        "{stderr}"
    );
}

#[test]
fn chunks_with_cpu_is_refused() {
    let dir = TempDir::new("cli-chunks");
    std::fs::write(dir.path("e.toml"), "").unwrap();
    let (ok, stderr, written) = render(&dir, "e.toml", &["--chunks", "2"]);
    assert!(!ok && !written, "{stderr}");
    assert!(
        stderr.contains("--chunks applies to the GPU renderer; --cpu ignores it"),
        "{stderr}"
    );
}

#[test]
fn a_zero_timeout_is_refused() {
    let dir = TempDir::new("cli-timeout");
    std::fs::write(dir.path("e.toml"), "").unwrap();
    let (ok, stderr, written) = render(&dir, "e.toml", &["--timeout", "0"]);
    assert!(!ok && !written, "{stderr}");
    assert!(stderr.contains("--timeout"), "{stderr}");
}

/// `--eye` on the default teapot (a camera framed automatically) clips
/// around the teapot as seen from the new eye: the framing's far plane,
/// chosen for its own eye, culled the whole teapot from 30 units away.
#[test]
fn moving_a_framed_camera_recomputes_its_clipping_planes() {
    let dir = TempDir::new("cli-eye");
    assert_seen_from_far(&dir, None);
}

/// Renders `scene` (the default teapot without one) from an eye 30 units
/// away (64 x 48, on the CPU) and asserts that the teapot shows.
fn assert_seen_from_far(dir: &TempDir, scene: Option<&str>) {
    let out = dir.path("far.png");
    let scene = scene.map(|name| dir.path(name));
    let mut args = vec!["render"];
    args.extend(scene.as_deref().map(path_str));
    args.extend([
        "--cpu", "--width", "64", "--height", "48", "--spp", "1", "--eye", "0,-30,2", "-o",
    ]);
    args.push(path_str(&out));
    let (ok, stderr) = run_cli(&args);
    assert!(ok, "{scene:?}: {stderr}");
    assert!(!stderr.contains("covered no sample"), "{scene:?}: {stderr}");
    let image = image::open(&out).unwrap().to_rgba8();
    let background = *image.get_pixel(0, 0);
    let drawn = image.pixels().filter(|&&p| p != background).count();
    assert!(drawn > 20, "{scene:?}: {drawn} pixels show the teapot");
}

/// A `MotionBegin` without its `MotionEnd` before `WorldEnd` is an error
/// naming both lines (it rendered a blank image with exit 0 before), and a
/// warning under `--lenient`.
#[test]
fn an_unclosed_motion_block_is_an_error_unless_lenient() {
    let dir = TempDir::new("cli-motion");
    std::fs::write(
        dir.path("m.rib"),
        "Format 16 12 1\nProjection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 5\nMotionBegin [0 1]\nTranslate 0 0 0\nTranslate 0.2 0 0\nSphere 1 -1 1 360\nWorldEnd\n",
    )
    .unwrap();
    let (ok, stderr, written) = render(&dir, "m.rib", &[]);
    assert!(!ok && !written, "{stderr}");
    assert!(
        stderr.contains(
            "m.rib:9:1: WorldEnd: the MotionBegin of line 5 is still open inside the WorldBegin of line 3 (MotionEnd missing before this WorldEnd)"
        ) && stderr.contains("--lenient"),
        "{stderr}"
    );
    let (ok, stderr, written) = render(&dir, "m.rib", &["--lenient"]);
    assert!(ok && written, "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("MotionBegin of line 5 is still open"),
        "{stderr}"
    );
    // The sphere counts as a later motion sample of the open block and is
    // dropped; the image is the background, which is said too.
    assert!(stderr.contains("the scene has no objects"), "{stderr}");
}

/// A shader whose texture file is missing fails the run with the object and
/// the path; `--lenient` makes it a warning and renders the object in its
/// colour (a surface) or undisplaced (a displacement).
#[test]
fn a_missing_texture_names_the_object_and_the_path_unless_lenient() {
    let dir = TempDir::new("cli-missing-texture");
    std::fs::write(
        dir.path("painted.toml"),
        "[[objects]]\nmodel = \"teapot\"\n\
         surface = { shader = \"wgsl\", file = \"builtin:paintedplastic\", parameters = { texturename = \"gone.png\" } }\n",
    )
    .unwrap();
    std::fs::write(
        dir.path("bumpy.toml"),
        "[[objects]]\nmodel = \"teapot\"\n\
         displacement = { source = \"shader\", file = \"builtin:bumpy\", parameters = { Km = 0.1, texturename = \"gone.png\" } }\n",
    )
    .unwrap();
    for scene in ["painted.toml", "bumpy.toml"] {
        let (ok, stderr, written) = render(&dir, scene, &[]);
        assert!(!ok && !written, "{scene}: {stderr}");
        assert!(
            stderr.contains("object 0") && stderr.contains("gone.png"),
            "{scene}: {stderr}"
        );
        let (ok, stderr, written) = render(&dir, scene, &["--lenient"]);
        assert!(ok && written, "{scene} --lenient: {stderr}");
        assert!(
            stderr.contains("warning: object 0") && stderr.contains("gone.png"),
            "{scene} --lenient: {stderr}"
        );
    }
}

/// A RIB scene has no ambient term and here no light: an object whose
/// texture is missing renders under `--lenient` with RenderMan's
/// `defaultsurface`, which needs no light, in its own colour
/// (`Cs * (Ka + Kd * d^2)` with Ka = 0.2, Kd = 0.8 and `d` the cosine
/// between the view ray and the normal, about 1 at the sphere's middle).
#[test]
fn lenient_renders_a_shader_with_a_missing_texture_in_its_colour() {
    use reyes::color::linear_to_srgb8;
    let dir = TempDir::new("cli-missing-texture-rib");
    std::fs::write(
        dir.path("painted.rib"),
        "Format 16 12 1\nPixelFilter \"box\" 1 1\nQuantize \"rgba\" 255 0 255 0\n\
         Projection \"perspective\" \"fov\" [30]\nWorldBegin\n\
         Color [1 0.5 0.25]\nSurface \"paintedplastic\" \"texturename\" \"gone.png\"\n\
         Translate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\n",
    )
    .unwrap();
    let (ok, stderr, written) = render(&dir, "painted.rib", &[]);
    assert!(!ok && !written, "{stderr}");
    assert!(stderr.contains("gone.png"), "{stderr}");
    let (ok, stderr, written) = render(&dir, "painted.rib", &["--lenient"]);
    assert!(ok && written, "--lenient: {stderr}");
    assert!(stderr.contains("defaultsurface"), "{stderr}");
    let image = image::open(dir.path("out.png")).unwrap().to_rgba8();
    // The pixel beside the image's centre: its one sample lies within 3.6
    // degrees of the view axis (a pixel is 2.5 degrees), where the sphere's
    // normal is within 18 degrees of the axis too: d^2 is between 0.85 and 1.
    let pixel = image.get_pixel(8, 6);
    for (channel, cs) in [1.0_f32, 0.5, 0.25].into_iter().enumerate() {
        let lowest = linear_to_srgb8(cs * (0.2 + 0.8 * 0.85));
        let highest = linear_to_srgb8(cs);
        let got = pixel[channel];
        assert!(
            (lowest.saturating_sub(1)..=highest.saturating_add(1)).contains(&got),
            "channel {channel}: {got}, expected {lowest}..={highest} (defaultsurface)"
        );
    }
}

/// A value given to a shader that declares no such parameter is warned
/// about once per shader and name, with the line that gives it, in TOML
/// and in RIB alike.
#[test]
fn an_unknown_shader_parameter_warns_once_with_its_line() {
    let dir = TempDir::new("cli-unknown-parameter");
    let surface = "surface = { shader = \"wgsl\", file = \"builtin:paintedplastic\", parameters";
    std::fs::write(
        dir.path("scene.toml"),
        format!(
            "[[objects]]\nmodel = \"teapot\"\n{surface} = {{ Kd = 0.5, shine = 2.0 }} }}\n\n\
             [[objects]]\nmodel = \"teapot\"\n{surface} = {{ shine = 3.0 }} }}\n"
        ),
    )
    .unwrap();
    std::fs::write(
        dir.path("scene.rib"),
        "Format 16 12 1\nWorldBegin\nLightSource \"ambientlight\" 1\n\
         AttributeBegin\nSurface \"plastic\" \"shine\" 2\nTranslate 0 0 5\nSphere 1 -1 1 360\nAttributeEnd\n\
         AttributeBegin\nSurface \"plastic\" \"shine\" 3\nTranslate 1 0 5\nSphere 1 -1 1 360\nAttributeEnd\n\
         WorldEnd\n",
    )
    .unwrap();
    for (scene, line) in [("scene.toml", 3), ("scene.rib", 5)] {
        let (ok, stderr, written) = render(&dir, scene, &[]);
        assert!(ok && written, "{scene}: {stderr}");
        let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("shine")).collect();
        assert_eq!(warnings.len(), 1, "{scene}: {stderr}");
        let at = format!("{}:{line}:", path_str(&dir.path(scene)));
        assert!(
            warnings[0].contains(&at),
            "{scene}: expected {at} in {}",
            warnings[0]
        );
    }
}

/// A scene whose camera's far plane falls short of the geometry renders
/// empty with advice that names the far plane (not only "check the
/// camera"), and `--far` (or `--near`) moves the plane from the command
/// line. Planes that cannot be are refused with the option's name.
#[test]
fn clipping_planes_are_named_and_set_from_the_command_line() {
    let dir = TempDir::new("cli-far");
    std::fs::write(
        dir.path("far.toml"),
        "[camera]\neye = [0.0, -30.0, 2.0]\ntarget = [0.0, 0.0, 1.0]\nup = [0.0, 0.0, 1.0]\n\
         fov_y_degrees = 30.0\nnear = 0.1\nfar = 10.0\n\n[[objects]]\nmodel = \"teapot\"\n",
    )
    .unwrap();
    let (ok, stderr, written) = render(&dir, "far.toml", &[]);
    assert!(ok && written, "{stderr}");
    assert!(
        stderr.contains("covered no sample")
            && stderr.contains("beyond the far plane (far = 10;")
            && stderr.contains("--far"),
        "{stderr}"
    );
    let (ok, stderr, written) = render(&dir, "far.toml", &["--far", "100"]);
    assert!(ok && written, "{stderr}");
    assert!(!stderr.contains("covered no sample"), "{stderr}");
    let (ok, stderr, written) = render(&dir, "far.toml", &["--near", "40", "--far", "100"]);
    assert!(ok && written, "{stderr}");
    assert!(
        stderr.contains("before the near plane or behind the eye (near = 40;")
            && stderr.contains("--near"),
        "{stderr}"
    );
    for (args, words) in [
        (
            &["--near", "0"][..],
            "--near 0: must be a finite distance > 0",
        ),
        (
            &["--far", "0.05"][..],
            "--far 0.05: the far plane (0.05) must be finite and beyond the near plane (0.1)",
        ),
        (
            &["--near", "20"][..],
            "--near 20: the far plane (10) must be finite and beyond the near plane (20)",
        ),
    ] {
        let (ok, stderr, written) = render(&dir, "far.toml", args);
        assert!(!ok && !written, "{args:?}: {stderr}");
        assert!(stderr.contains(words), "{args:?}: {stderr}");
    }
}

/// `--eye` recomputes an automatically framed camera's clipping planes for
/// a bare model and for a TOML scene without `[camera]`, as it does for
/// the default teapot (`moving_a_framed_camera_recomputes_its_clipping_planes`).
#[test]
fn an_eye_far_from_a_framed_model_still_sees_it() {
    let dir = TempDir::new("cli-eye-model");
    let teapot = reyes::model::Model::teapot();
    std::fs::write(dir.path("teapot.bpt"), reyes::load::bpt::write(&teapot)).unwrap();
    std::fs::write(
        dir.path("scene.toml"),
        "[[objects]]\nmodel = \"teapot.bpt\"\n",
    )
    .unwrap();
    for scene in ["teapot.bpt", "scene.toml"] {
        assert_seen_from_far(&dir, Some(scene));
    }
}
