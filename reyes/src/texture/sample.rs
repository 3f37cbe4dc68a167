//! Anisotropic trilinear filtering on the CPU, over the same tables the GPU
//! reads.
//!
//! `shaders/reyes/library_texture.wgsl` repeats every function here
//! operation for operation (each WGSL function names its twin), on the same
//! f16 texels, so the two agree to float rounding.
//!
//! * Footprint: the parallelogram `st + x a + y b`, `x, y` in
//!   `[-1/2, 1/2]`, with `a` and `b` its two axes. Measured in level-0
//!   texels (`|(a.s * width, a.t * height)|`), `major` is the longer axis
//!   and `minor` the shorter.
//! * Probes along the longer axis: the filter's width is `w = max(minor,
//!   major / MAX_ANISOTROPY)`, and `n = ceil(major / max(w, 1))` trilinear
//!   probes (at most [`MAX_ANISOTROPY`]) sit at the centres of `n` equal
//!   pieces of the longer axis, `st + major_axis * ((i + 1/2) / n - 1/2)`;
//!   their mean is the result. A footprint longer than `MAX_ANISOTROPY`
//!   times its width is blurred across, never aliased along.
//! * Level of detail: `lod = log2(w)`, clamped to `[0, levels - 1]`; `w <=
//!   1` is level 0, a non-finite axis the coarsest level (with one probe).
//! * Within a level: bilinear between texel centres. `s = 0` is the left
//!   edge of texel 0 and `s = 1` the right edge of the last, so texel `i` of
//!   an `n`-texel level has its centre at `(i + 0.5) / n`. The wrap mode of
//!   each axis is applied to each of the four taps.
//! * Between levels: `c0 + (c1 - c0) * fract(lod)`.
//!
//! A non-finite s or t samples transparent black, and so does an unknown
//! texture id.

use glam::{Vec2, Vec4};

use super::Wrap;
use super::gpu::TextureInfo;
use super::mipmap::{next_side, unpack};

/// One level of a texture: where its texels start, and its size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Level {
    /// First texel of the level in the texel buffer.
    pub(super) offset: u32,
    /// Width in texels.
    pub(super) width: u32,
    /// Height in texels.
    pub(super) height: u32,
}

/// `x` is neither NaN nor infinite, judged on its bits as the WGSL must
/// (WGSL has no `isNan`, and a fast-math compiler may fold comparisons).
pub(super) fn is_finite(x: f32) -> bool {
    x.to_bits() & 0x7f80_0000 != 0x7f80_0000
}

/// Level `level` of `info`: the levels before it, walked from level 0.
pub(super) fn level(info: &TextureInfo, level: u32) -> Level {
    let mut at = Level {
        offset: info.offset,
        width: info.width,
        height: info.height,
    };
    for _ in 0..level {
        at.offset += at.width * at.height;
        at.width = next_side(at.width);
        at.height = next_side(at.height);
    }
    at
}

/// `i` folded into `0..n` by `wrap`, or -1 for a black tap outside.
fn wrap_index(i: i32, n: u32, wrap: u32) -> i32 {
    let n = n.cast_signed();
    if wrap == Wrap::Periodic.code() {
        ((i % n) + n) % n
    } else if wrap == Wrap::Clamp.code() {
        i.clamp(0, n - 1)
    } else if i < 0 || i >= n {
        -1
    } else {
        i
    }
}

/// The two taps along one axis of an `n`-texel level and the blend between
/// them, for coordinate `s`.
///
/// Periodic coordinates are first reduced to `[0, 1]` (`s - floor(s)`), and
/// the others clamped to `[-1, n]` texels, which changes no result (beyond
/// the edge every tap is the edge texel, or black) but keeps the texel
/// indices small, exact in `f32` and in range for the conversion to `i32`.
fn taps(s: f32, n: u32, wrap: u32) -> (i32, i32, f32) {
    let size = n as f32;
    let x = if wrap == Wrap::Periodic.code() {
        (s - s.floor()) * size - 0.5
    } else {
        (s * size - 0.5).clamp(-1.0, size)
    };
    let x0 = x.floor();
    let i = x0 as i32;
    (wrap_index(i, n, wrap), wrap_index(i + 1, n, wrap), x - x0)
}

/// Texel `(i, j)` of `level`; black for a tap outside (-1).
fn texel(texels: &[[u32; 2]], level: Level, i: i32, j: i32) -> Vec4 {
    if i < 0 || j < 0 {
        return Vec4::ZERO;
    }
    let at = level.offset as usize + j as usize * level.width as usize + i as usize;
    texels.get(at).map_or(Vec4::ZERO, |&t| unpack(t))
}

