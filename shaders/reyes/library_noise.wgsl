// RenderMan's noise and snoise: gradient noise after Perlin's improved
// noise (2002), the twin of reyes/src/noise.rs, with the same arithmetic
// in the same order (each function names the Rust function it mirrors).
//
// Not a module on its own: reyes::noise::noise_wgsl() puts the constants
// it shares with Rust before it (NOISE_PERMUTATION, generated from
// reyes::noise::PERMUTATION, the NOISE*_BOUND and the VNOISE_OFFSET_*).
// Helpers are prefixed noise_ so as not to collide with the renderer's
// other libraries.

// The table, in a variable: a constant array indexed at run time is
// copied into a local before every access (naga's SPIR-V spills it), which
// makes the 4D noise's 64 lookups slow to run and very slow to compile.
var<private> noise_permutation: array<u32, 64> = NOISE_PERMUTATION;

// reyes::noise::perm: PERMUTATION[i mod 256], four entries to a word.
fn noise_perm(i: u32) -> u32 {
    let j = i & 255u;
    return (noise_permutation[j >> 2u] >> ((j & 3u) * 8u)) & 255u;
}

// reyes::noise::lattice: x = the cell modulo 256 (exact), y = the offset
// of x in its cell.
fn noise_lattice(x: f32) -> vec2<f32> {
    let cell = floor(x);
    let wrapped = cell - 256.0 * floor(cell / 256.0);
    return vec2<f32>(wrapped, x - cell);
}

// reyes::noise::fade.
fn noise_fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// reyes::noise::lerp.
fn noise_lerp(t: f32, a: f32, b: f32) -> f32 {
    return a + t * (b - a);
}

// reyes::noise::grad1.
fn noise_grad1(h: u32, x: f32) -> f32 {
    let g = f32((h & 7u) + 1u) * 0.125;
    return select(-g * x, g * x, (h & 8u) == 0u);
}

// reyes::noise::grad2.
fn noise_grad2(hash: u32, x: f32, y: f32) -> f32 {
    let h = hash & 7u;
    let u0 = select(y, x, h < 6u);
    let v0 = select(0.0, y, h < 4u);
    let u = select(-u0, u0, (h & 1u) == 0u);
    let v = select(-v0, v0, (h & 2u) == 0u);
    return u + v;
}

// reyes::noise::grad3.
fn noise_grad3(hash: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15u;
    let u0 = select(y, x, h < 8u);
    let v0 = select(select(z, x, h == 12u || h == 14u), y, h < 4u);
    let u = select(-u0, u0, (h & 1u) == 0u);
    let v = select(-v0, v0, (h & 2u) == 0u);
    return u + v;
}

// reyes::noise::grad4.
fn noise_grad4(hash: u32, x: f32, y: f32, z: f32, w: f32) -> f32 {
    let h = hash & 31u;
    let u0 = select(y, x, h < 24u);
    let v0 = select(z, y, h < 16u);
    let t0 = select(w, z, h < 8u);
    let u = select(-u0, u0, (h & 1u) == 0u);
    let v = select(-v0, v0, (h & 2u) == 0u);
    let t = select(-t0, t0, (h & 4u) == 0u);
    return u + v + t;
}

// reyes::noise::unit.
fn noise_unit(sum: f32, bound: f32) -> f32 {
    return clamp(0.5 + 0.5 * (sum / bound), 0.0, 1.0);
}

// The hashes of reyes::noise's closures `h`.
fn noise_hash2(x: u32, y: u32) -> u32 {
    return noise_perm(noise_perm(x) + y);
}

fn noise_hash3(x: u32, y: u32, z: u32) -> u32 {
    return noise_perm(noise_perm(noise_perm(x) + y) + z);
}

fn noise_hash4(x: u32, y: u32, z: u32, w: u32) -> u32 {
    return noise_perm(noise_perm(noise_perm(noise_perm(x) + y) + z) + w);
}

// reyes::noise::perlin1.
fn noise_perlin1(px: f32) -> f32 {
    let lx = noise_lattice(px);
    let xi = u32(lx.x);
    let x = lx.y;
    let u = noise_fade(x);
    return noise_lerp(u, noise_grad1(noise_perm(xi), x), noise_grad1(noise_perm(xi + 1u), x - 1.0));
}

// reyes::noise::perlin2.
fn noise_perlin2(p: vec2<f32>) -> f32 {
    let lx = noise_lattice(p.x);
    let ly = noise_lattice(p.y);
    let xi = u32(lx.x);
    let yi = u32(ly.x);
    let x = lx.y;
    let y = ly.y;
    let u = noise_fade(x);
    let v = noise_fade(y);
    return noise_lerp(
        v,
        noise_lerp(u, noise_grad2(noise_hash2(xi, yi), x, y), noise_grad2(noise_hash2(xi + 1u, yi), x - 1.0, y)),
        noise_lerp(
            u,
            noise_grad2(noise_hash2(xi, yi + 1u), x, y - 1.0),
            noise_grad2(noise_hash2(xi + 1u, yi + 1u), x - 1.0, y - 1.0),
        ),
    );
}

