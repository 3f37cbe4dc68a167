//! The depth resolve ([`crate::depth`]): per pixel, the camera-space depth
//! of its samples' nearest surfaces, filtered by the scene's
//! [`DepthFilter`]. `resolve_depth` in `shaders/reyes/resolve.wgsl` mirrors
//! it operation for operation.

use image::{Rgba, Rgba32FImage};

use super::framebuffer::Framebuffer;
use crate::color::{CLEAR_KEY, key_depth};
use crate::depth::{DepthFilter, DepthProjection, NO_SURFACE, finish_depths};

/// Resolves `framebuffer` into depths: per pixel the minimum (with
/// [`DepthFilter::Max`] the maximum, with [`DepthFilter::Average`] the
/// mean, summed in sample order) over its own covered samples of each
/// sample's depth, in every channel, alpha 1;
/// [`NO_SURFACE`] and alpha 0 where no sample is covered. A sample's depth
/// is, with [`DepthFilter::Min`], its nearest surface's camera-space depth
/// ([`DepthProjection::view_depth`] of the key's NDC depth); with
/// [`DepthFilter::Midpoint`], the mean of that and the second-nearest
/// surface's ([`Framebuffer::second`], which must be kept), or
/// [`NO_SURFACE`] where there is none (a pixel whose samples all see a
/// single surface is [`NO_SURFACE`] with alpha 1). Also returns, row-major, the number of covered
/// samples of every pixel.
pub fn resolve_depth(
    framebuffer: &Framebuffer,
    projection: DepthProjection,
    filter: DepthFilter,
) -> (Rgba32FImage, Vec<u16>) {
    let (width, height) = (framebuffer.width, framebuffer.height);
    let mut image = Rgba32FImage::new(width, height);
    let mut coverage = vec![0u16; width as usize * height as usize];
    for y in 0..height {
        for x in 0..width {
            let mut depth = 0.0f32;
            let mut covered = 0u16;
            let start = framebuffer.index(x, y, 0);
            for (s, &key) in framebuffer.pixel(x, y).iter().enumerate() {
                if key == CLEAR_KEY {
                    continue;
                }
                let nearest = projection.view_depth(key_depth(key));
                let z = match filter {
                    DepthFilter::Min | DepthFilter::Max | DepthFilter::Average => nearest,
                    DepthFilter::Midpoint => match framebuffer.second[start + s] {
                        u32::MAX => NO_SURFACE,
                        second => 0.5 * (nearest + projection.view_depth(f32::from_bits(second))),
                    },
                };
                depth = if covered == 0 {
                    z
                } else {
                    match filter {
                        DepthFilter::Max => depth.max(z),
                        DepthFilter::Average => depth + z,
                        DepthFilter::Min | DepthFilter::Midpoint => depth.min(z),
                    }
                };
                covered += 1;
            }
            if filter == DepthFilter::Average && covered != 0 {
                depth /= f32::from(covered);
            }
            // As the shader writes it, for finish_depths.
            let covered_flag = if covered == 0 { 0.0 } else { 1.0 };
            let finite = if depth.is_finite() && covered != 0 { 1.0 } else { 0.0 };
            let raw = if finite == 1.0 { depth } else { 0.0 };
            image.put_pixel(x, y, Rgba([raw, finite, 0.0, covered_flag]));
            coverage[y as usize * width as usize + x as usize] = covered;
        }
    }
    finish_depths(&mut image);
    (image, coverage)
}
