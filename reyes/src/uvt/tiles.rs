//! [`InterleaveTiles`]: the tiles of Interleave UVT over the full image and
//! the permutation each takes, by Sattlecker and Steinberger's rule.

/// Interleave UVT's tiles over an image: their side, how many permutations
/// of their pixel offsets there are, and how many tiles make a row of the
/// full image, which is all the choice of a tile's permutation needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InterleaveTiles {
    /// Side, in pixels, of a tile (`K`, one of
    /// [`super::INTERLEAVE_TILES`]).
    pub tile: u32,
    /// Number of precomputed permutations (`P`, 1 to
    /// [`super::MAX_INTERLEAVE_PERMUTATIONS`]).
    pub permutations: u32,
    /// Tiles in a row of the full image (`scenewidth / gridsize` of the
    /// published rule), counting a partial last tile, so that
    /// `tilenumber` numbers the tiles one by one whatever the width.
    pub row_tiles: u32,
}

impl InterleaveTiles {
    /// The tiles of side `tile` over an image `image_width` pixels wide
    /// (the full image, not a screen tile of it), choosing among
    /// `permutations` permutations.
    pub fn new(tile: u32, permutations: u32, image_width: u32) -> InterleaveTiles {
        debug_assert!(tile > 0 && permutations > 0, "{tile} {permutations}");
        InterleaveTiles {
            tile,
            permutations,
            row_tiles: image_width.div_ceil(tile),
        }
    }

    /// The permutation tile `(tx, ty)` (counted in absolute pixel
    /// coordinates of the full image) takes: Sattlecker and Steinberger's
    /// equations 2 and 3, `tilenumber = ty * row_tiles + tx` and
    /// `(tilenumber + tx + ty) mod P`. They add `tx + ty` to the tile number
    /// because widths that are multiples of `K * P` would otherwise give
    /// every tile of a column the same permutation. The arithmetic wraps
    /// like the shaders' `u32`, and does not wrap for an image of fewer
    /// than 2^32 pixels.
    pub fn permutation(&self, tx: u32, ty: u32) -> u32 {
        let tilenumber = ty.wrapping_mul(self.row_tiles).wrapping_add(tx);
        tilenumber.wrapping_add(tx).wrapping_add(ty) % self.permutations
    }
}
