//! The CPU side of the subdivision: the escape count and the border walk the
//! WGSL mirrors, each tile's decision, and the whole subdivision (and brute
//! force) the GPU's image and counters are checked against, each under the
//! plain arithmetic or under a driver's [`Contraction`].

use super::{BLOCK_THREADS, Contraction, MIN_SIZE, Magnitude, Tile, UNWRITTEN, View};
#[cfg(doc)]
use super::{BORDER_WGSL, ESCAPE_WGSL, TILE_BODY};

/// The escape count of pixel `(px, py)`: the iterations until `|z| > 2`, at
/// most `max_iter` (the points taken to be in the set). Mirrored by
/// `escape_count` in [`ESCAPE_WGSL`], operation for operation, with nothing
/// fused ([`Contraction::PLAIN`]).
pub fn escape_count(view: &View, px: u32, py: u32) -> u32 {
    escape_count_with(view, px, py, Contraction::PLAIN)
}

/// [`escape_count`] with the multiply-adds `contraction` names fused
/// (`f32::mul_add`, one rounding): the bits a driver that fused them
/// computes.
pub fn escape_count_with(view: &View, px: u32, py: u32, contraction: Contraction) -> u32 {
    let coordinate = |origin: f32, p: u32| {
        if contraction.coordinates {
            (p as f32).mul_add(view.step, origin)
        } else {
            origin + p as f32 * view.step
        }
    };
    let cr = coordinate(view.x0, px);
    let ci = coordinate(view.y0, py);
    let (mut zr, mut zi) = (0.0f32, 0.0f32);
    let mut n = 0;
    let magnitude = |zr: f32, zi: f32| match contraction.magnitude {
        Magnitude::Plain => zr * zr + zi * zi,
        Magnitude::FusedReal => zr.mul_add(zr, zi * zi),
        Magnitude::FusedImaginary => zi.mul_add(zi, zr * zr),
    };
    // `<=`, as in the WGSL: a NaN magnitude ends the loop.
    while n < view.max_iter && magnitude(zr, zi) <= 4.0 {
        let next = if contraction.real {
            (zr - zi).mul_add(zr + zi, cr)
        } else {
            (zr - zi) * (zr + zi) + cr
        };
        zi = if contraction.imaginary {
            (2.0 * zr).mul_add(zi, ci)
        } else {
            2.0 * zr * zi + ci
        };
        zr = next;
        n += 1;
    }
    n
}

/// The `i`-th pixel of `tile`'s border, clockwise from its top-left corner,
/// for `i < 4 (size - 1)`. Mirrored by `border_pixel` in [`BORDER_WGSL`].
pub fn border_pixel(tile: &Tile, i: u32) -> (u32, u32) {
    let e = tile.size - 1;
    let k = i % e;
    let (dx, dy) = match i / e {
        0 => (k, 0),
        1 => (e, k),
        2 => (e - k, e),
        _ => (0, e - k),
    };
    (tile.x + dx, tile.y + dy)
}

/// What one tile does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    /// Fill the square with this count.
    Fill(u32),
    /// Enqueue the four quarters.
    Split,
    /// Hand the square to `Block`.
    Block,
}

/// The decision for one tile, mirrored by [`TILE_BODY`].
pub fn decide(view: &View, tile: &Tile) -> Decision {
    decide_with(view, tile, Contraction::PLAIN)
}

/// [`decide`] with the border's counts under `contraction`.
pub fn decide_with(view: &View, tile: &Tile, contraction: Contraction) -> Decision {
    decision(tile, &border_counts(view, tile, contraction))
}

/// The escape counts of `tile`'s border, in [`border_pixel`] order.
fn border_counts(view: &View, tile: &Tile, contraction: Contraction) -> Vec<u32> {
    (0..4 * (tile.size - 1))
        .map(|i| {
            let (x, y) = border_pixel(tile, i);
            escape_count_with(view, x, y, contraction)
        })
        .collect()
}

/// The decision for a tile whose border has `counts`.
fn decision(tile: &Tile, counts: &[u32]) -> Decision {
    let lo = counts.iter().copied().min();
    let hi = counts.iter().copied().max();
    match lo {
        Some(lo) if Some(lo) == hi => Decision::Fill(lo),
        _ if tile.size > MIN_SIZE => Decision::Split,
        _ => Decision::Block,
    }
}

/// The quarters of a split tile.
pub fn quarters(tile: &Tile) -> [Tile; 4] {
    let half = tile.size / 2;
    [0, 1, 2, 3].map(|k| Tile {
        x: tile.x + half * (k & 1),
        y: tile.y + half * (k >> 1),
        size: half,
    })
}

/// The result of a Mariani–Silver subdivision, and what it took.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Subdivision {
    /// Escape count per pixel, row by row.
    pub counts: Vec<u32>,
    /// Tiles processed (the roots included).
    pub tiles: u64,
    /// Tiles filled from their border.
    pub filled: u64,
    /// Tiles split in four.
    pub split: u64,
    /// Tiles handed to `Block`.
    pub blocks: u64,
    /// Pixels whose escape count was iterated (borders and blocks; a pixel
    /// on several borders counts each time).
    pub escape_pixels: u64,
    /// Their escape counts summed: the iterations of the per-pixel loop.
    pub iterations: u64,
}

/// The CPU reference: the same subdivision, with the same decisions, on an
/// explicit stack.
pub fn cpu_mariani_silver(view: &View) -> Subdivision {
    cpu_mariani_silver_with(view, Contraction::PLAIN)
}

/// [`cpu_mariani_silver`] with every escape count under `contraction`: the
/// decisions depend on the counts, so the tiles and their counters can
/// differ from the plain subdivision's too.
pub fn cpu_mariani_silver_with(view: &View, contraction: Contraction) -> Subdivision {
    let mut out = Subdivision {
        counts: vec![UNWRITTEN; view.pixels()],
        ..Subdivision::default()
    };
    let width = view.width as usize;
    let mut stack = view.roots();
    while let Some(tile) = stack.pop() {
        let border = border_counts(view, &tile, contraction);
        out.tiles += 1;
        out.escape_pixels += border.len() as u64;
        out.iterations += border.iter().map(|&n| u64::from(n)).sum::<u64>();
        match decision(&tile, &border) {
            Decision::Fill(n) => {
                for y in tile.y..tile.y + tile.size {
                    let row = y as usize * width;
                    out.counts[row + tile.x as usize..row + (tile.x + tile.size) as usize].fill(n);
                }
                out.filled += 1;
            }
            Decision::Split => {
                stack.extend(quarters(&tile));
                out.split += 1;
            }
            Decision::Block => {
                for y in tile.y..tile.y + MIN_SIZE {
                    for x in tile.x..tile.x + MIN_SIZE {
                        let n = escape_count_with(view, x, y, contraction);
                        out.counts[y as usize * width + x as usize] = n;
                        out.iterations += u64::from(n);
                    }
                }
                out.blocks += 1;
                out.escape_pixels += u64::from(BLOCK_THREADS);
            }
        }
    }
    out
}

/// Every pixel's escape count, computed directly.
pub fn cpu_brute_force(view: &View) -> Vec<u32> {
    cpu_brute_force_with(view, Contraction::PLAIN)
}

/// [`cpu_brute_force`] under `contraction`.
pub fn cpu_brute_force_with(view: &View, contraction: Contraction) -> Vec<u32> {
    (0..view.height)
        .flat_map(|y| (0..view.width).map(move |x| (x, y)))
        .map(|(x, y)| escape_count_with(view, x, y, contraction))
        .collect()
}
