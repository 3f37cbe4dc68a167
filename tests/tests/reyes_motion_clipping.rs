//! Motion that leaves the view: a grid point that lies past the far plane,
//! before the near plane or behind the eye at one end of the shutter is
//! seen during the part of the shutter in which it is in view
//! (`reyes::reference::raster5d::visible_span`), instead of taking its
//! micropolygons out of the whole shutter.
//!
//! The teapot is seen from `[0, -20, 1.5]` and moves along the view axis:
//! away past the far plane (`translate = [0, 2000, 0]`), or through the
//! eye to behind it (`[0, -40, 0]`). Both used to render nothing, with no
//! sample tested, on the GPU and on the CPU. Each now renders a visible
//! streak, in every 5D sampling mode, and the GPU agrees with the CPU
//! reference.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer};
use reyes::prepare::PreparedScene;
use reyes::reference::{self, Rendered};
use reyes::scene::{CameraDesc, Projection, Sampling, Scene, Transform};
use tests::reyes_support::{agreement, assert_counts_close, gpu_turn, renderer};

/// The modes that sample time and lens.
const MODES: [Sampling; 5] = Sampling::TIME_AND_LENS;

/// The teapot seen from `[0, -20, 1.5]` (near 0.1, far 1000), moving by
/// `motion` during the shutter (none: still).
fn scene(motion: Option<Vec3>, sampling: Sampling) -> Scene {
    let mut scene = Scene::default_teapot();
    scene.resolution.width = 64;
    scene.resolution.height = 48;
    scene.spp = 4;
    scene.sampling = sampling;
    scene.camera = Some(CameraDesc {
        eye: Vec3::new(0.0, -20.0, 1.5),
        target: Vec3::new(0.0, 0.0, 1.5),
        up: Vec3::Z,
        fov_y_degrees: 40.0,
        near: 0.1,
        far: 1000.0,
        projection: Projection::Perspective,
        ortho_height: None,
    });
    for object in &mut scene.objects {
        object.transform_close = motion.map(|translate| Transform {
            translate: object.transform.translate + translate,
            ..object.transform
        });
    }
    scene
}

/// The scene moving by `motion` in `mode`, on the GPU and on the CPU, which
/// must agree (coverage, colours and sample counts).
fn render_both(
    renderer: &mut GpuRenderer<'_>,
    motion: Vec3,
    mode: Sampling,
) -> (GpuRendered, Rendered) {
    let prepared = PreparedScene::load(&scene(Some(motion), mode)).expect("scene prepares");
    let g = renderer.render(&prepared).expect("GPU render");
    let c = reference::render(&prepared);
    let a = agreement(&g, &c);
    eprintln!(
        "{mode:?}: GPU tested {} hit {}, CPU tested {} hit {}, {a:?}",
        g.stats.samples_tested, g.stats.samples_hit, c.stats.samples_tested, c.stats.samples_hit
    );
    a.assert_at_least(&format!("{mode:?}"), 0.99, 0.98);
    assert_counts_close(
        "samples tested",
        g.stats.samples_tested,
        c.stats.samples_tested,
    );
    assert_counts_close("samples hit", g.stats.samples_hit, c.stats.samples_hit);
    (g, c)
}

fn covered(coverage: &[bool]) -> usize {
    coverage.iter().filter(|&&c| c).count()
}

#[gpu_test]
fn a_teapot_receding_past_the_far_plane_streaks_while_in_view() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    let still = reference::render(&PreparedScene::load(&scene(None, Sampling::Bbox)).unwrap());
    let still_pixels = covered(&still.coverage);
    assert!(still_pixels > 100, "the still teapot covers {still_pixels}");
    for mode in MODES {
        let (g, c) = render_both(&mut renderer, Vec3::new(0.0, 2000.0, 0.0), mode);
        for (who, coverage) in [("GPU", &g.coverage), ("CPU", &c.coverage)] {
            // The teapot shrinks towards the view's centre as it recedes:
            // its streak lies inside the still teapot's silhouette (up to
            // a pixel of sampling noise at the rim) and fills a good part
            // of it, seen for the half of the shutter before it passes
            // the far plane.
            let pixels = covered(coverage);
            let outside = coverage
                .iter()
                .zip(&still.coverage)
                .filter(|&(&m, &s)| m && !s)
                .count();
            assert!(
                pixels * 4 >= still_pixels,
                "{who} {mode:?}: the streak covers {pixels} of the still teapot's {still_pixels} pixels"
            );
            assert!(
                outside * 20 <= pixels,
                "{who} {mode:?}: {outside} of {pixels} streak pixels lie outside the still teapot"
            );
        }
    }
}

#[gpu_test]
fn a_teapot_moving_through_the_eye_streaks_while_in_front_of_it() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    for mode in MODES {
        let (g, c) = render_both(&mut renderer, Vec3::new(0.0, -40.0, 0.0), mode);
        // On its way to the eye the teapot grows until it fills the view.
        for (who, coverage) in [("GPU", &g.coverage), ("CPU", &c.coverage)] {
            let fraction = covered(coverage) as f64 / coverage.len() as f64;
            assert!(
                fraction >= 0.9,
                "{who} {mode:?}: the streak covers {fraction:.3} of the frame"
            );
        }
    }
}
