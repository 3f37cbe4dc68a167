//! [`UvtTables`]: the time/lens tables of one sample count and Interleave
//! tiling, built on the host, and the lookups both renderers make in them.

use glam::Vec2;

use crate::sampling::{grid_size, hash};

use super::tuples::{interleave_tuples, permutation, stratified_tuples, unit};
use super::{
    INTERLEAVE_TILES, InterleaveTiles, MAX_INTERLEAVE_PERMUTATIONS, PixelTuples, TABLE_SIDE,
    TimeLens, concentric_disk, lens_stratum_box,
};

/// The time/lens tables of one sample count and Interleave tiling.
#[derive(Debug, Clone, PartialEq)]
pub struct UvtTables {
    /// Samples per pixel.
    pub spp: u32,
    /// Interleave UVT's tiles over the image (their side `K`) and the
    /// permutation each takes.
    pub tiles: InterleaveTiles,
    /// Simple UVT: tuple of sample `s` of every pixel.
    pub simple: Vec<TimeLens>,
    /// Interleave UVT: the `spp * K^2` tuples of a tile.
    pub interleave: Vec<TimeLens>,
    /// Interleave UVT: `inverse[p * N + n]` is the sample of a tile (with
    /// permutation `p`) that carries tuple `n`.
    pub inverse: Vec<u32>,
    /// Interleave UVT: `slot_of_pixel[p * K^2 + (y % K) * K + x % K]` is
    /// the slot whose tuples pixel `(x, y)` takes in a tile with
    /// permutation `p` (the inverse of the permutation's pixel offsets).
    pub slot_of_pixel: Vec<u32>,
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
    /// Interleave `tiles` (of a side in [`INTERLEAVE_TILES`], with 1 to
    /// [`MAX_INTERLEAVE_PERMUTATIONS`] permutations).
    pub fn new(spp: u32, tiles: InterleaveTiles) -> UvtTables {
        UvtTables::seeded(spp, tiles, 0)
    }

    /// The tables of [`UvtTables::new`] with the per-pixel table's times
    /// and lens positions drawn for `seed` (a frame's number): seed 0 gives
    /// the tables of `new`, another seed other pseudo-random orders and
    /// jitter, equally stratified, so that successive frames of a sequence
    /// do not repeat one noise pattern. The table's pixel `(px, py)` takes
    /// the hashes of the pixel `(px + seed * TABLE_SIDE, py)` of a wider
    /// table. The Simple and Interleave tuples are the same for every seed.
    pub fn seeded(spp: u32, tiles: InterleaveTiles, seed: u32) -> UvtTables {
        let InterleaveTiles {
            tile, permutations, ..
        } = tiles;
        debug_assert!(INTERLEAVE_TILES.contains(&tile), "Interleave tile {tile}");
        debug_assert!(
            (1..=MAX_INTERLEAVE_PERMUTATIONS).contains(&permutations),
            "Interleave permutations {permutations}"
        );
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
        let mut inverse = Vec::with_capacity((permutations * tuples) as usize);
        let mut slot_of_pixel = vec![0; (permutations * slots) as usize];
        for p in 0..permutations {
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
        let pairing = permutation(spp, [0, 0, 8]);
        let interval_lens = pairing
            .iter()
            .map(|&lens| lens_stratum_box(lens % k, lens / k, k))
            .collect();
        let mut pixel = Vec::with_capacity((TABLE_SIDE * TABLE_SIDE * spp) as usize);
        let mut sample_in_stratum = Vec::with_capacity(pixel.capacity());
        for py in 0..TABLE_SIDE {
            for px in 0..TABLE_SIDE {
                let hx = px.wrapping_add(seed.wrapping_mul(TABLE_SIDE));
                let times = permutation(spp, [hx, py, 2]);
                let mut inverse_times = vec![0; spp as usize];
                for s in 0..spp {
                    let stratum = times[s as usize];
                    inverse_times[stratum as usize] = s;
                    let lens = pairing[stratum as usize];
                    let jitter = |c| unit(hash(hx, py, s, c));
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
            tiles,
            simple: stratified_tuples(k, 5),
            interleave: interleave_tuples(k, tile, &pairing),
            inverse,
            slot_of_pixel,
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

    /// The sample of tile `(tx, ty)` that carries Interleave tuple `n`: its
    /// pixel and its sample index in that pixel.
    pub fn interleave_sample(&self, tx: u32, ty: u32, n: u32) -> (u32, u32, u32) {
        let p = self.tiles.permutation(tx, ty);
        let j = self.inverse[(p * self.interleave_tuples() + n) as usize];
        let (q, tile) = (j / self.spp, self.tiles.tile);
        (tx * tile + q % tile, ty * tile + q / tile, j % self.spp)
    }

    /// The Interleave slot of pixel `(x, y)`: the slot whose tuples its
    /// tile gives it under the tile's permutation.
    pub fn interleave_slot(&self, x: u32, y: u32) -> u32 {
        let tile = self.tiles.tile;
        let p = self.tiles.permutation(x / tile, y / tile);
        self.slot_of_pixel[(p * tile * tile + (y % tile) * tile + x % tile) as usize]
    }

    /// The time and lens of sample `s` of pixel `(x, y)` for the bounding
    /// box and INTERVAL.
    pub fn pixel_tuple(&self, tuples: PixelTuples, x: u32, y: u32, s: u32) -> TimeLens {
        match tuples {
            PixelTuples::Table => self.pixel[self.pixel_index(x, y, s)],
            PixelTuples::Interleave => {
                let (q, tile) = (self.interleave_slot(x, y), self.tiles.tile);
                let stratum = self.slot_stratum[(q * self.spp + s) as usize];
                self.interleave[(stratum * tile * tile + q) as usize]
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
}
