// Shadow maps: RenderMan's shadow() lookup, percentage-closer filtered.
// Every function repeats its Rust twin in reyes/src/shadow/mod.rs operation
// for operation, in the same order, so that the GPU and the CPU reference
// shadow alike (up to the GPU's float contraction).
//
// Compiled in only for frames where some light has a shadow
// (reyes::gpu::graph; other frames get a light_visibility that returns 1).
// The maps live in height_texels (reyes::gpu::buffers::FloatLayout): a
// table of SHADOW_MAP_FLOATS floats per map (reyes::gpu::shadow_maps:
// world-to-clip by columns, the world-to-camera z row, then width, height
// and first texel by their bits), and the depths, +inf stored as
// SHADOW_NO_DEPTH (f32::MAX) since WGSL has no infinity. A light points at
// its maps with shadow_table (the float offset of its first map's entry)
// and shadow_maps (how many).

// One map of the table: reyes::shadow::ShadowMap without its depths.
struct ShadowMapEntry {
    world_to_clip: mat4x4<f32>,
    camera_z: vec4<f32>,
    width: u32,
    height: u32,
    first_texel: u32,
}

// reyes::shadow::MapPoint, with `inside` for Option's Some.
struct ShadowMapPoint {
    inside: bool,
    texel: vec2<f32>,
    depth: f32,
}

fn shadow_vec4(at: u32) -> vec4<f32> {
    return vec4<f32>(height_texels[at], height_texels[at + 1u], height_texels[at + 2u], height_texels[at + 3u]);
}

// The table entry at float offset `at`.
fn shadow_map_entry(at: u32) -> ShadowMapEntry {
    return ShadowMapEntry(
        mat4x4<f32>(shadow_vec4(at), shadow_vec4(at + 4u), shadow_vec4(at + 8u), shadow_vec4(at + 12u)),
        shadow_vec4(at + 16u),
        bitcast<u32>(height_texels[at + 20u]),
        bitcast<u32>(height_texels[at + 21u]),
        bitcast<u32>(height_texels[at + 22u]),
    );
}

// reyes::shadow::camera_z: ((r.x x + r.y y) + r.z z) + r.w.
fn shadow_camera_z(row: vec4<f32>, p: vec3<f32>) -> f32 {
    return ((row.x * p.x + row.y * p.y) + row.z * p.z) + row.w;
}

// reyes::shadow::ShadowMap::locate. The tests on w and on the texel are
// written so that a NaN fails them, as in the reference; a non-finite
// point (which the reference never finds in a map either) is outside.
fn shadow_locate(map: ShadowMapEntry, p: vec3<f32>) -> ShadowMapPoint {
    let outside = ShadowMapPoint(false, vec2<f32>(0.0), 0.0);
    if (!is_finite3(p)) {
        return outside;
    }
    let m = map.world_to_clip;
    let clip = ((m[0] * p.x + m[1] * p.y) + m[2] * p.z) + m[3];
    if (is_nan_f32(clip.w) || clip.w <= 0.0) {
        return outside;
    }
    let x = clip.x / clip.w;
    let y = clip.y / clip.w;
    let width = f32(map.width);
    let height = f32(map.height);
    let texel = vec2<f32>((x * 0.5 + 0.5) * width, (0.5 - y * 0.5) * height);
    if (!is_finite_f32(texel.x) || !is_finite_f32(texel.y)) {
        return outside;
    }
    let inside = texel.x >= 0.0 && texel.x <= width && texel.y >= 0.0 && texel.y <= height;
    if (!inside) {
        return outside;
    }
    return ShadowMapPoint(true, texel, -shadow_camera_z(map.camera_z, p));
}

// reyes::shadow::ShadowMap::depth_at: texel (x, y) clamped to the edges.
// `x` and `y` are floors already clamped to [-1, width] and [-1, height]
// (shadow_compare_bilinear), so the i32s neither saturate nor overflow.
fn shadow_depth_at(map: ShadowMapEntry, x: i32, y: i32) -> f32 {
    let cx = u32(clamp(x, 0, i32(map.width) - 1));
    let cy = u32(clamp(y, 0, i32(map.height) - 1));
    return height_texels[map.first_texel + cy * map.width + cx];
}