// reyes::noise::perlin3.
fn noise_perlin3(p: vec3<f32>, offset: vec3<u32>) -> f32 {
    let lx = noise_lattice(p.x);
    let ly = noise_lattice(p.y);
    let lz = noise_lattice(p.z);
    let xi = u32(lx.x) + offset.x;
    let yi = u32(ly.x) + offset.y;
    let zi = u32(lz.x) + offset.z;
    let x = lx.y;
    let y = ly.y;
    let z = lz.y;
    let u = noise_fade(x);
    let v = noise_fade(y);
    let w = noise_fade(z);
    let x1 = x - 1.0;
    let y1 = y - 1.0;
    let z1 = z - 1.0;
    return noise_lerp(
        w,
        noise_lerp(
            v,
            noise_lerp(u, noise_grad3(noise_hash3(xi, yi, zi), x, y, z), noise_grad3(noise_hash3(xi + 1u, yi, zi), x1, y, z)),
            noise_lerp(u, noise_grad3(noise_hash3(xi, yi + 1u, zi), x, y1, z), noise_grad3(noise_hash3(xi + 1u, yi + 1u, zi), x1, y1, z)),
        ),
        noise_lerp(
            v,
            noise_lerp(u, noise_grad3(noise_hash3(xi, yi, zi + 1u), x, y, z1), noise_grad3(noise_hash3(xi + 1u, yi, zi + 1u), x1, y, z1)),
            noise_lerp(
                u,
                noise_grad3(noise_hash3(xi, yi + 1u, zi + 1u), x, y1, z1),
                noise_grad3(noise_hash3(xi + 1u, yi + 1u, zi + 1u), x1, y1, z1),
            ),
        ),
    );
}

// reyes::noise::perlin4_slice.
fn noise_perlin4_slice(cell: vec4<u32>, x: f32, y: f32, z: f32, w: f32, u: f32, v: f32, s: f32) -> f32 {
    let xi = cell.x;
    let yi = cell.y;
    let zi = cell.z;
    let wi = cell.w;
    let x1 = x - 1.0;
    let y1 = y - 1.0;
    let z1 = z - 1.0;
    return noise_lerp(
        s,
        noise_lerp(
            v,
            noise_lerp(
                u,
                noise_grad4(noise_hash4(xi, yi, zi, wi), x, y, z, w),
                noise_grad4(noise_hash4(xi + 1u, yi, zi, wi), x1, y, z, w),
            ),
            noise_lerp(
                u,
                noise_grad4(noise_hash4(xi, yi + 1u, zi, wi), x, y1, z, w),
                noise_grad4(noise_hash4(xi + 1u, yi + 1u, zi, wi), x1, y1, z, w),
            ),
        ),
        noise_lerp(
            v,
            noise_lerp(
                u,
                noise_grad4(noise_hash4(xi, yi, zi + 1u, wi), x, y, z1, w),
                noise_grad4(noise_hash4(xi + 1u, yi, zi + 1u, wi), x1, y, z1, w),
            ),
            noise_lerp(
                u,
                noise_grad4(noise_hash4(xi, yi + 1u, zi + 1u, wi), x, y1, z1, w),
                noise_grad4(noise_hash4(xi + 1u, yi + 1u, zi + 1u, wi), x1, y1, z1, w),
            ),
        ),
    );
}

// reyes::noise::perlin4.
fn noise_perlin4(p: vec3<f32>, t: f32) -> f32 {
    let lx = noise_lattice(p.x);
    let ly = noise_lattice(p.y);
    let lz = noise_lattice(p.z);
    let lw = noise_lattice(t);
    let cell = vec4<u32>(u32(lx.x), u32(ly.x), u32(lz.x), u32(lw.x));
    let x = lx.y;
    let y = ly.y;
    let z = lz.y;
    let w = lw.y;
    let u = noise_fade(x);
    let v = noise_fade(y);
    let s = noise_fade(z);
    let r = noise_fade(w);
    return noise_lerp(
        r,
        noise_perlin4_slice(cell, x, y, z, w, u, v, s),
        noise_perlin4_slice(cell + vec4<u32>(0u, 0u, 0u, 1u), x, y, z, w - 1.0, u, v, s),
    );
}

// reyes::noise::noise1.
fn noise1(x: f32) -> f32 {
    return noise_unit(noise_perlin1(x), NOISE1_BOUND);
}

// reyes::noise::noise2.
fn noise2(p: vec2<f32>) -> f32 {
    return noise_unit(noise_perlin2(p), NOISE2_BOUND);
}

// reyes::noise::noise3.
fn noise3(p: vec3<f32>) -> f32 {
    return noise_unit(noise_perlin3(p, vec3<u32>(0u)), NOISE3_BOUND);
}

// reyes::noise::noise4.
fn noise4(p: vec3<f32>, t: f32) -> f32 {
    return noise_unit(noise_perlin4(p, t), NOISE4_BOUND);
}

// reyes::noise::vnoise3.
fn vnoise3(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        noise3(p),
        noise_unit(noise_perlin3(p, VNOISE_OFFSET_1), NOISE3_BOUND),
        noise_unit(noise_perlin3(p, VNOISE_OFFSET_2), NOISE3_BOUND),
    );
}

// reyes::noise::snoise1.
fn snoise1(x: f32) -> f32 {
    return 2.0 * noise1(x) - 1.0;
}

// reyes::noise::snoise2.
fn snoise2(p: vec2<f32>) -> f32 {
    return 2.0 * noise2(p) - 1.0;
}

// reyes::noise::snoise3.
fn snoise3(p: vec3<f32>) -> f32 {
    return 2.0 * noise3(p) - 1.0;
}

// reyes::noise::snoise4.
fn snoise4(p: vec3<f32>, t: f32) -> f32 {
    return 2.0 * noise4(p, t) - 1.0;
}

// reyes::noise::svnoise3.
fn svnoise3(p: vec3<f32>) -> vec3<f32> {
    return 2.0 * vnoise3(p) - vec3<f32>(1.0);
}
