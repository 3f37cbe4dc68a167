//! Unit tests of the time/lens tables.

use glam::Vec2;

use rand::Rng;

use super::*;
use crate::sampling::grid_size;
use crate::test_random::fresh_rng;

/// The tables of `spp` samples and tiles of side `tile`, with the default
/// permutations, over a 640-pixel-wide image.
fn tables(spp: u32, tile: u32) -> UvtTables {
    UvtTables::new(
        spp,
        InterleaveTiles::new(tile, DEFAULT_INTERLEAVE_PERMUTATIONS, 640),
    )
}

#[test]
fn disk_map_stays_in_the_disk_and_reaches_its_rim() {
    let mut max: f32 = 0.0;
    for i in 0..=32 {
        for j in 0..=32 {
            let p = concentric_disk(i as f32 / 32.0, j as f32 / 32.0);
            assert!(p.length() <= 1.0 + 1e-6, "{p}");
            max = max.max(p.length());
        }
    }
    assert!(max > 0.999);
}

#[test]
fn pixel_table_stratifies_time_within_every_pixel() {
    for spp in [1, 4, 16, 64, 100, 256] {
        let tables = tables(spp, 2);
        for (x, y) in [(0, 0), (5, 63), (70, 200)] {
            let mut seen = vec![false; spp as usize];
            for s in 0..spp {
                let i = tables.pixel_index(x, y, s);
                let t = tables.pixel[i].t;
                assert!((0.0..1.0).contains(&t));
                let stratum = (t * spp as f32) as usize;
                assert!(!seen[stratum], "two samples in stratum {stratum}");
                seen[stratum] = true;
                // The inverse names the sample of this stratum.
                let owner = tables.sample_in_stratum[tables.pixel_index(x, y, stratum as u32)];
                assert_eq!(owner, s);
                assert!(tables.pixel[i].lens.length() <= 1.0 + 1e-6);
            }
        }
        // The table repeats every TABLE_SIDE pixels.
        assert_eq!(tables.pixel_index(3, 4, 0), tables.pixel_index(67, 132, 0));
    }
}

#[test]
fn every_interleave_tuple_has_exactly_one_sample_per_tile() {
    for (spp, tile) in [1, 4, 16]
        .into_iter()
        .flat_map(|spp| INTERLEAVE_TILES.map(|k| (spp, k)))
    {
        let tables = tables(spp, tile);
        let n = tables.interleave_tuples();
        assert_eq!(n, spp * tile * tile);
        for (tx, ty) in [(0, 0), (1, 0), (17, 33)] {
            let mut seen = std::collections::HashSet::new();
            for tuple in 0..n {
                let (x, y, s) = tables.interleave_sample(tx, ty, tuple);
                assert_eq!((x / tile, y / tile), (tx, ty));
                assert!(s < spp);
                assert!(seen.insert((x, y, s)), "sample reused");
            }
        }
    }
}

/// Sattlecker and Steinberger's equations 2 and 3, computed here in `u64`
/// from the image width: `tilenumber = ty * ceil(width / K) + tx` and
/// `(tilenumber + tx + ty) mod P`, for random widths, tile sides,
/// permutation counts and tiles of the image.
#[test]
fn a_tile_takes_the_published_permutation() {
    let (seed, mut rng) = fresh_rng("a_tile_takes_the_published_permutation");
    for _ in 0..2000 {
        let tile = INTERLEAVE_TILES[rng.random_range(0..INTERLEAVE_TILES.len())];
        let permutations = rng.random_range(1..=MAX_INTERLEAVE_PERMUTATIONS);
        let (width, height) = (rng.random_range(1..5000u32), rng.random_range(1..5000u32));
        let tiles = InterleaveTiles::new(tile, permutations, width);
        let (tx, ty) = (
            rng.random_range(0..width.div_ceil(tile)),
            rng.random_range(0..height.div_ceil(tile)),
        );
        let scene_tiles = u64::from(width).div_ceil(u64::from(tile));
        let tilenumber = u64::from(ty) * scene_tiles + u64::from(tx);
        let expected = (tilenumber + u64::from(tx) + u64::from(ty)) % u64::from(permutations);
        assert_eq!(
            u64::from(tiles.permutation(tx, ty)),
            expected,
            "seed {seed}: K {tile}, P {permutations}, width {width}, tile ({tx}, {ty})"
        );
    }
}

