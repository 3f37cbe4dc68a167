// Reyes library shared by the procedure bodies: patch access, De Casteljau,
// projection, the bound test (with displacement bounds), Bernstein
// evaluation with exact tangents, shading, sampling, rasterization and
// packing; displacement heights live in displacement.wgsl. Every function
// mirrors the CPU reference (`reyes::reference`, `reyes::bezier`,
// `reyes::camera`, `reyes::color`, `reyes::sampling`) operation for
// operation, in the same order, so that both produce the same decisions and
// (up to the GPU's float contraction) the same values. The constants (NEAR_EPS, STAT_*, DECIDE_*,
// ...) are generated from the Rust side and prepended to this file.

// The structs of the resources (Frame, Object, Light) and of the work item
// (PatchItem) are generated from their Rust definitions
// (reyes::gpu::buffers, reyes::gpu::objects, reyes::gpu::graph) and declared
// before this library.

// ---------------------------------------------------------------- statistics

// Adds to a 64-bit counter kept as (low, high) words: the add that wraps the
// low word is the only one that sees `old > MAX - n`, so it carries exactly once.
fn stat_add64(index: u32, n: u32) {
    if (n == 0u) {
        return;
    }
    let old = atomicAdd(&stats[index], n);
    if (old > 0xffffffffu - n) {
        atomicAdd(&stats[index + 1u], 1u);
    }
}

// ------------------------------------------------- non-finite grid points

// reyes::nonfinite: the NON_FINITE_* bits of the stage that first turned a
// grid point's position infinite or NaN (each mirrors the function of the
// same name there, without the `_sources`).

// nonfinite::dice_sources: the transform when the patch's own point is not
// finite, else when the final position `moved` is not, the displacement of
// a displaced object (the transform otherwise).
fn dice_non_finite(patch_point: vec3<f32>, displaced: bool, moved: vec3<f32>) -> u32 {
    if (!is_finite3(patch_point)) {
        return NON_FINITE_TRANSFORM;
    }
    if (!is_finite3(moved)) {
        return select(NON_FINITE_TRANSFORM, NON_FINITE_DISPLACEMENT, displaced);
    }
    return 0u;
}

// nonfinite::camera_sources: a finite world position whose clip or pixel
// position is not finite.
fn camera_non_finite(world: vec3<f32>, clip: vec4<f32>, pixel: vec3<f32>) -> u32 {
    if (is_finite3(world) && !(is_finite4(clip) && is_finite3(pixel))) {
        return NON_FINITE_CAMERA;
    }
    return 0u;
}

// nonfinite::close_sources: the motion lost the finite `moved`, else the
// camera lost the close position.
fn close_non_finite(moved: vec3<f32>, close_position: vec3<f32>, close_clip: vec4<f32>, close: vec3<f32>) -> u32 {
    if (is_finite3(moved) && !is_finite3(close_position)) {
        return NON_FINITE_TRANSFORM;
    }
    return camera_non_finite(close_position, close_clip, close);
}

// nonfinite::Sources::count_into: one per source in `sources`.
fn count_non_finite(sources: u32) {
    if (sources == 0u) {
        return;
    }
    for (var b = 0u; b < 3u; b += 1u) {
        if ((sources & (1u << b)) != 0u) {
            atomicAdd(&stats[STAT_NON_FINITE + b], 1u);
        }
    }
}

// reyes::camera::towards_eye: the direction from `position` towards the
// viewer, exactly eye - position for a perspective camera (w = 1).
fn towards_eye(position: vec3<f32>) -> vec3<f32> {
    return frame.eye.xyz - position * frame.eye.w;
}

// ------------------------------------------------------------ patch access

fn patch_point(p: ptr<function, array<f32, 48>>, index: u32) -> vec3<f32> {
    return vec3<f32>((*p)[3u * index], (*p)[3u * index + 1u], (*p)[3u * index + 2u]);
}

fn set_patch_point(p: ptr<function, array<f32, 48>>, index: u32, value: vec3<f32>) {
    (*p)[3u * index] = value.x;
    (*p)[3u * index + 1u] = value.y;
    (*p)[3u * index + 2u] = value.z;
}

// Control point k (0..4) of line `line` along direction u (a row, points
// line * 4 + k) or v (a column, points k * 4 + line).
fn line_index(along_u: bool, line: u32, k: u32) -> u32 {
    return select(k * 4u + line, line * 4u + k, along_u);
}

// ------------------------------------------------------------ De Casteljau

// Splits row or column `line` at 1/2 (reyes::bezier::split_cubic, same order)
// and stores the halves into `lo` (lower parameter half) and `hi`.
fn split_line(
    p: ptr<function, array<f32, 48>>,
    along_u: bool,
    line: u32,
    lo: ptr<function, array<f32, 48>>,
    hi: ptr<function, array<f32, 48>>,
) {
    let i0 = line_index(along_u, line, 0u);
    let i1 = line_index(along_u, line, 1u);
    let i2 = line_index(along_u, line, 2u);
    let i3 = line_index(along_u, line, 3u);
    let p0 = patch_point(p, i0);
    let p1 = patch_point(p, i1);
    let p2 = patch_point(p, i2);
    let p3 = patch_point(p, i3);
    let l1 = (p0 + p1) * 0.5;
    let m = (p1 + p2) * 0.5;
    let r2 = (p2 + p3) * 0.5;
    let l2 = (l1 + m) * 0.5;
    let r1 = (m + r2) * 0.5;
    let mid = (l2 + r1) * 0.5;
    set_patch_point(lo, i0, p0);
    set_patch_point(lo, i1, l1);
    set_patch_point(lo, i2, l2);
    set_patch_point(lo, i3, mid);
    set_patch_point(hi, i0, mid);
    set_patch_point(hi, i1, r1);
    set_patch_point(hi, i2, r2);
    set_patch_point(hi, i3, p3);
}

