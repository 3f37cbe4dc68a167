// Clearing and resolving the sample framebuffer (a plain compute shader, run
// around the megakernel). The framebuffer holds one 64-bit key per sample,
// (depth bits << 32) | packed colour; here it is viewed as pairs of u32
// words (little-endian: x = low word = colour, y = high word = depth), so
// neither entry point needs 64-bit atomics.

// `ResolveParams` and `CLEAR_WORKGROUP` are declared before this file from
// their Rust definitions (reyes::gpu::resolve).

@group(0) @binding(0) var<uniform> params: ResolveParams;
@group(0) @binding(1) var<storage, read_write> keys: array<vec2<u32>>;
// One RGBA8 pixel per word (r in the low byte), row-major.
@group(0) @binding(2) var<storage, read_write> image: array<u32>;
// The number of the pixel's samples that were covered.
@group(0) @binding(3) var<storage, read_write> coverage: array<u32>;

const CLEAR_WORD: u32 = 0xffffffffu;

// Index of a 1D element from a 2D dispatch (large buffers need more
// workgroups than one dimension allows).
fn flat_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.y * groups.x * CLEAR_WORKGROUP + id.x;
}

// Sets every key to CLEAR_KEY (u64::MAX): "no fragment yet".
@compute @workgroup_size(256)
fn clear(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(id, groups);
    if (i < arrayLength(&keys)) {
        keys[i] = vec2<u32>(CLEAR_WORD, CLEAR_WORD);
    }
}

// reyes::color::linear_to_srgb, then * 255 rounded half away from zero.
fn linear_to_srgb8(c_in: f32) -> u32 {
    let c = clamp(c_in, 0.0, 1.0);
    var s = c * 12.92;
    if (c > 0.0031308) {
        s = 1.055 * pow(c, 1.0 / 2.4) - 0.055;
    }
    let x = s * 255.0;
    let f = floor(x);
    return u32(select(f, f + 1.0, x - f >= 0.5));
}

// reyes::reference::resolve::resolve: linear average of the samples
// (uncovered ones take the background), sRGB-encoded, alpha 255.
@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.width || id.y >= params.height) {
        return;
    }
    let pixel = id.y * params.width + id.x;
    var sum = vec3<f32>(0.0);
    var covered = 0u;
    for (var s = 0u; s < params.spp; s += 1u) {
        let key = keys[pixel * params.spp + s];
        if (key.x == CLEAR_WORD && key.y == CLEAR_WORD) {
            sum += params.background.xyz;
        } else {
            covered += 1u;
            let packed = key.x;
            sum += vec3<f32>(
                f32(packed & 0x3ffu) / 1023.0,
                f32((packed >> 10u) & 0x3ffu) / 1023.0,
                f32((packed >> 20u) & 0x3ffu) / 1023.0,
            );
        }
    }
    let c = sum * (1.0 / f32(params.spp));
    image[pixel] = linear_to_srgb8(c.x) | (linear_to_srgb8(c.y) << 8u)
        | (linear_to_srgb8(c.z) << 16u) | (255u << 24u);
    coverage[pixel] = covered;
}
