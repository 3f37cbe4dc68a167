// ------------------------------------------------------ surface shader shadows
//
// RenderMan's shadow(name, P) for surface shaders: part of the interface
// (docs/shaders.md, "Shadow maps"), compiled into the megakernel with the
// user shaders only.

// A shadow map, as a shader parameter of this type names one: the scene
// gives its file and its filter (reyes::surface_shader::ShadowDesc), and
// the renderer fills in every field (reyes::surface_shader::ShadowSlot).
struct ShadowId {
    // Where the map lies in the renderer's buffers (none: no shadow).
    map: u32,
    // The side of the lookups' square grid.
    side: u32,
    // The filter region's width in texels, blur included.
    region: f32,
    // How far behind the nearest surface the light sees a point must lie
    // to be in its shadow, in world units.
    bias: f32,
}

// RenderMan's shadow(name, P): the fraction of the filter region around
// the world-space point P's place in the map whose surfaces lie nearer the
// light than P, less the bias, percentage-closer filtered: 0 lit, 1 in
// shadow. 0 where P falls outside the map, or the scene gives no map.
// reyes::surface_shader::ShadowSlot::occlusion.
fn shadow(id: ShadowId, P: vec3<f32>) -> f32 {
    return host_shadow(id, P);
}
