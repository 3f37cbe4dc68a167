//! The WGSL of `Refine`: the fixed-point integrand, a 64-bit atomic
//! accumulator, and the body mirroring the CPU's decision.

/// WGSL shared by the body: the integrand and a 64-bit atomic accumulator.
pub(crate) const WGSL_LIBRARY: &str = "
// The full 64-bit product a * b as (low, high), from 16-bit halves.
fn mul_wide(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let low = (p00 & 0xffffu) | (mid << 16u);
    let high = a1 * b1 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(low, high);
}

fn f(x: u32) -> u32 {
    var total = 0u;
    for (var j = 0u; j < arrayLength(&bumps); j += 1u) {
        let b = bumps[j];
        let d = select(x - b.center, b.center - x, b.center >= x);
        if (d < b.width) {
            let g = b.width * b.width - d * d;
            // height * g <= 2^25, so this is height * g^2 exactly; the shift
            // (8..=24, never 0 or 32) leaves at most height * 2^16.
            let p = mul_wide(b.height * g, g);
            total += (p.x >> b.shift) | (p.y << (32u - b.shift));
        }
    }
    return total;
}

// Adds `value` to the 64-bit counter (low, high) at tally[index]. Every wrap
// of the low word is seen by exactly one adder, which carries it, so the
// result is independent of the order of the additions.
fn add_u64(index: u32, value: u32) {
    let old = atomicAdd(&tally[index], value);
    if (old + value < old) {
        atomicAdd(&tally[index + 1u], 1u);
    }
}
";

/// The body of `Refine`, mirroring [`classify`].
pub(super) const REFINE_BODY: &str = "
if (valid) {
    let h = ROOT_WIDTH >> item.depth;
    let q = h / 4u;
    let fl = f(item.a + q);
    let fr = f(item.a + 3u * q);
    let t = item.fa + 4u * item.fm + item.fb;
    let tl = item.fa + 4u * fl + item.fm;
    let tr = item.fm + 4u * fr + item.fb;
    let diff = i32(tl + tr) - 2i * i32(t);
    let ok = u32(abs(diff)) <= THRESHOLD;
    if (ok || item.depth == MAX_DEPTH) {
        let base = TALLY_STRIDE * item.depth;
        atomicAdd(&tally[base], 1u);
        if (!ok) {
            atomicAdd(&tally[base + 1u], 1u);
        }
        add_u64(base + 2u, 8u * (tl + tr) - t);
    } else {
        enqueue_Refine(Interval(item.a, item.depth + 1u, item.fa, fl, item.fm));
        enqueue_Refine(Interval(item.a + h / 2u, item.depth + 1u, item.fm, fr, item.fb));
    }
}
";
