// The host side of the surface shader interface, stubbed out: a user's
// surface shader is checked against surface_api.wgsl and these alone
// (reyes::surface_shader::check), never against the renderer's buffers.
fn host_light_count() -> u32 {
    return 0u;
}

fn host_light(i: u32, position: vec3<f32>) -> LightSample {
    return LightSample(vec3<f32>(0.0), vec3<f32>(0.0));
}

fn host_ambient() -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn host_texture(index: u32, st: vec2<f32>, axis_a: vec2<f32>, axis_b: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(0.0);
}

fn host_environment(index: u32, R: vec3<f32>, dRdu: vec3<f32>, dRdv: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(0.0);
}

fn host_shadow(id: ShadowId, position: vec3<f32>) -> f32 {
    return 0.0;
}
