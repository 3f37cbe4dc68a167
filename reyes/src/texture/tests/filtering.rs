//! The mip chains and the CPU filter: level sizes and values, wrap modes,
//! level 0 reproduced at one texel per pixel, minification without moire.

use glam::Vec2;
use rand::Rng;

use super::*;
use crate::test_random::fresh_rng;

/// Adds a `width x height` image whose texel `(x, y)` is `f(x, y)`.
fn texture(
    set: &mut TextureSet,
    width: u32,
    height: u32,
    wrap: Wrap,
    f: impl Fn(u32, u32) -> Vec4,
) -> TextureId {
    let texels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| f(x, y))
        .collect();
    set.add_linear(Path::new("memory"), width, height, texels, wrap, wrap)
        .unwrap()
}

#[test]
fn a_4096_square_chain_takes_at_most_a_third_more() {
    let level0 = 4096u64 * 4096;
    let chain = mipmap::chain_texels(4096, 4096);
    assert_eq!(mipmap::level_count(4096, 4096), 13);
    assert!(chain as f64 <= 1.34 * level0 as f64, "{chain} texels");
    // The real builder lays out exactly that many texels, non-power-of-two
    // sizes included.
    for (w, h) in [(256, 256), (300, 200), (97, 61)] {
        let mut set = TextureSet::default();
        let id = texture(&mut set, w, h, Wrap::Periodic, |x, y| {
            Vec4::splat((x + y) as f32)
        });
        let texels = set.texels.len() as u64;
        assert_eq!(texels, mipmap::chain_texels(w, h), "{w} x {h}");
        assert!(
            texels as f64 <= 1.34 * f64::from(w * h),
            "{w} x {h}: {texels}"
        );
        // The last level is 1 x 1 and ends the buffer.
        let info = *set.info(id).unwrap();
        let last = sample::level(&info, info.levels - 1);
        assert_eq!(
            last,
            sample::Level {
                offset: texels as u32 - 1,
                width: 1,
                height: 1
            }
        );
    }
}

#[test]
fn odd_levels_are_area_averages() {
    // 5 x 3 -> 2 x 1 -> 1 x 1. Each level-1 texel is the mean of the
    // level-0 image over its area, found here by point sampling a grid
    // fine enough that its cells never straddle a texel edge.
    let value = |x: u32, y: u32| (x * 3 + y * 7) as f32 * 0.125;
    let mut set = TextureSet::default();
    let id = texture(&mut set, 5, 3, Wrap::Periodic, |x, y| {
        Vec4::splat(value(x, y))
    });
    let info = *set.info(id).unwrap();
    assert_eq!(info.levels, 3);
    let level1 = sample::level(&info, 1);
    assert_eq!((level1.width, level1.height), (2, 1));
    const FINE: u32 = 60;
    for i in 0..2u32 {
        let mut sum = 0.0f64;
        for a in 0..FINE {
            for b in 0..FINE {
                // Cell centres over [i * 2.5, (i + 1) * 2.5) x [0, 3).
                let x = (f64::from(i) + (f64::from(a) + 0.5) / f64::from(FINE)) * 2.5;
                let y = (f64::from(b) + 0.5) / f64::from(FINE) * 3.0;
                sum += f64::from(value(x as u32, y as u32));
            }
        }
        let mean = sum / f64::from(FINE * FINE);
        let got = mipmap::unpack(set.texels[(level1.offset + i) as usize]);
        assert_f16_close(got.x, mean, &format!("level 1 texel {i}"));
    }
    // The last level is the mean of the whole image.
    let all: f64 = (0..3)
        .flat_map(|y| (0..5).map(move |x| f64::from(value(x, y))))
        .sum();
    let last = mipmap::unpack(set.texels[sample::level(&info, 2).offset as usize]);
    assert_f16_close(last.x, all / 15.0, "level 2");
}

#[test]
fn wrap_modes_pick_their_taps() {
    let values = [1.0, 2.0, 4.0, 8.0];
    let tiny = Vec2::splat(1e-6);
    let mut set = TextureSet::default();
    let ids = [Wrap::Periodic, Wrap::Clamp, Wrap::Black]
        .map(|wrap| texture(&mut set, 4, 1, wrap, |x, _| Vec4::splat(values[x as usize])));
    let at = |id, s: f32| set.sample(id, Vec2::new(s, 0.5), tiny, tiny).x;
    let [periodic, clamp, black] = ids;
    // Inside, the modes agree: texel centres are exact, edges blend.
    for id in ids {
        assert_eq!(at(id, 0.125), 1.0);
        assert_eq!(at(id, 0.625), 4.0);
        assert_eq!(at(id, 0.25), 1.5);
    }
    // Left of s = 0: the last texel, the first one, black.
    assert_eq!(at(periodic, -0.125), 8.0);
    assert_eq!(at(clamp, -0.125), 1.0);
    assert_eq!(at(black, -0.125), 0.0);
    // On the edge itself, half of each.
    assert_eq!(at(periodic, 0.0), 4.5);
    assert_eq!(at(clamp, 0.0), 1.0);
    assert_eq!(at(black, 0.0), 0.5);
    assert_eq!(at(periodic, 1.0), 4.5);
    assert_eq!(at(black, 1.0), 4.0);
    // Far outside.
    assert_eq!(at(periodic, 7.375), 2.0);
    assert_eq!(at(periodic, -7.625), 2.0);
    assert_eq!(at(clamp, 1e9), 8.0);
    assert_eq!(at(clamp, -1e9), 1.0);
    assert_eq!(at(black, 3.0), 0.0);
    // Along t likewise (a 1 x 4 image), and the modes are per axis.
    let mut set = TextureSet::default();
    let texels = values.iter().map(|&v| Vec4::splat(v)).collect();
    let id = set
        .add_linear(
            Path::new("column"),
            1,
            4,
            texels,
            Wrap::Black,
            Wrap::Periodic,
        )
        .unwrap();
    assert_eq!(set.sample(id, Vec2::new(0.5, -0.125), tiny, tiny).x, 8.0);
    assert_eq!(set.sample(id, Vec2::new(1.5, 0.375), tiny, tiny).x, 0.0);
    // Black is transparent black: alpha too.
    assert_eq!(
        set.sample(id, Vec2::new(-0.5, 0.375), tiny, tiny),
        Vec4::ZERO
    );
}

