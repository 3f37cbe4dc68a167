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

// reyes::sampling::sample_position: sample s of this image's pixel (x, y),
// in the full image's pixels (as the grid points are, see to_pixel).
fn sample_position(x: u32, y: u32, s: u32) -> vec2<f32> {
    let kf = f32(frame.k);
    let gx = x + frame.origin_x;
    let gy = y + frame.origin_y;
    var offset = vec2<f32>((f32(s % frame.k) + 0.5) / kf, (f32(s / frame.k) + 0.5) / kf);
    if (frame.jitter != 0u) {
        let jx = (f32(jitter_hash(gx, gy, s, 0u)) / 4294967296.0 - 0.5) / kf;
        let jy = (f32(jitter_hash(gx, gy, s, 1u)) / 4294967296.0 - 0.5) / kf;
        offset += vec2<f32>(jx, jy);
    }
    return vec2<f32>(f32(gx), f32(gy)) + offset;
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
