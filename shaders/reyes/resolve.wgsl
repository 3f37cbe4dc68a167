// Clearing and resolving the sample framebuffer (a plain compute shader, run
// around the megakernel). The framebuffer holds one 64-bit key per sample,
// (depth bits << 32) | packed colour; here it is viewed as pairs of u32
// words (little-endian: x = low word = colour, y = high word = depth), so
// neither entry point needs 64-bit atomics.

// `ResolveParams`, `CLEAR_WORKGROUP`, the FILTER_* codes, the jitter
// hash's constants and its function (`jitter_hash`, shared with the
// megakernel's library_raster.wgsl) are declared before this file from
// their Rust definitions (reyes::gpu::resolve).

@group(0) @binding(0) var<uniform> params: ResolveParams;
@group(0) @binding(1) var<storage, read_write> keys: array<vec2<u32>>;
// One linear RGBA pixel per vec4, row-major: the filtered value as it is
// (not clamped, not encoded), alpha 1. The host encodes it as 8 bits
// (reyes::quantize) and writes it as EXR.
@group(0) @binding(2) var<storage, read_write> image: array<vec4<f32>>;
// The number of the pixel's samples that were covered.
@group(0) @binding(3) var<storage, read_write> coverage: array<u32>;

const CLEAR_WORD: u32 = 0xffffffffu;

// Index of a 1D element from a 2D dispatch (large buffers need more
// workgroups than one dimension allows).
fn flat_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.y * groups.x * CLEAR_WORKGROUP + id.x;
}

// Sets every key to CLEAR_KEY (u64::MAX): "no fragment yet" (in a frame of
// the midpoint depth filter, both depths: none yet).
@compute @workgroup_size(256)
fn clear(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(id, groups);
    if (i < arrayLength(&keys)) {
        keys[i] = vec2<u32>(CLEAR_WORD, CLEAR_WORD);
    }
}

// The colour of a sample's key: its packed colour, or the background.
fn key_color(key: vec2<u32>) -> vec3<f32> {
    if (key.x == CLEAR_WORD && key.y == CLEAR_WORD) {
        return params.background.xyz;
    }
    return vec3<f32>(
        f32(key.x & 0x3ffu) / 1023.0,
        f32((key.x >> 10u) & 0x3ffu) / 1023.0,
        f32((key.x >> 20u) & 0x3ffu) / 1023.0,
    );
}

// reyes::sampling::sample_offset of sample s of the pixel at absolute
// coordinates (gx, gy).
fn sample_offset(gx: u32, gy: u32, s: u32) -> vec2<f32> {
    let kf = f32(params.k);
    var offset = vec2<f32>((f32(s % params.k) + 0.5) / kf, (f32(s / params.k) + 0.5) / kf);
    if (params.jitter != 0u) {
        let jx = (f32(jitter_hash(gx, gy, s, 0u)) / 4294967296.0 - 0.5) / kf;
        let jy = (f32(jitter_hash(gx, gy, s, 1u)) / 4294967296.0 - 0.5) / kf;
        offset += vec2<f32>(jx, jy);
    }
    return offset;
}

// reyes::filter: RenderMan's windowed sinc in one axis.
fn windowed_sinc(x: f32, width: f32) -> f32 {
    if (x == 0.0) {
        return 1.0;
    }
    let px = PI * x;
    return cos(0.5 * px / width) * sin(px) / px;
}

// reyes::filter::PixelFilter::weight: the weight of a sample (x, y)
// pixels from the pixel's centre, 0 outside the window.
fn filter_weight(x: f32, y: f32) -> f32 {
    let hx = 0.5 * params.xwidth;
    let hy = 0.5 * params.ywidth;
    if (abs(x) > hx || abs(y) > hy) {
        return 0.0;
    }
    switch params.filter_kind {
        case FILTER_TRIANGLE: {
            return (1.0 - abs(x) / hx) * (1.0 - abs(y) / hy);
        }
        case FILTER_GAUSSIAN: {
            let u = x / hx;
            let v = y / hy;
            return exp(-2.0 * (u * u + v * v));
        }
        case FILTER_CATMULL_ROM: {
            let r2 = x * x + y * y;
            let r = sqrt(r2);
            if (r < 1.0) {
                return 3.0 * r * r2 - 5.0 * r2 + 2.0;
            }
            if (r < 2.0) {
                return -r * r2 + 5.0 * r2 - 8.0 * r + 4.0;
            }
            return 0.0;
        }
        case FILTER_SINC: {
            return windowed_sinc(x, params.xwidth) * windowed_sinc(y, params.ywidth);
        }
        default: {
            // FILTER_BOX.
            return 1.0;
        }
    }
}

