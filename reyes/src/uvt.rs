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
//!   (`K` is the tile side, 2, 3 or 4: [`INTERLEAVE_TILES`]), shared by the
//!   `K x K`-pixel tiles, in `K^2` pixel slots of `spp` tuples; each slot's
//!   tuples cover every time stratum and every `k x k` lens stratum of a
//!   pixel once (see `interleave_tuples`), as Fatahalian et al. (2009) keep
//!   them, with the per-pixel table's UV-T pairing. A tile gives slot `q`
//!   to its pixel `ρ_p(q)` (row-major), where
//!   `p` ([`UvtTables::tile_permutation`]) picks one of
//!   [`INTERLEAVE_PERMUTATIONS`] precomputed permutations of the pixel
//!   offsets per tile, which breaks the repetition of the pattern while
//!   every pixel stays stratified. The table stores, for a tuple, which
//!   sample `j` of the tile (pixel `j / spp`, sample `j % spp` of it)
//!   carries it. Tiles are counted in absolute pixel coordinates, so a
//!   screen tile of the renderer may start anywhere in an Interleave tile.
//! * **Per-pixel table** ([`UvtTables::pixel`]), used by the bounding-box and
//!   INTERVAL modes: `TABLE_SIDE x TABLE_SIDE` pixels with `spp` samples
//!   each, repeated over the screen. Within a pixel the times are stratified
//!   (one sample per time stratum, in a random order per pixel), and the
//!   sample in time stratum `i` takes its lens position in lens stratum
//!   `π(i)` of a `k x k` grid, for one pairing `π` shared by every pixel
//!   ([`UvtTables::pairing`]): Fatahalian et al.'s UV-T pairing (2009,
//!   §3.2.1), so that INTERVAL's box for interval `i` grows by the circle
//!   of confusion over lens region `π(i)` alone
//!   ([`UvtTables::interval_lens`]), not the whole lens. Times and lens
//!   positions are jittered within their strata. Each entry also names the
//!   sample of its pixel whose time lies in stratum `s`, which is how
//!   INTERVAL finds the one sample of a pixel inside time interval `s`.
//! * **Interleave tuples per pixel** ([`PixelTuples::Interleave`]), used by
//!   the bounding box and INTERVAL under Adaptive sampling: each sample
//!   takes the Interleave tuple it carries ([`UvtTables::pixel_tuple`]).
//!   Adaptive samples some grids with INTERVAL and others with Interleave
//!   UVT; with the per-pixel table, a sample had one time and lens for the
//!   first and another for the second, so the shared edges of grids sampled
//!   differently neither covered nor double-covered it exactly under motion
//!   and blur. With one tuple per sample, the two modes differ only in how
//!   they find the samples a micropolygon may cover, and Adaptive renders
//!   Interleave UVT's image.
//!
//! Lens squares map to the disk with Shirley and Chiu's concentric map,
//! which keeps strata compact.

use glam::Vec2;

use crate::modes::Sampling;
use crate::sampling::{grid_size, hash};

/// The sides, in pixels, that the tiles of Interleave UVT (`K`) may have:
/// the sizes Fatahalian et al. and Sattlecker and Steinberger measure.
pub const INTERLEAVE_TILES: [u32; 3] = [2, 3, 4];
/// The default side of Interleave UVT's tiles.
pub const DEFAULT_INTERLEAVE_TILE: u32 = 2;
/// Number of precomputed pixel-offset permutations a tile chooses from
/// (`P`), as in both papers.
pub const INTERLEAVE_PERMUTATIONS: u32 = 64;
/// How far, in lens units (the unit disk), the lens box of an INTERVAL
/// interval ([`UvtTables::interval_lens`]) reaches past the region's image
/// as sampled: more than the bulge of the region's curved sides between
/// the samples taken along each side, and more than f32 rounding of a jittered
/// lens position.
pub const LENS_BOX_MARGIN: f32 = 1.0 / 512.0;
/// Samples per side of a lens stratum when its image on the disk is bounded.
const LENS_BOX_STEPS: u32 = 64;
/// Side, in pixels, of the per-pixel table, which repeats over the screen.
pub const TABLE_SIDE: u32 = 64;
/// Hash channel that picks a tile's permutation (channels 0 and 1 jitter
/// screen positions).
pub const PERMUTATION_CHANNEL: u32 = 6;
/// Interleave UVT's choice of permutations repeats every this many pixels
/// (a multiple of every tile side in [`INTERLEAVE_TILES`]), so that the
/// slot of every pixel fits one table ([`UvtTables::pixel_slot`]) that the
/// bounding box and INTERVAL read under Adaptive without hashing or
/// dividing by the tile side per sample.
pub const INTERLEAVE_PERIOD: u32 = 96;
const _: () = {
    let mut i = 0;
    while i < INTERLEAVE_TILES.len() {
        assert!(INTERLEAVE_PERIOD.is_multiple_of(INTERLEAVE_TILES[i]));
        i += 1;
    }
};