/// With `P = 1` every tile takes the one permutation, so the pattern
/// repeats with the tile's period (the left of the paper's Figure 10);
/// with 64, a 32 x 32 patch of tiles uses every one when a row has an even
/// number of tiles (640 pixels: 320, 214 and 160 tiles). With an odd
/// number `W`, `ty * (W + 1) + 2 * tx` is even and the published rule uses
/// only the even permutations.
#[test]
fn one_permutation_repeats_the_tile_and_64_are_all_used() {
    for tile in INTERLEAVE_TILES {
        let one = UvtTables::new(16, InterleaveTiles::new(tile, 1, 320));
        for (x, y) in (0..40 * 40).map(|i| (i % 40, i / 40)) {
            for s in 0..16 {
                assert_eq!(
                    one.pixel_tuple(PixelTuples::Interleave, x, y, s),
                    one.pixel_tuple(PixelTuples::Interleave, x % tile, y % tile, s)
                );
            }
        }
        let used = |width| {
            let tiles = InterleaveTiles::new(tile, 64, width);
            (0..1024)
                .map(|i| tiles.permutation(i % 32, i / 32))
                .collect::<std::collections::HashSet<u32>>()
        };
        assert_eq!(used(640).len(), 64, "K {tile}");
        let odd = used(tile * 81);
        assert!(odd.len() == 32 && odd.iter().all(|p| p % 2 == 0), "K {tile}");
    }
}

/// INTERVAL's UV-T pairing: in every pixel, the sample of time stratum
/// `i` lies in lens stratum `pairing[i]`, inside its interval's lens
/// box, and the boxes are much smaller than the lens (with the boxes
/// of the whole disk, INTERVAL with a lens alone tests what the
/// bounding box does).
#[test]
fn every_pixel_pairs_time_and_lens_strata_inside_the_interval_boxes() {
    for spp in [1, 4, 16, 64, 225, 256] {
        let tables = tables(spp, 2);
        let k = grid_size(spp);
        let mut seen = tables.pairing.clone();
        seen.sort_unstable();
        assert_eq!(
            seen,
            (0..spp).collect::<Vec<_>>(),
            "pairing is a permutation"
        );
        for (x, y) in [(0, 0), (5, 63), (70, 200), (63, 1)] {
            for s in 0..spp {
                let tl = tables.pixel[tables.pixel_index(x, y, s)];
                let stratum = (tl.t * spp as f32) as usize;
                let [lo, hi] = tables.interval_lens[stratum];
                assert!(
                    tl.lens.cmpge(lo).all() && tl.lens.cmple(hi).all(),
                    "spp {spp}, pixel ({x}, {y}), sample {s}: lens {} outside [{lo}, {hi}]",
                    tl.lens
                );
                let (a, b) = disk_to_square(tl.lens);
                let lens =
                    ((b * k as f32) as u32).min(k - 1) * k + ((a * k as f32) as u32).min(k - 1);
                assert_eq!(lens, tables.pairing[stratum]);
            }
        }
        // The whole lens is 2 x 2; a region's box is about a stratum's
        // size, 2 / k across (larger at the rim, where strata are arcs).
        let mut area = 0.0;
        for [lo, hi] in &tables.interval_lens {
            let side = *hi - *lo;
            assert!(side.max_element() <= 4.0 / k as f32, "spp {spp}: {lo} {hi}");
            area += side.x * side.y;
        }
        let mean_side = (area / spp as f32).sqrt();
        assert!(
            mean_side <= 2.5 / k as f32,
            "spp {spp}: mean box side {mean_side}"
        );
    }
}

