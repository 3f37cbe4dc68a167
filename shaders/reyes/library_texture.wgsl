// Textures: anisotropic trilinear filtering of mip-mapped RGBA textures stored as f16
// pairs (two pack2x16float words per texel, decoded by texture_unpack). Every function repeats its
// Rust twin in reyes/src/texture/sample.rs operation for operation, on the
// same texels, so the GPU and the CPU reference filter alike.
//
// The module declares the TextureInfo struct (reyes::texture::TextureInfo)
// and four functions that read the tables of
// reyes::texture::TextureSet::gpu_tables, wherever the module keeps them:
//   texture_count() -> u32                  textures (ids 0 .. count)
//   texture_info(id: u32) -> TextureInfo    one entry per texture id
//   texture_packed_count() -> u32           texels of every mip chain
//   texture_packed(at: u32) -> vec2<u32>    texel `at`, level 0 first

// reyes::texture::Wrap::code.
const TEXTURE_WRAP_PERIODIC: u32 = 0u;
const TEXTURE_WRAP_CLAMP: u32 = 1u;
const TEXTURE_WRAP_BLACK: u32 = 2u;

// reyes::texture::MAX_ANISOTROPY: the most probes along a footprint.
const TEXTURE_MAX_ANISOTROPY: u32 = 16u;

// std::f32::consts::PI and TAU, as f32 (the nearest f32 to the decimal).
const TEXTURE_PI: f32 = 3.1415927;
const TEXTURE_TAU: f32 = 6.2831855;

// reyes::texture::sample::Level.
struct TextureLevel {
    offset: u32,
    width: u32,
    height: u32,
}

// reyes::texture::sample::Probes.
struct TextureProbes {
    lod: f32,
    count: u32,
    major_axis: vec2<f32>,
}

// The two taps along one axis and the blend between them
// (reyes::texture::sample::taps returns them as a tuple).
struct TextureTaps {
    i0: i32,
    i1: i32,
    f: f32,
}

// reyes::texture::sample::is_finite.
fn texture_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// reyes::texture::sample::level.
fn texture_level(info: TextureInfo, level: u32) -> TextureLevel {
    var at = TextureLevel(info.offset, info.width, info.height);
    for (var k = 0u; k < level; k++) {
        at.offset += at.width * at.height;
        at.width = max(at.width / 2u, 1u);
        at.height = max(at.height / 2u, 1u);
    }
    return at;
}

// reyes::texture::sample::wrap_index.
fn texture_wrap_index(i: i32, n: u32, wrap: u32) -> i32 {
    let size = i32(n);
    if (wrap == TEXTURE_WRAP_PERIODIC) {
        return ((i % size) + size) % size;
    } else if (wrap == TEXTURE_WRAP_CLAMP) {
        return clamp(i, 0, size - 1);
    } else if (i < 0 || i >= size) {
        return -1;
    }
    return i;
}

// reyes::texture::sample::taps.
fn texture_taps(s: f32, n: u32, wrap: u32) -> TextureTaps {
    let size = f32(n);
    var x: f32;
    if (wrap == TEXTURE_WRAP_PERIODIC) {
        x = (s - floor(s)) * size - 0.5;
    } else {
        x = clamp(s * size - 0.5, -1.0, size);
    }
    let x0 = floor(x);
    let i = i32(x0);
    return TextureTaps(texture_wrap_index(i, n, wrap), texture_wrap_index(i + 1, n, wrap), x - x0);
}

