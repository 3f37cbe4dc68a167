// ------------------------------------------------------------ standard surfaces
//
// RenderMan's standard surface shaders (RenderMan Interface Specification
// 3.2, "Standard RenderMan Shaders"), written against the surface shader
// interface (surface_api.wgsl) as a user's shader is. N faces the eye
// already (Nf). Their CPU twins: reyes::reference::shade::shade_surface.

fn constant(ctx: ShadingContext) -> SurfaceOutput {
    return SurfaceOutput(ctx.Os * ctx.Cs, ctx.Os);
}

fn matte(ctx: ShadingContext, Ka: f32, Kd: f32) -> SurfaceOutput {
    let Ci = ctx.Cs * (ambient() * Ka + diffuse(ctx, ctx.N) * Kd);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}

fn metal(ctx: ShadingContext, Ka: f32, Ks: f32, roughness: f32) -> SurfaceOutput {
    let V = view_direction(ctx);
    let Ci = ctx.Cs * (ambient() * Ka + specular(ctx, ctx.N, V, roughness) * Ks);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}

fn plastic(ctx: ShadingContext, Ka: f32, Kd: f32, Ks: f32, roughness: f32, specularcolor: vec3<f32>) -> SurfaceOutput {
    let V = view_direction(ctx);
    let Ci = ctx.Cs * (ambient() * Ka + diffuse(ctx, ctx.N) * Kd)
        + specularcolor * specular(ctx, ctx.N, V, roughness) * Ks;
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}

// d = normalize(I) . N, squared: a headlight that needs no lights.
fn defaultsurface(ctx: ShadingContext, Ka: f32, Kd: f32) -> SurfaceOutput {
    let d = dot3(view_direction(ctx), ctx.N);
    let Ci = ctx.Cs * (Ka + Kd * d * d);
    return SurfaceOutput(ctx.Os * Ci, ctx.Os);
}
