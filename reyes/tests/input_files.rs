//! Input files: every reader (models, scenes, WGSL, height maps) refuses
//! devices, FIFOs, directories and links to them without blocking, caps the
//! size, accepts a byte-order mark, quotes at most an excerpt of a bad line,
//! and checks a PNG's size from its header.
//!
//! Every read that could block or run away runs under [`bounded`], and the
//! readers are given small caps, so a broken check fails the test instead of
//! hanging it.

mod files;

use std::path::Path;

use files::{TempDir, bounded, mkfifo, symlink};
use reyes::displacement::{DisplacementError, HeightMap};
use reyes::input::{self, FileKind, InputError, InputKind};
use reyes::load::{LoadError, bez, bpt};
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::{Scene, SceneError};

/// The cap given to readers that take one: small, so that a broken
/// regular-file check reads a device for a moment, not for minutes.
const SMALL: u64 = 1 << 20;

/// A reader: loads `path` and returns the [`InputError`] it was refused
/// with, or a description of what happened instead.
type Reader = fn(&Path) -> Result<InputError, String>;

fn model(path: &Path) -> Result<InputError, String> {
    match Model::load_with_limit(path, SMALL) {
        Err(LoadError::Input(e)) => Ok(e),
        Err(other) => Err(format!("{other:?}")),
        Ok(_) => Err("loaded".into()),
    }
}

fn scene(path: &Path) -> Result<InputError, String> {
    match Scene::load(path) {
        Err(SceneError::Input(e)) => Ok(e),
        Err(other) => Err(format!("{other:?}")),
        Ok(_) => Err("loaded".into()),
    }
}

fn wgsl(path: &Path) -> Result<InputError, String> {
    match input::read_text(path, InputKind::Wgsl, SMALL) {
        Err(e) => Ok(e),
        Ok(text) => Err(format!("read {} bytes", text.len())),
    }
}

fn height_map(path: &Path) -> Result<InputError, String> {
    match HeightMap::load_with_limit(path, SMALL) {
        Err(DisplacementError::Input(e)) => Ok(e),
        Err(other) => Err(format!("{other:?}")),
        Ok(_) => Err("decoded".into()),
    }
}

/// A scene (given as text) naming `path` as its model: read when prepared.
fn scene_model(path: &Path) -> Result<InputError, String> {
    let text = format!("[[objects]]\nmodel = {:?}\n", path.display().to_string());
    let scene = Scene::from_toml_str(&text).map_err(|e| e.to_string())?;
    match PreparedScene::load(&scene) {
        Err(SceneError::Model {
            source: LoadError::Input(e),
            ..
        }) => Ok(e),
        Err(other) => Err(format!("{other:?}")),
        Ok(_) => Err("prepared".into()),
    }
}

/// A scene naming `path` as a height map: `[objects.displacement] source = ...`.
fn scene_height_map(path: &Path) -> Result<InputError, String> {
    let text = format!(
        "[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\nsource = {:?}\nscale = 0.1\n",
        path.display().to_string()
    );
    let scene = Scene::from_toml_str(&text).map_err(|e| e.to_string())?;
    match PreparedScene::load(&scene) {
        Err(SceneError::Displacement {
            source: DisplacementError::Input(e),
            ..
        }) => Ok(e),
        Err(other) => Err(format!("{other:?}")),
        Ok(_) => Err("prepared".into()),
    }
}

/// Every reader with the extension its file needs.
const READERS: [(&str, &str, Reader); 7] = [
    ("bpt-model", "bpt", model),
    ("bez-model", "bez", model),
    ("scene", "toml", scene),
    ("wgsl", "wgsl", wgsl),
    ("height-map", "png", height_map),
    ("scene-model", "bpt", scene_model),
    ("scene-height-map", "png", scene_height_map),
];

/// Asserts that `reader` refuses `path` as `expected`, within the time bound.
fn assert_refused(name: &str, reader: Reader, path: &Path, expected: FileKind) {
    let shown = path.to_path_buf();
    let outcome = bounded(&format!("{name} reading {}", shown.display()), path, {
        let path = path.to_path_buf();
        move || reader(&path)
    });
    let error = match outcome {
        Ok(error) => error,
        Err(other) => panic!(
            "{name}: {} should be refused as {expected}, got {other}",
            shown.display()
        ),
    };
    match &error {
        InputError::NotRegularFile { path: p, file, .. } => {
            assert_eq!(*file, expected, "{name}: {}", shown.display());
            assert_eq!(*p, shown, "{name}: the error names the path as given");
        }
        other => panic!(
            "{name}: {} should be refused as {expected}, got {other:?}",
            shown.display()
        ),
    }
    // The message names the path and what it is.
    let message = error.to_string();
    assert!(
        message.contains(&shown.display().to_string()) && message.contains("not a regular file"),
        "{message}"
    );
}

