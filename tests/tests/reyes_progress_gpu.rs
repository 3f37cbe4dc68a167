//! The GPU renderer's progress events (`reyes::progress`): a frame starts,
//! the driver compiles the megakernel on the renderer's first frame only,
//! tiles and batches follow in order, and the frame finishes. The frame is
//! a small teapot, in two tiles of four batches each;
//! its megakernel is the default one the other GPU tests compile too.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use gpu_test::gpu_test;
use reyes::gpu::GpuOptions;
use reyes::prepare::PreparedScene;
use reyes::progress::{AdapterSummary, Progress, ProgressEvent};
use tests::reyes_support::{framed_teapot, gpu_turn, renderer};

/// An event without its durations, which the test cannot predict.
fn timeless(event: &ProgressEvent) -> ProgressEvent {
    match event.clone() {
        ProgressEvent::CompileFinished { adapter, .. } => ProgressEvent::CompileFinished {
            adapter,
            elapsed: Duration::ZERO,
        },
        ProgressEvent::FrameFinished { .. } => ProgressEvent::FrameFinished {
            elapsed: Duration::ZERO,
        },
        other => other,
    }
}

#[gpu_test]
fn frames_report_the_compile_once_and_their_tiles_and_batches_in_order() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let seen = Arc::new(Mutex::new(Vec::new()));
    let sink = seen.clone();
    let options = GpuOptions {
        timeout: Duration::from_secs(900),
        // 128 x 48 at 1 spp in two tiles of 64 x 48 (tiles are multiples of
        // 64 pixels); the teapot's 32 patches in 4 batches.
        max_tile_samples: Some(64 * 64),
        max_batch_patches: Some(8),
        progress: Progress::new(move |event| sink.lock().unwrap().push(event.clone())),
        ..GpuOptions::default()
    };
    let mut renderer = renderer(gpu, options);
    let scene = PreparedScene::load(&framed_teapot(128, 48, 1)).expect("scene prepares");
    let adapter = AdapterSummary::of(&gpu.adapter.get_info());

    let first = renderer.render(&scene).expect("first frame");
    let events = std::mem::take(&mut *seen.lock().unwrap());
    assert_eq!((first.tiles, first.batches), (2, 8), "{events:#?}");
    let frame = ProgressEvent::FrameStarted {
        width: 128,
        height: 48,
        spp: 1,
    };
    let tile = |tile| ProgressEvent::TileStarted { tile, tiles: 2 };
    let batches = (1..=4).map(|batch| ProgressEvent::BatchFinished { batch, batches: 4 });
    let finished = ProgressEvent::FrameFinished {
        elapsed: Duration::ZERO,
    };
    let mut expected = vec![
        frame.clone(),
        tile(1),
        ProgressEvent::CompileStarted {
            adapter: adapter.clone(),
        },
        ProgressEvent::CompileFinished {
            adapter,
            elapsed: Duration::ZERO,
        },
    ];
    expected.extend(batches.clone());
    expected.push(tile(2));
    expected.extend(batches.clone());
    expected.push(finished.clone());
    assert_eq!(
        events.iter().map(timeless).collect::<Vec<_>>(),
        expected,
        "{events:#?}"
    );
    let (
        Some(ProgressEvent::CompileFinished {
            elapsed: compile, ..
        }),
        Some(ProgressEvent::FrameFinished {
            elapsed: frame_time,
        }),
    ) = (events.get(3), events.last())
    else {
        unreachable!("checked above");
    };
    eprintln!("compile {compile:?} within the first frame's {frame_time:?}");
    assert!(compile <= frame_time);

    // The pipeline is made: a second frame compiles nothing.
    renderer.render(&scene).expect("second frame");
    let events = std::mem::take(&mut *seen.lock().unwrap());
    let mut expected = vec![frame, tile(1)];
    expected.extend(batches.clone());
    expected.push(tile(2));
    expected.extend(batches);
    expected.push(finished);
    assert_eq!(
        events.iter().map(timeless).collect::<Vec<_>>(),
        expected,
        "{events:#?}"
    );
}

/// A renderer that alternates between two variants of the megakernel (a
/// still frame and one that samples time and lens, as the viewer does when
/// motion blur is toggled) compiles each variant once: the second frame of
/// each variant takes its parked program back.
#[gpu_test]
fn alternating_variants_compile_each_once() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let seen = Arc::new(Mutex::new(Vec::new()));
    let sink = seen.clone();
    let options = GpuOptions {
        timeout: Duration::from_secs(900),
        progress: Progress::new(move |event| sink.lock().unwrap().push(event.clone())),
        ..GpuOptions::default()
    };
    let mut renderer = renderer(gpu, options);
    let still = PreparedScene::load(&framed_teapot(64, 48, 1)).expect("scene prepares");
    let mut blurred_scene = framed_teapot(64, 48, 1);
    blurred_scene.sampling = reyes::modes::Sampling::Interleave;
    let blurred = PreparedScene::load(&blurred_scene).expect("scene prepares");
    assert_ne!(
        reyes::gpu::KernelVariant::of(&still),
        reyes::gpu::KernelVariant::of(&blurred)
    );
    let mut images = Vec::new();
    for scene in [&still, &blurred, &still, &blurred] {
        images.push(renderer.render(scene).expect("frame renders").image);
        assert_eq!(renderer.variant(), reyes::gpu::KernelVariant::of(scene));
    }
    let compiles = seen
        .lock()
        .unwrap()
        .iter()
        .filter(|e| matches!(e, ProgressEvent::CompileStarted { .. }))
        .count();
    assert_eq!(compiles, 2, "one compile per variant");
    // The programs taken back render what they rendered before.
    assert!(images[0] == images[2] && images[1] == images[3]);
}