#[test]
fn one_texel_per_pixel_reproduces_level_0() {
    let (seed, mut rng) = fresh_rng("one_texel_per_pixel_reproduces_level_0");
    for (w, h) in [(64, 32), (37, 23)] {
        let values: Vec<Vec4> = (0..w * h)
            .map(|_| Vec4::from_array([(); 4].map(|_| rng.random_range(0.0..4.0))))
            .collect();
        let mut set = TextureSet::default();
        for wrap in [Wrap::Periodic, Wrap::Clamp, Wrap::Black] {
            let id = set
                .add_linear(Path::new("random"), w, h, values.clone(), wrap, wrap)
                .unwrap();
            let (a, b) = (
                Vec2::new(1.0 / w as f32, 0.0),
                Vec2::new(0.0, 1.0 / h as f32),
            );
            for y in 0..h {
                for x in 0..w {
                    let st = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                    let got = set.sample(id, st, a, b);
                    let want = stored(&set, id, x, y);
                    if w.is_power_of_two() && h.is_power_of_two() {
                        // The centres are exact in binary: so is the sample.
                        assert_eq!(got, want, "seed {seed}, {w} x {h} {wrap:?} ({x}, {y})");
                    } else {
                        // (x + 0.5) / w rounds, and so does its product with
                        // the size: the texel coordinate is off by an ulp of
                        // the size, which moves that much weight between two
                        // taps whose values differ by at most the range (4).
                        let coordinate_ulp = w.max(h) as f32 * f32::EPSILON;
                        let tolerance = 2.0 * coordinate_ulp * 4.0;
                        let error = (got - want).abs().max_element();
                        assert!(
                            error <= tolerance,
                            "seed {seed}, {w} x {h} {wrap:?} ({x}, {y}): {error} > {tolerance}"
                        );
                    }
                }
            }
        }
    }
}

/// Mean and variance of `samples`.
fn moments(samples: &[f32]) -> (f64, f64) {
    let n = samples.len() as f64;
    let mean = samples.iter().map(|&s| f64::from(s)).sum::<f64>() / n;
    let variance = samples
        .iter()
        .map(|&s| (f64::from(s) - mean).powi(2))
        .sum::<f64>()
        / n;
    (mean, variance)
}

/// Samples of texture `id` (`size` texels square) over a 61 x 53 grid of
/// positions at irregular spacings, with a square footprint of `footprint`
/// texels.
fn grid_samples(set: &TextureSet, id: TextureId, size: u32, footprint: f32) -> Vec<f32> {
    let side = footprint / size as f32;
    let (a, b) = (Vec2::new(side, 0.0), Vec2::new(0.0, side));
    let mut samples = Vec::new();
    for j in 0..53 {
        for i in 0..61 {
            let st = Vec2::new(i as f32 * 0.016_381 + 0.003, j as f32 * 0.018_713 + 0.007);
            samples.push(set.sample(id, st, a, b).x);
        }
    }
    samples
}

#[test]
fn minified_checkerboards_converge_to_their_mean() {
    let mut set = TextureSet::default();
    // One-texel checks: unfiltered (level 0) bilinear samples alias
    // (variance 0.25 / 9 at uniformly spread positions); any footprint of
    // 8 to 64 texels sees the mean.
    let fine = texture(&mut set, 256, 256, Wrap::Periodic, |x, y| {
        Vec4::splat(((x + y) % 2) as f32)
    });
    let (_, aliased) = moments(&grid_samples(&set, fine, 256, 0.0));
    assert!(aliased > 0.02, "level 0: variance {aliased}");
    for footprint in [8.0, 11.0, 16.0, 23.0, 32.0, 45.0, 64.0] {
        for sample in grid_samples(&set, fine, 256, footprint) {
            assert!((sample - 0.5).abs() < 1e-3, "{footprint} texels: {sample}");
        }
    }
    // 32-texel checks on 512 x 512: the variance over the grid falls as the
    // footprint (and the level) rises, down to the mean at 64 texels.
    let coarse = texture(&mut set, 512, 512, Wrap::Periodic, |x, y| {
        Vec4::splat(((x / 32 + y / 32) % 2) as f32)
    });
    let mut previous = f64::INFINITY;
    for footprint in [8.0, 11.0, 16.0, 23.0, 32.0, 45.0, 64.0] {
        let (mean, variance) = moments(&grid_samples(&set, coarse, 512, footprint));
        eprintln!("{footprint} texels: mean {mean:.4}, variance {variance:.5}");
        assert!((mean - 0.5).abs() < 0.03, "{footprint} texels: mean {mean}");
        assert!(
            variance < previous,
            "{footprint} texels: variance {variance} >= {previous}"
        );
        previous = variance;
    }
    assert!(previous < 1e-6, "64 texels: variance {previous}");
}

