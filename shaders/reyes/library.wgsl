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

// ------------------------------------------------------------ float helpers

// Written with bit tests: the driver may assume no NaN/Inf in comparisons.
fn is_finite_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_nan_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

fn is_finite3(v: vec3<f32>) -> bool {
    return is_finite_f32(v.x) && is_finite_f32(v.y) && is_finite_f32(v.z);
}

fn is_finite4(v: vec4<f32>) -> bool {
    return is_finite3(v.xyz) && is_finite_f32(v.w);
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

// Rust's `f32::round` for x >= 0 (halves away from zero); WGSL's round()
// rounds halves to even, which would differ from the reference on ties.
fn round_half_up(x: f32) -> f32 {
    let f = floor(x);
    return select(f, f + 1.0, x - f >= 0.5);
}

fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// glam's cross product, term for term.
fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// reyes::camera::towards_eye: the direction from `position` towards the
// viewer, exactly eye - position for a perspective camera (w = 1).
fn towards_eye(position: vec3<f32>) -> vec3<f32> {
    return frame.eye.xyz - position * frame.eye.w;
}

// glam's normalize_or_zero: v * (1 / |v|) when that reciprocal is finite and > 0.
fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    if (is_finite_f32(rcp) && rcp > 0.0) {
        return v * rcp;
    }
    return vec3<f32>(0.0);
}

fn dist2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    let d = b - a;
    return sqrt(d.x * d.x + d.y * d.y);
}

fn dist3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return sqrt(dot3(b - a, b - a));
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

