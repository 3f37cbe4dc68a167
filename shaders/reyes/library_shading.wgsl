// ------------------------------------------------------------ evaluation

// reyes::bezier::bernstein and bernstein_quadratic.
fn bernstein(t: f32) -> vec4<f32> {
    let mt = 1.0 - t;
    return vec4<f32>(mt * mt * mt, 3.0 * t * mt * mt, 3.0 * t * t * mt, t * t * t);
}

fn bernstein_quadratic(t: f32) -> vec3<f32> {
    let mt = 1.0 - t;
    return vec3<f32>(mt * mt, 2.0 * t * mt, t * t);
}

// sum over rows v of wv[v] * (sum over u of wu[u] * p[v * 4 + u]), rows
// written out in the reference's order.
fn tensor_row(p: ptr<function, array<f32, 48>>, v: u32, wu: vec4<f32>) -> vec3<f32> {
    return patch_point(p, v * 4u) * wu.x
        + patch_point(p, v * 4u + 1u) * wu.y
        + patch_point(p, v * 4u + 2u) * wu.z
        + patch_point(p, v * 4u + 3u) * wu.w;
}

fn tensor(p: ptr<function, array<f32, 48>>, wu: vec4<f32>, wv: vec4<f32>) -> vec3<f32> {
    var sum = tensor_row(p, 0u, wu) * wv.x;
    sum += tensor_row(p, 1u, wu) * wv.y;
    sum += tensor_row(p, 2u, wu) * wv.z;
    sum += tensor_row(p, 3u, wu) * wv.w;
    return sum;
}

// reyes::bezier::tangent_s: dP/ds in difference form, exactly zero along a
// collapsed edge (four equal points).
fn tangent_s_row(p: ptr<function, array<f32, 48>>, v: u32, q: vec3<f32>) -> vec3<f32> {
    let p0 = patch_point(p, v * 4u);
    let p1 = patch_point(p, v * 4u + 1u);
    let p2 = patch_point(p, v * 4u + 2u);
    let p3 = patch_point(p, v * 4u + 3u);
    return (p1 - p0) * q.x + (p2 - p1) * q.y + (p3 - p2) * q.z;
}

fn tangent_s(p: ptr<function, array<f32, 48>>, s: f32, wv: vec4<f32>) -> vec3<f32> {
    let q = bernstein_quadratic(s);
    var sum = tangent_s_row(p, 0u, q) * wv.x;
    sum += tangent_s_row(p, 1u, q) * wv.y;
    sum += tangent_s_row(p, 2u, q) * wv.z;
    sum += tangent_s_row(p, 3u, q) * wv.w;
    return sum * 3.0;
}

// reyes::bezier::tangent_t: dP/dt in difference form.
fn tangent_t_row(p: ptr<function, array<f32, 48>>, v: u32, wu: vec4<f32>) -> vec3<f32> {
    let d0 = patch_point(p, v * 4u + 4u) - patch_point(p, v * 4u);
    let d1 = patch_point(p, v * 4u + 5u) - patch_point(p, v * 4u + 1u);
    let d2 = patch_point(p, v * 4u + 6u) - patch_point(p, v * 4u + 2u);
    let d3 = patch_point(p, v * 4u + 7u) - patch_point(p, v * 4u + 3u);
    return d0 * wu.x + d1 * wu.y + d2 * wu.z + d3 * wu.w;
}

fn tangent_t(p: ptr<function, array<f32, 48>>, wu: vec4<f32>, t: f32) -> vec3<f32> {
    let q = bernstein_quadratic(t);
    var sum = tangent_t_row(p, 0u, wu) * q.x;
    sum += tangent_t_row(p, 1u, wu) * q.y;
    sum += tangent_t_row(p, 2u, wu) * q.z;
    return sum * 3.0;
}

