//! Resolve: average each pixel's samples into an 8-bit sRGB image.

use glam::Vec3;
use image::{Rgba, RgbaImage};

use super::framebuffer::Framebuffer;
use crate::color::{CLEAR_KEY, key_color, linear_to_srgb8, unpack_rgb10};

/// Resolves the framebuffer: uncovered samples take the (linear) background,
/// covered samples their unpacked colour; the average is taken in linear
/// space and encoded as sRGB, alpha 255. Also returns, row-major, the
/// number of covered samples of every pixel.
pub fn resolve(framebuffer: &Framebuffer, background: Vec3) -> (RgbaImage, Vec<u8>) {
    let (width, height) = (framebuffer.width, framebuffer.height);
    let mut image = RgbaImage::new(width, height);
    let mut coverage = vec![0u8; width as usize * height as usize];
    let inv_spp = 1.0 / framebuffer.spp as f32;
    for y in 0..height {
        for x in 0..width {
            let mut sum = Vec3::ZERO;
            let mut covered = 0u8;
            for &key in framebuffer.pixel(x, y) {
                if key == CLEAR_KEY {
                    sum += background;
                } else {
                    covered += 1;
                    sum += unpack_rgb10(key_color(key));
                }
            }
            let c = sum * inv_spp;
            image.put_pixel(
                x,
                y,
                Rgba([
                    linear_to_srgb8(c.x),
                    linear_to_srgb8(c.y),
                    linear_to_srgb8(c.z),
                    255,
                ]),
            );
            coverage[y as usize * width as usize + x as usize] = covered;
        }
    }
    (image, coverage)
}
