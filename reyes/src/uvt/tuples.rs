//! Time/lens tuples and the permutations that pair and place them: the
//! hashed permutations, Simple UVT's stratified tuples and the tuples of an
//! Interleave UVT tile.

use glam::Vec2;

use crate::sampling::hash;

use super::concentric_disk;

/// A time and a lens position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeLens {
    /// Time in `[0, 1)`, from shutter open to close.
    pub t: f32,
    /// Lens position in the unit disk.
    pub lens: Vec2,
}

/// A uniform float in `[0, 1)` from a hash.
pub(super) fn unit(h: u32) -> f32 {
    // 24 bits: exactly representable, and never rounds up to 1.
    (h >> 8) as f32 / 16_777_216.0
}

/// A pseudo-random permutation of `0..n` (Fisher-Yates driven by the hash).
pub(super) fn permutation(n: u32, key: [u32; 3]) -> Vec<u32> {
    let mut p: Vec<u32> = (0..n).collect();
    for i in (1..n).rev() {
        let j = hash(key[0], key[1], key[2] * 4096 + i, 9) % (i + 1);
        p.swap(i as usize, j as usize);
    }
    p
}

/// `n = m * m` tuples: tuple `i` has the centre of time stratum `i` and the
/// centre of lens stratum `π(i)` of an `m x m` grid.
pub(super) fn stratified_tuples(m: u32, key: u32) -> Vec<TimeLens> {
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
pub(super) fn interleave_tuples(k: u32, tile: u32, pairing: &[u32]) -> Vec<TimeLens> {
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
