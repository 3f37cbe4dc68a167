//! Shared support for the Reyes GPU tests: taking turns on the two cores,
//! and comparing a GPU render with the CPU reference.

use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Duration;

use glam::Vec3;
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer};
use reyes::reference::Rendered;
use reyes::scene::{CameraDesc, Scene};

/// lavapipe has 2 cores: renders from parallel tests would only compete for
/// them (and for llvmpipe's loop budget, see
/// `scheduler::Quirks::long_body_iteration_budget`), so GPU tests take turns.
static GPU_TURN: Mutex<()> = Mutex::new(());

/// Waits for this test's turn on the GPU.
pub fn gpu_turn() -> MutexGuard<'static, ()> {
    // A test that panicked while holding the lock does not poison the others.
    GPU_TURN.lock().unwrap_or_else(PoisonError::into_inner)
}

/// How closely two renders agree.
#[derive(Debug)]
pub struct Agreement {
    /// Fraction of pixels the GPU covered.
    pub coverage: f64,
    /// Intersection over union of the coverage masks.
    pub iou: f64,
    /// Fraction of pixels covered by both whose channels all differ by <= 2.
    pub within_2: f64,
    /// Largest channel difference over pixels covered by both.
    pub max_diff: u8,
    /// Pixels covered by both.
    pub both: usize,
}

impl Agreement {
    /// Asserts the coverage IoU and the fraction of shared pixels within
    /// 2/255 reach the given floors; `what` names the render in the message.
    pub fn assert_at_least(&self, what: &str, iou: f64, within_2: f64) {
        assert!(
            self.iou >= iou,
            "{what}: coverage IoU {:.5} < {iou}",
            self.iou
        );
        assert!(
            self.within_2 >= within_2,
            "{what}: only {:.4} of {} object pixels within 2/255 < {within_2} (max diff {})",
            self.within_2,
            self.both,
            self.max_diff
        );
    }
}

/// Coverage and colour agreement of a GPU render with the CPU reference.
pub fn agreement(gpu: &GpuRendered, cpu: &Rendered) -> Agreement {
    assert_eq!(gpu.coverage.len(), cpu.coverage.len());
    let pixels = gpu.coverage.len();
    let (mut both, mut either, mut within, mut max_diff) = (0usize, 0usize, 0usize, 0u8);
    for (i, (&g, &c)) in gpu.coverage.iter().zip(&cpu.coverage).enumerate() {
        either += usize::from(g || c);
        if g && c {
            both += 1;
            let diff = (0..3)
                .map(|ch| gpu.image.as_raw()[4 * i + ch].abs_diff(cpu.image.as_raw()[4 * i + ch]))
                .max()
                .unwrap_or(0);
            max_diff = max_diff.max(diff);
            within += usize::from(diff <= 2);
        }
    }
    Agreement {
        coverage: gpu.coverage.iter().filter(|&&c| c).count() as f64 / pixels as f64,
        iou: if either == 0 {
            1.0
        } else {
            both as f64 / either as f64
        },
        within_2: if both == 0 {
            1.0
        } else {
            within as f64 / both as f64
        },
        max_diff,
        both,
    }
}

/// The counters that describe the same work on both sides. They are exactly
/// equal unless float contraction moves a bound decision at a threshold;
/// one such flip changes the counts by a few pieces, so 1% is allowed.
pub fn assert_counts_close(what: &str, gpu: u64, cpu: u64) {
    let tolerance = (cpu / 100).max(2);
    assert!(
        gpu.abs_diff(cpu) <= tolerance,
        "{what}: GPU {gpu}, CPU {cpu} (tolerance {tolerance})"
    );
}

/// How long a test frame may run: llvmpipe compiles the megakernel lazily
/// at its first dispatch, which takes minutes on a 2-core machine when
/// Mesa's shader cache does not hold the module yet (a new user function,
/// queue policy or chunk count makes a new one). Cached, test frames take
/// seconds.
pub const COLD_COMPILE_TIMEOUT: Duration = Duration::from_secs(900);

/// [`renderer`] with [`COLD_COMPILE_TIMEOUT`].
pub fn patient_renderer(gpu: &scheduler::Gpu) -> GpuRenderer<'_> {
    renderer(
        gpu,
        GpuOptions {
            timeout: COLD_COMPILE_TIMEOUT,
            ..GpuOptions::default()
        },
    )
}

/// The camera of the card and wall scenes: at the origin, looking down -z
/// with y up and a 60 degree view, near 0.1, far 100.
pub fn camera_down_z() -> CameraDesc {
    CameraDesc {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        fov_y_degrees: 60.0,
        near: 0.1,
        far: 100.0,
        projection: reyes::scene::Projection::Perspective,
        ortho_height: None,
    }
}

