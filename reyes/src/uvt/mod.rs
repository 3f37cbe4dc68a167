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
//!   to its pixel `ρ_p(q)` (row-major), where `p`
//!   ([`InterleaveTiles::permutation`]) picks one of `P` precomputed
//!   permutations of the pixel offsets per tile (`P` =
//!   [`DEFAULT_INTERLEAVE_PERMUTATIONS`] unless the scene says otherwise),
//!   by Sattlecker and Steinberger's rule (their equations 2 and 3):
//!   `tilenumber = ty * (width / K) + tx`, `p = (tilenumber + tx + ty) mod
//!   P`. This breaks the repetition of the pattern while every pixel stays
//!   stratified; `P = 1` gives every tile the same pattern. The table
//!   stores, for a tuple, which sample `j` of the tile (pixel `j / spp`,
//!   sample `j % spp` of it) carries it. Tiles are counted in absolute
//!   pixel coordinates of the full image, so a screen tile of the renderer
//!   may start anywhere in an Interleave tile.
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
//!
//! The module is cut along its responsibilities: `tuples` (the stratified
//! and Interleave tuples and the permutations behind them), `tiles`
//! (which permutation an Interleave tile takes), `lens` (the
//! concentric disk map and INTERVAL's lens boxes), `tables` (the
//! [`UvtTables`] built from them and their lookups), `layout` (the tables
//! as the GPU reads them). Every public item is re-exported here.

use crate::modes::Sampling;

mod layout;
mod lens;
mod tables;
mod tiles;
mod tuples;

#[cfg(test)]
mod tests;

pub use layout::UvtLayout;
pub use lens::{LENS_BOX_MARGIN, concentric_disk, lens_stratum_box};
pub use tables::UvtTables;
pub use tiles::InterleaveTiles;
pub use tuples::TimeLens;

/// The sides, in pixels, that the tiles of Interleave UVT (`K`) may have:
/// the sizes Fatahalian et al. and Sattlecker and Steinberger measure.
pub const INTERLEAVE_TILES: [u32; 3] = [2, 3, 4];
/// The default side of Interleave UVT's tiles.
pub const DEFAULT_INTERLEAVE_TILE: u32 = 2;
/// Number of precomputed pixel-offset permutations a tile chooses from
/// (`P`) unless the scene sets `interleave_permutations`: 64, as in both
/// papers.
pub const DEFAULT_INTERLEAVE_PERMUTATIONS: u32 = 64;
/// The largest `P` a scene may ask for. Tiles of 2 x 2 pixels have only 24
/// distinct permutations, and the tables grow with `P` (`P * spp * K^2`
/// inverse entries), so more buys nothing.
pub const MAX_INTERLEAVE_PERMUTATIONS: u32 = 256;
/// Side, in pixels, of the per-pixel table, which repeats over the screen.
pub const TABLE_SIDE: u32 = 64;

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
