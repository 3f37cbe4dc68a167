// The texture alone, unlit: for the test that a texture seen at one texel
// per pixel comes back as it is (tests/tests/reyes_user_surfaces_gpu.rs).
struct Parameters {
    map: TextureId,
}

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    return SurfaceOutput(texture(ctx, params.map, ctx.s, ctx.t).rgb, ctx.Os);
}
