//! Screen tiles: [`plan_tiles`] splits a frame whose sample framebuffer
//! exceeds the device's limits into [`Tile`]s.

/// Screen tiles start at multiples of this many pixels. The renderer's
/// per-pixel 5D sample table repeats every [`crate::uvt::TABLE_SIDE`] (64)
/// pixels, indexed by the pixel coordinates of the frame being rendered; a
/// tile whose origin is a multiple of it gives every pixel the samples it
/// has in the untiled frame, so tiling changes the image only through
/// float rounding. The jitter, and Interleave UVT's tiles and their
/// permutations, follow absolute pixel coordinates
/// ([`crate::camera::Camera::origin`]).
pub const TILE_ALIGN: u32 = 64;
const _: () = assert!(
    TILE_ALIGN.is_multiple_of(crate::uvt::TABLE_SIDE),
    "tile origins must keep the sample tables' period"
);

/// A screen tile: the pixels `[x0, x0 + width) x [y0, y0 + height)` of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl Tile {
    /// The tile grown by `margin` pixels on every side (`[columns, rows]`),
    /// clipped to a `width x height` image: what a tile renders so that a
    /// pixel filter reaching `margin` pixels finds every sample of its
    /// window.
    pub fn expanded(&self, margin: [u32; 2], width: u32, height: u32) -> Tile {
        let x0 = self.x0.saturating_sub(margin[0]);
        let y0 = self.y0.saturating_sub(margin[1]);
        let x1 = (self.x0 + self.width).saturating_add(margin[0]).min(width);
        let y1 = (self.y0 + self.height)
            .saturating_add(margin[1])
            .min(height);
        Tile {
            x0,
            y0,
            width: x1 - x0,
            height: y1 - y0,
        }
    }

    /// Its pixels.
    pub fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }
}

/// [`plan_tiles`] for tiles that render `margin` pixels beyond their edges
/// ([`Tile::expanded`]): each expanded tile holds at most `max_pixels`. The
/// tiles are planned for a smaller budget until their margins fit (at most
/// 64 times, each by an eighth). `None` when no plan fits.
pub fn plan_tiles_with_margin(
    width: u32,
    height: u32,
    max_pixels: u64,
    margin: [u32; 2],
) -> Option<Vec<Tile>> {
    let mut budget = max_pixels;
    for _ in 0..64 {
        let tiles = plan_tiles(width, height, budget)?;
        if tiles
            .iter()
            .all(|t| t.expanded(margin, width, height).pixels() <= max_pixels)
        {
            return Some(tiles);
        }
        budget -= (budget / 8).max(1);
    }
    None
}

