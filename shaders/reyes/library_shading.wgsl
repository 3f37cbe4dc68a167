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

// reyes::reference::shade::shade_with: Lambert + two-sided Blinn-Phong
// (the normal already faces the eye), clamped to [0, 1].
fn shade(position: vec3<f32>, normal: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    let view = normalize_or_zero(towards_eye(position));
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    for (var l = 0u; l < frame.light_count; l += 1u) {
        let light = lights[l];
        // reyes::prepare::PreparedLight::at: w = 1 marks a point light,
        // whose xyz is its position.
        var to_light = light.to_light.xyz;
        var falloff = 1.0;
        if (light.to_light.w != 0.0) {
            let toward = light.to_light.xyz - position;
            falloff = 1.0 / max(dot3(toward, toward), POINT_LIGHT_MIN_DISTANCE_SQUARED);
            to_light = normalize_or_zero(toward);
        }
        diffuse += light.radiance.xyz * (max(dot3(normal, to_light), 0.0) * falloff);
        let half_vector = normalize_or_zero(to_light + view);
        specular += light.radiance.xyz * (pow_nonneg(max(dot3(normal, half_vector), 0.0), frame.shininess) * falloff);
    }
    let color = albedo * (vec3<f32>(frame.ambient) + diffuse) + specular * frame.specular_strength;
    return clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
}

