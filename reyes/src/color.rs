//! Colour conversions and the packed formats used by the sample framebuffer.
//!
//! Shading happens in linear RGB. A micropolygon's colour is stored in the
//! framebuffer in 30 bits (10 per channel) next to its depth, in one 64-bit
//! *sample key*: depth in the high 32 bits, colour in the low 32 bits. Taking
//! the `u64` minimum of keys therefore keeps the nearest fragment, and breaks
//! depth ties by the smaller packed colour, so the result does not depend on
//! the order in which fragments arrive (this is what lets a GPU use one
//! `atomicMin` per sample).

use glam::Vec3;

/// The key of a sample that no fragment has covered (the framebuffer's clear value).
pub const CLEAR_KEY: u64 = u64::MAX;

/// Largest value of one 10-bit channel.
const CHANNEL_MAX: f32 = 1023.0;

/// Converts one linear channel value to sRGB (the IEC 61966-2-1 transfer
/// function). The input is clamped to `[0, 1]`.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Converts one sRGB channel value to linear. The input is clamped to `[0, 1]`.
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Encodes a linear channel value as an 8-bit sRGB value (rounded to nearest).
pub fn linear_to_srgb8(c: f32) -> u8 {
    // The clamp in linear_to_srgb keeps the product within [0, 255].
    (linear_to_srgb(c) * 255.0).round() as u8
}

/// Quantizes one channel to 10 bits: `round(clamp(c, 0, 1) * 1023)`.
/// NaN maps to 0.
fn quantize10(c: f32) -> u32 {
    // `as` saturates and maps NaN to 0, so this never panics.
    (c.clamp(0.0, 1.0) * CHANNEL_MAX).round() as u32
}

/// Packs a linear colour into 30 bits: `r | g << 10 | b << 20`, each channel
/// `round(clamp(c, 0, 1) * 1023)`.
pub fn pack_rgb10(color: Vec3) -> u32 {
    quantize10(color.x) | (quantize10(color.y) << 10) | (quantize10(color.z) << 20)
}

/// The average of four packed colours, channel by channel in integers:
/// `(c0 + c1 + c2 + c3 + 2) / 4` (a micropolygon's colour from its corners').
pub fn average_rgb10(colors: [u32; 4]) -> u32 {
    let channel = |shift: u32| {
        let sum: u32 = colors.iter().map(|c| (c >> shift) & 0x3ff).sum();
        ((sum + 2) / 4) << shift
    };
    channel(0) | channel(10) | channel(20)
}

/// The colour of a sample inside a triangle whose corners `a`, `b`, `c`
/// carry the packed colours `colors`, from the sample's edge functions
/// `edges = [E_bc, E_ca, E_ab]` (their sum is the triangle's doubled area
/// `area`): channel by channel `round((E_bc a + E_ca b + E_ab c) / area)`,
/// the same barycentric weights the sample's depth uses. Three equal
/// colours (constant shading, the grids picture) are returned unchanged.
pub fn blend_rgb10(colors: [u32; 3], edges: [f32; 3], area: f32) -> u32 {
    if colors[0] == colors[1] && colors[1] == colors[2] {
        return colors[0];
    }
    let channel = |shift: u32| {
        let [a, b, c] = colors.map(|packed| ((packed >> shift) & 0x3ff) as f32);
        let value = (edges[0] * a + edges[1] * b + edges[2] * c) / area;
        // `as` saturates (and maps NaN to 0): the clamp keeps 10 bits.
        ((value + 0.5).floor() as u32).min(0x3ff) << shift
    };
    channel(0) | channel(10) | channel(20)
}

/// Unpacks a colour packed by [`pack_rgb10`] (the inverse up to quantization).
pub fn unpack_rgb10(packed: u32) -> Vec3 {
    let channel = |shift: u32| ((packed >> shift) & 0x3ff) as f32 / CHANNEL_MAX;
    Vec3::new(channel(0), channel(10), channel(20))
}

/// Builds a sample key: `(depth.to_bits() as u64) << 32 | packed_colour`.
///
/// For depths in `[0, 1]` (non-negative floats) the bit pattern increases with
/// the value, so comparing keys compares depths first.
pub fn pack_key(depth: f32, packed_color: u32) -> u64 {
    (u64::from(depth.to_bits()) << 32) | u64::from(packed_color)
}

/// The depth stored in a sample key.
pub fn key_depth(key: u64) -> f32 {
    f32::from_bits((key >> 32) as u32)
}

/// The packed colour stored in a sample key.
pub fn key_color(key: u64) -> u32 {
    (key & 0xffff_ffff) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blending_weighs_the_corners_barycentrically() {
        let (red, green, blue) = (0x3ff, 0x3ff << 10, 0x3ff << 20);
        // At a corner, that corner's colour; in the middle, a third each.
        assert_eq!(blend_rgb10([red, green, blue], [2.0, 0.0, 0.0], 2.0), red);
        assert_eq!(blend_rgb10([red, green, blue], [0.0, 0.0, 2.0], 2.0), blue);
        let third = blend_rgb10([red, green, blue], [1.0, 1.0, 1.0], 3.0);
        assert_eq!(third, 341 | (341 << 10) | (341 << 20));
        // Equal colours pass through exactly, whatever the weights' rounding.
        let grey = 0x155 | (0x155 << 10) | (0x155 << 20);
        assert_eq!(blend_rgb10([grey; 3], [0.1, 0.7, 0.2000001], 1.0), grey);
        // Halfway between 0 and 1 rounds up; weights a hair over the area
        // stay within 10 bits.
        assert_eq!(blend_rgb10([0, 1, 0], [1.0, 1.0, 0.0], 2.0), 1);
        assert_eq!(
            blend_rgb10([red, red, 0], [1.0, 1.0000001, 0.0], 2.0) & 0x3ff,
            0x3ff
        );
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255u32 {
            let s = i as f32 / 255.0;
            let back = linear_to_srgb(srgb_to_linear(s));
            assert!((back - s).abs() < 1e-5, "{s} -> {back}");
            assert_eq!(linear_to_srgb8(srgb_to_linear(s)), i as u8);
        }
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(2.0), 255);
    }

    #[test]
    fn rgb10_packing() {
        assert_eq!(pack_rgb10(Vec3::ZERO), 0);
        assert_eq!(pack_rgb10(Vec3::ONE), 0x3fff_ffff);
        assert_eq!(pack_rgb10(Vec3::new(1.0, 0.0, 0.0)), 0x3ff);
        assert_eq!(pack_rgb10(Vec3::new(0.0, 1.0, 0.0)), 0x3ff << 10);
        assert_eq!(pack_rgb10(Vec3::new(0.0, 0.0, 1.0)), 0x3ff << 20);
        assert_eq!(pack_rgb10(Vec3::new(-3.0, f32::NAN, 7.0)), 0x3ff << 20);
        let c = Vec3::new(0.25, 0.5, 0.75);
        let back = unpack_rgb10(pack_rgb10(c));
        assert!((back - c).abs().max_element() <= 0.5 / 1023.0 + 1e-7);
    }

    #[test]
    fn keys_order_by_depth_then_colour() {
        let near = pack_key(0.25, 0x3fff_ffff);
        let far = pack_key(0.5, 0);
        assert!(near < far);
        assert!(pack_key(0.5, 1) < pack_key(0.5, 2));
        assert!(pack_key(1.0, 0x3fff_ffff) < CLEAR_KEY);
        assert_eq!(key_depth(near), 0.25);
        assert_eq!(key_color(near), 0x3fff_ffff);
    }
}
