//! The time and lens coordinates of samples (the "uvt" of a 5D sample
//! `(x, y, u, v, t)`), as tables built on the host and read by both the CPU
//! reference and the GPU, so both test exactly the same samples.
//!
//! A sample's screen position is always [`crate::sampling::sample_position`];
//! what differs between the sampling modes is which time `t` in `[0, 1)`
//! and lens position (a point of the unit disk) it carries:
//!
//! * **Simple UVT** ([`UvtTables::simple`]): `spp` tuples shared by every
//!   pixel; sample `s` of each pixel has tuple `s`. Tuple `i` has time
//!   stratum `i` (its centre) and lens stratum `π(i)` (its centre) of a
//!   `k x k` grid on the lens square, mapped to the disk, for a fixed
//!   pseudo-random permutation `π`.
//! * **Interleave UVT** ([`UvtTables::interleave`]): `N = spp * K^2` tuples
//!   (`K = INTERLEAVE_TILE`), shared by the `K x K`-pixel tiles, in `K^2`
//!   pixel slots of `spp` tuples; each slot's tuples cover every time
//!   stratum and every `k x k` lens stratum of a pixel once (see
//!   `interleave_tuples`), as Fatahalian et al. (2009) keep them. A tile
//!   gives slot `q` to its pixel `ρ_p(q)` (row-major), where
//!   `p = hash(tx, ty, 0, PERMUTATION_CHANNEL) % INTERLEAVE_PERMUTATIONS` picks
//!   one of a few precomputed permutations of the pixel offsets per tile,
//!   which breaks the repetition of the pattern while every pixel stays
//!   stratified. The table stores, for a tuple, which sample `j` of the tile
//!   (pixel `j / spp`, sample `j % spp` of it) carries it.
//! * **Per-pixel table** ([`UvtTables::pixel`]), used by the bounding-box and
//!   INTERVAL modes: `TABLE_SIDE x TABLE_SIDE` pixels with `spp` samples
//!   each, repeated over the screen. Within a pixel the times are stratified
//!   (one sample per time stratum, in a random order per pixel) and so are
//!   the lens positions (an independent random order); both are jittered
//!   within their strata. Each entry also names the sample of its pixel
//!   whose time lies in stratum `s`, which is how INTERVAL finds the one
//!   sample of a pixel inside time interval `s`.
//!
//! Lens squares map to the disk with Shirley and Chiu's concentric map,
//! which keeps strata compact.

use glam::Vec2;

use crate::sampling::{grid_size, hash};

/// Side, in pixels, of the tiles of Interleave UVT (`K`).
pub const INTERLEAVE_TILE: u32 = 2;
/// Number of precomputed tuple permutations a tile chooses from (`P`).
pub const INTERLEAVE_PERMUTATIONS: u32 = 8;
/// Side, in pixels, of the per-pixel table, which repeats over the screen.
pub const TABLE_SIDE: u32 = 64;
/// Hash channel that picks a tile's permutation (channels 0 and 1 jitter
/// screen positions).
pub const PERMUTATION_CHANNEL: u32 = 6;

/// A time and a lens position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeLens {
    /// Time in `[0, 1)`, from shutter open to close.
    pub t: f32,
    /// Lens position in the unit disk.
    pub lens: Vec2,
}