// One f16 (the low 16 bits of `bits`) as f32, exactly: WGSL's
// unpack2x16float done with integer operations, which need no shader
// capability (naga asks SHADER_FLOAT16_IN_FLOAT32 for unpack2x16float).
// The set stores no infinity or NaN. Twin of half::f16::to_f32 in
// reyes::texture::mipmap::unpack.
fn texture_half(bits: u32) -> f32 {
    let sign = (bits & 0x8000u) << 16u;
    let exponent = (bits >> 10u) & 0x1fu;
    let mantissa = bits & 0x3ffu;
    if (exponent == 0u) {
        // Zero or subnormal: mantissa * 2^-24, a normal f32.
        return bitcast<f32>(sign | bitcast<u32>(ldexp(f32(mantissa), -24)));
    }
    // Normal: the exponent rebiased from 15 to 127.
    return bitcast<f32>(sign | ((exponent + 112u) << 23u) | (mantissa << 13u));
}

// reyes::texture::mipmap::unpack.
fn texture_unpack(packed: vec2<u32>) -> vec4<f32> {
    return vec4<f32>(
        texture_half(packed.x & 0xffffu),
        texture_half(packed.x >> 16u),
        texture_half(packed.y & 0xffffu),
        texture_half(packed.y >> 16u),
    );
}

// reyes::texture::sample::texel.
fn texture_texel(level: TextureLevel, i: i32, j: i32) -> vec4<f32> {
    if (i < 0 || j < 0) {
        return vec4<f32>(0.0);
    }
    let at = level.offset + u32(j) * level.width + u32(i);
    if (at >= texture_packed_count()) {
        return vec4<f32>(0.0);
    }
    return texture_unpack(texture_packed(at));
}

// reyes::texture::sample::bilinear.
fn texture_bilinear(info: TextureInfo, index: u32, st: vec2<f32>) -> vec4<f32> {
    let at = texture_level(info, index);
    let s = texture_taps(st.x, at.width, info.wrap_s);
    let t = texture_taps(st.y, at.height, info.wrap_t);
    let t00 = texture_texel(at, s.i0, t.i0);
    let t10 = texture_texel(at, s.i1, t.i0);
    let t01 = texture_texel(at, s.i0, t.i1);
    let t11 = texture_texel(at, s.i1, t.i1);
    let top = t00 + (t10 - t00) * s.f;
    let bottom = t01 + (t11 - t01) * s.f;
    return top + (bottom - top) * t.f;
}

// reyes::texture::sample::axis_texels.
fn texture_axis_texels(info: TextureInfo, axis: vec2<f32>) -> f32 {
    let x = axis.x * f32(info.width);
    let y = axis.y * f32(info.height);
    return sqrt(x * x + y * y);
}

// reyes::texture::sample::probes.
fn texture_probes(info: TextureInfo, axis_a: vec2<f32>, axis_b: vec2<f32>) -> TextureProbes {
    let coarsest = f32(info.levels - 1u);
    let a = texture_axis_texels(info, axis_a);
    let b = texture_axis_texels(info, axis_b);
    if (!texture_is_finite(a) || !texture_is_finite(b)) {
        return TextureProbes(coarsest, 1u, vec2<f32>(0.0));
    }
    var major_axis = axis_a;
    var major = a;
    var minor = b;
    if (a < b) {
        major_axis = axis_b;
        major = b;
        minor = a;
    }
    let width = max(minor, major / f32(TEXTURE_MAX_ANISOTROPY));
    let count = u32(clamp(ceil(major / max(width, 1.0)), 1.0, f32(TEXTURE_MAX_ANISOTROPY)));
    var lod = 0.0;
    if (width > 1.0) {
        lod = min(log2(width), coarsest);
    }
    return TextureProbes(lod, count, major_axis);
}

// reyes::texture::sample::trilinear.
fn texture_trilinear(info: TextureInfo, st: vec2<f32>, lod: f32) -> vec4<f32> {
    let base = floor(lod);
    let blend = lod - base;
    let fine = u32(base);
    let c0 = texture_bilinear(info, fine, st);
    if (blend <= 0.0) {
        return c0;
    }
    let c1 = texture_bilinear(info, min(fine + 1u, info.levels - 1u), st);
    return c0 + (c1 - c0) * blend;
}

