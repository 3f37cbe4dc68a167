// RenderMan's bumpy, written against the shader interface as a user
// displacement shader is (a RIB `Displacement "bumpy"` with a "texturename"
// runs it): P moves along N by Km times the texture's first channel at
// (s, t) (docs/shaders.md). The renderer takes the new normal from the
// displaced points, as the specification's `N = calculatenormal(P)` does.
struct Parameters {
    Km: f32,
    texturename: TextureId,
}

const DEFAULTS = Parameters(1.0, TextureId(0u));

fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32> {
    // N is unit length already (zero where the surface is degenerate, where
    // normalize would give NaN).
    let amp = params.Km * texture(ctx, params.texturename, ctx.s, ctx.t).r;
    return ctx.P + amp * ctx.N;
}
