//! The lookup against arithmetic: where a point falls in a map and how
//! deep (the light's geometry, computed here from its pose), and how the
//! percentage-closer filter spreads a shadow's edge (a box over a ramp).

use glam::{Mat4, Vec3};
use rand::Rng;

use super::*;
use crate::camera::Camera;
use crate::test_random::{fresh_rng, random_vec3};

/// A map of `width x height` texels from an orthographic light at `z = 10`
/// looking down -z over the square `[-1, 1]^2`, whose texels left of
/// column `edge` hold depth 5 (an occluder at `z = 5`) and the rest +inf.
fn half_covered_map(width: u32, height: u32, edge: u32) -> ShadowMap {
    let camera = Camera::new(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        0.5,
        width,
        height,
        1.0,
        100.0,
    )
    .orthographic(2.0);
    let depths = (0..width * height)
        .map(|i| if i % width < edge { 5.0 } else { f32::INFINITY })
        .collect();
    ShadowMap::from_camera(&camera, depths)
}

/// The world-space point on the plane `z = 0` at texel column `x` (the
/// middle row) of [`half_covered_map`]'s map (2 units high, as wide as
/// its texels' aspect makes it).
fn ground_at_texel(map: &ShadowMap, x: f32) -> Vec3 {
    let half_width = map.width as f32 / map.height as f32;
    Vec3::new((2.0 * x / map.width as f32 - 1.0) * half_width, 0.0, 0.0)
}

#[test]
fn a_point_lies_where_the_lights_pose_puts_it() {
    let (seed, mut rng) = fresh_rng("a_point_lies_where_the_lights_pose_puts_it");
    for _ in 0..200 {
        let eye = random_vec3(&mut rng, 20.0);
        let target = eye + random_vec3(&mut rng, 5.0);
        if (target - eye).length() < 0.5 || (target - eye).normalize().y.abs() > 0.95 {
            continue;
        }
        let fov = rng.random_range(0.3f32..2.0);
        let camera = Camera::new(eye, target, Vec3::Y, fov, 64, 48, 0.1, 1000.0);
        let map = ShadowMap::from_camera(&camera, vec![1.0; 64 * 48]);
        // A point on the axis at distance d lies at the image's centre,
        // d deep.
        let axis = (target - eye).normalize();
        let d = rng.random_range(0.5f32..50.0);
        let at = map.locate(eye + d * axis).expect("on the axis, in view");
        assert!(
            (at.texel - glam::Vec2::new(32.0, 24.0)).length() < 1e-2,
            "seed {seed}: {at:?}"
        );
        assert!(
            (at.depth - d).abs() < 1e-4 * d.max(1.0),
            "seed {seed}: {at:?} vs {d}"
        );
        // A point off the axis: its depth is its distance along the axis,
        // and the tangent of its angle from the axis scales to pixels.
        let right = axis.cross(Vec3::Y).normalize();
        let up = right.cross(axis);
        let (a, b) = (
            rng.random_range(-0.4f32..0.4),
            rng.random_range(-0.4f32..0.4),
        );
        let tan_half = (fov / 2.0).tan();
        let p = eye + d * (axis + a * tan_half * (64.0 / 48.0) * right + b * tan_half * up);
        let at = map.locate(p).expect("in view");
        let expected = glam::Vec2::new(32.0 + a * 32.0, 24.0 - b * 24.0);
        assert!(
            (at.texel - expected).length() < 2e-2,
            "seed {seed}: {at:?} vs {expected}"
        );
        assert!((at.depth - d).abs() < 1e-4 * d.max(1.0), "seed {seed}");
        // Behind the light: nowhere.
        assert_eq!(map.locate(eye - d * axis), None, "seed {seed}");
    }
}

#[test]
fn a_point_is_shadowed_only_behind_the_occluder_by_more_than_the_bias() {
    let map = half_covered_map(64, 64, 32);
    let filter = ShadowFilter {
        bias: 0.1,
        ..ShadowFilter::default()
    };
    let left = ground_at_texel(&map, 8.0);
    let right = ground_at_texel(&map, 56.0);
    assert_eq!(map.occlusion(left, &filter), 1.0);
    assert_eq!(map.occlusion(right, &filter), 0.0);
    // The occluder's own surface (depth 5) and a point within the bias
    // behind it are lit; a point beyond the bias is not.
    assert_eq!(map.occlusion(left + Vec3::Z * 5.0, &filter), 0.0);
    assert_eq!(map.occlusion(left + Vec3::Z * 4.95, &filter), 0.0);
    assert_eq!(map.occlusion(left + Vec3::Z * 4.85, &filter), 1.0);
    // Outside the map: lit.
    assert_eq!(map.occlusion(Vec3::new(-1.5, 0.0, 0.0), &filter), 0.0);
}

/// The 10%-90% width, in texels, of the shadow edge of
/// [`half_covered_map`] under `filter`, scanned at 1/64 texel.
fn edge_width(map: &ShadowMap, filter: &ShadowFilter) -> f32 {
    let scan: Vec<(f32, f32)> = (0..map.width * 64)
        .map(|i| {
            let x = i as f32 / 64.0;
            (x, map.occlusion(ground_at_texel(map, x), filter))
        })
        .collect();
    for pair in scan.windows(2) {
        assert!(
            pair[1].1 <= pair[0].1 + 1e-6,
            "the shadow fades monotonically: {pair:?}"
        );
    }
    let crossing = |level: f32| scan.iter().find(|(_, o)| *o <= level).expect("crosses").0;
    crossing(0.1) - crossing(0.9)
}

