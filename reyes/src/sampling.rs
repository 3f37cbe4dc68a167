//! Sample positions within a pixel, including the deterministic jitter hash.
//!
//! A pixel has `spp = k * k` samples on a `k x k` grid of strata. Sample
//! `s = syi * k + sxi` of pixel `(x, y)` is at
//! `(x + (sxi + 0.5) / k + jx, y + (syi + 0.5) / k + jy)`, where the jitter
//! `(jx, jy)` is zero unless jitter is enabled, in which case
//! `jx = (hash(x, y, s, 0) as f32 / 2^32 - 0.5) / k` and likewise `jy` with
//! channel 1: a uniform offset within the sample's stratum that is the same
//! on every run and on every device.

use glam::Vec2;

use crate::params::{HASH_MIX, HASH_MULTIPLIERS};

/// The jitter hash (PCG/murmur-style integer mixing, all arithmetic wrapping):
///
/// ```text
/// h = x*0x8da6b343 ^ y*0xd8163841 ^ s*0xcb1ab31f ^ c*0x165667b1
/// h ^= h >> 16; h *= 0x7feb352d; h ^= h >> 15; h *= 0x846ca68b; h ^= h >> 16
/// ```
pub fn hash(x: u32, y: u32, s: u32, c: u32) -> u32 {
    let [mx, my, ms, mc] = HASH_MULTIPLIERS;
    let mut h = x.wrapping_mul(mx) ^ y.wrapping_mul(my) ^ s.wrapping_mul(ms) ^ c.wrapping_mul(mc);
    h ^= h >> 16;
    h = h.wrapping_mul(HASH_MIX[0]);
    h ^= h >> 15;
    h = h.wrapping_mul(HASH_MIX[1]);
    h ^= h >> 16;
    h
}

/// `k = sqrt(spp)` for a valid (perfect-square) sample count.
pub fn grid_size(spp: u32) -> u32 {
    let k = f64::from(spp).sqrt().round() as u32;
    debug_assert_eq!(k * k, spp, "spp must be a perfect square");
    k
}

/// The offset of sample `s` inside pixel `(x, y)` (each coordinate in `[0, 1]`),
/// for `k * k` samples per pixel.
pub fn sample_offset(x: u32, y: u32, s: u32, k: u32, jitter: bool) -> Vec2 {
    let kf = k as f32;
    let (sxi, syi) = (s % k, s / k);
    let mut offset = Vec2::new((sxi as f32 + 0.5) / kf, (syi as f32 + 0.5) / kf);
    if jitter {
        const TWO_POW_32: f32 = 4_294_967_296.0;
        let jx = (hash(x, y, s, 0) as f32 / TWO_POW_32 - 0.5) / kf;
        let jy = (hash(x, y, s, 1) as f32 / TWO_POW_32 - 0.5) / kf;
        offset += Vec2::new(jx, jy);
    }
    offset
}

/// The position of sample `s` of pixel `(x, y)` in pixel coordinates.
pub fn sample_position(x: u32, y: u32, s: u32, k: u32, jitter: bool) -> Vec2 {
    Vec2::new(x as f32, y as f32) + sample_offset(x, y, s, k, jitter)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_known_values() {
        // Pinned so that a GPU port can check its implementation against these.
        assert_eq!(hash(0, 0, 0, 0), 0);
        let h = hash(1, 0, 0, 0);
        let mut e = 0x8da6_b343u32;
        e ^= e >> 16;
        e = e.wrapping_mul(0x7feb_352d);
        e ^= e >> 15;
        e = e.wrapping_mul(0x846c_a68b);
        e ^= e >> 16;
        assert_eq!(h, e);
        assert_ne!(hash(3, 4, 5, 0), hash(3, 4, 5, 1));
    }

    #[test]
    fn samples_stay_in_their_strata() {
        for k in 1..=8u32 {
            for s in 0..k * k {
                for jitter in [false, true] {
                    let o = sample_offset(17, 23, s, k, jitter);
                    let (sxi, syi) = ((s % k) as f32, (s / k) as f32);
                    let kf = k as f32;
                    assert!(o.x >= sxi / kf && o.x <= (sxi + 1.0) / kf, "{o} {k} {s}");
                    assert!(o.y >= syi / kf && o.y <= (syi + 1.0) / kf, "{o} {k} {s}");
                }
            }
        }
    }
}
