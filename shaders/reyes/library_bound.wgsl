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
    let width = f32(frame.full_width);
    let height = f32(frame.full_height);
    let box_lo = vec2<f32>((xl * 0.5 + 0.5) * width, (0.5 - yh * 0.5) * height);
    let box_hi = vec2<f32>((xh * 0.5 + 0.5) * width, (0.5 - yl * 0.5) * height);
    return max(max(max(p.x - box_lo.x, box_hi.x - p.x), p.y - box_lo.y), box_hi.y - p.y);
}

// reyes::reference::bound::fits: the undisplaced box, grown by `growth` on
// every side, fits the threshold; the growth takes at most a fraction of it.
fn fits(size: f32, growth: f32, t: f32) -> bool {
    return size <= max(t - 2.0 * growth, t * DISPLACED_DICE_FRACTION);
}

// reyes::reference::bound::bound, given the reductions: `flags` (merged
// outcodes), `size` (larger side of the pixel bbox), `growth` (largest
// pixel_growth of the points), the u/v extents in pixels (`u2`, `v2`) and
// in world space (`u3`, `v3`).
// `grid` is the piece's (nu, nv) from piece_grid, 0 in a direction that
// must be split.
fn decide(flags: u32, size: f32, growth: f32, u2: f32, v2: f32, u3: f32, v3: f32, split_depth: u32, grid: vec2<u32>, dice_threshold: f32) -> u32 {
    if ((flags & PLANE_BITS) != 0u) {
        return DECIDE_CULL;
    }
    if ((flags & UNPROJECTABLE) != 0u) {
        if (split_depth >= frame.max_split_depth) {
            return DECIDE_DROP;
        }
        return select(DECIDE_SPLIT_V, DECIDE_SPLIT_U, u3 >= v3);
    }
    if (grid.x != 0u && grid.y != 0u && fits(size, growth, dice_threshold)) {
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