// 1 where texel (x, y)'s nearest surface lies nearer than `depth`. An
// empty texel holds SHADOW_NO_DEPTH, which no finite depth exceeds
// (shadow_occlusion_at keeps `depth` at most that), as +inf in the reference.
fn shadow_occludes(map: ShadowMapEntry, x: i32, y: i32, depth: f32) -> f32 {
    return select(0.0, 1.0, shadow_depth_at(map, x, y) < depth);
}

// reyes::shadow::ShadowMap::compare_bilinear.
fn shadow_compare_bilinear(map: ShadowMapEntry, texel: vec2<f32>, depth: f32) -> f32 {
    let at = texel - 0.5;
    let x0 = floor(at.x);
    let y0 = floor(at.y);
    let fx = at.x - x0;
    let fy = at.y - y0;
    // Beyond the edges every texel clamps to the edge's: the same texels.
    let ix = i32(clamp(x0, -1.0, f32(map.width)));
    let iy = i32(clamp(y0, -1.0, f32(map.height)));
    let top = shadow_occludes(map, ix, iy, depth) * (1.0 - fx) + shadow_occludes(map, ix + 1, iy, depth) * fx;
    let bottom = shadow_occludes(map, ix, iy + 1, depth) * (1.0 - fx) + shadow_occludes(map, ix + 1, iy + 1, depth) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// reyes::shadow::ShadowMap::occlusion_at with a filter of `grid_side`
// lookups per side (ShadowFilter::grid_side, computed on the host, here
// narrowed to the region) over `region` texels (the filter's width plus
// its blur times the map's larger side), less `bias`.
fn shadow_occlusion_at(map: ShadowMapEntry, at: ShadowMapPoint, grid_side: u32, region: f32, bias: f32) -> f32 {
    // reyes::shadow::region_grid_side: one lookup per side more than the
    // texels the region spans, at most the samples' grid.
    let side = min(grid_side, u32(min(ceil(region) + 1.0, 16.0)));
    // A depth past f32's range compares as the reference's infinities do:
    // +inf as the largest depth (beyond every surface but the empty
    // texels'), -inf and NaN as one no texel lies nearer than.
    var depth = at.depth - bias;
    if (!is_finite_f32(depth)) {
        let positive = !is_nan_f32(depth) && (bitcast<u32>(depth) & 0x80000000u) == 0u;
        depth = select(-SHADOW_NO_DEPTH, SHADOW_NO_DEPTH, positive);
    }
    let step = region / f32(side);
    // reyes::shadow::grid_rotation: the grid turned by atan(1 / side).
    let norm = 1.0 / sqrt(f32(side * side + 1u));
    let grid_cos = f32(side) * norm;
    let grid_sin = norm;
    let half = 0.5 * f32(side - 1u);
    var sum = 0.0;
    for (var j = 0u; j < side; j += 1u) {
        for (var i = 0u; i < side; i += 1u) {
            let u = step * (f32(i) - half);
            let v = step * (f32(j) - half);
            let texel = vec2<f32>(at.texel.x + (grid_cos * u - grid_sin * v), at.texel.y + (grid_sin * u + grid_cos * v));
            sum += shadow_compare_bilinear(map, texel, depth);
        }
    }
    return sum / f32(side * side);
}

// reyes::shadow::LightShadowMaps::visibility: 1 - the occlusion in the
// first of the light's maps whose image holds `p`; 1 where none does.
fn light_visibility(light: Light, p: vec3<f32>) -> f32 {
    for (var k = 0u; k < light.shadow_maps; k += 1u) {
        let map = shadow_map_entry(light.shadow_table + k * SHADOW_MAP_FLOATS);
        let at = shadow_locate(map, p);
        if (at.inside) {
            let region = light.shadow_width + light.shadow_blur * f32(max(map.width, map.height));
            return 1.0 - shadow_occlusion_at(map, at, light.shadow_side, region, light.shadow_bias);
        }
    }
    return 1.0;
}
