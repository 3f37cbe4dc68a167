//! Unit tests of [`super`]: formats, the checks before a render, and
//! all-or-nothing writes.

use std::fs;

use super::*;

/// A fresh directory under the system temp directory, canonical so that
/// resolved paths compare equal to paths built from it.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("reyes-output-test-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    fs::canonicalize(dir).unwrap()
}

/// A small image with distinct channels.
fn sample_image() -> RgbaImage {
    RgbaImage::from_fn(3, 2, |x, y| {
        Rgba([10 * x as u8, 200, 30 + 100 * y as u8, 255])
    })
}

/// A small linear image with values no 8-bit code decodes to, negative
/// ones and ones above 1 (a sinc filter's ringing, a bright light).
fn sample_linear() -> Rgba32FImage {
    Rgba32FImage::from_fn(3, 2, |x, y| {
        let v = 0.1234 + 0.377 * x as f32 - 0.2 * y as f32;
        Rgba([v, 2.5 * v, -0.01 * (x as f32), 1.0])
    })
}

#[test]
fn writes_and_reports_errors() {
    let dir = scratch("write");
    let path = dir.join("nested").join("img.png");
    let image = sample_image();
    write_png(&image, &path).unwrap();
    let back = image::open(&path).unwrap().to_rgba8();
    assert_eq!(back, image);
    // A path whose parent is a file cannot be created.
    let bad = path.join("below-a-file.png");
    assert!(matches!(
        write_png(&image, &bad),
        Err(OutputError::CreateDir { .. })
    ));
    // Only the image is left: no temporary or probe file.
    assert_eq!(fs::read_dir(dir.join("nested")).unwrap().count(), 1);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_extension_chooses_the_format() {
    assert_eq!(
        ImageFormat::from_path(Path::new("a.png")).unwrap(),
        ImageFormat::Png
    );
    assert_eq!(
        ImageFormat::from_path(Path::new("a.PnG")).unwrap(),
        ImageFormat::Png
    );
    assert_eq!(
        ImageFormat::from_path(Path::new("d/a.EXR")).unwrap(),
        ImageFormat::Exr
    );
    for refused in ["a.jpg", "a", "a.png.txt", ".png"] {
        let error = ImageFormat::from_path(Path::new(refused)).unwrap_err();
        let text = error.to_string();
        assert!(text.starts_with(refused) && text.contains(".exr"), "{text}");
    }
}

#[test]
fn exr_holds_linear_floats() {
    let dir = scratch("exr");
    let path = dir.join("img.exr");
    let image = sample_image();
    write_image(&image, &path).unwrap();
    let back = image::open(&path).unwrap();
    let back = back.as_rgba32f().expect("an Rgba32F image");
    assert_eq!(back.dimensions(), image.dimensions());
    for (x, y, pixel) in image.enumerate_pixels() {
        let read = back.get_pixel(x, y).0;
        for c in 0..3 {
            let expected = srgb_to_linear(f32::from(pixel[c]) / 255.0);
            assert!((read[c] - expected).abs() < 1e-6, "{x},{y}: {read:?}");
        }
        assert_eq!(read[3], 1.0);
    }
    // sRGB 200 is linear 0.578 (not 200/255 = 0.784).
    assert!((back.get_pixel(0, 0)[1] - 0.577_580).abs() < 1e-5);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_render_s_exr_holds_its_floats_as_they_are() {
    let dir = scratch("exr-floats");
    let linear = sample_linear();
    for (path, plan) in [
        (dir.join("direct.exr"), None),
        (
            dir.join("plan.exr"),
            Some(OutputPlan::check(&dir.join("plan.exr"), None, &[]).unwrap()),
        ),
    ] {
        match plan {
            None => write_rendered_image(&sample_image(), &linear, &path).unwrap(),
            Some(plan) => plan
                .write(&sample_image(), &linear, &RenderStats::default())
                .unwrap(),
        }
        let back = image::open(&path).unwrap();
        let back = back.as_rgba32f().expect("an Rgba32F image");
        assert_eq!(back, &linear, "{}", path.display());
    }
    // The PNG beside it is the 8-bit image.
    let png = dir.join("r.png");
    write_rendered_image(&sample_image(), &linear, &png).unwrap();
    assert_eq!(image::open(&png).unwrap().to_rgba8(), sample_image());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn other_formats_are_refused_without_a_file() {
    let dir = scratch("jpg");
    let path = dir.join("sub").join("img.jpg");
    assert!(matches!(
        write_image(&sample_image(), &path),
        Err(OutputError::UnknownFormat { .. })
    ));
    assert!(matches!(
        OutputPlan::check(&path, None, &[]),
        Err(OutputError::UnknownFormat { .. })
    ));
    assert!(!dir.join("sub").exists());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn one_file_named_twice_is_refused_before_anything_is_created() {
    let dir = scratch("same");
    let image = dir.join("new").join("same.png");
    let other_spelling = dir.join("x").join("..").join("new").join("./same.png");
    let error = OutputPlan::check(&image, Some(&other_spelling), &[]).unwrap_err();
    assert!(matches!(error, OutputError::SameFile { .. }), "{error}");
    assert!(error.to_string().contains("image and the statistics JSON"));
    assert!(!dir.join("new").exists(), "a directory was created");
    // An input named as an output.
    let scene = dir.join("scene.toml");
    fs::write(&scene, "").unwrap();
    let error = OutputPlan::check(&image, Some(&scene), &[("scene", &scene)]).unwrap_err();
    assert!(error.to_string().contains("input scene"), "{error}");
    fs::remove_dir_all(&dir).unwrap();
}

#[cfg(unix)]
#[test]
fn a_link_to_the_image_is_the_image() {
    let dir = scratch("link");
    std::os::unix::fs::symlink("r.png", dir.join("link.json")).unwrap();
    let error = OutputPlan::check(&dir.join("r.png"), Some(&dir.join("link.json")), &[]);
    assert!(matches!(error, Err(OutputError::SameFile { .. })));
    // Writing through a link replaces its target and keeps the link.
    std::os::unix::fs::symlink("real.png", dir.join("shown.png")).unwrap();
    write_image(&sample_image(), dir.join("shown.png")).unwrap();
    assert!(
        fs::symlink_metadata(dir.join("shown.png"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        image::open(dir.join("real.png")).unwrap().to_rgba8(),
        sample_image()
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn both_outputs_get_their_directories() {
    let dir = scratch("dirs");
    let image = dir.join("images").join("r.png");
    let stats = dir.join("stats").join("deep").join("r.json");
    let plan = OutputPlan::check(&image, Some(&stats), &[]).unwrap();
    assert!(dir.join("images").is_dir() && dir.join("stats/deep").is_dir());
    plan.write(&sample_image(), &sample_linear(), &RenderStats::default())
        .unwrap();
    let json: RenderStats = serde_json::from_str(&fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(json, RenderStats::default());
    assert_eq!(image::open(&image).unwrap().to_rgba8(), sample_image());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn directories_and_devices_are_no_output() {
    let dir = scratch("kinds");
    fs::create_dir(dir.join("d.png")).unwrap();
    let error = OutputPlan::check(&dir.join("d.png"), None, &[]).unwrap_err();
    assert!(matches!(error, OutputError::NotAFile { .. }), "{error}");
    if Path::new("/dev/null").exists() {
        let error =
            OutputPlan::check(&dir.join("r.png"), Some(Path::new("/dev/null")), &[]).unwrap_err();
        assert!(matches!(error, OutputError::NotAFile { .. }), "{error}");
    }
    for no_name in ["", "/"] {
        let error = OutputPlan::check(&dir.join("r.png"), Some(Path::new(no_name)), &[]);
        assert!(
            matches!(error, Err(OutputError::NoFileName { .. })),
            "{error:?}"
        );
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_failing_stats_write_leaves_the_old_image() {
    let dir = scratch("all-or-nothing");
    let image = dir.join("r.png");
    fs::write(&image, b"old image").unwrap();
    let stats = dir.join("stats").join("r.json");
    let plan = OutputPlan::check(&image, Some(&stats), &[]).unwrap();
    // The statistics' directory goes away while the frame renders.
    fs::remove_dir_all(dir.join("stats")).unwrap();
    let error = plan
        .write(&sample_image(), &sample_linear(), &RenderStats::default())
        .unwrap_err();
    assert!(matches!(error, OutputError::Write { .. }), "{error}");
    assert_eq!(fs::read(&image).unwrap(), b"old image");
    assert_eq!(
        fs::read_dir(&dir).unwrap().count(),
        1,
        "a temporary file is left"
    );
    fs::remove_dir_all(&dir).unwrap();
}
