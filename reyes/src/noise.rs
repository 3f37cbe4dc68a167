//! RenderMan's `noise` and `snoise`: gradient noise after Perlin's
//! "improved noise" (2002), in one to four dimensions, and the
//! vector-valued `point noise` ([`vnoise3`]).
//!
//! * Every `noise*` returns a value in `[0, 1]`, exactly `0.5` at the
//!   integer lattice points; `snoise* = 2 noise* - 1` is in `[-1, 1]`.
//! * The noise is deterministic (one fixed permutation table,
//!   [`PERMUTATION`]) and periodic with period 256 along every axis:
//!   `noise3(p + 256 e) == noise3(p)` for any axis `e`, as long as the sum
//!   is exact in `f32`.
//! * Any finite input is accepted, of any magnitude: the lattice cell is
//!   reduced modulo 256 in floating point without a conversion that could
//!   overflow. Non-finite inputs give an unspecified value (NaN here).
//!
//! The GPU twin is `shaders/reyes/library_noise.wgsl`, the same
//! arithmetic in the same order; [`noise_wgsl`] prefixes it with the
//! permutation table generated from [`PERMUTATION`], so the two share one
//! table.
//!
//! The raw gradient sums are divided by their largest possible magnitude
//! over all gradient choices (the `*_BOUND` constants, checked by the
//! tests), so the results stay inside `[0, 1]` without depending on the
//! table; the final clamp only absorbs rounding.

use glam::{UVec3, Vec2, Vec3};

/// The permutation of `0..256` that hashes lattice points: Fisher-Yates
/// driven by SplitMix64 from a fixed seed (so it is generated, not a
/// pasted table, and the WGSL twin is generated from it too).
pub const PERMUTATION: [u8; 256] = permutation(0x005E_ED0F_A11F_1E1D);

/// `PERMUTATION` shuffled from `seed`.
const fn permutation(seed: u64) -> [u8; 256] {
    let mut table = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        table[i] = i as u8;
        i += 1;
    }
    let mut state = seed;
    let mut i = 255;
    while i > 0 {
        // SplitMix64.
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let j = (z % (i as u64 + 1)) as usize;
        let t = table[i];
        table[i] = table[j];
        table[j] = t;
        i -= 1;
    }
    table
}

/// The largest `|sum|` of the 1D gradient sum: gradients are at most 1
/// long, and `(1 - s) x + s (1 - x)` (with `s` the fade of `x`) peaks at
/// `x = 0.5`.
pub const NOISE1_BOUND: f32 = 0.5;
/// The largest `|sum|` in 2D: the gradients' components are in
/// `{-1, 0, 1}`, so each corner contributes at most the L1 norm of its
/// offset, and the weighted sum peaks at the cell's centre.
pub const NOISE2_BOUND: f32 = 1.0;
/// The largest `|sum|` in 3D (Perlin's 12 edge gradients): each corner
/// contributes at most the sum of its two largest offset components; the
/// weighted sum's maximum over the cell is 1.03636 (near `(0.355, 0.5,
/// 0.519)`), rounded up.
pub const NOISE3_BOUND: f32 = 1.037;
/// The largest `|sum|` in 4D (the 32 gradients with three `+-1`
/// components): the three largest offset components per corner, whose
/// weighted sum peaks at 1.53659, rounded up.
pub const NOISE4_BOUND: f32 = 1.537;

/// The lattice offsets of [`vnoise3`]'s second and third components: whole
/// cells, so that every component is 0.5 at the lattice points, and far
/// apart in the hash, so that the three are unrelated at any one point.
pub const VNOISE_OFFSETS: [UVec3; 2] = [UVec3::new(89, 37, 173), UVec3::new(151, 211, 59)];

/// `PERMUTATION[i mod 256]`.
fn perm(i: u32) -> u32 {
    u32::from(PERMUTATION[(i & 255) as usize])
}

/// The lattice cell of `x` modulo 256 and the offset of `x` in it. Exact
/// for every finite `x`: `floor(x) - 256 floor(floor(x) / 256)` divides by
/// a power of two and subtracts integers of the same binade.
fn lattice(x: f32) -> (u32, f32) {
    let cell = x.floor();
    let wrapped = cell - 256.0 * (cell / 256.0).floor();
    (wrapped as u32, x - cell)
}

/// Perlin's quintic fade, `6t^5 - 15t^4 + 10t^3`.
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// `a + t (b - a)`.
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// The 1D gradient of hash `h` (magnitude `1/8 ..= 1`, either sign) times
/// the offset `x`.
fn grad1(h: u32, x: f32) -> f32 {
    let g = ((h & 7) + 1) as f32 * 0.125;
    if h & 8 == 0 { g * x } else { -g * x }
}

/// The 2D gradient of hash `h` dotted with `(x, y)`: the four diagonals
/// `(+-1, +-1)` and the four axes.
fn grad2(h: u32, x: f32, y: f32) -> f32 {
    let h = h & 7;
    let u = if h < 6 { x } else { y };
    let v = if h < 4 { y } else { 0.0 };
    let u = if h & 1 == 0 { u } else { -u };
    let v = if h & 2 == 0 { v } else { -v };
    u + v
}