/// A Reyes renderer on the shared test device: like `tests::gpu()`, a
/// machine that cannot run the test fails loudly instead of passing by
/// skipping.
pub fn renderer(gpu: &scheduler::Gpu, options: GpuOptions) -> GpuRenderer<'_> {
    GpuRenderer::new(gpu, options).unwrap_or_else(|e| {
        panic!(
            "the Reyes GPU renderer cannot run on {}: {e}",
            gpu.describe()
        )
    })
}

/// The default teapot scene at `width x height`, `spp` samples, framed for
/// that aspect ratio and narrowed from 40 to 34 degrees so the teapot
/// covers about a fifth of the image (the framing fits the whole bounding
/// box, whose corners lie well outside the teapot's silhouette).
pub fn framed_teapot(width: u32, height: u32, spp: u32) -> Scene {
    let mut scene = Scene::default_teapot();
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = spp;
    let (lo, hi) = reyes::model::Model::teapot().bounds();
    let camera = CameraDesc::framing(lo, hi, width as f32 / height as f32);
    scene.camera = Some(CameraDesc {
        fov_y_degrees: 34.0,
        ..camera
    });
    scene
}

/// A GPU frame in the form [`agreement`] compares against, to compare two
/// GPU frames.
pub fn as_reference(frame: &GpuRendered) -> Rendered {
    Rendered {
        image: frame.image.clone(),
        linear: frame.linear.clone(),
        coverage: frame.coverage.clone(),
        covered_samples: frame.covered_samples.clone(),
        stats: frame.stats.clone(),
    }
}

/// Asserts that two GPU frames are the same picture bit for bit: the
/// float image, the 8-bit image, the coverage and the covered samples of
/// every pixel (a frame rendered in screen tiles against the whole frame).
pub fn assert_identical(what: &str, a: &GpuRendered, b: &GpuRendered) {
    assert_eq!(a.image.dimensions(), b.image.dimensions(), "{what}: sizes");
    let width = a.image.width() as usize;
    let floats = |frame: &GpuRendered| -> Vec<u32> {
        frame.linear.as_raw().iter().map(|v| v.to_bits()).collect()
    };
    let (fa, fb) = (floats(a), floats(b));
    let differing: Vec<usize> = (0..fa.len()).filter(|&i| fa[i] != fb[i]).collect();
    if let Some(&first) = differing.first() {
        let pixel = first / 4;
        panic!(
            "{what}: {} float channels differ; the first at pixel ({}, {}): {} against {}",
            differing.len(),
            pixel % width,
            pixel / width,
            f32::from_bits(fa[first]),
            f32::from_bits(fb[first])
        );
    }
    assert!(
        a.image.as_raw() == b.image.as_raw(),
        "{what}: the 8-bit images differ"
    );
    assert!(a.coverage == b.coverage, "{what}: the coverage differs");
    assert!(
        a.covered_samples == b.covered_samples,
        "{what}: the covered sample counts differ"
    );
}

/// A renderer whose screen tiles hold at most `max_tile_samples` samples.
pub fn tiled_renderer(gpu: &scheduler::Gpu, max_tile_samples: u64) -> GpuRenderer<'_> {
    renderer(
        gpu,
        GpuOptions {
            max_tile_samples: Some(max_tile_samples),
            ..GpuOptions::default()
        },
    )
}

/// Renders `scene` whole with `whole` and in screen tiles with `tiled`,
/// asserts that the first took one tile and the second several, and that
/// each agrees with `cpu` (IoU >= 0.995, 99% of the shared pixels within
/// 2/255); returns the two frames, whole first. `what` names the case.
pub fn assert_whole_and_tiled_agree<'g>(
    what: &str,
    scene: &reyes::prepare::PreparedScene,
    whole: &mut GpuRenderer<'g>,
    tiled: &mut GpuRenderer<'g>,
    cpu: &Rendered,
) -> [GpuRendered; 2] {
    [("whole", whole), ("tiled", tiled)].map(|(mode, renderer)| {
        let frame = renderer.render(scene).expect("GPU render");
        let what = format!("{what}, {mode}");
        let a = agreement(&frame, cpu);
        eprintln!("{what} ({} tile(s)): {a:?}", frame.tiles);
        assert_eq!(
            frame.tiles > 1,
            mode == "tiled",
            "{what}: {} tile(s)",
            frame.tiles
        );
        a.assert_at_least(&what, 0.995, 0.99);
        frame
    })
}
