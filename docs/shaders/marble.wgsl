// Marble: veins from turbulence (sums of |snoise|) along x, over a
// plastic-like base. A surface shader for the Reyes renderer
// (docs/shaders.md); parameters as in RenderMan's example shaders.
struct Parameters {
    Ka: f32,
    Kd: f32,
    Ks: f32,
    roughness: f32,
    veining: f32,
    vein_color: vec3<f32>,
}

const DEFAULTS = Parameters(1.0, 0.8, 0.4, 0.08, 6.0, vec3<f32>(0.15, 0.1, 0.08));

// Four octaves of |snoise|, each half the size and weight of the last.
fn turbulence(p: vec3<f32>) -> f32 {
    var sum = 0.0;
    var scale = 1.0;
    for (var octave = 0; octave < 4; octave += 1) {
        sum += abs(snoise3(p * scale)) / scale;
        scale *= 2.0;
    }
    return sum;
}

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let p = ctx.P * 0.7;
    // Thin dark veins where the turbulent stripes cross zero.
    let vein = abs(sin(params.veining * (p.x + 1.5 * turbulence(p))));
    let base = mix(params.vein_color, ctx.Cs, smoothstep(0.0, 0.4, vein));
    let V = view_direction(ctx);
    let Ci = base * (params.Ka * ambient() + params.Kd * diffuse(ctx, ctx.N))
        + params.Ks * specular(ctx, ctx.N, V, params.roughness);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}
