// A texture over s, t, marbled with noise: the texture and noise helpers
// of the shader interface, for the GPU-against-reference test
// (tests/tests/reyes_user_surfaces_gpu.rs holds its Rust twin).
struct Parameters {
    map: TextureId,
    veins: f32,
}

const DEFAULTS = Parameters(TextureId(0u), 0.15);

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let texel = texture(ctx, params.map, ctx.s, ctx.t);
    let marble = params.veins * snoise3(ctx.P * 3.0);
    let lit = ambient() + diffuse(ctx, ctx.N);
    let Ci = ctx.Cs * texel.rgb * lit + vec3<f32>(marble);
    return SurfaceOutput(Ci, ctx.Os);
}
