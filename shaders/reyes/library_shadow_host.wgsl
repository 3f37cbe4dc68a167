// The host side of the interface's shadow(): the user shaders' lookup on
// the frame's shadow maps (library_shadow.wgsl). Compiled in with user
// shaders in frames with shadow maps (reyes::gpu::graph; other frames with
// user shaders get a host_shadow that returns 0). Every step repeats
// reyes::surface_shader::ShadowSlot::occlusion.

fn host_shadow(id: ShadowId, p: vec3<f32>) -> f32 {
    // The renderer puts the map's table entry in `map`, or NO_SHADOW.
    if (id.map == NO_SHADOW) {
        return 0.0;
    }
    let map = shadow_map_entry(id.map);
    let at = shadow_locate(map, p);
    if (!at.inside) {
        return 0.0;
    }
    // ShadowFilter::grid_side of side * side samples.
    return shadow_occlusion_at(map, at, clamp(id.side, 1u, 16u), id.region, id.bias);
}