#[test]
fn the_penumbra_is_a_box_over_the_bilinear_ramp_and_widens_with_blur() {
    // The occluder's edge lies at texel column 64 of 128. One bilinear
    // comparison ramps from 1 to 0 over one texel; `samples` of them
    // spread over a region `r = width + blur * 128` texels wide average it
    // over a box of width `r`. The 10%-90% width of a unit ramp is 0.8; of
    // a box of width r >> 1 over it, 0.8 r.
    let map = half_covered_map(128, 8, 64);
    let mut widths = Vec::new();
    for blur in [0.0, 0.05, 0.1, 0.2] {
        let filter = ShadowFilter {
            samples: 256,
            blur,
            ..ShadowFilter::default()
        };
        let width = edge_width(&map, &filter);
        let region = filter.width + blur * 128.0;
        if blur > 0.0 {
            let expected = 0.8 * region;
            assert!(
                (width - expected).abs() < 0.1 * expected,
                "blur {blur}: the 10-90% width is {width} texels, not about {expected}"
            );
        } else {
            assert!((0.6..=1.4).contains(&width), "blur 0: {width} texels");
        }
        // The edge stays centred on the occluder's edge.
        let half = map.occlusion(ground_at_texel(&map, 64.0), &filter);
        assert!((half - 0.5).abs() < 0.02, "blur {blur}: {half} at the edge");
        widths.push(width);
    }
    assert!(widths.windows(2).all(|w| w[1] > w[0]), "{widths:?}");
}

/// A soft edge along the map's columns fades without steps: the lookups'
/// grid is turned, so its 64 lookups meet the edge one after another
/// (about a texel apart here) instead of in 8 rows of 8 (8 texels apart,
/// with flat steps between, which an unturned grid shows).
#[test]
fn a_soft_edge_along_the_maps_texels_fades_without_steps() {
    let map = half_covered_map(256, 8, 128);
    let filter = ShadowFilter {
        samples: 64,
        blur: 0.25,
        ..ShadowFilter::default()
    };
    // A region of 65 texels, 8 x 8 lookups about 8 texels apart.
    let scan: Vec<f32> = (0..160 * 16)
        .map(|i| map.occlusion(ground_at_texel(&map, 48.0 + i as f32 / 16.0), &filter))
        .collect();
    let mut longest = 0;
    let mut run = 0;
    for pair in scan.windows(2) {
        let inside = pair[0] > 0.02 && pair[0] < 0.98;
        run = if inside && (pair[1] - pair[0]).abs() < 1e-6 {
            run + 1
        } else {
            0
        };
        longest = longest.max(run);
    }
    let longest = longest as f32 / 16.0;
    assert!(
        longest < 1.5,
        "a flat step {longest} texels long in the penumbra"
    );
}

#[test]
fn one_sample_and_no_width_is_the_plain_depth_test() {
    let map = half_covered_map(16, 16, 8);
    let filter = ShadowFilter {
        samples: 1,
        width: 0.0,
        ..ShadowFilter::default()
    };
    // At a texel's centre a single comparison reads that texel alone.
    for x in 0..16 {
        let expected = if x < 8 { 1.0 } else { 0.0 };
        let o = map.occlusion(ground_at_texel(&map, x as f32 + 0.5), &filter);
        assert_eq!(o, expected, "texel {x}");
    }
}

#[test]
fn a_point_light_takes_the_first_map_that_holds_the_point() {
    let covered = half_covered_map(8, 8, 8);
    let moved = ShadowMap {
        world_to_clip: covered.world_to_clip * Mat4::from_translation(Vec3::new(-4.0, 0.0, 0.0)),
        world_to_camera: covered.world_to_camera
            * Mat4::from_translation(Vec3::new(-4.0, 0.0, 0.0)),
        ..covered.clone()
    };
    let maps = [covered, moved];
    let light = LightShadowMaps {
        maps: &maps,
        filter: ShadowFilter::default(),
    };
    // Inside the first map, shadowed; inside the second only (which is the
    // first moved 4 units along +x), shadowed by it; in neither, lit.
    assert_eq!(light.visibility(Vec3::ZERO), 0.0);
    assert_eq!(light.visibility(Vec3::new(4.0, 0.0, 0.0)), 0.0);
    assert_eq!(light.visibility(Vec3::new(10.0, 0.0, 0.0)), 1.0);
}

#[test]
fn a_map_with_bad_texels_or_matrices_names_the_problem() {
    let mut map = half_covered_map(4, 4, 2);
    assert_eq!(map.problem(), None);
    map.depths[3] = f32::NAN;
    assert!(map.problem().unwrap().contains("NaN"));
    map.depths.pop();
    assert!(map.problem().unwrap().contains("15 depths"));
    let filter = ShadowFilter {
        blur: -1.0,
        ..ShadowFilter::default()
    };
    assert!(filter.problem().unwrap().contains("blur"));
}

#[test]
fn encoded_maps_read_back_exactly() {
    let map = half_covered_map(5, 3, 2);
    let bytes = file::encode(&map, "shadow").unwrap();
    let dir = std::env::temp_dir().join(format!("reyes-shadow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("map.shad");
    std::fs::write(&path, bytes).unwrap();
    let read = read_shadow_map(&path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(read, map);
}
