//! Mip chains: the level sizes, the box-filtered reduction and the packed
//! f16 storage.
//!
//! Level `k + 1` is `max(1, floor(w / 2)) x max(1, floor(h / 2))` texels for
//! a level `k` of `w x h` (OpenGL's rule), down to 1 x 1: `floor(log2(max(w,
//! h))) + 1` levels. Every level covers the whole image, `[0, 1]` in s and t.
//!
//! Each texel of the smaller level is the area-weighted average of the
//! texels of the larger level under it (a box filter). Along an even side
//! that is the usual 2 x 2 average. Along an odd side `n = 2m + 1` a new
//! texel spans `n / m` old ones (a little over two), so it takes three with
//! weights such as `(m, m, 1) / n`, `(m - 1, m, 2) / n`, ...: no old texel
//! is dropped or counted twice, and the image does not shift. The weights
//! are exact rationals, computed in integers, applied along s then t.
//!
//! The chain is built in `f32` from the decoded image, each level from the
//! unrounded one above it, and only then packed to f16 for storage.

use glam::Vec4;
use half::f16;

use super::load::LinearImage;

/// Number of levels of a `width x height` chain: `floor(log2(max side)) + 1`.
pub fn level_count(width: u32, height: u32) -> u32 {
    u32::BITS - width.max(height).max(1).leading_zeros()
}

/// The side after `side` in the chain.
pub fn next_side(side: u32) -> u32 {
    (side / 2).max(1)
}

/// Texels of the whole chain of a `width x height` image.
pub fn chain_texels(width: u32, height: u32) -> u64 {
    let (mut w, mut h) = (width, height);
    let mut texels = 0u64;
    for _ in 0..level_count(width, height) {
        texels += u64::from(w) * u64::from(h);
        (w, h) = (next_side(w), next_side(h));
    }
    texels
}

/// Stores an RGBA texel as WGSL's `pack2x16float` would: `[pack(r, g),
/// pack(b, a)]`, the first component of each pair in the low 16 bits.
/// Values round to the nearest f16 (ties to even); finite values beyond the
/// f16 range clamp to +-65504.
pub fn pack(texel: Vec4) -> [u32; 2] {
    let half = |c: f32| {
        u32::from(f16::from_f32(c.clamp(f32::from(f16::MIN), f32::from(f16::MAX))).to_bits())
    };
    [
        half(texel.x) | (half(texel.y) << 16),
        half(texel.z) | (half(texel.w) << 16),
    ]
}

/// The texel [`pack`] stored: WGSL's `unpack2x16float` of each word.
pub fn unpack(packed: [u32; 2]) -> Vec4 {
    let half = |bits: u32| f32::from(f16::from_bits(bits as u16));
    Vec4::new(
        half(packed[0] & 0xffff),
        half(packed[0] >> 16),
        half(packed[1] & 0xffff),
        half(packed[1] >> 16),
    )
}

/// The box weights of a reduction from `n` texels to `m = next_side(n)`
/// along one axis: for each new texel, the old texels it covers and their
/// weights (summing to 1).
///
/// New texel `i` spans `[i n / m, (i + 1) n / m)` in old texels. Measured in
/// units of `1 / m` old texel, it spans `[i n, (i + 1) n)` and old texel `j`
/// spans `[j m, (j + 1) m)`, so their overlap is an integer and the weight
/// is `overlap / n`.
fn box_weights(n: u32, m: u32) -> Vec<Vec<(usize, f32)>> {
    let (n, m) = (u64::from(n), u64::from(m));
    (0..m)
        .map(|i| {
            let (start, end) = (i * n, (i + 1) * n);
            (start / m..end.div_ceil(m))
                .filter_map(|j| {
                    let overlap = end.min((j + 1) * m).saturating_sub(start.max(j * m));
                    (overlap > 0).then(|| (j as usize, (overlap as f64 / n as f64) as f32))
                })
                .collect()
        })
        .collect()
}

/// The next level of the chain after `image`.
fn reduce(image: &LinearImage) -> LinearImage {
    let (w, h) = (image.width as usize, image.height as usize);
    let (w2, h2) = (next_side(image.width), next_side(image.height));
    // Along s first: h rows of w2 texels.
    let across = box_weights(image.width, w2);
    let mut rows = Vec::with_capacity(h * w2 as usize);
    for y in 0..h {
        let row = &image.texels[y * w..(y + 1) * w];
        rows.extend(across.iter().map(|taps| {
            taps.iter()
                .fold(Vec4::ZERO, |sum, &(x, weight)| sum + row[x] * weight)
        }));
    }
    // Then along t.
    let down = box_weights(image.height, h2);
    let mut texels = Vec::with_capacity(w2 as usize * h2 as usize);
    for taps in &down {
        for x in 0..w2 as usize {
            texels.push(taps.iter().fold(Vec4::ZERO, |sum, &(y, weight)| {
                sum + rows[y * w2 as usize + x] * weight
            }));
        }
    }
    LinearImage {
        width: w2,
        height: h2,
        texels,
    }
}

/// The packed chain of `image`, level 0 first, each level row-major.
pub(super) fn build(image: LinearImage) -> Vec<[u32; 2]> {
    let levels = level_count(image.width, image.height);
    let total = chain_texels(image.width, image.height);
    let mut packed = Vec::with_capacity(usize::try_from(total).unwrap_or(0));
    let mut level = image;
    for k in 0..levels {
        packed.extend(level.texels.iter().map(|&t| pack(t)));
        if k + 1 < levels {
            level = reduce(&level);
        }
    }
    packed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_counts_follow_the_longer_side() {
        assert_eq!(level_count(1, 1), 1);
        assert_eq!(level_count(2, 1), 2);
        assert_eq!(level_count(3, 3), 2);
        assert_eq!(level_count(4, 3), 3);
        assert_eq!(level_count(5, 200), 8);
        assert_eq!(level_count(4096, 4096), 13);
    }

    #[test]
    fn weights_cover_every_old_texel_once() {
        for n in 1..40u32 {
            let m = next_side(n);
            let weights = box_weights(n, m);
            assert_eq!(weights.len(), m as usize);
            // Each new texel's weights sum to 1; each old texel's weights,
            // summed over the new texels, to m / n (its share of the total).
            let mut per_old = vec![0.0f64; n as usize];
            for taps in &weights {
                let sum: f64 = taps.iter().map(|&(_, w)| f64::from(w)).sum();
                assert!((sum - 1.0).abs() < 1e-6, "n = {n}: {taps:?}");
                for &(j, w) in taps {
                    per_old[j] += f64::from(w);
                }
            }
            for share in per_old {
                assert!(
                    (share - f64::from(m) / f64::from(n)).abs() < 1e-6,
                    "n = {n}"
                );
            }
        }
        // The odd case written out: 5 -> 2, each new texel spans 2.5 old.
        assert_eq!(
            box_weights(5, 2),
            vec![
                vec![(0, 0.4), (1, 0.4), (2, 0.2)],
                vec![(2, 0.2), (3, 0.4), (4, 0.4)]
            ]
        );
    }

    #[test]
    fn pack_rounds_like_f16_and_unpacks_exactly() {
        let t = Vec4::new(0.1, 1.0, -2.5, 70000.0);
        let back = unpack(pack(t));
        assert_eq!(back.x, f32::from(f16::from_f32(0.1)));
        assert_eq!(back.y, 1.0);
        assert_eq!(back.z, -2.5);
        assert_eq!(back.w, 65504.0);
        // The low half holds the first component.
        assert_eq!(pack(Vec4::new(1.0, 0.0, 0.0, 0.0)), [0x3c00, 0]);
    }
}
