//! The WGSL of the two procedures: the shared per-pixel function and border
//! walk, and the bodies of `Tile` and `Block`.

#[cfg(doc)]
use super::Contraction;

/// The per-pixel function, shared by both procedures (and by the flat
/// dispatch the benchmark compares with). A driver may fuse its
/// multiply-adds; the checks find out which ([`Contraction`]).
pub const ESCAPE_WGSL: &str = "
fn escape_count(px: u32, py: u32) -> u32 {
    let cr = X0 + f32(px) * STEP;
    let ci = Y0 + f32(py) * STEP;
    var zr = 0.0f;
    var zi = 0.0f;
    var n = 0u;
    while (n < MAX_ITER && zr * zr + zi * zi <= 4.0f) {
        // Not zr * zr - zi * zi + cr, which lavapipe reassociates.
        let next = (zr - zi) * (zr + zi) + cr;
        zi = 2.0f * zr * zi + ci;
        zr = next;
        n += 1u;
    }
    return n;
}
";

/// The border walk of `Tile`.
pub const BORDER_WGSL: &str = "
// The i-th pixel of the tile's border, clockwise from its top-left corner.
fn border_pixel(tile: Tile, i: u32) -> vec2<u32> {
    let e = tile.size - 1u;
    let k = i % e;
    var d: vec2<u32>;
    switch (i / e) {
        case 0u: { d = vec2<u32>(k, 0u); }
        case 1u: { d = vec2<u32>(e, k); }
        case 2u: { d = vec2<u32>(e - k, e); }
        default: { d = vec2<u32>(0u, e - k); }
    }
    return vec2<u32>(tile.x, tile.y) + d;
}
";

/// The body of `Tile`. Scratch holds each thread's (min, max) over its share
/// of the border; after the barrier (at the top level, reached by every
/// thread) all threads of the item read all of them, so they agree on the
/// decision without a second barrier.
pub const TILE_BODY: &str = "
var lo = 0xffffffffu;
var hi = 0u;
if (valid) {
    for (var i = thread; i < 4u * (item.size - 1u); i += TILE_THREADS) {
        let p = border_pixel(item, i);
        let n = escape_count(p.x, p.y);
        lo = min(lo, n);
        hi = max(hi, n);
    }
    scratch_store_u32(slot, 2u * thread, lo);
    scratch_store_u32(slot, 2u * thread + 1u, hi);
}
workgroupBarrier();
if (valid) {
    for (var t = 0u; t < TILE_THREADS; t += 1u) {
        lo = min(lo, scratch_load_u32(slot, 2u * t));
        hi = max(hi, scratch_load_u32(slot, 2u * t + 1u));
    }
    if (lo == hi) {
        // One count all around: fill the square with it.
        for (var i = thread; i < item.size * item.size; i += TILE_THREADS) {
            counts[(item.y + i / item.size) * WIDTH + item.x + i % item.size] = lo;
        }
    } else if (item.size > MIN_SIZE) {
        // Split in four, one child per thread.
        if (thread < 4u) {
            let half = item.size / 2u;
            enqueue_Tile(Tile(item.x + half * (thread & 1u), item.y + half * (thread >> 1u), half));
        }
    } else if (thread == 0u) {
        enqueue_Block(Block(item.x, item.y));
    }
}
";

/// The body of `Block`: one pixel per thread.
pub const BLOCK_BODY: &str = "
if (valid) {
    let x = item.x + thread % MIN_SIZE;
    let y = item.y + thread / MIN_SIZE;
    counts[y * WIDTH + x] = escape_count(x, y);
}
";