/// Bilinear sample of level `index` of `info` at `st`.
fn bilinear(info: &TextureInfo, texels: &[[u32; 2]], index: u32, st: Vec2) -> Vec4 {
    let at = level(info, index);
    let (i0, i1, fx) = taps(st.x, at.width, info.wrap_s);
    let (j0, j1, fy) = taps(st.y, at.height, info.wrap_t);
    let t00 = texel(texels, at, i0, j0);
    let t10 = texel(texels, at, i1, j0);
    let t01 = texel(texels, at, i0, j1);
    let t11 = texel(texels, at, i1, j1);
    let top = t00 + (t10 - t00) * fx;
    let bottom = t01 + (t11 - t01) * fx;
    top + (bottom - top) * fy
}

/// Length of a footprint axis in level-0 texels.
fn axis_texels(info: &TextureInfo, axis: Vec2) -> f32 {
    let x = axis.x * info.width as f32;
    let y = axis.y * info.height as f32;
    (x * x + y * y).sqrt()
}

/// Most trilinear probes along a footprint's longer axis: the longest
/// ratio of its axes that the filter resolves. Beyond it the filter widens
/// across the footprint (blurs) rather than leaving gaps between probes
/// (aliases). 16 is what graphics hardware offers at most.
pub const MAX_ANISOTROPY: u32 = 16;

/// How a footprint is filtered: `probes` trilinear lookups at level of
/// detail `lod`, spread along `major_axis` (in (s, t)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Probes {
    /// Level of detail of every probe, in `[0, levels - 1]`.
    pub(super) lod: f32,
    /// Number of probes, in `1..=MAX_ANISOTROPY`.
    pub(super) count: u32,
    /// The footprint's longer axis, in (s, t).
    pub(super) major_axis: Vec2,
}

/// The probes that filter the footprint `(axis_a, axis_b)`.
pub(super) fn probes(info: &TextureInfo, axis_a: Vec2, axis_b: Vec2) -> Probes {
    let coarsest = (info.levels - 1) as f32;
    let a = axis_texels(info, axis_a);
    let b = axis_texels(info, axis_b);
    if !is_finite(a) || !is_finite(b) {
        return Probes {
            lod: coarsest,
            count: 1,
            major_axis: Vec2::ZERO,
        };
    }
    let (major_axis, major, minor) = if a >= b {
        (axis_a, a, b)
    } else {
        (axis_b, b, a)
    };
    let width = minor.max(major / MAX_ANISOTROPY as f32);
    // One probe per filter width along the longer axis, and at least one
    // per level-0 texel where the filter is level 0 (width below a texel).
    let count = (major / width.max(1.0))
        .ceil()
        .clamp(1.0, MAX_ANISOTROPY as f32) as u32;
    let lod = if width <= 1.0 {
        0.0
    } else {
        width.log2().min(coarsest)
    };
    Probes {
        lod,
        count,
        major_axis,
    }
}

/// Trilinear sample of `info` at `st` and level of detail `lod`.
fn trilinear(info: &TextureInfo, texels: &[[u32; 2]], st: Vec2, lod: f32) -> Vec4 {
    let base = lod.floor();
    let blend = lod - base;
    let fine = base as u32;
    let c0 = bilinear(info, texels, fine, st);
    if blend <= 0.0 {
        return c0;
    }
    let c1 = bilinear(info, texels, (fine + 1).min(info.levels - 1), st);
    c0 + (c1 - c0) * blend
}

/// The filtered texture `id` of `infos` at `st`, for a shading point whose
/// footprint spans `axis_a` and `axis_b` in (s, t).
pub(super) fn sample(
    infos: &[TextureInfo],
    texels: &[[u32; 2]],
    id: u32,
    st: Vec2,
    axis_a: Vec2,
    axis_b: Vec2,
) -> Vec4 {
    let Some(info) = infos.get(id as usize) else {
        return Vec4::ZERO;
    };
    filter(info, texels, st, axis_a, axis_b)
}

/// The filtered texture `info` at `st` over the footprint `(axis_a,
/// axis_b)`, with `info`'s wrap modes; a non-finite `st` gives transparent
/// black.
pub(super) fn filter(
    info: &TextureInfo,
    texels: &[[u32; 2]],
    st: Vec2,
    axis_a: Vec2,
    axis_b: Vec2,
) -> Vec4 {
    if !is_finite(st.x) || !is_finite(st.y) {
        return Vec4::ZERO;
    }
    let probes = probes(info, axis_a, axis_b);
    let count = probes.count as f32;
    let mut sum = Vec4::ZERO;
    for i in 0..probes.count {
        let along = (i as f32 + 0.5) / count - 0.5;
        sum += trilinear(info, texels, st + probes.major_axis * along, probes.lod);
    }
    sum / count
}