/// Dense points of every lens stratum lie in its box.
#[test]
fn lens_stratum_boxes_hold_their_strata() {
    for k in [1, 2, 3, 4, 8] {
        for (col, row) in (0..k * k).map(|i| (i % k, i / k)) {
            let [lo, hi] = lens_stratum_box(col, row, k);
            for i in 0..=40 {
                for j in 0..=40 {
                    let a = (col as f32 + i as f32 / 40.0) / k as f32;
                    let b = (row as f32 + j as f32 / 40.0) / k as f32;
                    let p = concentric_disk(a, b);
                    assert!(
                        p.cmpge(lo).all() && p.cmple(hi).all(),
                        "k {k} ({col}, {row}): {p}"
                    );
                }
            }
        }
    }
}

#[test]
fn tuples_stratify_time_and_lens() {
    let tables = tables(16, 2);
    let mut times: Vec<f32> = tables.simple.iter().map(|t| t.t).collect();
    times.sort_by(f32::total_cmp);
    for (i, t) in times.iter().enumerate() {
        assert!((t - (i as f32 + 0.5) / 16.0).abs() < 1e-6);
    }
    let layout = tables.layout();
    assert_eq!(tables.to_floats().len(), layout.floats as usize);
    assert_eq!(
        layout.pixel as usize,
        4 * (tables.simple.len() + tables.interleave.len() + tables.interval_lens.len())
    );
    assert_eq!(layout.interleave, 4 * 16);
}

/// The square point that [`concentric_disk`] maps to `p`.
fn disk_to_square(p: Vec2) -> (f32, f32) {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let r = p.length();
    let phi = p.y.atan2(p.x);
    let (x, y) = if (-FRAC_PI_4..=FRAC_PI_4).contains(&phi) {
        (r, r * phi / FRAC_PI_4)
    } else if phi > FRAC_PI_4 && phi <= 3.0 * FRAC_PI_4 {
        (r * (FRAC_PI_2 - phi) / FRAC_PI_4, r)
    } else if (-3.0 * FRAC_PI_4..-FRAC_PI_4).contains(&phi) {
        (-r * (-FRAC_PI_2 - phi) / FRAC_PI_4, -r)
    } else {
        let shifted = if phi > 0.0 { phi - PI } else { phi + PI };
        (-r, -r * shifted / FRAC_PI_4)
    };
    ((x + 1.0) * 0.5, (y + 1.0) * 0.5)
}

/// Under [`PixelTuples::Interleave`], the bounding box and INTERVAL give
/// every sample the Interleave tuple it carries, INTERVAL finds for
/// interval `i` the sample whose tuple lies in time stratum `i`, and
/// that tuple's lens lies in the interval's lens box (the per-pixel
/// table's UV-T pairing), so INTERVAL's boxes hold it.
#[test]
fn adaptive_pixels_carry_their_interleave_tuples() {
    for (spp, tile) in [1, 4, 16, 64, 144, 256]
        .into_iter()
        .flat_map(|spp| INTERLEAVE_TILES.map(|k| (spp, k)))
    {
        let tables = tables(spp, tile);
        let n = tables.interleave_tuples();
        for (tx, ty) in [(0, 0), (1, 0), (5, 9), (31, 17)] {
            for tuple in 0..n {
                let (x, y, s) = tables.interleave_sample(tx, ty, tuple);
                let carried = tables.interleave[tuple as usize];
                assert_eq!(
                    tables.pixel_tuple(PixelTuples::Interleave, x, y, s),
                    carried,
                    "spp {spp}, K {tile}, pixel ({x}, {y}), sample {s}"
                );
                let stratum = tuple / (tile * tile);
                assert_eq!((carried.t * spp as f32) as u32, stratum);
                assert_eq!(
                    tables.pixel_sample_in_stratum(PixelTuples::Interleave, x, y, stratum),
                    s
                );
                let [lo, hi] = tables.interval_lens[stratum as usize];
                assert!(
                    carried.lens.cmpge(lo).all() && carried.lens.cmple(hi).all(),
                    "spp {spp}, K {tile}: tuple {tuple} lens {} outside [{lo}, {hi}]",
                    carried.lens
                );
            }
        }
    }
}

