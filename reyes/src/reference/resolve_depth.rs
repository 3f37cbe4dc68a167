//! The depth resolve ([`crate::depth`]): per pixel, the camera-space depth
//! of its samples' nearest surfaces, filtered by the scene's
//! [`DepthFilter`]. `resolve_depth` in `shaders/reyes/resolve.wgsl` mirrors
//! it operation for operation.

use image::{Rgba, Rgba32FImage};

use super::framebuffer::Framebuffer;
use crate::color::{CLEAR_KEY, key_depth};
use crate::depth::{DepthFilter, DepthProjection, mark_empty};

/// Resolves `framebuffer` into depths: per pixel, with [`DepthFilter::Min`],
/// the minimum over its own samples of the nearest surface's camera-space
/// depth ([`DepthProjection::view_depth`] of the key's NDC depth), in every
/// channel, alpha 1; [`crate::depth::NO_SURFACE`] and alpha 0 where no
/// sample is covered. Also returns, row-major, the number of covered
/// samples of every pixel.
pub fn resolve_depth(
    framebuffer: &Framebuffer,
    projection: DepthProjection,
    filter: DepthFilter,
) -> (Rgba32FImage, Vec<u8>) {
    let (width, height) = (framebuffer.width, framebuffer.height);
    let mut image = Rgba32FImage::new(width, height);
    let mut coverage = vec![0u8; width as usize * height as usize];
    for y in 0..height {
        for x in 0..width {
            let mut depth = 0.0f32;
            let mut covered = 0u8;
            for &key in framebuffer.pixel(x, y) {
                if key == CLEAR_KEY {
                    continue;
                }
                let z = match filter {
                    DepthFilter::Min => projection.view_depth(key_depth(key)),
                };
                depth = if covered == 0 { z } else { depth.min(z) };
                covered += 1;
            }
            let alpha = if covered == 0 { 0.0 } else { 1.0 };
            image.put_pixel(x, y, Rgba([depth, depth, depth, alpha]));
            coverage[y as usize * width as usize + x as usize] = covered;
        }
    }
    mark_empty(&mut image);
    (image, coverage)
}