/// Splits a `width x height` image into screen tiles of at most
/// `max_pixels` pixels each, row by row from the top left.
///
/// One tile covers the whole image when it fits. Otherwise tile origins are
/// multiples of [`TILE_ALIGN`] and the tiles are full-width bands of rows
/// when a band of [`TILE_ALIGN`] rows fits (one band spans every column, so
/// patches are bound and culled against fewer tiles), else tiles about as
/// wide as they are high; either way the tile size is then evened out so
/// that the last row or column of tiles is not much smaller than the others.
/// Tiles at the right and bottom edges are clipped to the image.
///
/// `None` when even the smallest aligned tile, `min(width, 64) x
/// min(height, 64)` pixels, exceeds `max_pixels`.
pub fn plan_tiles(width: u32, height: u32, max_pixels: u64) -> Option<Vec<Tile>> {
    let (w, h) = (u64::from(width), u64::from(height));
    if w * h <= max_pixels {
        return Some(vec![Tile {
            x0: 0,
            y0: 0,
            width,
            height,
        }]);
    }
    let align = u64::from(TILE_ALIGN);
    if w.min(align) * h.min(align) > max_pixels {
        return None;
    }
    let down = |n: u64| n / align * align;
    // In every branch the side that is smaller than its extent is a
    // positive multiple of `align` (see the checks above), so evening out
    // below keeps the tiles within `max_pixels`.
    let rows = down(max_pixels / w);
    let (tile_w, tile_h) = if rows >= align {
        (w, rows)
    } else if h <= align {
        // Too few rows for aligned bands: columns of the full height.
        (down(max_pixels / h), h)
    } else {
        // The largest aligned square that fits, widened to use the budget.
        let side = down(max_pixels.isqrt()).max(align);
        (down(max_pixels / side), side)
    };
    // The smallest aligned size that needs no more tiles than `tile`.
    let even = |extent: u64, tile: u64| {
        if tile >= extent {
            extent
        } else {
            let count = extent.div_ceil(tile);
            extent.div_ceil(count).div_ceil(align) * align
        }
    };
    let (tile_w, tile_h) = (even(w, tile_w), even(h, tile_h));
    let mut tiles = Vec::new();
    for y0 in (0..h).step_by(tile_h as usize) {
        for x0 in (0..w).step_by(tile_w as usize) {
            // Every value is at most `width` or `height`, so these fit u32.
            tiles.push(Tile {
                x0: x0 as u32,
                y0: y0 as u32,
                width: tile_w.min(w - x0) as u32,
                height: tile_h.min(h - y0) as u32,
            });
        }
    }
    Some(tiles)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks that `tiles` cover the image exactly once, start at aligned
    /// origins and each hold at most `max_pixels` pixels.
    fn check_tiling(width: u32, height: u32, max_pixels: u64, tiles: &[Tile]) {
        let mut covered = vec![0u8; width as usize * height as usize];
        for tile in tiles {
            assert!(tile.width > 0 && tile.height > 0, "{tile:?}");
            assert!(
                u64::from(tile.width) * u64::from(tile.height) <= max_pixels,
                "{width}x{height}, {max_pixels}: {tile:?}"
            );
            if tiles.len() > 1 {
                assert!(tile.x0.is_multiple_of(TILE_ALIGN), "{tile:?}");
                assert!(tile.y0.is_multiple_of(TILE_ALIGN), "{tile:?}");
            }
            assert!(tile.x0 + tile.width <= width && tile.y0 + tile.height <= height);
            for y in tile.y0..tile.y0 + tile.height {
                for x in tile.x0..tile.x0 + tile.width {
                    covered[(y * width + x) as usize] += 1;
                }
            }
        }
        assert!(
            covered.iter().all(|&c| c == 1),
            "{width}x{height}, {max_pixels}: {tiles:?}"
        );
    }

    #[test]
    fn a_frame_that_fits_is_one_tile() {
        let tiles = plan_tiles(800, 600, 800 * 600).unwrap();
        assert_eq!(
            tiles,
            [Tile {
                x0: 0,
                y0: 0,
                width: 800,
                height: 600
            }]
        );
    }

    #[test]
    fn bands_are_preferred_and_evened_out() {
        // 1920x1080 at 64 spp under lavapipe's 128 MiB: 2^24 samples per tile.
        let tiles = plan_tiles(1920, 1080, (1 << 24) / 64).unwrap();
        check_tiling(1920, 1080, (1 << 24) / 64, &tiles);
        assert_eq!(tiles.len(), 9);
        assert!(tiles.iter().all(|t| t.x0 == 0 && t.width == 1920));
        // 800x600 at 64 spp: two bands (320 + 280 rows), not 320 + 256 + 24.
        let tiles = plan_tiles(800, 600, (1 << 24) / 64).unwrap();
        check_tiling(800, 600, (1 << 24) / 64, &tiles);
        let heights: Vec<u32> = tiles.iter().map(|t| t.height).collect();
        assert_eq!(heights, [320, 280]);
    }

    #[test]
    fn narrow_budgets_give_square_ish_tiles() {
        // 200x150 with room for 8192 pixels: no band of 64 rows fits.
        let tiles = plan_tiles(200, 150, 8192).unwrap();
        check_tiling(200, 150, 8192, &tiles);
        assert_eq!(tiles.len(), 6);
        assert!(tiles.iter().any(|t| !t.width.is_multiple_of(TILE_ALIGN)));
        assert!(tiles.iter().any(|t| !t.height.is_multiple_of(TILE_ALIGN)));
        // A short, wide image is cut into columns of its full height.
        let tiles = plan_tiles(10_000, 3, 1000).unwrap();
        check_tiling(10_000, 3, 1000, &tiles);
        assert!(tiles.iter().all(|t| t.y0 == 0 && t.height == 3));
    }

    #[test]
    fn impossible_budgets_are_refused() {
        assert_eq!(plan_tiles(200, 150, 64 * 64 - 1), None);
        assert_eq!(plan_tiles(10_000, 1, 63), None);
        assert_eq!(plan_tiles(30, 10_000, 30 * 64 - 1), None);
        assert!(plan_tiles(30, 10_000, 30 * 64).is_some());
    }

    #[test]
    fn random_plans_cover_the_image() {
        let mut state = 0x853c_49e6_748f_ea9bu64;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % n
        };
        for _ in 0..300 {
            let width = 1 + next(700) as u32;
            let height = 1 + next(700) as u32;
            let max_pixels = 1 + next(u64::from(width) * u64::from(height) + 5000);
            match plan_tiles(width, height, max_pixels) {
                Some(tiles) => check_tiling(width, height, max_pixels, &tiles),
                None => assert!(
                    u64::from(width.min(TILE_ALIGN)) * u64::from(height.min(TILE_ALIGN))
                        > max_pixels
                ),
            }
        }
    }
}