/// Interleave UVT as Fatahalian et al. keep it: in every tile, with
/// every permutation, each pixel's `spp` samples take every time
/// stratum and every `k x k` lens stratum once. The builder that
/// permuted all `spp * K^2` tuples of a tile failed this.
#[test]
fn every_interleave_pixel_keeps_its_time_and_lens_stratified() {
    use std::collections::{HashMap, HashSet};
    for (spp, tile) in [4, 16, 64, 256]
        .into_iter()
        .flat_map(|spp| INTERLEAVE_TILES.map(|k| (spp, k)))
    {
        let tables = tables(spp, tile);
        let k = grid_size(spp);
        let n = tables.interleave_tuples();
        for (tx, ty) in (0..64).map(|i| (i % 8, i / 8)) {
            let mut times = HashMap::<(u32, u32), HashSet<u32>>::new();
            let mut lenses = HashMap::<(u32, u32), HashSet<u32>>::new();
            for tuple in 0..n {
                let (x, y, _) = tables.interleave_sample(tx, ty, tuple);
                let tl = tables.interleave[tuple as usize];
                let (a, b) = disk_to_square(tl.lens);
                let back = concentric_disk(a, b);
                assert!(
                    (back - tl.lens).length() < 1e-4,
                    "{a} {b}: {back} vs {}",
                    tl.lens
                );
                let time = (tl.t * spp as f32) as u32;
                let lens = (b * k as f32) as u32 * k + (a * k as f32) as u32;
                for (strata, stratum, what) in
                    [(&mut times, time, "time"), (&mut lenses, lens, "lens")]
                {
                    // HashSet::insert is false for a stratum seen before.
                    assert!(
                        strata.entry((x, y)).or_default().insert(stratum),
                        "spp {spp}, K {tile}, tile ({tx}, {ty}): pixel ({x}, {y}) has {what} stratum {stratum} twice"
                    );
                }
            }
            assert!(times.values().all(|t| t.len() == spp as usize));
        }
    }
}

#[test]
fn a_seed_draws_other_stratified_times_and_seed_zero_is_unseeded() {
    let tiles = InterleaveTiles::new(2, DEFAULT_INTERLEAVE_PERMUTATIONS, 640);
    let unseeded = UvtTables::new(16, tiles);
    assert_eq!(UvtTables::seeded(16, tiles, 0).pixel, unseeded.pixel);
    let seven = UvtTables::seeded(16, tiles, 7);
    assert_eq!(seven, UvtTables::seeded(16, tiles, 7), "a seed's tables repeat");
    let differing = seven
        .pixel
        .iter()
        .zip(&unseeded.pixel)
        .filter(|(a, b)| a.t != b.t)
        .count();
    assert!(
        differing > seven.pixel.len() * 9 / 10,
        "{differing} of {} times differ",
        seven.pixel.len()
    );
    // Still one sample per time stratum in every pixel, each noted where
    // INTERVAL looks for it.
    for (x, y) in [(0, 0), (5, 63), (63, 17)] {
        let mut seen = [false; 16];
        for s in 0..16 {
            let stratum = (seven.pixel[seven.pixel_index(x, y, s)].t * 16.0) as usize;
            assert!(!seen[stratum], "pixel ({x}, {y}): stratum {stratum} twice");
            seen[stratum] = true;
            let noted = seven.sample_in_stratum[seven.pixel_index(x, y, stratum as u32)];
            assert_eq!(noted, s, "pixel ({x}, {y}), stratum {stratum}");
        }
    }
}