/// Which time and lens the bounding box and INTERVAL give a pixel's
/// samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelTuples {
    /// The per-pixel table ([`UvtTables::pixel`]): times and lens positions
    /// jittered within their strata.
    Table,
    /// The Interleave tuple each sample carries, so that grids sampled with
    /// INTERVAL and with Interleave UVT test every sample at the same time
    /// and lens position (Adaptive sampling).
    Interleave,
}

impl PixelTuples {
    /// The tuples of `sampling`'s pixels: Adaptive's agree with Interleave
    /// UVT's, every other mode reads the per-pixel table.
    pub fn for_sampling(sampling: Sampling) -> PixelTuples {
        match sampling {
            Sampling::Adaptive => PixelTuples::Interleave,
            Sampling::Bbox
            | Sampling::Simple
            | Sampling::Interleave
            | Sampling::Interval
            | Sampling::Nearest => PixelTuples::Table,
        }
    }
}

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
/// within coarse lens cell `pairing[s]` (of `k x k`), the UV-T pairing of
/// the per-pixel table. So each slot's `spp` tuples take every coarse time
/// and lens stratum once (Fatahalian et al. 2009), the tile's tuples use
/// every fine time stratum and every fine lens cell once, and the tuples of
/// time stratum `s` lie in INTERVAL's lens box for interval `s`.
fn interleave_tuples(k: u32, tile: u32, pairing: &[u32]) -> Vec<TimeLens> {
    let spp = k * k;
    let slots = tile * tile;
    let fine = k * tile;
    let n = spp * slots;
    (0..n)
        .map(|i| {
            let (s, q) = (i / slots, i % slots);
            let coarse = pairing[s as usize];
            let col = (coarse % k) * tile + q % tile;
            let row = (coarse / k) * tile + q / tile;
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

/// The bounding box, on the unit disk, of lens stratum `(col, row)` of a
/// `k x k` grid on the lens square, grown by [`LENS_BOX_MARGIN`] and
/// clamped to the disk's box: `[lo, hi]`.
///
/// The concentric map is continuous and maps the stratum's inside to the
/// inside of its image, so the image's extremes lie on the image of the
/// stratum's boundary, which is sampled here.
pub fn lens_stratum_box(col: u32, row: u32, k: u32) -> [Vec2; 2] {
    let (a0, b0) = (col as f32 / k as f32, row as f32 / k as f32);
    let (a1, b1) = ((col + 1) as f32 / k as f32, (row + 1) as f32 / k as f32);
    let mut lo = Vec2::INFINITY;
    let mut hi = Vec2::NEG_INFINITY;
    for step in 0..=LENS_BOX_STEPS {
        let f = step as f32 / LENS_BOX_STEPS as f32;
        let (a, b) = (a0 + (a1 - a0) * f, b0 + (b1 - b0) * f);
        for p in [
            concentric_disk(a, b0),
            concentric_disk(a, b1),
            concentric_disk(a0, b),
            concentric_disk(a1, b),
        ] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    [
        (lo - Vec2::splat(LENS_BOX_MARGIN)).max(Vec2::splat(-1.0)),
        (hi + Vec2::splat(LENS_BOX_MARGIN)).min(Vec2::splat(1.0)),
    ]
}

/// The time/lens tables of one sample count and Interleave tile side.
#[derive(Debug, Clone, PartialEq)]
pub struct UvtTables {
    /// Samples per pixel.
    pub spp: u32,
    /// Side, in pixels, of Interleave UVT's tiles (`K`).
    pub tile: u32,
    /// Simple UVT: tuple of sample `s` of every pixel.
    pub simple: Vec<TimeLens>,
    /// Interleave UVT: the `spp * K^2` tuples of a tile.
    pub interleave: Vec<TimeLens>,
    /// Interleave UVT: `inverse[p * N + n]` is the sample of a tile (with
    /// permutation `p`) that carries tuple `n`.
    pub inverse: Vec<u32>,
    /// Interleave UVT: `pixel_slot[(y % PERIOD) * PERIOD + x % PERIOD]` is
    /// the slot whose tuples pixel `(x, y)` takes, for `PERIOD` =
    /// [`INTERLEAVE_PERIOD`].
    pub pixel_slot: Vec<u32>,
    /// Interleave UVT: `slot_sample[q * spp + s]` is the sample index, in its
    /// pixel, of slot `q`'s tuple in time stratum `s` (tuple `s * K^2 + q`).
    pub slot_sample: Vec<u32>,
    /// The inverse of `slot_sample`: `slot_stratum[q * spp + i]` is the time
    /// stratum of the tuple that sample `i` of slot `q`'s pixel carries.
    pub slot_stratum: Vec<u32>,
    /// The UV-T pairing: `pairing[i]` is the lens stratum (`row * k + col`)
    /// of every pixel's sample in time stratum `i`.
    pub pairing: Vec<u32>,
    /// INTERVAL: the box `[lo, hi]` on the unit disk of the lens positions
    /// of the samples in time stratum `i` (lens stratum `pairing[i]`).
    pub interval_lens: Vec<[Vec2; 2]>,
    /// Per-pixel table: entry `(py * TABLE_SIDE + px) * spp + s` is sample
    /// `s` of table pixel `(px, py)`.
    pub pixel: Vec<TimeLens>,
    /// Per-pixel table: which sample of the pixel has its time in stratum
    /// `s` (same indexing as `pixel`).
    pub sample_in_stratum: Vec<u32>,
}

impl UvtTables {
    /// Builds the tables for `spp` (a perfect square) samples per pixel and
    /// Interleave tiles of `tile` pixels a side (one of [`INTERLEAVE_TILES`]).
    pub fn new(spp: u32, tile: u32) -> UvtTables {
        debug_assert!(INTERLEAVE_TILES.contains(&tile), "Interleave tile {tile}");
        let k = grid_size(spp);
        let slots = tile * tile;
        let tuples = spp * slots;
        // Tuple n = s * K^2 + q belongs to pixel slot q; its sample index in
        // the pixel is a fixed per-slot permutation of s, so that a sample's
        // screen stratum is not tied to its time stratum.
        let slot_sample: Vec<u32> = (0..slots)
            .flat_map(|q| permutation(spp, [q, 1, 5]))
            .collect();
        let mut slot_stratum = vec![0; slot_sample.len()];
        for (i, &sample) in slot_sample.iter().enumerate() {
            // Entry i is slot i / spp's sample of stratum i % spp.
            slot_stratum[i - i % spp as usize + sample as usize] = i as u32 % spp;
        }
        let mut inverse = Vec::with_capacity((INTERLEAVE_PERMUTATIONS * tuples) as usize);
        let mut slot_of_pixel = vec![0; (INTERLEAVE_PERMUTATIONS * slots) as usize];
        for p in 0..INTERLEAVE_PERMUTATIONS {
            // Only the pixel offsets are permuted: each pixel keeps one
            // slot's stratified tuples.
            let pixel_of_slot = permutation(slots, [p, 1, 1]);
            for (q, &pixel) in pixel_of_slot.iter().enumerate() {
                slot_of_pixel[(p * slots + pixel) as usize] = q as u32;
            }
            for s in 0..spp {
                for q in 0..slots {
                    inverse.push(
                        pixel_of_slot[q as usize] * spp + slot_sample[(q * spp + s) as usize],
                    );
                }
            }
        }
        let pixel_slot = (0..INTERLEAVE_PERIOD * INTERLEAVE_PERIOD)
            .map(|i| {
                let (x, y) = (i % INTERLEAVE_PERIOD, i / INTERLEAVE_PERIOD);
                let p = Self::tile_permutation(x / tile, y / tile, tile);
                slot_of_pixel[(p * slots + (y % tile) * tile + x % tile) as usize]
            })
            .collect();
        let pairing = permutation(spp, [0, 0, 8]);
        let interval_lens = pairing
            .iter()
            .map(|&lens| lens_stratum_box(lens % k, lens / k, k))
            .collect();
        let mut pixel = Vec::with_capacity((TABLE_SIDE * TABLE_SIDE * spp) as usize);
        let mut sample_in_stratum = Vec::with_capacity(pixel.capacity());
        for py in 0..TABLE_SIDE {
            for px in 0..TABLE_SIDE {
                let times = permutation(spp, [px, py, 2]);
                let mut inverse_times = vec![0; spp as usize];
                for s in 0..spp {
                    let stratum = times[s as usize];
                    inverse_times[stratum as usize] = s;
                    let lens = pairing[stratum as usize];
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
            tile,
            simple: stratified_tuples(k, 5),
            interleave: interleave_tuples(k, tile, &pairing),
            inverse,
            pixel_slot,
            slot_sample,
            slot_stratum,
            pairing,
            interval_lens,
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

    /// The permutation tile `(tx, ty)` of Interleave UVT with tiles of
    /// `tile` pixels a side uses (tiles counted in absolute pixel
    /// coordinates; the choice repeats every [`INTERLEAVE_PERIOD`] pixels).
    pub fn tile_permutation(tx: u32, ty: u32, tile: u32) -> u32 {
        let period = INTERLEAVE_PERIOD / tile;
        hash(tx % period, ty % period, 0, PERMUTATION_CHANNEL) % INTERLEAVE_PERMUTATIONS
    }

    /// The sample of tile `(tx, ty)` that carries Interleave tuple `n`: its
    /// pixel and its sample index in that pixel.
    pub fn interleave_sample(&self, tx: u32, ty: u32, n: u32) -> (u32, u32, u32) {
        let p = Self::tile_permutation(tx, ty, self.tile);
        let j = self.inverse[(p * self.interleave_tuples() + n) as usize];
        let q = j / self.spp;
        (
            tx * self.tile + q % self.tile,
            ty * self.tile + q / self.tile,
            j % self.spp,
        )
    }

    /// The Interleave slot of pixel `(x, y)`: the slot whose tuples its
    /// tile gives it.
    pub fn interleave_slot(&self, x: u32, y: u32) -> u32 {
        let period = INTERLEAVE_PERIOD;
        self.pixel_slot[((y % period) * period + x % period) as usize]
    }

    /// The time and lens of sample `s` of pixel `(x, y)` for the bounding
    /// box and INTERVAL.
    pub fn pixel_tuple(&self, tuples: PixelTuples, x: u32, y: u32, s: u32) -> TimeLens {
        match tuples {
            PixelTuples::Table => self.pixel[self.pixel_index(x, y, s)],
            PixelTuples::Interleave => {
                let q = self.interleave_slot(x, y);
                let stratum = self.slot_stratum[(q * self.spp + s) as usize];
                self.interleave[(stratum * self.tile * self.tile + q) as usize]
            }
        }
    }

    /// The sample of pixel `(x, y)` whose time lies in stratum `i`, which
    /// INTERVAL tests for time interval `i`.
    pub fn pixel_sample_in_stratum(&self, tuples: PixelTuples, x: u32, y: u32, i: u32) -> u32 {
        match tuples {
            PixelTuples::Table => self.sample_in_stratum[self.pixel_index(x, y, i)],
            PixelTuples::Interleave => {
                self.slot_sample[(self.interleave_slot(x, y) * self.spp + i) as usize]
            }
        }
    }

    /// The tables as the GPU reads them, `vec4<f32>` records in the order
    /// simple, interleave, INTERVAL lens boxes, pixel (`t, lens.x, lens.y, 0`
    /// for the tuples; `lo.x, lo.y, hi.x, hi.y` for the boxes; `t, lens.x,
    /// lens.y, sample_in_stratum` for the pixel table), then the interleave
    /// inverses, the pixels' slots, `slot_sample` and `slot_stratum`
    /// as `f32` (exact: they are below 2^24). Offsets are in
    /// [`UvtTables::layout`].
    pub fn to_floats(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.layout().floats as usize);
        for tuple in self.simple.iter().chain(&self.interleave) {
            out.extend([tuple.t, tuple.lens.x, tuple.lens.y, 0.0]);
        }
        for [lo, hi] in &self.interval_lens {
            out.extend([lo.x, lo.y, hi.x, hi.y]);
        }
        for (tuple, &s) in self.pixel.iter().zip(&self.sample_in_stratum) {
            out.extend([tuple.t, tuple.lens.x, tuple.lens.y, s as f32]);
        }
        out.extend(self.inverse.iter().map(|&j| j as f32));
        out.extend(self.pixel_slot.iter().map(|&q| q as f32));
        out.extend(self.slot_sample.iter().map(|&s| s as f32));
        out.extend(self.slot_stratum.iter().map(|&i| i as f32));
        out
    }

    /// Where each table starts in [`UvtTables::to_floats`], in floats.
    pub fn layout(&self) -> UvtLayout {
        UvtLayout::new(self.spp, self.tile)
    }
}

/// Offsets, in floats, of the tables in [`UvtTables::to_floats`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UvtLayout {
    /// Simple UVT tuples.
    pub simple: u32,
    /// Interleave UVT tuples.
    pub interleave: u32,
    /// INTERVAL's lens box per time stratum.
    pub interval_lens: u32,
    /// The per-pixel table.
    pub pixel: u32,
    /// Interleave inverse permutations.
    pub inverse: u32,
    /// [`UvtTables::pixel_slot`].
    pub pixel_slot: u32,
    /// [`UvtTables::slot_sample`].
    pub slot_sample: u32,
    /// [`UvtTables::slot_stratum`].
    pub slot_stratum: u32,
    /// Total floats.
    pub floats: u32,
}

impl UvtLayout {
    /// The layout of the tables for `spp` samples per pixel and Interleave
    /// tiles of `tile` pixels a side, without building them (buffer sizing
    /// needs only this).
    pub fn new(spp: u32, tile: u32) -> UvtLayout {
        let tuples = spp * tile * tile;
        let simple = 0;
        let interleave = simple + 4 * spp;
        let interval_lens = interleave + 4 * tuples;
        let pixel = interval_lens + 4 * spp;
        let inverse = pixel + 4 * TABLE_SIDE * TABLE_SIDE * spp;
        let pixel_slot = inverse + INTERLEAVE_PERMUTATIONS * tuples;
        let slot_sample = pixel_slot + INTERLEAVE_PERIOD * INTERLEAVE_PERIOD;
        let slot_stratum = slot_sample + tuples;
        UvtLayout {
            simple,
            interleave,
            interval_lens,
            pixel,
            inverse,
            pixel_slot,
            slot_sample,
            slot_stratum,
            floats: slot_stratum + tuples,
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
            let tables = UvtTables::new(spp, 2);
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
            let tables = UvtTables::new(spp, tile);
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
        // Over a 32 x 32 patch of tiles, nearly every one of the 64
        // permutations is picked (a hash modulo 64 over 1024 tiles).
        let perms: std::collections::HashSet<u32> = (0..1024)
            .map(|i| UvtTables::tile_permutation(i % 32, i / 32, 2))
            .collect();
        assert!(
            perms.len() >= 60,
            "tiles use only {} permutations",
            perms.len()
        );
    }

    /// INTERVAL's UV-T pairing: in every pixel, the sample of time stratum
    /// `i` lies in lens stratum `pairing[i]`, inside its interval's lens
    /// box, and the boxes are much smaller than the lens (with the boxes
    /// of the whole disk, INTERVAL with a lens alone tests what the
    /// bounding box does).
    #[test]
    fn every_pixel_pairs_time_and_lens_strata_inside_the_interval_boxes() {
        for spp in [1, 4, 16, 64] {
            let tables = UvtTables::new(spp, 2);
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
        let tables = UvtTables::new(16, 2);
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
        for (spp, tile) in [1, 4, 16, 64]
            .into_iter()
            .flat_map(|spp| INTERLEAVE_TILES.map(|k| (spp, k)))
        {
            let tables = UvtTables::new(spp, tile);
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
        for (spp, tile) in [4, 16, 64]
            .into_iter()
            .flat_map(|spp| INTERLEAVE_TILES.map(|k| (spp, k)))
        {
            let tables = UvtTables::new(spp, tile);
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
}