// reyes::camera::Camera::to_pixel: (px, py, ndc depth), y down.
fn to_pixel(c: vec4<f32>) -> vec3<f32> {
    let ndc = c.xyz / c.w;
    return vec3<f32>(
        (ndc.x * 0.5 + 0.5) * f32(frame.width),
        (0.5 - ndc.y * 0.5) * f32(frame.height),
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

// Merges outcodes: planes all points are outside of (AND), and whether any
// point is unprojectable (OR). Start from FLAGS_IDENTITY.
fn merge_flags(a: u32, b: u32) -> u32 {
    return ((a & b) & PLANE_BITS) | ((a | b) & UNPROJECTABLE);
}

// ------------------------------------------------------------ bound test

// The clip-space radius of a ball of `bound` world units.
fn clip_radius(bound: f32) -> vec4<f32> {
    return frame.clip_pad * bound;
}

// ------------------------------------------------ motion and lens (bound)

// glam's Mat4::transform_point3, term for term.
fn motion_close(object: Object, p: vec3<f32>) -> vec3<f32> {
    let m = object.motion;
    return (((m[0] * p.x + m[1] * p.y) + m[2] * p.z) + m[3]).xyz;
}

// reyes::motion::PreparedLens::coc: signed circle of confusion (pixels).
fn coc(w: f32) -> f32 {
    if (frame.aperture == 0.0) {
        return 0.0;
    }
    return frame.aperture * (1.0 / frame.focus - 1.0 / w) * frame.pixel_scale;
}

// reyes::motion::PreparedLens::world_shift.
fn lens_world_shift(w: f32, e: f32) -> f32 {
    if (frame.aperture == 0.0) {
        return 0.0;
    }
    return frame.aperture * max(abs((w - e) / frame.focus - 1.0), abs((w + e) / frame.focus - 1.0));
}

// The clip-space radius the bound test grows control point `p` (clip `c`)
// by for culling: the displacement radius `radius` of a sharp, still
// object, else reyes::motion::cull_radius (displacement, motion and lens
// shift; reyes::reference::bound::bound).
fn cull_clip_radius(object: Object, p: vec3<f32>, c: vec4<f32>, radius: vec4<f32>) -> vec4<f32> {
    if (object.moving == 0u && frame.aperture == 0.0) {
        return radius;
    }
    var stretch = 1.0;
    var moved = 0.0;
    if (object.moving != 0u) {
        stretch = object.motion_stretch;
        moved = dist3(p, motion_close(object, p));
    }
    let reach = object.displace_bound * stretch + moved;
    return frame.clip_pad * (reach + lens_world_shift(c.w, reach));
}

// reyes::reference::bound::pixel_growth: how far (pixels) the ball around a
// projectable point with clip-space `radius` reaches beyond the point on
// screen; 0 without displacement or when the ball reaches the eye plane.
fn pixel_growth(c: vec4<f32>, bound: f32, radius: vec4<f32>) -> f32 {
    if (bound == 0.0) {
        return 0.0;
    }
    let lo = c - radius;
    let hi = c + radius;
    if (lo.w <= NEAR_EPS) {
        return 0.0;
    }
    let p = to_pixel(c).xy;
    let xl = min(lo.x / lo.w, lo.x / hi.w);
    let xh = max(hi.x / lo.w, hi.x / hi.w);
    let yl = min(lo.y / lo.w, lo.y / hi.w);
    let yh = max(hi.y / lo.w, hi.y / hi.w);
    let width = f32(frame.width);
    let height = f32(frame.height);
    let box_lo = vec2<f32>((xl * 0.5 + 0.5) * width, (0.5 - yh * 0.5) * height);
    let box_hi = vec2<f32>((xh * 0.5 + 0.5) * width, (0.5 - yl * 0.5) * height);
    return max(max(max(p.x - box_lo.x, box_hi.x - p.x), p.y - box_lo.y), box_hi.y - p.y);
}

// reyes::reference::bound::fits: the undisplaced box, grown by `growth` on
// every side, fits the threshold; the growth takes at most a fraction of it.
fn fits(size: f32, growth: f32) -> bool {
    let t = frame.dice_threshold;
    return size <= max(t - 2.0 * growth, t * DISPLACED_DICE_FRACTION);
}

// reyes::reference::bound::bound, given the reductions: `flags` (merged
// outcodes), `size` (larger side of the pixel bbox), `growth` (largest
// pixel_growth of the points), the u/v extents in pixels (`u2`, `v2`) and
// in world space (`u3`, `v3`).
// `grid` is the piece's (nu, nv) from piece_grid, 0 in a direction that
// must be split.
fn decide(flags: u32, size: f32, growth: f32, u2: f32, v2: f32, u3: f32, v3: f32, split_depth: u32, grid: vec2<u32>) -> u32 {
    if ((flags & PLANE_BITS) != 0u) {
        return DECIDE_CULL;
    }
    if ((flags & UNPROJECTABLE) != 0u) {
        if (split_depth >= frame.max_split_depth) {
            return DECIDE_DROP;
        }
        return select(DECIDE_SPLIT_V, DECIDE_SPLIT_U, u3 >= v3);
    }
    if (grid.x != 0u && grid.y != 0u && fits(size, growth)) {
        return DECIDE_DICE;
    }
    if (split_depth >= frame.max_split_depth) {
        return DECIDE_DROP;
    }
    if (grid.x == 0u && grid.y != 0u) {
        return DECIDE_SPLIT_U;
    }
    if (grid.x != 0u && grid.y == 0u) {
        return DECIDE_SPLIT_V;
    }
    return select(DECIDE_SPLIT_V, DECIDE_SPLIT_U, u2 >= v2);
}

// f32::max semantics (a NaN operand is ignored), for the bbox size.
fn max_ignoring_nan(a: f32, b: f32) -> f32 {
    if (is_nan_f32(a)) { return b; }
    if (is_nan_f32(b)) { return a; }
    return max(a, b);
}

// Sends a piece where the bound test says, counting what it drops.
fn route(decision: u32, piece: PatchItem) {
    switch decision {
        case DECIDE_CULL: {
            atomicAdd(&stats[STAT_CULLED], 1u);
        }
        case DECIDE_DROP: {
            atomicAdd(&stats[STAT_DEPTH_GUARD_DROPS], 1u);
        }
        case DECIDE_DICE: {
            switch grid_class(piece.grid & 0xffu, piece.grid >> 8u) {
                case GRID_CLASS_SMALL: {
                    enqueue_DiceShadeSample16(piece);
                }
                case GRID_CLASS_MEDIUM: {
                    enqueue_DiceShadeSample64(piece);
                }
                default: {
                    enqueue_DiceShadeSample256(piece);
                }
            }
        }
        case DECIDE_SPLIT_U: {
            atomicAdd(&stats[STAT_SPLITS], 1u);
            enqueue_SplitU(piece);
        }
        default: {
            atomicAdd(&stats[STAT_SPLITS], 1u);
            enqueue_SplitV(piece);
        }
    }
}

// reyes::reference::bound::back_facing, the share of control point `k`:
// front * ((p_k - eye) x a) . b >= 0 for the 12 differences a along u and
// the 12 differences b along v.
fn back_facing_at(p: ptr<function, array<f32, 48>>, k: u32, front: f32) -> bool {
    // patch_point(p, k) - eye for a perspective camera, exactly.
    let r = -towards_eye(patch_point(p, k));
    for (var ka = 0u; ka < 12u; ka += 1u) {
        let row = ka / 3u;
        let column = ka % 3u;
        let a = patch_point(p, row * 4u + column + 1u) - patch_point(p, row * 4u + column);
        let c = cross3(r, a);
        for (var kb = 0u; kb < 12u; kb += 1u) {
            let b = patch_point(p, kb + 4u) - patch_point(p, kb);
            if (!(front * dot3(c, b) >= 0.0)) {
                return false;
            }
        }
    }
    return true;
}

// ------------------------------------------------------------ evaluation

// reyes::bezier::bernstein and bernstein_derivative.
fn bernstein(t: f32) -> vec4<f32> {
    let mt = 1.0 - t;
    return vec4<f32>(mt * mt * mt, 3.0 * t * mt * mt, 3.0 * t * t * mt, t * t * t);
}

fn bernstein_derivative(t: f32) -> vec4<f32> {
    let mt = 1.0 - t;
    return vec4<f32>(
        -3.0 * mt * mt,
        3.0 * mt * mt - 6.0 * t * mt,
        6.0 * t * mt - 3.0 * t * t,
        3.0 * t * t,
    );
}

// sum over rows v of wv[v] * (sum over u of wu[u] * p[v * 4 + u]), rows
// written out in the reference's order.
fn tensor_row(p: ptr<function, array<f32, 48>>, v: u32, wu: vec4<f32>) -> vec3<f32> {
    return patch_point(p, v * 4u) * wu.x
        + patch_point(p, v * 4u + 1u) * wu.y
        + patch_point(p, v * 4u + 2u) * wu.z
        + patch_point(p, v * 4u + 3u) * wu.w;
}

fn tensor(p: ptr<function, array<f32, 48>>, wu: vec4<f32>, wv: vec4<f32>) -> vec3<f32> {
    var sum = tensor_row(p, 0u, wu) * wv.x;
    sum += tensor_row(p, 1u, wu) * wv.y;
    sum += tensor_row(p, 2u, wu) * wv.z;
    sum += tensor_row(p, 3u, wu) * wv.w;
    return sum;
}

// reyes::reference::dice::degenerate.
fn degenerate(n: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> bool {
    let n2 = dot3(n, n);
    return !(n2 > DEGENERATE_NORMAL_REL_EPS * (dot3(a, a) * dot3(b, b))) || n2 == 0.0;
}

// The unnormalized normal dP/ds x dP/dt at (s, t).
fn tangent_normal(p: ptr<function, array<f32, 48>>, s: f32, t: f32) -> vec3<f32> {
    let bs = bernstein(s);
    let bt = bernstein(t);
    let d_ds = tensor(p, bernstein_derivative(s), bt);
    let d_dt = tensor(p, bs, bernstein_derivative(t));
    let n = cross3(d_ds, d_dt);
    if (degenerate(n, d_ds, d_dt)) {
        return vec3<f32>(0.0);
    }
    return n;
}

// reyes::reference::dice::surface_point: the unit normal facing `eye` at
// (s, t), with the degenerate-edge fallback (tangents re-evaluated at the
// clamped parameters, then the direction to the eye, then +z).
fn surface_normal(p: ptr<function, array<f32, 48>>, s: f32, t: f32, position: vec3<f32>) -> vec3<f32> {
    let to_eye = towards_eye(position);
    var n = tangent_normal(p, s, t);
    if (all(n == vec3<f32>(0.0))) {
        n = tangent_normal(
            p,
            clamp(s, DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
            clamp(t, DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
        );
        if (all(n == vec3<f32>(0.0))) {
            n = to_eye;
        }
    }
    n = normalize_or_zero(n);
    if (all(n == vec3<f32>(0.0))) {
        n = vec3<f32>(0.0, 0.0, 1.0);
    }
    if (dot3(n, to_eye) < 0.0) {
        n = -n;
    }
    return n;
}

// ------------------------------------------------------------ shading

// Rust's powf on [0, inf): 0^0 = 1, 0^y = 0; WGSL leaves pow(0, y) undefined.
fn pow_nonneg(x: f32, y: f32) -> f32 {
    if (x <= 0.0) {
        return select(0.0, 1.0, y == 0.0);
    }
    return pow(x, y);
}

// reyes::reference::shade::shade_with: Lambert + two-sided Blinn-Phong
// (the normal already faces the eye), clamped to [0, 1].
fn shade(position: vec3<f32>, normal: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    let view = normalize_or_zero(towards_eye(position));
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    for (var l = 0u; l < frame.light_count; l += 1u) {
        let light = lights[l];
        // reyes::prepare::PreparedLight::at: w = 1 marks a point light,
        // whose xyz is its position.
        var to_light = light.to_light.xyz;
        var falloff = 1.0;
        if (light.to_light.w != 0.0) {
            let toward = light.to_light.xyz - position;
            falloff = 1.0 / max(dot3(toward, toward), POINT_LIGHT_MIN_DISTANCE_SQUARED);
            to_light = normalize_or_zero(toward);
        }
        diffuse += light.radiance.xyz * (max(dot3(normal, to_light), 0.0) * falloff);
        let half_vector = normalize_or_zero(to_light + view);
        specular += light.radiance.xyz * (pow_nonneg(max(dot3(normal, half_vector), 0.0), frame.shininess) * falloff);
    }
    let color = albedo * (vec3<f32>(frame.ambient) + diffuse) + specular * frame.specular_strength;
    return clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
}

// ------------------------------------------------------------ packing

// reyes::color::pack_rgb10.
fn pack_rgb10(c: vec3<f32>) -> u32 {
    let q = vec3<u32>(
        u32(round_half_up(clamp(c.x, 0.0, 1.0) * 1023.0)),
        u32(round_half_up(clamp(c.y, 0.0, 1.0) * 1023.0)),
        u32(round_half_up(clamp(c.z, 0.0, 1.0) * 1023.0)),
    );
    return q.x | (q.y << 10u) | (q.z << 20u);
}

// Clamps a depth into [0, 1] and turns -0.0 into +0.0 (reference key_depth).
fn key_depth(z: f32) -> f32 {
    let d = clamp(z, 0.0, 1.0);
    return select(d, 0.0, d == 0.0);
}

// The depth test: keeps the minimum (depth bits << 32 | colour) per sample.
fn offer(x: u32, y: u32, s: u32, depth: f32, color: u32) {
    let index = (y * frame.width + x) * frame.spp + s;
    let key = (u64(bitcast<u32>(key_depth(depth))) << 32u) | u64(color);
    atomicMin(&framebuffer[index], key);
}

// ------------------------------------------------------------ sampling

// reyes::sampling::hash.
fn jitter_hash(x: u32, y: u32, s: u32, c: u32) -> u32 {
    var h = (x * HASH_MUL_X) ^ (y * HASH_MUL_Y) ^ (s * HASH_MUL_S) ^ (c * HASH_MUL_C);
    h ^= h >> 16u;
    h *= HASH_MIX_0;
    h ^= h >> 15u;
    h *= HASH_MIX_1;
    h ^= h >> 16u;
    return h;
}

// reyes::sampling::sample_position.
fn sample_position(x: u32, y: u32, s: u32) -> vec2<f32> {
    let kf = f32(frame.k);
    var offset = vec2<f32>((f32(s % frame.k) + 0.5) / kf, (f32(s / frame.k) + 0.5) / kf);
    if (frame.jitter != 0u) {
        let gx = x + frame.origin_x;
        let gy = y + frame.origin_y;
        let jx = (f32(jitter_hash(gx, gy, s, 0u)) / 4294967296.0 - 0.5) / kf;
        let jy = (f32(jitter_hash(gx, gy, s, 1u)) / 4294967296.0 - 0.5) / kf;
        offset += vec2<f32>(jx, jy);
    }
    return vec2<f32>(f32(x), f32(y)) + offset;
}

// ------------------------------------------------------------ rasterization

// A projected grid point: (px, py, depth, clip w).
fn usable(p: vec4<f32>) -> bool {
    return p.w > NEAR_EPS && p.z >= 0.0 && p.z <= 1.0;
}

fn edge_raw(a: vec2<f32>, b: vec2<f32>, p: vec2<f32>) -> f32 {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Edge function evaluated from the lexicographically smaller endpoint, so
// two triangles sharing an edge get exactly opposite values (reference `edge`).
fn edge(a: vec2<f32>, b: vec2<f32>, p: vec2<f32>) -> f32 {
    if (a.x < b.x || (a.x == b.x && a.y <= b.y)) {
        return edge_raw(a, b, p);
    }
    return -edge_raw(b, a, p);
}

// Top-left rule (reference `owns`): a top edge (horizontal, pointing right)
// or a left edge (pointing up on the y-down screen) owns samples on it.
fn owns(a: vec2<f32>, b: vec2<f32>) -> bool {
    let d = b - a;
    return d.y < 0.0 || (d.y == 0.0 && d.x > 0.0);
}

// reyes::reference::raster::shows_front: grid triangle (a, b, c) shows the
// front of an object whose front is along front * (dP/du x dP/dv); every
// triangle of a two-sided object (front = 0) is drawn.
fn drawn_face(a: vec2<f32>, b: vec2<f32>, c: vec2<f32>, front: f32) -> bool {
    return front == 0.0 || front * edge(a, b, c) < 0.0;
}

fn inside(e: f32, a: vec2<f32>, b: vec2<f32>) -> bool {
    return e > 0.0 || (e == 0.0 && owns(a, b));
}

// A grid point's clip position in DiceShadeSample's scratch words
// w..w+4 (at open; at close from w + 5).
fn scratch_store_clip(slot: u32, w: u32, clip: vec4<f32>) {
    scratch_store_f32(slot, w, clip.x);
    scratch_store_f32(slot, w + 1u, clip.y);
    scratch_store_f32(slot, w + 2u, clip.z);
    scratch_store_f32(slot, w + 3u, clip.w);
}

fn grid_clip(slot: u32, w: u32) -> vec4<f32> {
    return vec4<f32>(scratch_load_f32(slot, w), scratch_load_f32(slot, w + 1u), scratch_load_f32(slot, w + 2u), scratch_load_f32(slot, w + 3u));
}

// A projected grid point at shutter open, (px, py, depth, clip w).
fn grid_point(slot: u32, w: u32) -> vec4<f32> {
    let clip = grid_clip(slot, w);
    return vec4<f32>(to_pixel(clip), clip.w);
}

// reyes::color::average_rgb10: a micropolygon's colour from its corners'.
fn average_rgb10(c0: u32, c1: u32, c2: u32, c3: u32) -> u32 {
    var packed = 0u;
    for (var shift = 0u; shift < 30u; shift += 10u) {
        let sum = ((c0 >> shift) & 0x3ffu) + ((c1 >> shift) & 0x3ffu) + ((c2 >> shift) & 0x3ffu) + ((c3 >> shift) & 0x3ffu);
        packed |= ((sum + 2u) / 4u) << shift;
    }
    return packed;
}

// reyes::color::blend_rgb10: a sample's colour from its triangle's corner
// colours (a, b, c), weighted by its edge functions (E_bc, E_ca, E_ab) over
// the doubled area, as its depth is. Equal colours pass through unchanged.
fn blend_rgb10(colors: vec3<u32>, edges: vec3<f32>, area: f32) -> u32 {
    if (colors.x == colors.y && colors.y == colors.z) {
        return colors.x;
    }
    var packed = 0u;
    for (var shift = 0u; shift < 30u; shift += 10u) {
        let corner = vec3<f32>((colors >> vec3<u32>(shift)) & vec3<u32>(0x3ffu));
        let value = ((edges.x * corner.x + edges.y * corner.y) + edges.z * corner.z) / area;
        packed |= min(u32(max(floor(value + 0.5), 0.0)), 0x3ffu) << shift;
    }
    return packed;
}

// Samples tested, hit, and skipped untested (reyes::RenderStats) by one
// thread, added to the statistics once per item.
struct SampleCounts {
    tested: u32,
    hit: u32,
    skipped: u32,
}
