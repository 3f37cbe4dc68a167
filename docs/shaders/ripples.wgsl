// Ripples for docs/shaders.md: a displacement shader that moves P along N
// by rings of a sine around the patch's middle, roughened by noise.
struct Parameters {
    amplitude: f32,
    rings: f32,
    roughness: f32,
}

const DEFAULTS = Parameters(0.04, 3.0, 0.3);

fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32> {
    let r = length(vec2<f32>(ctx.s, ctx.t) - vec2<f32>(0.5));
    let wave = sin(6.2831855 * params.rings * r);
    let grain = params.roughness * snoise3(ctx.P * 6.0);
    return ctx.P + ctx.N * params.amplitude * (wave + grain);
}
