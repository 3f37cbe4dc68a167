//! The tables as the GPU reads them: one `f32` buffer
//! ([`UvtTables::to_floats`]) and the offsets of its tables ([`UvtLayout`]).

use super::{TABLE_SIDE, UvtTables};

impl UvtTables {
    /// The tables as the GPU reads them, `vec4<f32>` records in the order
    /// simple, interleave, INTERVAL lens boxes, pixel (`t, lens.x, lens.y, 0`
    /// for the tuples; `lo.x, lo.y, hi.x, hi.y` for the boxes; `t, lens.x,
    /// lens.y, sample_in_stratum` for the pixel table), then the interleave
    /// inverses, `slot_of_pixel`, `slot_sample` and `slot_stratum`
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
        out.extend(self.slot_of_pixel.iter().map(|&q| q as f32));
        out.extend(self.slot_sample.iter().map(|&s| s as f32));
        out.extend(self.slot_stratum.iter().map(|&i| i as f32));
        out
    }

    /// Where each table starts in [`UvtTables::to_floats`], in floats.
    pub fn layout(&self) -> UvtLayout {
        UvtLayout::new(self.spp, self.tiles.tile, self.tiles.permutations)
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
    /// [`UvtTables::slot_of_pixel`].
    pub slot_of_pixel: u32,
    /// [`UvtTables::slot_sample`].
    pub slot_sample: u32,
    /// [`UvtTables::slot_stratum`].
    pub slot_stratum: u32,
    /// Total floats.
    pub floats: u32,
}

impl UvtLayout {
    /// The layout of the tables for `spp` samples per pixel and Interleave
    /// tiles of `tile` pixels a side with `permutations` permutations,
    /// without building them (buffer sizing needs only this).
    pub fn new(spp: u32, tile: u32, permutations: u32) -> UvtLayout {
        let tuples = spp * tile * tile;
        let simple = 0;
        let interleave = simple + 4 * spp;
        let interval_lens = interleave + 4 * tuples;
        let pixel = interval_lens + 4 * spp;
        let inverse = pixel + 4 * TABLE_SIDE * TABLE_SIDE * spp;
        let slot_of_pixel = inverse + permutations * tuples;
        let slot_sample = slot_of_pixel + permutations * tile * tile;
        let slot_stratum = slot_sample + tuples;
        UvtLayout {
            simple,
            interleave,
            interval_lens,
            pixel,
            inverse,
            slot_of_pixel,
            slot_sample,
            slot_stratum,
            floats: slot_stratum + tuples,
        }
    }
}
