// A displacement shader that reads every input of the shading context a
// displacement shader sees, with noise and a texture, for the
// GPU-against-reference test (tests/tests/reyes_displacement_shaders_gpu.rs
// holds its Rust twin, term for term).
struct Parameters {
    amplitude: f32,
    frequency: f32,
    bumps: TextureId,
}

const DEFAULTS = Parameters(0.04, 3.0, TextureId(0u));

fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32> {
    let wave = sin(6.2831855 * params.frequency * (ctx.s + 0.5 * ctx.t));
    let grain = snoise3(ctx.P * 4.0);
    let bump = texture(ctx, params.bumps, ctx.u, ctx.v).r;
    // The view and the parametrization, weakly: a displaced point may
    // depend on anything fixed over the frame.
    let facing = 0.2 * dot(normalize(ctx.E - ctx.P), ctx.N) + 0.1 * dot(normalize(ctx.I), ctx.Ng);
    let stretch = 0.05 * length(cross(ctx.dPdu, ctx.dPdv)) + 0.1 * (ctx.dstdu.x + ctx.dstdv.y);
    let steps = ctx.du + ctx.dv + ctx.time;
    let h = params.amplitude * (wave + 0.5 * grain + bump + facing + stretch + ctx.Cs.g) + steps;
    return ctx.P + ctx.N * h + ctx.Os * 0.0;
}
