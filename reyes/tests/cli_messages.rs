//! Messages name the real cause (issue 42, item 5), for the command line:
//! an EXR that cannot be written names its path and the OS error (not the
//! encoder's "Format error decoding OpenExr"), and a model whose file name
//! is not UTF-8 is read by its path as given. (The RIB's messages are
//! checked in `rib_structure.rs`, the GPU timeout's advice in
//! `reyes::gpu::render_error`.)

mod files;

use std::path::{Path, PathBuf};
use std::process::Command;

use files::{TempDir, run_cli, run_command};

/// A tiny CPU frame: its float EXR is 32 x 24 x 16 bytes, 12 KiB.
const TINY: [&str; 7] = ["--cpu", "--width", "32", "--height", "24", "--spp", "1"];

fn path_str(path: &Path) -> &str {
    path.to_str().expect("temp paths are UTF-8")
}

/// A small tmpfs mounted on `dir`, unmounted on drop; `None` (with a
/// notice) where none can be mounted (not root, no `mount`).
struct SmallDisk(PathBuf);

impl SmallDisk {
    /// A 4 KiB one.
    fn mount(dir: &Path) -> Option<SmallDisk> {
        SmallDisk::mount_sized(dir, "4k")
    }

    /// One of `size` (`mount`'s spelling: `64k`).
    fn mount_sized(dir: &Path, size: &str) -> Option<SmallDisk> {
        std::fs::create_dir_all(dir).unwrap();
        let mounted = Command::new("mount")
            .args([
                "-t",
                "tmpfs",
                "-o",
                &format!("size={size}"),
                "tmpfs",
                path_str(dir),
            ])
            .output()
            .is_ok_and(|o| o.status.success());
        if !mounted {
            println!("NOTICE: cannot mount a tmpfs here; skipping the full-disk check");
            return None;
        }
        Some(SmallDisk(dir.to_path_buf()))
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// Asserts that `stderr` is a write error naming `image` and `os_error`,
/// not the encoder's message.
fn assert_names_the_file(stderr: &str, image: &Path, os_error: &str) {
    assert!(
        stderr.contains(&format!(
            "error: cannot write {}: {os_error}",
            image.display()
        )),
        "{stderr}"
    );
    assert!(!stderr.contains("Format error"), "{stderr}");
}

#[test]
fn an_exr_on_a_full_disk_names_its_path_and_the_os_error() {
    let temp = TempDir::new("msg-exr-full");
    let mount = temp.path("disk");
    let Some(_disk) = SmallDisk::mount(&mount) else {
        return;
    };
    let image = mount.join("r.exr");
    let mut args = vec!["render"];
    args.extend(TINY);
    args.extend(["-o", path_str(&image)]);
    let (ok, stderr) = run_cli(&args);
    assert!(!ok, "{stderr}");
    assert_names_the_file(&stderr, &image, "No space left on device");
    // Nothing partial is left.
    let left: Vec<_> = std::fs::read_dir(&mount).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn an_exr_past_the_file_size_limit_names_its_path_and_the_os_error() {
    let temp = TempDir::new("msg-exr-limit");
    let image = temp.path("r.exr");
    let script = format!(
        "ulimit -f 2 || exit 99; exec \"$0\" render {} -o \"$1\"",
        TINY.join(" ")
    );
    if !Command::new("sh")
        .args(["-c", "ulimit -f 2"])
        .status()
        .is_ok_and(|s| s.success())
    {
        println!("NOTICE: no sh with ulimit -f; skipping the size-limit check");
        return;
    }
    let mut command = Command::new("sh");
    command.args(["-c", &script, env!("CARGO_BIN_EXE_reyes"), path_str(&image)]);
    let (ok, stderr) = run_command(command);
    assert!(!ok, "{stderr}");
    assert_names_the_file(&stderr, &image, "File too large");
}

#[cfg(unix)]
#[test]
fn a_model_whose_name_is_not_utf8_is_read_by_its_path() {
    use std::os::unix::ffi::OsStrExt;
    let temp = TempDir::new("msg-non-utf8");
    // Byte 0xff is no UTF-8; the name shows as U+FFFD in messages only.
    let name = std::ffi::OsStr::from_bytes(b"\xffmodel.bpt");
    let model = temp.path("").join(name);
    if std::fs::write(
        &model,
        reyes::load::bpt::write(&reyes::model::Model::teapot()),
    )
    .is_err()
    {
        println!("NOTICE: the file system refuses a non-UTF-8 name; skipping");
        return;
    }
    let out = temp.path("out.png");
    // As it is, reframed for another size, moved, and with its camera
    // placed: each reads the model by its path.
    let small = ["--width", "32", "--height", "24"];
    for extra in [
        &[][..],
        &small[..],
        &[&small[..], &["--spin", "10"]].concat()[..],
        &[&small[..], &["--eye", "0,-30,5"]].concat()[..],
    ] {
        let _ = std::fs::remove_file(&out);
        let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
        command
            .arg("render")
            .arg(&model)
            .args(["--cpu", "--spp", "1", "-o", path_str(&out)])
            .args(extra);
        let (ok, stderr) = run_command(command);
        assert!(ok && out.exists(), "{extra:?}: {stderr}");
        assert!(
            !stderr.contains("cannot read model file"),
            "{extra:?}: {stderr}"
        );
    }
}

#[cfg(unix)]
#[test]
fn a_height_map_whose_name_is_not_utf8_displaces_as_its_copy() {
    use std::os::unix::ffi::OsStrExt;
    let temp = TempDir::new("msg-non-utf8-displace");
    let map = image::GrayImage::from_fn(8, 8, |x, y| image::Luma([(30 * (x ^ y)) as u8]));
    let plain = temp.path("plain.png");
    map.save(&plain).unwrap();
    let name = std::ffi::OsStr::from_bytes(b"\xffheights.png");
    let odd = temp.path("").join(name);
    if std::fs::copy(&plain, &odd).is_err() {
        println!("NOTICE: the file system refuses a non-UTF-8 name; skipping");
        return;
    }
    // The same heights by both names: the same picture, byte for byte.
    let render = |map: &Path, out: &Path| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
        command
            .arg("render")
            .args(["--cpu", "--spp", "1", "--width", "64", "--height", "48"])
            .arg("--displace")
            .arg(map)
            .args(["--displace-scale", "0.3", "-o", path_str(out)]);
        let (ok, stderr) = run_command(command);
        assert!(ok && out.exists(), "{}: {stderr}", map.display());
        std::fs::read(out).unwrap()
    };
    let flat = temp.path("flat.png");
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command.arg("render").args([
        "--cpu", "--spp", "1", "--width", "64", "--height", "48", "-o",
    ]);
    command.arg(&flat);
    let (ok, stderr) = run_command(command);
    assert!(ok, "{stderr}");
    let by_plain = render(&plain, &temp.path("by-plain.png"));
    assert_ne!(by_plain, std::fs::read(&flat).unwrap(), "nothing displaced");
    assert_eq!(render(&odd, &temp.path("by-odd.png")), by_plain);
}

/// The files of `dir` and their bytes, sorted by name.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut all: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| {
            let entry = entry.unwrap();
            (
                entry.file_name().to_string_lossy().into_owned(),
                std::fs::read(entry.path()).unwrap(),
            )
        })
        .collect();
    all.sort();
    all
}

