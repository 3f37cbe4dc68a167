//! `reyes cache info` and `reyes cache clear` on a directory named by
//! `REYES_CACHE_DIR`: both work when it does not exist, list and remove
//! only the pipeline cache files, and leave every other file alone. A GPU
//! render writes its pipeline there, and `--no-pipeline-cache` writes
//! nothing.

mod files;

use std::fs;
use std::path::Path;
use std::process::Command;

use files::TempDir;
use gpu_test::gpu_test;

/// Two names the scheduler writes: a cache file and a temporary one.
const OURS: [&str; 2] = [
    "wgpu_pipeline_cache_vulkan_65541_0-0123456789abcdef-fedcba9876543210.wgpucache",
    "wgpu_pipeline_cache_vulkan_4098_29695-0123456789abcdef-0000000000000001.wgpucache.tmp77",
];

/// Runs `reyes ARGS` with `REYES_CACHE_DIR=dir`; returns success, stdout
/// and stderr.
fn reyes(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .env("REYES_CACHE_DIR", dir)
        .env("RUST_LOG", "reyes=warn,scheduler=info")
        .args(args)
        .output()
        .expect("reyes starts");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn a_missing_directory_is_empty_and_stays_missing() {
    let temp = TempDir::new("cache-missing");
    let dir = temp.path("pipelines");
    let (ok, out, err) = reyes(&dir, &["cache", "info"]);
    assert!(ok, "{err}");
    assert!(out.contains(&dir.display().to_string()), "{out}");
    assert!(out.contains("does not exist"), "{out}");
    assert!(out.contains("0 file(s), 0 bytes"), "{out}");
    let (ok, out, err) = reyes(&dir, &["cache", "clear"]);
    assert!(ok, "{err}");
    assert!(out.contains("removed 0 file(s)"), "{out}");
    assert!(!dir.exists());
}

#[test]
fn info_and_clear_touch_only_pipeline_files() {
    let temp = TempDir::new("cache-files");
    let dir = temp.path("pipelines");
    fs::create_dir_all(dir.join("mesa_shader_cache")).unwrap();
    fs::write(dir.join("mesa_shader_cache/index"), b"the driver's").unwrap();
    fs::write(dir.join("notes.txt"), b"not ours").unwrap();
    fs::write(
        dir.join("wgpu_pipeline_cache_notes.txt"),
        b"not ours either",
    )
    .unwrap();
    fs::write(dir.join(OURS[0]), vec![1u8; 3000]).unwrap();
    fs::write(dir.join(OURS[1]), vec![2u8; 100]).unwrap();

    let (ok, out, err) = reyes(&dir, &["cache", "info"]);
    assert!(ok, "{err}");
    assert!(out.contains(OURS[0]) && out.contains(OURS[1]), "{out}");
    assert!(out.contains("2 file(s), 3.0 KiB"), "{out}");
    assert!(!out.contains("notes") && !out.contains("mesa"), "{out}");

    let (ok, out, err) = reyes(&dir, &["cache", "clear"]);
    assert!(ok, "{err}");
    assert!(out.contains(OURS[0]) && out.contains(OURS[1]), "{out}");
    assert!(out.contains("removed 2 file(s)"), "{out}");
    assert!(!dir.join(OURS[0]).exists() && !dir.join(OURS[1]).exists());
    assert!(dir.join("notes.txt").exists());
    assert!(dir.join("wgpu_pipeline_cache_notes.txt").exists());
    assert!(dir.join("mesa_shader_cache/index").exists());

    let (ok, out, _) = reyes(&dir, &["cache", "info"]);
    assert!(ok && out.contains("0 file(s)"), "{out}");
}

#[gpu_test]
fn a_render_keeps_its_pipeline_unless_told_not_to() {
    let temp = TempDir::new("cache-render");
    let dir = temp.path("pipelines");
    let image = temp.path("tiny.png");
    let image = image.to_str().unwrap();
    let tiny = ["render", "--width", "64", "--height", "48", "-o", image];

    let off = temp.path("off");
    let (ok, _, err) = reyes(&off, &[&tiny[..], &["--no-pipeline-cache"]].concat());
    assert!(ok, "{err}");
    assert!(!off.exists(), "--no-pipeline-cache wrote {}", off.display());
    assert!(err.contains("cache Off"), "{err}");

    let (ok, _, err) = reyes(&dir, &tiny);
    assert!(ok, "{err}");
    assert!(err.contains("cache Miss"), "{err}");
    let (ok, out, _) = reyes(&dir, &["cache", "info"]);
    assert!(ok && out.contains("1 file(s)"), "{out}");

    let (ok, _, err) = reyes(&dir, &tiny);
    assert!(ok, "{err}");
    assert!(err.contains("cache Hit"), "{err}");
}