// reyes::texture::sample::sample (reyes::texture::TextureSet::sample): the
// filtered linear RGBA of texture `id` at `st`, for a footprint spanning
// `axis_a` and `axis_b` in (s, t). An unknown id or a non-finite `st` gives
// transparent black.
fn texture_sample(id: u32, st: vec2<f32>, axis_a: vec2<f32>, axis_b: vec2<f32>) -> vec4<f32> {
    if (id >= texture_count()) {
        return vec4<f32>(0.0);
    }
    return texture_filter(texture_info(id), st, axis_a, axis_b);
}

// reyes::texture::sample::filter: texture `info` at `st` over the
// footprint, with info's wrap modes; a non-finite `st` gives transparent
// black.
fn texture_filter(info: TextureInfo, st: vec2<f32>, axis_a: vec2<f32>, axis_b: vec2<f32>) -> vec4<f32> {
    if (!texture_is_finite(st.x) || !texture_is_finite(st.y)) {
        return vec4<f32>(0.0);
    }
    let probes = texture_probes(info, axis_a, axis_b);
    let count = f32(probes.count);
    var sum = vec4<f32>(0.0);
    for (var i = 0u; i < probes.count; i++) {
        let along = (f32(i) + 0.5) / count - 0.5;
        sum += texture_trilinear(info, st + probes.major_axis * along, probes.lod);
    }
    return sum / count;
}

// ------------------------------------------------ latitude-longitude maps
// RenderMan's environment(name, R) over a latitude-longitude map: the
// convention, the footprint and the edge cases are documented on the twin,
// reyes::texture::environment.

// reyes::texture::environment::latlong_st.
fn texture_latlong_st(r: vec3<f32>) -> vec2<f32> {
    let rho = sqrt(r.x * r.x + r.y * r.y);
    var longitude = 0.0;
    if (rho != 0.0) {
        longitude = atan2(r.y, r.x);
    }
    let latitude = atan2(r.z, rho);
    return vec2<f32>(longitude / TEXTURE_TAU, 0.5 - latitude / TEXTURE_PI);
}

// reyes::texture::environment::latlong_axis.
fn texture_latlong_axis(r: vec3<f32>, dr: vec3<f32>) -> vec2<f32> {
    if (dr.x == 0.0 && dr.y == 0.0 && dr.z == 0.0) {
        return vec2<f32>(0.0);
    }
    let rho2 = r.x * r.x + r.y * r.y;
    let rho = sqrt(rho2);
    let r2 = rho2 + r.z * r.z;
    let ds = (r.x * dr.y - r.y * dr.x) / (TEXTURE_TAU * rho2);
    let dt = -(rho2 * dr.z - r.z * (r.x * dr.x + r.y * dr.y)) / (TEXTURE_PI * rho * r2);
    return vec2<f32>(ds, dt);
}

// reyes::texture::environment::environment
// (reyes::texture::TextureSet::environment): texture `id` as a
// latitude-longitude environment map seen along `r`, over the footprint of
// the direction's changes `dr_du` and `dr_dv`; periodic in longitude and
// clamped in latitude, whatever the texture's wrap modes.
fn texture_environment(id: u32, r: vec3<f32>, dr_du: vec3<f32>, dr_dv: vec3<f32>) -> vec4<f32> {
    if (id >= texture_count()) {
        return vec4<f32>(0.0);
    }
    if (!texture_is_finite(r.x) || !texture_is_finite(r.y) || !texture_is_finite(r.z)) {
        return vec4<f32>(0.0);
    }
    if (r.x == 0.0 && r.y == 0.0 && r.z == 0.0) {
        return vec4<f32>(0.0);
    }
    var info = texture_info(id);
    info.wrap_s = TEXTURE_WRAP_PERIODIC;
    info.wrap_t = TEXTURE_WRAP_CLAMP;
    return texture_filter(
        info,
        texture_latlong_st(r),
        texture_latlong_axis(r, dr_du),
        texture_latlong_axis(r, dr_dv),
    );
}