fn device(path: &str) -> Option<&Path> {
    let path = Path::new(path);
    if path.exists() {
        Some(path)
    } else {
        println!("NOTICE: {} not found; skipping it", path.display());
        None
    }
}

#[test]
fn devices_and_links_to_them_are_refused() {
    let dir = TempDir::new("devices");
    for name in ["/dev/zero", "/dev/urandom"] {
        let Some(target) = device(name) else {
            continue;
        };
        for (reader_name, extension, reader) in READERS {
            // Through a link with the extension the reader expects.
            let link = dir.path(&format!("{}-{reader_name}.{extension}", &name[5..]));
            if symlink(target, &link) {
                assert_refused(reader_name, reader, &link, FileKind::CharDevice);
            }
        }
        // Directly, for the readers that do not choose by extension.
        for reader in [scene, wgsl, height_map, scene_height_map] {
            assert_refused(name, reader, target, FileKind::CharDevice);
        }
    }
}

#[test]
fn fifos_are_refused_without_blocking() {
    let dir = TempDir::new("fifos");
    for (reader_name, extension, reader) in READERS {
        let fifo = dir.path(&format!("pipe-{reader_name}.{extension}"));
        if !mkfifo(&fifo) {
            return;
        }
        assert_refused(reader_name, reader, &fifo, FileKind::Fifo);
        let link = dir.path(&format!("link-{reader_name}.{extension}"));
        if symlink(&fifo, &link) {
            assert_refused(reader_name, reader, &link, FileKind::Fifo);
        }
    }
}

#[test]
fn directories_are_refused() {
    let dir = TempDir::new("directories");
    for (reader_name, extension, reader) in READERS {
        let sub = dir.path(&format!("dir-{reader_name}.{extension}"));
        std::fs::create_dir_all(&sub).unwrap();
        assert_refused(reader_name, reader, &sub, FileKind::Directory);
    }
}

#[test]
fn links_to_regular_files_are_read() {
    let dir = TempDir::new("links");
    let file = dir.path("teapot.bpt");
    std::fs::write(&file, bpt::write(&Model::teapot())).unwrap();
    let link = dir.path("link.bpt");
    if symlink(&file, &link) {
        assert_eq!(Model::load(&link).unwrap(), Model::teapot());
    }
}

#[test]
fn files_over_the_cap_are_refused() {
    let dir = TempDir::new("cap");
    let text = bpt::write(&Model::teapot());
    for extension in ["bpt", "bez"] {
        let path = dir.path(&format!("teapot.{extension}"));
        let body = if extension == "bpt" {
            text.clone()
        } else {
            bez::write(&Model::teapot())
        };
        std::fs::write(&path, &body).unwrap();
        let len = body.len() as u64;
        match Model::load_with_limit(&path, len - 1) {
            Err(LoadError::Input(InputError::TooLarge {
                size: Some(s),
                limit,
                ..
            })) => assert_eq!((s, limit), (len, len - 1)),
            other => panic!("{extension}: {other:?}"),
        }
        // Exactly at the cap is accepted.
        assert_eq!(Model::load_with_limit(&path, len).unwrap(), Model::teapot());
    }
    let path = dir.path("f.wgsl");
    std::fs::write(
        &path,
        "fn displacement_user(u: f32, v: f32) -> f32 { return u; }",
    )
    .unwrap();
    let e = input::read_text(&path, InputKind::Wgsl, 10).unwrap_err();
    assert!(matches!(e, InputError::TooLarge { limit: 10, .. }), "{e:?}");
    let message = e.to_string();
    assert!(
        message.contains("f.wgsl") && message.contains("--max-input-bytes"),
        "the message names the file and how to raise the cap: {message}"
    );
    let path = dir.path("bumps.png");
    std::fs::write(&path, include_bytes!("../assets/bumps.png")).unwrap();
    let e = HeightMap::load_with_limit(&path, 100).unwrap_err();
    assert!(
        matches!(
            e,
            DisplacementError::Input(InputError::TooLarge { limit: 100, .. })
        ),
        "{e:?}"
    );
    assert!(HeightMap::load_with_limit(&path, SMALL).is_ok());
}

#[test]
fn byte_order_marks_are_accepted() {
    let dir = TempDir::new("bom");
    let bom = "\u{feff}";
    let path = dir.path("teapot.bpt");
    std::fs::write(&path, format!("{bom}{}", bpt::write(&Model::teapot()))).unwrap();
    assert_eq!(Model::load(&path).unwrap(), Model::teapot());
    let path = dir.path("teapot.bez");
    std::fs::write(&path, format!("{bom}{}", bez::write(&Model::teapot()))).unwrap();
    assert_eq!(Model::load(&path).unwrap(), Model::teapot());
    // The parsers accept one in text given directly too.
    assert_eq!(
        bpt::parse(&format!("{bom}{}", bpt::write(&Model::teapot()))).unwrap(),
        Model::teapot()
    );
    let path = dir.path("scene.toml");
    std::fs::write(
        &path,
        format!("{bom}spp = 9\n[[objects]]\nmodel = \"teapot\"\n"),
    )
    .unwrap();
    assert_eq!(Scene::load(&path).unwrap().spp, 9);
    let path = dir.path("f.wgsl");
    let function = "fn displacement_user(u: f32, v: f32) -> f32 { return u; }\n";
    std::fs::write(&path, format!("{bom}{function}")).unwrap();
    let text = input::read_text(&path, InputKind::Wgsl, InputKind::Wgsl.limit()).unwrap();
    assert_eq!(text, function, "the mark is removed, not passed on to naga");
}

