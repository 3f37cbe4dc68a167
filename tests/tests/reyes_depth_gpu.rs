//! The depth output on the GPU: the same depths as the CPU reference on a
//! plane, a sphere and the teapot (whole and in screen tiles), and the
//! plane's distance by arithmetic. The reference itself is checked
//! against arithmetic in `reyes/tests/depth_output.rs`.

use gpu_test::gpu_test;
use reyes::depth::{NO_SURFACE, depths};
use reyes::gpu::GpuOptions;
use reyes::prepare::PreparedScene;
use reyes::rib::RibScene;
use reyes::{Aov, reference};
use tests::reyes_support::{framed_teapot, gpu_turn, renderer};

/// A 64 x 48 RIB depth frame of 2 x 2 samples whose world holds `world`,
/// after the options `options`.
fn rib_frame_with(options: &str, world: &str) -> PreparedScene {
    let text = format!(
        "Format 64 48 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" 40\nClipping 0.5 100\nDisplay \"d.z\" \"zfile\" \"z\"\n{options}\nWorldBegin\n{world}\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "depth.rib").expect("the RIB reads");
    PreparedScene::new(&rib.scene, &rib.models).expect("scene prepares")
}

/// [`rib_frame_with`] the default depth filter, min.
fn rib_frame(world: &str) -> PreparedScene {
    rib_frame_with("", world)
}

/// Two squares facing the camera: half-width 1 at depth 4, half-width 3
/// behind it at depth 6.
const TWO_PLANES: &str = "AttributeBegin\nTranslate 0 0 4\nPolygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]\nAttributeEnd\nTranslate 0 0 6\nPolygon \"P\" [-3 -3 0  3 -3 0  3 3 0  -3 3 0]";

#[gpu_test]
fn midpoint_depth_matches_the_reference_and_the_arithmetic() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    let midpoint = "Hider \"hidden\" \"depthfilter\" \"midpoint\"";
    let planes = rib_frame_with(midpoint, TWO_PLANES);
    // A closed sphere: its front and its back, 4 and 6 deep on the axis.
    let sphere = rib_frame_with(midpoint, "Translate 0 0 5\nSphere 1 -1 1 360");
    let mut teapot = framed_teapot(96, 72, 4);
    teapot.aov = Aov::Z;
    teapot.depth_filter = reyes::depth::DepthFilter::Midpoint;
    let teapot = PreparedScene::load(&teapot).expect("scene prepares");
    for (what, scene) in [
        ("planes", &planes),
        ("sphere", &sphere),
        ("teapot", &teapot),
    ] {
        assert!(scene.keeps_second_depth());
        let cpu = depths(&reference::render(scene).linear);
        let gpu = renderer.render(scene).expect("GPU render");
        assert_eq!(
            renderer.variant(),
            reyes::gpu::KernelVariant::of(scene),
            "{what}"
        );
        assert_eq!(
            renderer.variant().depth_test,
            reyes::gpu::DepthTest::SecondDepth,
            "{what}"
        );
        let d = depths(&gpu.linear);
        assert_same_depths(&format!("{what}, midpoint"), &d, &cpu);
        let centre = d[24 * 64 + 32];
        match what {
            "planes" => {
                assert!((centre - 5.0).abs() < 5e-4, "centre {centre}");
                // The far square alone: nothing behind it.
                assert_eq!(d[0], NO_SURFACE);
            }
            "sphere" => assert!((centre - 5.0).abs() < 2e-3, "centre {centre}"),
            _ => {}
        }
    }
}

/// Asserts the GPU's depths `gpu` agree with the reference's `cpu`: the
/// same pixels covered but for a few along silhouettes (where a sample on
/// a micropolygon's edge may fall either way), and the covered ones
/// within a relative 1e-5 but for as few (where the nearest micropolygon
/// of an edge sample differs), none beyond 1%.
fn assert_same_depths(what: &str, gpu: &[f32], cpu: &[f32]) {
    assert_eq!(gpu.len(), cpu.len(), "{what}: sizes");
    let mut coverage_differs = 0;
    let mut close = 0;
    let mut both = 0;
    for (i, (&g, &c)) in gpu.iter().zip(cpu).enumerate() {
        match (g == NO_SURFACE, c == NO_SURFACE) {
            (true, true) => {}
            (false, false) => {
                both += 1;
                let diff = (g - c).abs();
                assert!(diff <= 0.01 * c, "{what}: pixel {i}: GPU {g}, CPU {c}");
                if diff <= 1e-5 * c {
                    close += 1;
                }
            }
            _ => coverage_differs += 1,
        }
    }
    eprintln!(
        "{what}: {both} pixels covered by both, {close} within 1e-5, {coverage_differs} covered by one"
    );
    assert!(both > 0, "{what}: nothing covered");
    assert!(
        coverage_differs * 200 <= gpu.len(),
        "{what}: {coverage_differs} pixels covered by one renderer only"
    );
    assert!(
        close * 100 >= both * 99,
        "{what}: {close} of {both} within 1e-5"
    );
}

#[gpu_test]
fn depth_matches_the_reference_and_the_arithmetic() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut whole = renderer(gpu, GpuOptions::default());
    let mut tiled = renderer(
        gpu,
        GpuOptions {
            max_tile_samples: Some(192 * 64 * 4),
            ..GpuOptions::default()
        },
    );
    let plane = rib_frame("Translate 0 0 5\nPolygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]");
    let sphere = rib_frame("Translate 0 0 5\nSphere 1 -1 1 360");
    let mut teapot = framed_teapot(192, 144, 4);
    teapot.aov = Aov::Z;
    teapot.jitter = true;
    let teapot = PreparedScene::load(&teapot).expect("scene prepares");
    for (what, scene) in [("plane", &plane), ("sphere", &sphere), ("teapot", &teapot)] {
        let cpu = depths(&reference::render(scene).linear);
        let gpu = whole.render(scene).expect("GPU render");
        assert_same_depths(what, &depths(&gpu.linear), &cpu);
        if what == "teapot" {
            // The tiles' depths are put together as the colours are.
            let in_tiles = tiled.render(scene).expect("tiled GPU render");
            assert!(in_tiles.tiles > 1, "{what}: {} tile(s)", in_tiles.tiles);
            assert_same_depths(&format!("{what} in tiles"), &depths(&in_tiles.linear), &cpu);
        }
        if what == "plane" {
            // The centre pixels of the plane 5 units down the view axis.
            let d = depths(&gpu.linear);
            for (x, y) in [(32, 24), (22, 16), (41, 31)] {
                let z = d[y * 64 + x];
                assert!((z - 5.0).abs() < 5e-4, "pixel ({x}, {y}): {z}");
            }
        }
        if what == "sphere" {
            let nearest = depths(&gpu.linear)
                .into_iter()
                .fold(f32::INFINITY, f32::min);
            assert!((nearest - 4.0).abs() < 2e-3, "nearest {nearest}");
        }
    }
}

#[gpu_test]
fn max_and_average_depths_match_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    for filter in ["max", "average"] {
        let hider = format!("Hider \"hidden\" \"depthfilter\" \"{filter}\"");
        let planes = rib_frame_with(&hider, TWO_PLANES);
        let cpu = depths(&reference::render(&planes).linear);
        let gpu = depths(&renderer.render(&planes).expect("GPU render").linear);
        assert_same_depths(&format!("planes, {filter}"), &gpu, &cpu);
        // The frame's corner sees the far square alone.
        assert!((gpu[0] - 6.0).abs() < 5e-4, "{filter}: corner {}", gpu[0]);
    }
}