// reyes::reference::dice::degenerate.
fn degenerate(n: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> bool {
    let n2 = dot3(n, n);
    return !(n2 > DEGENERATE_NORMAL_REL_EPS * (dot3(a, a) * dot3(b, b))) || n2 == 0.0;
}

// The unnormalized normal dP/ds x dP/dt at (s, t).
fn tangent_normal(p: ptr<function, array<f32, 48>>, s: f32, t: f32) -> vec3<f32> {
    let bs = bernstein(s);
    let bt = bernstein(t);
    let d_ds = tangent_s(p, s, bt);
    let d_dt = tangent_t(p, bs, t);
    let n = cross3(d_ds, d_dt);
    if (degenerate(n, d_ds, d_dt)) {
        return vec3<f32>(0.0);
    }
    return n;
}

// reyes::reference::dice::surface_point: the unit normal facing `eye` at
// (s, t), with the degenerate-edge fallback (tangents re-evaluated at the
// clamped parameters, then the direction to the eye, then +z).
fn surface_normal(p: ptr<function, array<f32, 48>>, s: f32, t: f32, position: vec3<f32>) -> vec3<f32> {
    let to_eye = towards_eye(position);
    var n = tangent_normal(p, s, t);
    if (all(n == vec3<f32>(0.0))) {
        n = tangent_normal(
            p,
            clamp(s, DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
            clamp(t, DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
        );
        if (all(n == vec3<f32>(0.0))) {
            n = to_eye;
        }
    }
    n = normalize_or_zero(n);
    if (all(n == vec3<f32>(0.0))) {
        n = vec3<f32>(0.0, 0.0, 1.0);
    }
    if (dot3(n, to_eye) < 0.0) {
        n = -n;
    }
    return n;
}

// ------------------------------------------------------------ shading

// reyes::reference::shade::Lighting::light_at: distantlight, pointlight
// and spotlight as RenderMan computes Cl (reyes::shading::PreparedLight::at),
// scaled by the fraction of the light its shadow maps let through
// (light_visibility: library_shadow.wgsl, or 1 in frames without shadows).
fn light_at(light: Light, position: vec3<f32>) -> LightSample {
    if (light.kind == LIGHT_DISTANT) {
        return LightSample(light.to_light.xyz, light.radiance.xyz * light_visibility(light, position));
    }
    let toward = light.to_light.xyz - position;
    let distance_squared = max(dot3(toward, toward), POINT_LIGHT_MIN_DISTANCE_SQUARED);
    let l = normalize_or_zero(toward);
    var attenuation = 1.0 / distance_squared;
    if (light.kind == LIGHT_SPOT) {
        let cos_angle = -dot3(l, light.axis.xyz);
        if (!(cos_angle >= light.cos_outside)) {
            return LightSample(l, vec3<f32>(0.0));
        }
        attenuation *= pow_nonneg(cos_angle, light.beam_distribution)
            * smoothstep_rm(light.cos_outside, light.cos_inside, cos_angle);
    }
    return LightSample(l, light.radiance.xyz * attenuation * light_visibility(light, position));
}

// The host side of the surface shader interface (surface_api.wgsl): the
// frame's lights, read-only.
fn host_light_count() -> u32 {
    return frame.light_count;
}

fn host_light(i: u32, position: vec3<f32>) -> LightSample {
    return light_at(lights[i], position);
}

// Slot `slot` of the user shaders' parameters (reyes::gpu::buffers::FloatLayout).
fn shader_parameter(slot: u32) -> vec4<f32> {
    let base = frame.parameter_floats + 4u * slot;
    return vec4<f32>(height_texels[base], height_texels[base + 1u], height_texels[base + 2u], height_texels[base + 3u]);
}

fn host_ambient() -> vec3<f32> {
    return vec3<f32>(frame.ambient_red, frame.ambient_green, frame.ambient_blue);
}

// reyes::prepare::WorldPatch::st_at: input patch `index`'s s, t at (u, v).
fn patch_st(index: u32, u: f32, v: f32) -> vec2<f32> {
    let base = frame.st_floats + 8u * index;
    let a = vec2<f32>(height_texels[base], height_texels[base + 1u]);
    let b = vec2<f32>(height_texels[base + 2u], height_texels[base + 3u]);
    let c = vec2<f32>(height_texels[base + 4u], height_texels[base + 5u]);
    let d = vec2<f32>(height_texels[base + 6u], height_texels[base + 7u]);
    let bottom = a + (b - a) * u;
    let top = c + (d - c) * u;
    return bottom + (top - bottom) * v;
}

// An input patch's s, t at (u, v) and their derivatives along u and v
// (reyes::prepare::WorldPatch::st_frame).
struct PatchSt {
    st: vec2<f32>,
    dstdu: vec2<f32>,
    dstdv: vec2<f32>,
}

fn patch_st_frame(index: u32, u: f32, v: f32) -> PatchSt {
    return PatchSt(
        patch_st(index, u, v),
        patch_st(index, 1.0, v) - patch_st(index, 0.0, v),
        patch_st(index, u, 1.0) - patch_st(index, u, 0.0),
    );
}

// The shading context of a grid point of the input patch `q` (number
// `input_patch`) at (u, v),
// moved to `position` with the unit normal `normal` facing the eye; `ng`
// is the undisplaced surface's (zero: the same as `normal`), `step` the
// grid's (du, dv).
fn shading_context(
    q: ptr<function, array<f32, 48>>,
    input_patch: u32,
    object: Object,
    position: vec3<f32>,
    normal: vec3<f32>,
    ng: vec3<f32>,
    uv: vec2<f32>,
    step: vec2<f32>,
) -> ShadingContext {
    let to_eye = towards_eye(position);
    let bu = bernstein(uv.x);
    let bv = bernstein(uv.y);
    let st = patch_st_frame(input_patch, uv.x, uv.y);
    return ShadingContext(
        position,
        normal,
        select(ng, normal, all(ng == vec3<f32>(0.0))),
        -to_eye,
        position + to_eye,
        uv.x,
        uv.y,
        step.x,
        step.y,
        st.st.x,
        st.st.y,
        tangent_s(q, uv.x, bv),
        tangent_t(q, bu, uv.y),
        st.dstdu,
        st.dstdv,
        object.color.xyz,
        vec3<f32>(1.0),
        0.0,
    );
}

// reyes::reference::shade::shade_surface: the object's surface shader
// (SURFACE_*, or the scene's user shader `object.user_shader`), its Ci
// clamped to [0, 1].
fn shade(ctx: ShadingContext, object: Object) -> vec3<f32> {
    var out = SurfaceOutput(ctx.Cs, ctx.Os);
    switch object.surface {
        case SURFACE_MATTE: {
            out = matte(ctx, object.ka, object.kd);
        }
        case SURFACE_METAL: {
            out = metal(ctx, object.ka, object.ks, object.roughness);
        }
        case SURFACE_PLASTIC: {
            out = plastic(ctx, object.ka, object.kd, object.ks, object.roughness, object.specular_color.xyz);
        }
        case SURFACE_DEFAULT_SURFACE: {
            out = defaultsurface(ctx, object.ka, object.kd);
        }
        case SURFACE_USER: {
            out = user_surface(object.user_shader, ctx, object.parameters);
        }
        default: {
            out = constant(ctx);
        }
    }
    return clamp(out.Ci, vec3<f32>(0.0), vec3<f32>(1.0));
}
