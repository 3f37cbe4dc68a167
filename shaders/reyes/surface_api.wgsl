// ------------------------------------------------------------ surface shaders
//
// The interface every surface shader is written against, the standard ones
// (surfaces_standard.wgsl) and the user's (reyes::surface_shader), as
// docs/shaders.md documents it. It reaches the renderer only through the
// read-only `host_*` functions, which the megakernel defines in
// library_shading.wgsl and the user shader check stubs out
// (surface_host_stub.wgsl), so that a user shader is checked on its own.

// What a surface shader sees at a shading point, with RenderMan's names.
// N and Ng are unit length and face the eye (RenderMan's Nf).
struct ShadingContext {
    // The point being shaded, in world space.
    P: vec3<f32>,
    // The shading normal (displaced, when the object is).
    N: vec3<f32>,
    // The geometric normal of the undisplaced surface.
    Ng: vec3<f32>,
    // The incident direction, from the eye to P (not normalized).
    I: vec3<f32>,
    // The eye.
    E: vec3<f32>,
    // The surface parameters in the input patch, and their step to the
    // neighbouring grid point.
    u: f32,
    v: f32,
    du: f32,
    dv: f32,
    // The texture coordinates (u, v unless the scene gives them).
    s: f32,
    t: f32,
    // The surface's derivatives along u and v.
    dPdu: vec3<f32>,
    dPdv: vec3<f32>,
    // The derivatives of (s, t) along u and along v.
    dstdu: vec2<f32>,
    dstdv: vec2<f32>,
    // The object's colour and opacity.
    Cs: vec3<f32>,
    Os: vec3<f32>,
    // The shading time, 0 at shutter open.
    time: f32,
}

// What a surface shader returns: RenderMan's Ci and Oi. Oi is recorded
// but not used: every surface is opaque.
struct SurfaceOutput {
    Ci: vec3<f32>,
    Oi: vec3<f32>,
}

// One light as seen from a point: the unit vector towards the light and
// its colour there (zero outside a spotlight's cone).
struct LightSample {
    L: vec3<f32>,
    Cl: vec3<f32>,
}

// A texture, as a shader parameter of this type names one: the scene
// gives its file (reyes::surface_shader::ParameterKind::Texture).
struct TextureId {
    index: u32,
}

// RenderMan's texture(name, s, t): the texture's filtered linear RGBA at
// (s, t), over the shading point's footprint in (s, t) (the grid's step
// along u and v). For coordinates that are not the context's s, t (scaled,
// say), use texture_footprint with their own footprint.
fn texture(ctx: ShadingContext, id: TextureId, s: f32, t: f32) -> vec4<f32> {
    return host_texture(id.index, vec2<f32>(s, t), ctx.dstdu * ctx.du, ctx.dstdv * ctx.dv);
}

// The texture's filtered RGBA at `st` over the footprint spanned by
// `axis_a` and `axis_b` in (s, t).
fn texture_footprint(id: TextureId, st: vec2<f32>, axis_a: vec2<f32>, axis_b: vec2<f32>) -> vec4<f32> {
    return host_texture(id.index, st, axis_a, axis_b);
}

// RenderMan's environment(name, R): texture `id` read as a
// latitude-longitude environment map along the world-space direction `R`
// (any length), RenderMan's convention: s = 0 to 1 is longitude 0 to 360
// degrees, atan2(R.y, R.x), periodic; t = 0 to 1 is latitude +90 (+z, the
// top of the picture) to -90 degrees, clamped. Bilinear in the finest level:
// the shader gives no derivative of R, which its change across the
// micropolygon needs (environment_footprint takes one). A zero or
// non-finite R gives transparent black. reyes::texture::environment.
fn environment(ctx: ShadingContext, id: TextureId, R: vec3<f32>) -> vec4<f32> {
    return host_environment(id.index, R, vec3<f32>(0.0), vec3<f32>(0.0));
}

// The environment along `R` filtered over the footprint of R's change
// across the micropolygon, `dRdu` along u and `dRdv` along v (each already
// times the grid's step, as dPdu * du is).
fn environment_footprint(id: TextureId, R: vec3<f32>, dRdu: vec3<f32>, dRdv: vec3<f32>) -> vec4<f32> {
    return host_environment(id.index, R, dRdu, dRdv);
}

// The number of lights that illuminate (ambient lights are in ambient()).
fn light_count() -> u32 {
    return host_light_count();
}

// RenderMan's illuminance(P, axis, angle) for light `i`: the light's L
// and Cl when L is within `angle` (radians) of `axis`, else Cl = 0.
fn illuminance(i: u32, P: vec3<f32>, axis: vec3<f32>, angle: f32) -> LightSample {
    var light = host_light(i, P);
    if (dot(light.L, axis) <= cos(angle) * length(axis)) {
        light.Cl = vec3<f32>(0.0);
    }
    return light;
}

// RenderMan's ambient(): the sum of the ambient lights.
fn ambient() -> vec3<f32> {
    return host_ambient();
}

// RenderMan's diffuse(N): the sum over the lights within 90 degrees of N
// of Cl * (N . L). N must be unit length.
// reyes::reference::shade::Lighting::diffuse.
fn diffuse(ctx: ShadingContext, N: vec3<f32>) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < host_light_count(); i += 1u) {
        let light = host_light(i, ctx.P);
        let cosine = dot3(N, light.L);
        if (cosine > 0.0) {
            sum += light.Cl * cosine;
        }
    }
    return sum;
}

// RenderMan's specular(N, V, roughness): the sum over the lights within
// 90 degrees of N of Cl * max(N . H, 0)^(1 / roughness), H the unit half
// vector of L and V. N and V must be unit length.
// reyes::reference::shade::Lighting::specular.
fn specular(ctx: ShadingContext, N: vec3<f32>, V: vec3<f32>, roughness: f32) -> vec3<f32> {
    let exponent = min(1.0 / roughness, MAX_SPECULAR_EXPONENT);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < host_light_count(); i += 1u) {
        let light = host_light(i, ctx.P);
        if (dot3(N, light.L) > 0.0) {
            let H = normalize_or_zero(light.L + V);
            sum += light.Cl * pow_nonneg(max(dot3(N, H), 0.0), exponent);
        }
    }
    return sum;
}

// The unit vector from P towards the eye (RenderMan's -normalize(I)).
fn view_direction(ctx: ShadingContext) -> vec3<f32> {
    return normalize_or_zero(-ctx.I);
}

// Rust's powf on [0, inf): 0^0 = 1, 0^y = 0; WGSL leaves pow(0, y) undefined.
fn pow_nonneg(x: f32, y: f32) -> f32 {
    if (x <= 0.0) {
        return select(0.0, 1.0, y == 0.0);
    }
    return pow(x, y);
}

// RenderMan's smoothstep(min, max, x): a step where min == max (WGSL's
// smoothstep is undefined for min >= max).
// reyes::shading::smoothstep.
fn smoothstep_rm(lo: f32, hi: f32, x: f32) -> f32 {
    if (x < lo) {
        return 0.0;
    }
    if (x >= hi) {
        return 1.0;
    }
    let t = (x - lo) / (hi - lo);
    return t * t * (3.0 - 2.0 * t);
}
