// RenderMan's paintedplastic, written against the shader interface as a user
// shader is (a RIB "paintedplastic" with a "texturename" runs it): plastic
// whose colour is Cs times a texture over s, t (docs/shaders.md).
struct Parameters {
    Ka: f32,
    Kd: f32,
    Ks: f32,
    roughness: f32,
    specularcolor: vec3<f32>,
    texturename: TextureId,
}

const DEFAULTS = Parameters(1.0, 0.5, 0.5, 0.1, vec3<f32>(1.0), TextureId(0u));

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let paint = texture(ctx, params.texturename, ctx.s, ctx.t).rgb;
    let V = view_direction(ctx);
    let Ci = ctx.Cs * paint * (params.Ka * ambient() + params.Kd * diffuse(ctx, ctx.N))
        + params.specularcolor * params.Ks * specular(ctx, ctx.N, V, params.roughness);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}
