// A surface shader that reads every input of the shading context and
// every lighting helper, for the GPU-against-reference test
// (tests/tests/reyes_user_surfaces_gpu.rs holds its Rust twin).
struct Parameters {
    Kd: f32,
    tint: vec3<f32>,
    bands: u32,
    striped: bool,
}

const DEFAULTS = Parameters(0.7, vec3<f32>(1.0, 0.8, 0.6), 6u, true);

// A helper of the shader's own, named like nothing in the renderer: soft
// bands (a hard edge would move with the dicing, as it does in any Reyes
// renderer, and tiles may dice a little differently).
fn band(x: f32, count: u32) -> f32 {
    return 0.5 + 0.5 * sin(6.2831853 * x * f32(count));
}

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let V = -normalize(ctx.I);
    var stripe = 1.0;
    if (params.striped) {
        stripe = 0.6 + 0.4 * band(ctx.s + ctx.t, params.bands);
    }
    // Facing ratio from the geometric normal, and the grid's steps, the
    // tangents and the eye, each bounded so the colour stays in range.
    let facing = abs(dot(ctx.Ng, V));
    // du, dv change with the dicing (as RenderMan's do), so weighted lightly.
    let steps = clamp((ctx.du + ctx.dv) * 0.02, 0.0, 0.2);
    let tangents = clamp(length(cross(ctx.dPdu, ctx.dPdv)) * 0.05, 0.0, 0.2);
    let eye = clamp(dot(normalize(ctx.E - ctx.P), ctx.N) * 0.1, 0.0, 0.1);
    let lit = ambient() + diffuse(ctx, ctx.N) * params.Kd
        + specular(ctx, ctx.N, V, 0.2) * 0.5;
    var rim = vec3<f32>(0.0);
    // The lights within 1.2 radians of N, fading to zero at the cone's
    // edge (a hard edge would move with the dicing).
    for (var i = 0u; i < light_count(); i += 1u) {
        let light = illuminance(i, ctx.P, ctx.N, 1.2);
        rim += light.Cl * max(dot(light.L, ctx.N) - cos(1.2), 0.0) * 0.3;
    }
    let base = ctx.Cs * params.tint * stripe * (0.5 + 0.5 * facing);
    let Ci = base * lit + vec3<f32>(ctx.u * steps, ctx.v * tangents, eye) + rim + vec3<f32>(ctx.time);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}