// The whole split, written out for the 4 lines (no loop: cheap and exempt
// from the driver's loop limiter).
fn split_patch(
    p: ptr<function, array<f32, 48>>,
    along_u: bool,
    lo: ptr<function, array<f32, 48>>,
    hi: ptr<function, array<f32, 48>>,
) {
    split_line(p, along_u, 0u, lo, hi);
    split_line(p, along_u, 1u, lo, hi);
    split_line(p, along_u, 2u, lo, hi);
    split_line(p, along_u, 3u, lo, hi);
}

// The (u0, v0, u1, v1) rectangle of half `which` (0: lower) of `uv`.
fn split_uv(uv: vec4<f32>, along_u: bool, which: u32) -> vec4<f32> {
    if (along_u) {
        let um = (uv.x + uv.z) * 0.5;
        return select(vec4<f32>(um, uv.y, uv.z, uv.w), vec4<f32>(uv.x, uv.y, um, uv.w), which == 0u);
    }
    let vm = (uv.y + uv.w) * 0.5;
    return select(vec4<f32>(uv.x, vm, uv.z, uv.w), vec4<f32>(uv.x, uv.y, uv.z, vm), which == 0u);
}

// ------------------------------------------------------------ projection

// glam's Mat4 * Vec4 order: ((c0 x + c1 y) + c2 z) + c3 (w = 1).
fn to_clip(p: vec3<f32>) -> vec4<f32> {
    let m = frame.view_proj;
    return ((m[0] * p.x + m[1] * p.y) + m[2] * p.z) + m[3];
}

// reyes::camera::Camera::to_pixel of the full image: (px, py, ndc depth),
// y down. Pixel positions are the full image's in a screen tile too (the
// tile's origin is subtracted only from integer pixel and stratum
// indices), so a tile places, splits, dices and samples bit for bit as the
// whole frame does.
fn to_pixel(c: vec4<f32>) -> vec3<f32> {
    let ndc = c.xyz / c.w;
    return vec3<f32>(
        (ndc.x * 0.5 + 0.5) * f32(frame.full_width),
        (0.5 - ndc.y * 0.5) * f32(frame.full_height),
        ndc.z,
    );
}

fn to_pixel2(p: vec3<f32>) -> vec2<f32> {
    return to_pixel(to_clip(p)).xy;
}

// reyes::reference::bound::outcode: the clip planes (bits 0..5, reference
// order: left, right, bottom, top, far, near) that the ball around a point
// with clip-space `radius` is entirely outside of, plus UNPROJECTABLE when
// the point itself has w <= NEAR_EPS or z < 0. A zero radius gives the
// point's own outcode.
fn outcode(c: vec4<f32>, radius: vec4<f32>) -> u32 {
    let lo = c - radius;
    let hi = c + radius;
    var code = 0u;
    if (hi.x < -hi.w) { code |= 1u; }
    if (lo.x > hi.w) { code |= 2u; }
    if (hi.y < -hi.w) { code |= 4u; }
    if (lo.y > hi.w) { code |= 8u; }
    if (lo.z > hi.w) { code |= 16u; }
    if (hi.z < 0.0) { code |= 32u; }
    if (c.w <= NEAR_EPS || c.z < 0.0) { code |= UNPROJECTABLE; }
    return code;
}

// The outcode of `c` (a clip position of the full image) against the
// frame's window, a screen tile's frustum (reyes::camera::Camera::window,
// window_clip): x and y scaled and shifted into the window's clip space,
// the radius grown by the same map. The whole frame's window is the
// identity and keeps the outcode as it is.
fn window_outcode(c: vec4<f32>, radius: vec4<f32>) -> u32 {
    let s = frame.window;
    if (all(s == vec4<f32>(1.0, 1.0, 0.0, 0.0))) {
        return outcode(c, radius);
    }
    let windowed = vec4<f32>(s.x * c.x + s.z * c.w, s.y * c.y + s.w * c.w, c.z, c.w);
    let grown = vec4<f32>(
        abs(s.x) * radius.x + abs(s.z) * radius.w,
        abs(s.y) * radius.y + abs(s.w) * radius.w,
        radius.z,
        radius.w,
    );
    return outcode(windowed, grown);
}

// Merges outcodes: planes all points are outside of (AND), and whether any
// point is unprojectable (OR). Start from FLAGS_IDENTITY.
fn merge_flags(a: u32, b: u32) -> u32 {
    return ((a & b) & PLANE_BITS) | ((a | b) & UNPROJECTABLE);
}