/// Perlin's improved 3D gradient of hash `h` (the 12 cube edges, four
/// repeated) dotted with `(x, y, z)`.
fn grad3(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    let u = if h & 1 == 0 { u } else { -u };
    let v = if h & 2 == 0 { v } else { -v };
    u + v
}

/// The 4D gradient of hash `h` (three `+-1` components, one zero: 32 of
/// them) dotted with `(x, y, z, w)`.
fn grad4(h: u32, x: f32, y: f32, z: f32, w: f32) -> f32 {
    let h = h & 31;
    let u = if h < 24 { x } else { y };
    let v = if h < 16 { y } else { z };
    let t = if h < 8 { z } else { w };
    let u = if h & 1 == 0 { u } else { -u };
    let v = if h & 2 == 0 { v } else { -v };
    let t = if h & 4 == 0 { t } else { -t };
    u + v + t
}

/// `0.5 + 0.5 sum / bound`, clamped to `[0, 1]` against rounding.
fn unit(sum: f32, bound: f32) -> f32 {
    (0.5 + 0.5 * (sum / bound)).clamp(0.0, 1.0)
}

/// The raw 1D gradient sum.
fn perlin1(x: f32) -> f32 {
    let (xi, x) = lattice(x);
    let u = fade(x);
    lerp(u, grad1(perm(xi), x), grad1(perm(xi + 1), x - 1.0))
}

/// The raw 2D gradient sum.
fn perlin2(p: Vec2) -> f32 {
    let (xi, x) = lattice(p.x);
    let (yi, y) = lattice(p.y);
    let u = fade(x);
    let v = fade(y);
    let h = |i: u32, j: u32| perm(perm(xi + i) + yi + j);
    lerp(
        v,
        lerp(u, grad2(h(0, 0), x, y), grad2(h(1, 0), x - 1.0, y)),
        lerp(
            u,
            grad2(h(0, 1), x, y - 1.0),
            grad2(h(1, 1), x - 1.0, y - 1.0),
        ),
    )
}

/// The raw 3D gradient sum with the lattice shifted by `offset` cells in
/// the hash (not in the coordinates, so the offsets inside the cell stay
/// exact).
fn perlin3(p: Vec3, offset: UVec3) -> f32 {
    let (xi, x) = lattice(p.x);
    let (yi, y) = lattice(p.y);
    let (zi, z) = lattice(p.z);
    let (xi, yi, zi) = (xi + offset.x, yi + offset.y, zi + offset.z);
    let u = fade(x);
    let v = fade(y);
    let w = fade(z);
    let h = |i: u32, j: u32, k: u32| perm(perm(perm(xi + i) + yi + j) + zi + k);
    let (x1, y1, z1) = (x - 1.0, y - 1.0, z - 1.0);
    lerp(
        w,
        lerp(
            v,
            lerp(u, grad3(h(0, 0, 0), x, y, z), grad3(h(1, 0, 0), x1, y, z)),
            lerp(u, grad3(h(0, 1, 0), x, y1, z), grad3(h(1, 1, 0), x1, y1, z)),
        ),
        lerp(
            v,
            lerp(u, grad3(h(0, 0, 1), x, y, z1), grad3(h(1, 0, 1), x1, y, z1)),
            lerp(
                u,
                grad3(h(0, 1, 1), x, y1, z1),
                grad3(h(1, 1, 1), x1, y1, z1),
            ),
        ),
    )
}

/// The trilinear blend of the 3D cell at 4D cell `(xi, yi, zi, wi)` with
/// offsets `(x, y, z, w)` and fades `(u, v, s)`: one of [`perlin4`]'s two
/// `w` slices.
#[expect(
    clippy::too_many_arguments,
    reason = "mirrors the WGSL function, which takes the same scalars"
)]
fn perlin4_slice(cell: [u32; 4], x: f32, y: f32, z: f32, w: f32, u: f32, v: f32, s: f32) -> f32 {
    let [xi, yi, zi, wi] = cell;
    let h = |i: u32, j: u32, k: u32| perm(perm(perm(perm(xi + i) + yi + j) + zi + k) + wi);
    let (x1, y1, z1) = (x - 1.0, y - 1.0, z - 1.0);
    lerp(
        s,
        lerp(
            v,
            lerp(
                u,
                grad4(h(0, 0, 0), x, y, z, w),
                grad4(h(1, 0, 0), x1, y, z, w),
            ),
            lerp(
                u,
                grad4(h(0, 1, 0), x, y1, z, w),
                grad4(h(1, 1, 0), x1, y1, z, w),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad4(h(0, 0, 1), x, y, z1, w),
                grad4(h(1, 0, 1), x1, y, z1, w),
            ),
            lerp(
                u,
                grad4(h(0, 1, 1), x, y1, z1, w),
                grad4(h(1, 1, 1), x1, y1, z1, w),
            ),
        ),
    )
}

