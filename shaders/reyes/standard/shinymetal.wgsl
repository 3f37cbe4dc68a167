// RenderMan's shinymetal, written against the shader interface as a user
// shader is (a RIB "shinymetal" with a "texturename" runs it): metal that
// also reflects a latitude-longitude environment map along
// D = reflect(I, Nf), in world space (docs/shaders.md).
//
// world_x, world_y and world_z are RenderMan's vtransform("current",
// "world"): the images of the renderer's world axes in the space the map is
// read in. They are the identity by default (the renderer's world space, a
// TOML scene's); a RIB scene's are its camera's, since the renderer's world
// is RenderMan's camera space there (reyes::rib).
struct Parameters {
    Ka: f32,
    Ks: f32,
    Kr: f32,
    roughness: f32,
    texturename: TextureId,
    world_x: vec3<f32>,
    world_y: vec3<f32>,
    world_z: vec3<f32>,
}

const DEFAULTS = Parameters(
    1.0,
    1.0,
    1.0,
    0.1,
    TextureId(0u),
    vec3<f32>(1.0, 0.0, 0.0),
    vec3<f32>(0.0, 1.0, 0.0),
    vec3<f32>(0.0, 0.0, 1.0),
);

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let V = view_direction(ctx);
    // reflect(I, Nf), written out so that the Rust twin repeats it exactly.
    let R = ctx.I - 2.0 * dot3(ctx.N, ctx.I) * ctx.N;
    let D = R.x * params.world_x + R.y * params.world_y + R.z * params.world_z;
    let Ci = ctx.Cs * (params.Ka * ambient()
        + params.Ks * specular(ctx, ctx.N, V, params.roughness)
        + params.Kr * environment(ctx, params.texturename, D).rgb);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}
