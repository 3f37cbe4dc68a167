// Pure arithmetic helpers, free of the renderer's globals: the megakernel's
// library and the surface shader interface (surface_api.wgsl, which user
// shaders are checked against on their own) both use them.

// ------------------------------------------------------------ float helpers

// Written with bit tests: the driver may assume no NaN/Inf in comparisons.
fn is_finite_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_nan_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

fn is_finite3(v: vec3<f32>) -> bool {
    return is_finite_f32(v.x) && is_finite_f32(v.y) && is_finite_f32(v.z);
}

fn is_finite4(v: vec4<f32>) -> bool {
    return is_finite3(v.xyz) && is_finite_f32(v.w);
}

// ------------------------------------------------------------ vector helpers

// Rust's `f32::round` for x >= 0 (halves away from zero); WGSL's round()
// rounds halves to even, which would differ from the reference on ties.
fn round_half_up(x: f32) -> f32 {
    let f = floor(x);
    return select(f, f + 1.0, x - f >= 0.5);
}

fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// glam's cross product, term for term.
fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// glam's normalize_or_zero: v * (1 / |v|) when that reciprocal is finite and > 0.
fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    if (is_finite_f32(rcp) && rcp > 0.0) {
        return v * rcp;
    }
    return vec3<f32>(0.0);
}

fn dist2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    let d = b - a;
    return sqrt(d.x * d.x + d.y * d.y);
}

fn dist3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return sqrt(dot3(b - a, b - a));
}
