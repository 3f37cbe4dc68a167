//! Two frames of one RIB file in one `reyes render` on the GPU: they share
//! the renderer, so the second frame, of the same kernel variant and the
//! same patches (another size and camera), reuses the first's compiled
//! megakernel and pipeline instead of compiling again.

use std::path::PathBuf;
use std::process::Command;

use gpu_test::gpu_test;

/// The log line of a frame that created its pipeline (the driver's compile).
const CREATED: &str = "pipeline creation ";
/// The log line of a frame that reused an earlier frame's.
const REUSED: &str = "the pipeline of an earlier frame is reused (no compile)";

#[gpu_test]
fn two_frames_of_one_variant_compile_once() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_frames_gpu");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let frame = |n: u32, size: &str, shift: f32| {
        format!(
            "FrameBegin {n}\nFormat {size} 1\nTranslate {shift} 0 0\nWorldBegin\nTranslate 0 0 5\n\
             Sphere 1 -1 1 360\nWorldEnd\nFrameEnd\n"
        )
    };
    let text = format!(
        "PixelSamples 1 1\nProjection \"perspective\" \"fov\" 40\n{}{}",
        frame(1, "48 32", 0.0),
        frame(2, "32 48", 0.4)
    );
    let rib = dir.join("two.rib");
    std::fs::write(&rib, text).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .env("RUST_LOG", "reyes=info")
        .args(["render", "--quiet", "--no-pipeline-cache"])
        .arg(&rib)
        .arg("-o")
        .arg(dir.join("f.#.png"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("f.1.png (48x32, 1 spp)") && stdout.contains("f.2.png (32x48, 1 spp)"),
        "{stdout}"
    );
    assert_eq!(stderr.matches(CREATED).count(), 1, "{stderr}");
    assert_eq!(stderr.matches(REUSED).count(), 1, "{stderr}");
    assert!(!stderr.contains("new megakernel"), "{stderr}");
}