// The pixel of invocation `local` of workgroup `group`: one workgroup per
// 8x8 tile of pixels, the tiles numbered row by row over both dispatch
// dimensions. May lie past the frame's edge.
fn tile_pixel(group: vec3<u32>, local: vec3<u32>, groups: vec3<u32>) -> vec2<u32> {
    let tiles_x = (params.width + 7u) / 8u;
    let tile = group.y * groups.x + group.x;
    return vec2<u32>((tile % tiles_x) * 8u + local.x, (tile / tiles_x) * 8u + local.y);
}

// reyes::reference::resolve::resolve: the filter-weighted mean of the
// samples of the pixels around this one (uncovered ones take the
// background; pixels outside the frame are missing and the weights are
// normalized), or the plain mean of its own samples where the window holds
// no weight; linear, alpha 1.
//
// One workgroup per 8x8 tile of pixels, the tiles numbered row by row and
// dispatched over two dimensions (`tile_of`): a wide or a tall frame has
// more tiles in a row or a column than one dimension allows.
@compute @workgroup_size(8, 8)
fn resolve(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let id = tile_pixel(group, local, groups);
    if (id.x >= params.width || id.y >= params.height) {
        return;
    }
    let pixel = id.y * params.width + id.x;
    var own = vec3<f32>(0.0);
    var covered = 0u;
    for (var s = 0u; s < params.spp; s += 1u) {
        let key = keys[pixel * params.spp + s];
        if (!(key.x == CLEAR_WORD && key.y == CLEAR_WORD)) {
            covered += 1u;
        }
        own += key_color(key);
    }
    var sum = vec3<f32>(0.0);
    var weights = 0.0;
    let y0 = id.y - min(id.y, params.radius_y);
    let y1 = min(id.y + params.radius_y, params.height - 1u);
    let x0 = id.x - min(id.x, params.radius_x);
    let x1 = min(id.x + params.radius_x, params.width - 1u);
    for (var qy = y0; qy <= y1; qy += 1u) {
        for (var qx = x0; qx <= x1; qx += 1u) {
            let ox = f32(qx) - f32(id.x) - 0.5;
            let oy = f32(qy) - f32(id.y) - 0.5;
            let q = qy * params.width + qx;
            for (var s = 0u; s < params.spp; s += 1u) {
                let offset = sample_offset(qx + params.origin_x, qy + params.origin_y, s);
                let w = filter_weight(ox + offset.x, oy + offset.y);
                if (w != 0.0) {
                    sum += key_color(keys[q * params.spp + s]) * w;
                    weights += w;
                }
            }
        }
    }
    var c = own * (1.0 / f32(params.spp));
    if (weights > 0.0) {
        c = sum / weights;
    }
    image[pixel] = vec4<f32>(c, 1.0);
    coverage[pixel] = covered;
}

// reyes::depth::DepthProjection::view_depth: the camera-space depth of NDC
// depth d.
fn view_depth(d: f32) -> f32 {
    let range = params.depth_far - params.depth_near;
    if (params.depth_perspective != 0u) {
        return params.depth_near * params.depth_far / (params.depth_far - d * range);
    }
    return params.depth_near + d * range;
}

// reyes::reference::resolve_depth: the minimum (or the maximum, or the
// mean in sample order) over the pixel's own covered samples of each
// sample's depth: its nearest surface's
// camera-space depth, or with the midpoint filter the mean of that and the
// second-nearest's (which such a frame keeps in the key's low word,
// offer_second_depth.wgsl), +inf where there is none. Written raw as
// (depth, finite, 0, covered), 1 or 0 each flag, for
// reyes::depth::finish_depths (WGSL has no infinite constant).
// Tiles as in `resolve`.
@compute @workgroup_size(8, 8)
fn resolve_depth(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let id = tile_pixel(group, local, groups);
    if (id.x >= params.width || id.y >= params.height) {
        return;
    }
    let pixel = id.y * params.width + id.x;
    var depth = 0.0;
    var finite = false;
    var covered = 0u;
    for (var s = 0u; s < params.spp; s += 1u) {
        let index = pixel * params.spp + s;
        let key = keys[index];
        if (key.y == CLEAR_WORD) {
            continue;
        }
        covered += 1u;
        var z = view_depth(bitcast<f32>(key.y));
        if (params.depth_filter == DEPTH_FILTER_MIDPOINT) {
            let second = key.x;
            if (second == CLEAR_WORD) {
                continue;
            }
            z = 0.5 * (z + view_depth(bitcast<f32>(second)));
        }
        if (params.depth_filter == DEPTH_FILTER_MAX) {
            depth = select(z, max(depth, z), finite);
        } else if (params.depth_filter == DEPTH_FILTER_AVERAGE) {
            depth = select(z, depth + z, finite);
        } else {
            depth = select(z, min(depth, z), finite);
        }
        finite = true;
    }
    if (params.depth_filter == DEPTH_FILTER_AVERAGE && finite) {
        depth = depth / f32(covered);
    }
    image[pixel] = vec4<f32>(depth, select(0.0, 1.0, finite), 0.0, select(0.0, 1.0, covered != 0u));
    coverage[pixel] = covered;
}
