// The host side of the interface's textures, compiled in with the user
// shaders that can sample them (reyes::gpu::graph; without user shaders,
// host_texture is a stub there).
// The frame's textures (library_texture.wgsl), kept in height_texels by
// their bits (reyes::gpu::buffers::FloatLayout).
fn texture_count() -> u32 {
    return frame.texture_count;
}

fn texture_info(id: u32) -> TextureInfo {
    let base = frame.texture_floats + 8u * id;
    var word: array<u32, 8>;
    for (var k = 0u; k < 8u; k += 1u) {
        word[k] = bitcast<u32>(height_texels[base + k]);
    }
    return TextureInfo(word[0], word[1], word[2], word[3], word[4], word[5], word[6], word[7]);
}

fn texture_packed_count() -> u32 {
    return frame.texel_count;
}

fn texture_packed(at: u32) -> vec2<u32> {
    let base = frame.texel_floats + 2u * at;
    return vec2<u32>(bitcast<u32>(height_texels[base]), bitcast<u32>(height_texels[base + 1u]));
}

fn host_texture(index: u32, st: vec2<f32>, axis_a: vec2<f32>, axis_b: vec2<f32>) -> vec4<f32> {
    return texture_sample(index, st, axis_a, axis_b);
}

fn host_environment(index: u32, R: vec3<f32>, dRdu: vec3<f32>, dRdv: vec3<f32>) -> vec4<f32> {
    return texture_environment(index, R, dRdu, dRdv);
}