#[test]
fn the_shorter_axis_picks_the_level_and_the_longer_the_probes() {
    let mut set = TextureSet::default();
    let id = texture(&mut set, 64, 16, Wrap::Periodic, |_, _| Vec4::ONE);
    let info = *set.info(id).unwrap();
    assert_eq!(info.levels, 7);
    let probes = |a: Vec2, b: Vec2| {
        let p = sample::probes(&info, a, b);
        (p.lod, p.count)
    };
    // Measured in level-0 texels of each axis: 4 texels along s, 2 along t.
    assert_eq!(
        probes(Vec2::new(4.0 / 64.0, 0.0), Vec2::new(0.0, 2.0 / 16.0)),
        (1.0, 2)
    );
    assert_eq!(
        probes(Vec2::new(0.0, 8.0 / 16.0), Vec2::new(1.0 / 64.0, 0.0)),
        (0.0, 8)
    );
    // Round: one probe, at the level of its diameter. Diagonal: |(3, 4)| =
    // 5 texels.
    let diagonal = Vec2::new(3.0 / 64.0, 4.0 / 16.0);
    assert_eq!(
        probes(
            diagonal,
            diagonal.perp() * Vec2::new(16.0 / 64.0, 64.0 / 16.0)
        ),
        (5f32.log2(), 1)
    );
    // 64 texels long, none wide: at most 16 probes, 4 texels wide each.
    assert_eq!(probes(Vec2::new(1.0, 0.0), Vec2::ZERO), (2.0, 16));
    // Magnification is level 0 with one probe; beyond the last level, the
    // last level; a non-finite axis, the last level with one probe.
    assert_eq!(probes(Vec2::ZERO, Vec2::ZERO), (0.0, 1));
    assert_eq!(probes(Vec2::new(0.5 / 64.0, 0.0), Vec2::ZERO), (0.0, 1));
    assert_eq!(
        probes(Vec2::new(100.0, 0.0), Vec2::new(0.0, 400.0)),
        (6.0, 1)
    );
    assert_eq!(probes(Vec2::new(f32::INFINITY, 0.0), Vec2::ZERO), (6.0, 1));
    assert_eq!(probes(Vec2::new(f32::NAN, 0.0), Vec2::ZERO), (6.0, 1));
}

#[test]
fn bad_ids_and_coordinates_sample_black() {
    let mut set = TextureSet::default();
    let id = texture(&mut set, 4, 4, Wrap::Clamp, |_, _| Vec4::ONE);
    let small = Vec2::splat(0.01);
    assert_eq!(set.sample(id, Vec2::splat(0.5), small, small), Vec4::ONE);
    assert_eq!(
        set.sample(TextureId(1), Vec2::splat(0.5), small, small),
        Vec4::ZERO
    );
    for st in [Vec2::new(f32::NAN, 0.5), Vec2::new(0.5, f32::INFINITY)] {
        assert_eq!(set.sample(id, st, small, small), Vec4::ZERO);
    }
}

#[test]
fn an_empty_set_has_one_dummy_entry_each() {
    let set = TextureSet::default();
    let (infos, texels) = set.gpu_tables();
    assert_eq!(infos, vec![TextureInfo::DUMMY]);
    assert_eq!(texels, &[[0, 0]]);
    let mut set = TextureSet::default();
    texture(&mut set, 2, 2, Wrap::Black, |_, _| Vec4::ONE);
    let (infos, texels) = set.gpu_tables();
    assert_eq!(infos.len(), 1);
    assert_eq!(texels.len(), 5);
}

#[test]
fn in_memory_images_are_checked() {
    let mut set = TextureSet::default();
    let name = Path::new("procedural");
    let error = set
        .add_linear(name, 2, 2, vec![Vec4::ONE; 3], Wrap::Clamp, Wrap::Clamp)
        .unwrap_err();
    assert!(matches!(error, TextureError::Decode { .. }), "{error:?}");
    let error = set
        .add_linear(name, 1, 1, vec![Vec4::NAN], Wrap::Clamp, Wrap::Clamp)
        .unwrap_err();
    assert!(
        matches!(error, TextureError::NonFinite { x: 0, y: 0, .. }),
        "{error:?}"
    );
    assert!(set.is_empty());
}
