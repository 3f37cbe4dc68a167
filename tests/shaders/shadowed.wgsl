// The object's colour where the shadow map `key` lets the light through:
// Ci = Cs (1 - shadow(key, P)) (1 - shadow(fill, P)). `fill`, which the
// test leaves out, names no map and so never shadows.
struct Parameters {
    key: ShadowId,
    fill: ShadowId,
}

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let lit = (1.0 - shadow(params.key, ctx.P)) * (1.0 - shadow(params.fill, ctx.P));
    return SurfaceOutput(ctx.Cs * lit, ctx.Os);
}
