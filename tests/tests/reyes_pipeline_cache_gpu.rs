//! The Reyes renderer with a pipeline cache directory: a second renderer
//! with the same directory reports a hit (`GpuRenderer::last_pipeline`), a
//! corrupt file is rejected and replaced, and every frame is the same image.

use gpu_test::gpu_test;
use reyes::gpu::{GpuOptions, PipelineInfo};
use reyes::prepare::PreparedScene;
use scheduler::PipelineCacheState;
use tests::reyes_support::{COLD_COMPILE_TIMEOUT, framed_teapot, gpu_turn, renderer};

/// A frame of the small teapot with the cache in `dir`: the image's pixels
/// and the pipeline the renderer ran.
fn frame(gpu: &scheduler::Gpu, dir: &std::path::Path) -> (Vec<u8>, PipelineInfo) {
    let mut renderer = renderer(
        gpu,
        GpuOptions {
            timeout: COLD_COMPILE_TIMEOUT,
            pipeline_cache_dir: Some(dir.to_path_buf()),
            ..GpuOptions::default()
        },
    );
    assert_eq!(renderer.last_pipeline(), None, "no pipeline before a frame");
    let scene = PreparedScene::load(&framed_teapot(64, 48, 1)).unwrap();
    let rendered = renderer.render(&scene).expect("the frame renders");
    let info = renderer.last_pipeline().expect("a frame ran a pipeline");
    eprintln!("{info:?}");
    (rendered.image.into_raw(), info)
}

#[gpu_test]
fn a_second_renderer_hits_and_a_corrupt_file_is_replaced() {
    let _turn = gpu_turn();
    let gpu = tests::gpu();
    let dir = std::env::temp_dir().join(format!("reyes-pipeline-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);

    let (first, info) = frame(gpu, &dir);
    if info.cache == PipelineCacheState::Unsupported {
        eprintln!("the device cannot cache pipelines; nothing more to check");
        return;
    }
    assert_eq!(info.cache, PipelineCacheState::Miss);
    assert!(info.timings.first_dispatch.is_some());
    let files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(files.len(), 1, "{files:?}");

    let (second, info) = frame(gpu, &dir);
    assert_eq!(info.cache, PipelineCacheState::Hit);
    assert!(first == second, "a cached pipeline renders the same image");

    // Flip a byte in the middle: the file's hash no longer matches.
    let mut bytes = std::fs::read(&files[0]).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x55;
    std::fs::write(&files[0], &bytes).unwrap();
    let (third, info) = frame(gpu, &dir);
    assert!(
        matches!(info.cache, PipelineCacheState::Rejected(_)),
        "{:?}",
        info.cache
    );
    assert!(
        first == third,
        "a rejected file changes nothing in the image"
    );
    let (_, info) = frame(gpu, &dir);
    assert_eq!(info.cache, PipelineCacheState::Hit, "the file was replaced");
    std::fs::remove_dir_all(&dir).unwrap();
}