/// Shirley and Chiu's concentric map from `[0, 1]^2` to the unit disk.
pub fn concentric_disk(a: f32, b: f32) -> Vec2 {
    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
    if x == 0.0 && y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if x.abs() > y.abs() {
        (x, std::f32::consts::FRAC_PI_4 * (y / x))
    } else {
        (
            y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (x / y),
        )
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// A uniform float in `[0, 1)` from a hash.
fn unit(h: u32) -> f32 {
    // 24 bits: exactly representable, and never rounds up to 1.
    (h >> 8) as f32 / 16_777_216.0
}

/// A pseudo-random permutation of `0..n` (Fisher-Yates driven by the hash).
fn permutation(n: u32, key: [u32; 3]) -> Vec<u32> {
    let mut p: Vec<u32> = (0..n).collect();
    for i in (1..n).rev() {
        let j = hash(key[0], key[1], key[2] * 4096 + i, 9) % (i + 1);
        p.swap(i as usize, j as usize);
    }
    p
}

/// `n = m * m` tuples: tuple `i` has the centre of time stratum `i` and the
/// centre of lens stratum `π(i)` of an `m x m` grid.
fn stratified_tuples(m: u32, key: u32) -> Vec<TimeLens> {
    let n = m * m;
    let lens = permutation(n, [key, 0, 0]);
    (0..n)
        .map(|i| {
            let (col, row) = (lens[i as usize] % m, lens[i as usize] / m);
            TimeLens {
                t: (i as f32 + 0.5) / n as f32,
                lens: concentric_disk((col as f32 + 0.5) / m as f32, (row as f32 + 0.5) / m as f32),
            }
        })
        .collect()
}

/// The `N = spp * K^2` tuples of an Interleave UVT tile (`spp = k * k`):
/// tuple `n = s * K^2 + q` is the `s`-th tuple of pixel slot `q`. Its time is
/// the centre of fine stratum `n` of `N`, which lies in coarse stratum `s`
/// of `spp`; its lens position is the centre of fine cell `q` (of `K x K`)
/// within coarse lens cell `σ_q(s)` (of `k x k`), for a per-slot
/// permutation `σ_q`. So each slot's `spp` tuples take every coarse time
/// and lens stratum once (Fatahalian et al. 2009), and the tile's tuples
/// use every fine time stratum and every fine lens cell once.
fn interleave_tuples(k: u32, key: u32) -> Vec<TimeLens> {
    let spp = k * k;
    let slots = INTERLEAVE_TILE * INTERLEAVE_TILE;
    let fine = k * INTERLEAVE_TILE;
    let n = spp * slots;
    let lens_of: Vec<Vec<u32>> = (0..slots).map(|q| permutation(spp, [key, q, 4])).collect();
    (0..n)
        .map(|i| {
            let (s, q) = (i / slots, i % slots);
            let coarse = lens_of[q as usize][s as usize];
            let col = (coarse % k) * INTERLEAVE_TILE + q % INTERLEAVE_TILE;
            let row = (coarse / k) * INTERLEAVE_TILE + q / INTERLEAVE_TILE;
            TimeLens {
                t: (i as f32 + 0.5) / n as f32,
                lens: concentric_disk(
                    (col as f32 + 0.5) / fine as f32,
                    (row as f32 + 0.5) / fine as f32,
                ),
            }
        })
        .collect()
}

/// The time/lens tables of one sample count.
#[derive(Debug, Clone, PartialEq)]
pub struct UvtTables {
    /// Samples per pixel.
    pub spp: u32,
    /// Simple UVT: tuple of sample `s` of every pixel.
    pub simple: Vec<TimeLens>,
    /// Interleave UVT: the `spp * K^2` tuples of a tile.
    pub interleave: Vec<TimeLens>,
    /// Interleave UVT: `inverse[p * N + n]` is the sample of a tile (with
    /// permutation `p`) that carries tuple `n`.
    pub inverse: Vec<u32>,
    /// Per-pixel table: entry `(py * TABLE_SIDE + px) * spp + s` is sample
    /// `s` of table pixel `(px, py)`.
    pub pixel: Vec<TimeLens>,
    /// Per-pixel table: which sample of the pixel has its time in stratum
    /// `s` (same indexing as `pixel`).
    pub sample_in_stratum: Vec<u32>,
}

impl UvtTables {
    /// Builds the tables for `spp` (a perfect square) samples per pixel.
    pub fn new(spp: u32) -> UvtTables {
        let k = grid_size(spp);
        let slots = INTERLEAVE_TILE * INTERLEAVE_TILE;
        let tuples = spp * slots;
        // Tuple n = s * K^2 + q belongs to pixel slot q; its sample index in
        // the pixel is a fixed per-slot permutation of s, so that a sample's
        // screen stratum is not tied to its time stratum.
        let sample_of: Vec<Vec<u32>> = (0..slots).map(|q| permutation(spp, [q, 1, 5])).collect();
        let mut inverse = Vec::with_capacity((INTERLEAVE_PERMUTATIONS * tuples) as usize);
        for p in 0..INTERLEAVE_PERMUTATIONS {
            // Only the pixel offsets are permuted: each pixel keeps one
            // slot's stratified tuples.
            let pixel_of_slot = permutation(slots, [p, 1, 1]);
            for s in 0..spp {
                for q in 0..slots {
                    inverse
                        .push(pixel_of_slot[q as usize] * spp + sample_of[q as usize][s as usize]);
                }
            }
        }
        let mut pixel = Vec::with_capacity((TABLE_SIDE * TABLE_SIDE * spp) as usize);
        let mut sample_in_stratum = Vec::with_capacity(pixel.capacity());
        for py in 0..TABLE_SIDE {
            for px in 0..TABLE_SIDE {
                let times = permutation(spp, [px, py, 2]);
                let lenses = permutation(spp, [px, py, 3]);
                let mut inverse_times = vec![0; spp as usize];
                for s in 0..spp {
                    let stratum = times[s as usize];
                    inverse_times[stratum as usize] = s;
                    let lens = lenses[s as usize];
                    let jitter = |c| unit(hash(px, py, s, c));
                    pixel.push(TimeLens {
                        t: (stratum as f32 + jitter(2)) / spp as f32,
                        lens: concentric_disk(
                            ((lens % k) as f32 + jitter(3)) / k as f32,
                            ((lens / k) as f32 + jitter(4)) / k as f32,
                        ),
                    });
                }
                sample_in_stratum.extend(inverse_times);
            }
        }
        UvtTables {
            spp,
            simple: stratified_tuples(k, 5),
            interleave: interleave_tuples(k, 7),
            inverse,
            pixel,
            sample_in_stratum,
        }
    }

    /// Number of Interleave UVT tuples (`spp * K^2`).
    pub fn interleave_tuples(&self) -> u32 {
        self.interleave.len() as u32
    }

    /// Index of sample `s` of screen pixel `(x, y)` in the per-pixel table.
    pub fn pixel_index(&self, x: u32, y: u32, s: u32) -> usize {
        (((y % TABLE_SIDE) * TABLE_SIDE + x % TABLE_SIDE) * self.spp + s) as usize
    }

    /// The permutation tile `(tx, ty)` of Interleave UVT uses.
    pub fn tile_permutation(tx: u32, ty: u32) -> u32 {
        hash(tx, ty, 0, PERMUTATION_CHANNEL) % INTERLEAVE_PERMUTATIONS
    }

    /// The sample of tile `(tx, ty)` that carries Interleave tuple `n`: its
    /// pixel and its sample index in that pixel.
    pub fn interleave_sample(&self, tx: u32, ty: u32, n: u32) -> (u32, u32, u32) {
        let p = Self::tile_permutation(tx, ty);
        let j = self.inverse[(p * self.interleave_tuples() + n) as usize];
        let q = j / self.spp;
        (
            tx * INTERLEAVE_TILE + q % INTERLEAVE_TILE,
            ty * INTERLEAVE_TILE + q / INTERLEAVE_TILE,
            j % self.spp,
        )
    }

    /// The tables as the GPU reads them, `vec4<f32>` records in the order
    /// simple, interleave, pixel (`t, lens.x, lens.y, 0` for the tuples;
    /// `t, lens.x, lens.y, sample_in_stratum` for the pixel table), then the
    /// interleave inverses as `f32` (exact: they are below 2^24). Offsets are
    /// in [`UvtTables::layout`].
    pub fn to_floats(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.layout().floats as usize);
        for tuple in self.simple.iter().chain(&self.interleave) {
            out.extend([tuple.t, tuple.lens.x, tuple.lens.y, 0.0]);
        }
        for (tuple, &s) in self.pixel.iter().zip(&self.sample_in_stratum) {
            out.extend([tuple.t, tuple.lens.x, tuple.lens.y, s as f32]);
        }
        out.extend(self.inverse.iter().map(|&j| j as f32));
        out
    }

    /// Where each table starts in [`UvtTables::to_floats`], in floats.
    pub fn layout(&self) -> UvtLayout {
        UvtLayout::for_spp(self.spp)
    }
}

/// Offsets, in floats, of the tables in [`UvtTables::to_floats`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UvtLayout {
    /// Simple UVT tuples.
    pub simple: u32,
    /// Interleave UVT tuples.
    pub interleave: u32,
    /// The per-pixel table.
    pub pixel: u32,
    /// Interleave inverse permutations.
    pub inverse: u32,
    /// Total floats.
    pub floats: u32,
}

