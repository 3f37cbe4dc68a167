// ------------------------------------------------------------ evaluation

// reyes::bezier::bernstein and bernstein_derivative.
fn bernstein(t: f32) -> vec4<f32> {
    let mt = 1.0 - t;
    return vec4<f32>(mt * mt * mt, 3.0 * t * mt * mt, 3.0 * t * t * mt, t * t * t);
}

fn bernstein_derivative(t: f32) -> vec4<f32> {
    let mt = 1.0 - t;
    return vec4<f32>(
        -3.0 * mt * mt,
        3.0 * mt * mt - 6.0 * t * mt,
        6.0 * t * mt - 3.0 * t * t,
        3.0 * t * t,
    );
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

// reyes::reference::dice::degenerate.
fn degenerate(n: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> bool {
    let n2 = dot3(n, n);
    return !(n2 > DEGENERATE_NORMAL_REL_EPS * (dot3(a, a) * dot3(b, b))) || n2 == 0.0;
}

// The unnormalized normal dP/ds x dP/dt at (s, t).
fn tangent_normal(p: ptr<function, array<f32, 48>>, s: f32, t: f32) -> vec3<f32> {
    let bs = bernstein(s);
    let bt = bernstein(t);
    let d_ds = tensor(p, bernstein_derivative(s), bt);
    let d_dt = tensor(p, bs, bernstein_derivative(t));
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

// Rust's powf on [0, inf): 0^0 = 1, 0^y = 0; WGSL leaves pow(0, y) undefined.
fn pow_nonneg(x: f32, y: f32) -> f32 {
    if (x <= 0.0) {
        return select(0.0, 1.0, y == 0.0);
    }
    return pow(x, y);
}

// reyes::shading::smoothstep: RenderMan's, a step where min == max (WGSL's
// smoothstep is undefined for min >= max).
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

// What a light gives a surface point: the unit vector towards the light
// and its colour there, Cl (zero outside a spotlight's cone).
struct LightSample {
    l: vec3<f32>,
    cl: vec3<f32>,
}

// reyes::shading::PreparedLight::at: distantlight, pointlight and
// spotlight as RenderMan computes Cl.
fn light_at(light: Light, position: vec3<f32>) -> LightSample {
    if (light.kind == LIGHT_DISTANT) {
        return LightSample(light.to_light.xyz, light.radiance.xyz);
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
    return LightSample(l, light.radiance.xyz * attenuation);
}

// RenderMan's diffuse(N) and specular(N, V, roughness) at once, over the
// lights within 90 degrees of the normal (reyes::reference::shade::Lighting).
// A light outside a spotlight's cone adds zeros, as the reference skips it.
struct Illumination {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

fn illuminance(position: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, exponent: f32) -> Illumination {
    var sum = Illumination(vec3<f32>(0.0), vec3<f32>(0.0));
    for (var i = 0u; i < frame.light_count; i += 1u) {
        let sample = light_at(lights[i], position);
        let cosine = dot3(normal, sample.l);
        if (cosine > 0.0) {
            sum.diffuse += sample.cl * cosine;
            let half_vector = normalize_or_zero(sample.l + view);
            sum.specular += sample.cl * pow_nonneg(max(dot3(normal, half_vector), 0.0), exponent);
        }
    }
    return sum;
}

// reyes::reference::shade::shade_surface: the object's standard surface
// shader (SURFACE_*), clamped to [0, 1]. The normal faces the eye (Nf).
fn shade(position: vec3<f32>, normal: vec3<f32>, object: Object) -> vec3<f32> {
    let cs = object.color.xyz;
    let view = normalize_or_zero(towards_eye(position));
    let ambient = vec3<f32>(frame.ambient_red, frame.ambient_green, frame.ambient_blue);
    var color = cs;
    switch object.surface {
        case SURFACE_MATTE: {
            let lit = illuminance(position, normal, view, 0.0);
            color = cs * (ambient * object.ka + lit.diffuse * object.kd);
        }
        case SURFACE_METAL: {
            let lit = illuminance(position, normal, view, object.specular_exponent);
            color = cs * (ambient * object.ka + lit.specular * object.ks);
        }
        case SURFACE_PLASTIC: {
            let lit = illuminance(position, normal, view, object.specular_exponent);
            color = cs * (ambient * object.ka + lit.diffuse * object.kd)
                + object.specular_color.xyz * lit.specular * object.ks;
        }
        case SURFACE_DEFAULT_SURFACE: {
            let d = dot3(view, normal);
            color = cs * (object.ka + object.kd * d * d);
        }
        default: {
            // SURFACE_CONSTANT: Ci = Cs.
        }
    }
    return clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
}