#[test]
fn text_that_is_not_utf8_is_refused() {
    let dir = TempDir::new("utf8");
    let path = dir.path("bad.bpt");
    std::fs::write(&path, b"1\n3 3\n\xff\xfe\n").unwrap();
    let e = Model::load(&path).unwrap_err();
    assert!(
        matches!(e, LoadError::Input(InputError::NotUtf8 { offset: 6, .. })),
        "{e:?}"
    );
    assert!(e.to_string().contains("bad.bpt"), "{e}");
}

/// Parse errors quote at most an excerpt of a huge line.
#[test]
fn long_malformed_lines_give_short_errors() {
    let long = "7".repeat(4 << 20);
    let cases = [
        // A count line, a degree line, a coordinate, trailing text, a .bez index.
        ("count", format!("{long}x\n")),
        ("degree", format!("1\n3 {long}\n")),
        ("coordinate", format!("1\n3 3\n{}x 0 0\n", long.clone())),
        ("trailing", format!("0\n{long}\n")),
    ];
    for (what, text) in &cases {
        let e = bpt::parse(text).unwrap_err();
        let message = e.to_string();
        assert!(message.len() < 400, "{what}: {} bytes", message.len());
        assert!(
            message.contains('…'),
            "{what}: the cut is marked: {message}"
        );
    }
    let e = bez::parse(&format!("1\n{long}x,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1\n")).unwrap_err();
    assert!(
        matches!(e, LoadError::InvalidNumber { line: 2, .. }),
        "{e:?}"
    );
    assert!(e.to_string().len() < 400);
    // Also when read from a file, as the CLI does.
    let dir = TempDir::new("long-lines");
    let path = dir.path("long.bpt");
    std::fs::write(&path, &cases[2].1).unwrap();
    let message = Model::load(&path).unwrap_err().to_string();
    assert!(message.len() < 400, "{} bytes", message.len());
    // A line of millions of tokens is counted, not collected.
    let many = "1 ".repeat(1 << 20);
    let e = bpt::parse(&format!("1\n3 3\n{many}\n")).unwrap_err();
    assert!(
        matches!(e, LoadError::WrongCoordinateCount { line: 3, found } if found == 1 << 20),
        "{e:?}"
    );
}

/// TOML messages quote offending strings whole; they are bounded too.
#[test]
fn long_toml_values_give_short_errors() {
    let text = format!("spp = \"{}\"\n", "x".repeat(1 << 20));
    let e = Scene::from_toml_str(&text).unwrap_err();
    assert!(
        e.to_string().len() < 2 * input::MESSAGE_CHARS,
        "{}",
        e.to_string().len()
    );
}

/// A PNG whose IHDR declares `width` x `height`: a 1 x 1 grey PNG with the
/// header patched (and its CRC recomputed, so the decoder trusts it).
fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    let mut bytes = Vec::new();
    image::GrayImage::new(1, 1)
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    assert_eq!(&bytes[12..16], b"IHDR");
    bytes[16..20].copy_from_slice(&width.to_be_bytes());
    bytes[20..24].copy_from_slice(&height.to_be_bytes());
    // The CRC covers the chunk type and data: bytes 12..29.
    let crc = files::crc32(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    bytes
}

#[test]
fn png_size_is_checked_from_the_header() {
    let dir = TempDir::new("png-header");
    for (width, height) in [(60000, 60000), (20000, 20000), (4097, 1), (1, 5000)] {
        let bytes = png_claiming(width, height);
        let path = dir.path(&format!("claims-{width}x{height}.png"));
        std::fs::write(&path, &bytes).unwrap();
        for e in [
            HeightMap::decode(&bytes, &path).unwrap_err(),
            HeightMap::load(&path).unwrap_err(),
        ] {
            assert!(
                matches!(e, DisplacementError::TooLarge { width: w, height: h, max: 4096, .. } if (w, h) == (width, height)),
                "{width}x{height}: {e:?}"
            );
            assert!(e.to_string().contains("at most 4096x4096"), "{e}");
        }
    }
    // The patching itself is sound: at an accepted size the decoder gets to
    // the (too short) pixel data and fails there, not on the header.
    let bytes = png_claiming(64, 64);
    let e = HeightMap::decode(&bytes, Path::new("small.png")).unwrap_err();
    assert!(matches!(e, DisplacementError::Decode { .. }), "{e:?}");
}