impl UvtLayout {
    /// The layout of the tables for `spp` samples per pixel, without
    /// building them (buffer sizing needs only this).
    pub fn for_spp(spp: u32) -> UvtLayout {
        let tuples = spp * INTERLEAVE_TILE * INTERLEAVE_TILE;
        let simple = 0;
        let interleave = simple + 4 * spp;
        let pixel = interleave + 4 * tuples;
        let inverse = pixel + 4 * TABLE_SIDE * TABLE_SIDE * spp;
        UvtLayout {
            simple,
            interleave,
            pixel,
            inverse,
            floats: inverse + INTERLEAVE_PERMUTATIONS * tuples,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        for spp in [1, 4, 16, 64] {
            let tables = UvtTables::new(spp);
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
        for spp in [1, 4, 16] {
            let tables = UvtTables::new(spp);
            let n = tables.interleave_tuples();
            assert_eq!(n, spp * INTERLEAVE_TILE * INTERLEAVE_TILE);
            for (tx, ty) in [(0, 0), (1, 0), (17, 33)] {
                let mut seen = std::collections::HashSet::new();
                for tuple in 0..n {
                    let (x, y, s) = tables.interleave_sample(tx, ty, tuple);
                    assert_eq!((x / INTERLEAVE_TILE, y / INTERLEAVE_TILE), (tx, ty));
                    assert!(s < spp);
                    assert!(seen.insert((x, y, s)), "sample reused");
                }
            }
        }
        let perms: std::collections::HashSet<u32> = (0..64)
            .map(|i| UvtTables::tile_permutation(i % 8, i / 8))
            .collect();
        assert!(perms.len() > 4, "tiles should use several permutations");
    }

    #[test]
    fn tuples_stratify_time_and_lens() {
        let tables = UvtTables::new(16);
        let mut times: Vec<f32> = tables.simple.iter().map(|t| t.t).collect();
        times.sort_by(f32::total_cmp);
        for (i, t) in times.iter().enumerate() {
            assert!((t - (i as f32 + 0.5) / 16.0).abs() < 1e-6);
        }
        let layout = tables.layout();
        assert_eq!(tables.to_floats().len(), layout.floats as usize);
        assert_eq!(
            layout.pixel as usize,
            4 * (tables.simple.len() + tables.interleave.len())
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

    /// Interleave UVT as Fatahalian et al. keep it: in every tile, with
    /// every permutation, each pixel's `spp` samples take every time
    /// stratum and every `k x k` lens stratum once. The builder that
    /// permuted all `spp * K^2` tuples of a tile failed this.
    #[test]
    fn every_interleave_pixel_keeps_its_time_and_lens_stratified() {
        use std::collections::{HashMap, HashSet};
        for spp in [4, 16, 64] {
            let tables = UvtTables::new(spp);
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
                            "spp {spp}, tile ({tx}, {ty}): pixel ({x}, {y}) has {what} stratum {stratum} twice"
                        );
                    }
                }
                assert!(times.values().all(|t| t.len() == spp as usize));
            }
        }
    }
}