/// Fills the file system of `dir` with a file `filler`, to its last byte.
fn fill(dir: &Path) {
    use std::io::Write;
    let mut file = std::fs::File::create(dir.join("filler")).unwrap();
    let block = [0u8; 256];
    while file.write_all(&block).is_ok() {}
    let byte = [0u8; 1];
    while file.write_all(&byte).is_ok() {}
}

/// A RIB scene of one sphere, for `convert`.
const SPHERE_RIB: &str = "Format 32 24 1\nProjection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\n";

/// On a full disk, `render` (a PNG with its `--stats-json`) and `convert`
/// (a TOML and its `.bpt`) fail naming a path and the OS error, leave
/// nothing partial, and keep the previous outputs byte for byte.
#[test]
fn outputs_on_a_full_disk_fail_and_keep_the_previous_ones() {
    let temp = TempDir::new("msg-full-outputs");
    let mount = temp.path("disk");
    // Room for the previous outputs (a page each), then filled.
    let Some(_disk) = SmallDisk::mount_sized(&mount, "64k") else {
        return;
    };
    let rib = temp.path("in.rib");
    std::fs::write(&rib, SPHERE_RIB).unwrap();
    // The previous outputs, then nothing free.
    for (name, bytes) in [
        ("r.png", &b"previous png"[..]),
        ("s.json", b"{\"previous\": true}"),
        ("c.toml", b"# previous toml\n"),
        ("c-0.bpt", b"previous bpt"),
    ] {
        std::fs::write(mount.join(name), bytes).unwrap();
    }
    fill(&mount);
    let before = contents(&mount);
    let (image, json, toml) = (
        mount.join("r.png"),
        mount.join("s.json"),
        mount.join("c.toml"),
    );
    let mut render = vec!["render"];
    render.extend(TINY);
    render.extend(["-o", path_str(&image), "--stats-json", path_str(&json)]);
    let convert = vec!["convert", path_str(&rib), "-o", path_str(&toml)];
    for args in [render, convert] {
        let (ok, stderr) = run_cli(&args);
        assert!(!ok, "{args:?}: {stderr}");
        assert!(
            stderr.contains(&format!("cannot write {}", mount.display()))
                && stderr.contains("No space left on device"),
            "{args:?}: {stderr}"
        );
        assert!(
            contents(&mount) == before,
            "{args:?} changed the disk's files"
        );
    }
}

/// Past the file size limit (`ulimit -f 0`), `render` with `--stats-json`
/// fails naming a path and "File too large" (not a signal), and keeps the
/// previous PNG and JSON byte for byte.
#[test]
fn a_png_and_its_statistics_past_the_file_size_limit_keep_the_previous_ones() {
    if !Command::new("sh")
        .args(["-c", "ulimit -f 0"])
        .status()
        .is_ok_and(|s| s.success())
    {
        println!("NOTICE: no sh with ulimit -f; skipping the size-limit check");
        return;
    }
    let temp = TempDir::new("msg-png-limit");
    let dir = temp.path("out");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("r.png"), b"previous png").unwrap();
    std::fs::write(dir.join("s.json"), b"{\"previous\": true}").unwrap();
    let before = contents(&dir);
    let script = format!(
        "ulimit -f 0 || exit 99; exec \"$0\" render {} -o \"$1\" --stats-json \"$2\"",
        TINY.join(" ")
    );
    let mut command = Command::new("sh");
    command.args([
        "-c",
        &script,
        env!("CARGO_BIN_EXE_reyes"),
        path_str(&dir.join("r.png")),
        path_str(&dir.join("s.json")),
    ]);
    let (ok, stderr) = run_command(command);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains(&format!("cannot write {}", dir.display()))
            && stderr.contains("File too large"),
        "{stderr}"
    );
    assert!(
        contents(&dir) == before,
        "the previous outputs changed: {stderr}"
    );
}