/// The raw 4D gradient sum.
fn perlin4(p: Vec3, t: f32) -> f32 {
    let (xi, x) = lattice(p.x);
    let (yi, y) = lattice(p.y);
    let (zi, z) = lattice(p.z);
    let (wi, w) = lattice(t);
    let u = fade(x);
    let v = fade(y);
    let s = fade(z);
    let r = fade(w);
    lerp(
        r,
        perlin4_slice([xi, yi, zi, wi], x, y, z, w, u, v, s),
        perlin4_slice([xi, yi, zi, wi + 1], x, y, z, w - 1.0, u, v, s),
    )
}

/// RenderMan's `float noise(float)`: in `[0, 1]`, 0.5 at the integers.
pub fn noise1(x: f32) -> f32 {
    unit(perlin1(x), NOISE1_BOUND)
}

/// RenderMan's `float noise(float, float)` (here of a 2D point).
pub fn noise2(p: Vec2) -> f32 {
    unit(perlin2(p), NOISE2_BOUND)
}

/// RenderMan's `float noise(point)`.
pub fn noise3(p: Vec3) -> f32 {
    unit(perlin3(p, UVec3::ZERO), NOISE3_BOUND)
}

/// RenderMan's `float noise(point, float)`: 4D noise of a point and a
/// fourth coordinate (typically time).
pub fn noise4(p: Vec3, t: f32) -> f32 {
    unit(perlin4(p, t), NOISE4_BOUND)
}

/// RenderMan's `point noise(point)` (and `color`/`vector noise`): three
/// unrelated 3D noises, the first [`noise3`] itself, the others on the
/// lattice shifted by [`VNOISE_OFFSETS`] cells.
pub fn vnoise3(p: Vec3) -> Vec3 {
    Vec3::new(
        noise3(p),
        unit(perlin3(p, VNOISE_OFFSETS[0]), NOISE3_BOUND),
        unit(perlin3(p, VNOISE_OFFSETS[1]), NOISE3_BOUND),
    )
}

/// RenderMan's `snoise(float)`: `2 noise1(x) - 1`, in `[-1, 1]`.
pub fn snoise1(x: f32) -> f32 {
    2.0 * noise1(x) - 1.0
}

/// `2 noise2(p) - 1`.
pub fn snoise2(p: Vec2) -> f32 {
    2.0 * noise2(p) - 1.0
}

/// `2 noise3(p) - 1`.
pub fn snoise3(p: Vec3) -> f32 {
    2.0 * noise3(p) - 1.0
}

/// `2 noise4(p, t) - 1`.
pub fn snoise4(p: Vec3, t: f32) -> f32 {
    2.0 * noise4(p, t) - 1.0
}

/// `2 vnoise3(p) - 1`, per component.
pub fn svnoise3(p: Vec3) -> Vec3 {
    2.0 * vnoise3(p) - Vec3::ONE
}

/// The WGSL functions, `shaders/reyes/library_noise.wgsl`.
const LIBRARY_NOISE_WGSL: &str = include_str!("../../shaders/reyes/library_noise.wgsl");

/// The WGSL noise library: the constants it shares with this module (the
/// permutation table packed four entries to a `u32`, the bounds and the
/// `vnoise3` offsets), then `shaders/reyes/library_noise.wgsl`. A shader
/// that includes it can call `noise1` ... `noise4`, `snoise1` ...
/// `snoise4`, `vnoise3` and `svnoise3`, which match this module's functions
/// of the same names to within rounding.
pub fn noise_wgsl() -> String {
    use std::fmt::Write as _;
    let mut table = String::new();
    for (i, word) in PERMUTATION.chunks_exact(4).enumerate() {
        let packed = u32::from_le_bytes([word[0], word[1], word[2], word[3]]);
        let sep = if i % 8 == 0 { "\n    " } else { " " };
        // Writing to a String cannot fail.
        let _ = write!(table, "{sep}0x{packed:08x}u,");
    }
    let [a, b] = VNOISE_OFFSETS;
    format!(
        "// RenderMan noise (reyes::noise), generated by reyes::noise::noise_wgsl.\n\
         // reyes::noise::PERMUTATION, four entries to a word, the first in the low byte.\n\
         const NOISE_PERMUTATION: array<u32, 64> = array<u32, 64>({table}\n);\n\
         const NOISE1_BOUND: f32 = {:?};\n\
         const NOISE2_BOUND: f32 = {:?};\n\
         const NOISE3_BOUND: f32 = {:?};\n\
         const NOISE4_BOUND: f32 = {:?};\n\
         const VNOISE_OFFSET_1: vec3<u32> = vec3<u32>({}u, {}u, {}u);\n\
         const VNOISE_OFFSET_2: vec3<u32> = vec3<u32>({}u, {}u, {}u);\n\n\
         {LIBRARY_NOISE_WGSL}",
        NOISE1_BOUND, NOISE2_BOUND, NOISE3_BOUND, NOISE4_BOUND, a.x, a.y, a.z, b.x, b.y, b.z,
    )
}
