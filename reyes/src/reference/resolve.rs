//! Resolve: filter the samples around each pixel into a linear float image
//! (which `crate::quantize` encodes as the 8-bit one).

use glam::Vec3;
use image::{Rgba, Rgba32FImage};

use super::framebuffer::Framebuffer;
use crate::color::{CLEAR_KEY, key_color, unpack_rgb10};
use crate::filter::PixelFilter;
use crate::sampling::sample_offset;

/// How the resolve finds each sample's place in its pixel, as the
/// reference's rasterizer places it (`raster::SampleGrid::position`, in
/// frame pixel coordinates): the samples per pixel side and the jitter.
#[derive(Debug, Clone, Copy)]
pub struct SampleLayout {
    /// `k = sqrt(spp)`.
    pub k: u32,
    /// Whether samples are jittered.
    pub jitter: bool,
}

/// Resolves the framebuffer: uncovered samples take the (linear) background,
/// covered samples their unpacked colour; each pixel is the `filter`-weighted
/// mean of the samples of the pixels around it within the filter's window
/// (those outside the framebuffer are missing, and the weights of the
/// others are normalized), taken in linear space and kept as it is (no
/// clamping, no encoding), alpha 1. A pixel whose window holds no weight
/// (a window narrower than the sample spacing) takes the plain mean of its
/// own samples. Also returns,
/// row-major, the number of covered samples of every pixel.
/// `shaders/reyes/resolve.wgsl` mirrors it operation for operation.
pub fn resolve(
    framebuffer: &Framebuffer,
    background: Vec3,
    filter: &PixelFilter,
    layout: SampleLayout,
) -> (Rgba32FImage, Vec<u16>) {
    let (width, height) = (framebuffer.width, framebuffer.height);
    let mut image = Rgba32FImage::new(width, height);
    let mut coverage = vec![0u16; width as usize * height as usize];
    let color = |key: u64| {
        if key == CLEAR_KEY {
            background
        } else {
            unpack_rgb10(key_color(key))
        }
    };
    // Each sample's offset from its pixel's corner, per pixel.
    let offsets = |x: u32, y: u32| {
        (0..framebuffer.spp).map(move |s| sample_offset(x, y, s, layout.k, layout.jitter))
    };
    let [rx, ry] = filter.radius();
    for y in 0..height {
        for x in 0..width {
            let mut covered = 0u16;
            let mut own = Vec3::ZERO;
            for &key in framebuffer.pixel(x, y) {
                if key != CLEAR_KEY {
                    covered += 1;
                }
                own += color(key);
            }
            let mut sum = Vec3::ZERO;
            let mut weights = 0.0f32;
            for qy in y.saturating_sub(ry)..=(y + ry).min(height - 1) {
                for qx in x.saturating_sub(rx)..=(x + rx).min(width - 1) {
                    let (ox, oy) = (qx as f32 - x as f32 - 0.5, qy as f32 - y as f32 - 0.5);
                    for (offset, &key) in offsets(qx, qy).zip(framebuffer.pixel(qx, qy)) {
                        let w = filter.weight(ox + offset.x, oy + offset.y);
                        if w != 0.0 {
                            sum += color(key) * w;
                            weights += w;
                        }
                    }
                }
            }
            let c = if weights > 0.0 {
                sum / weights
            } else {
                own * (1.0 / framebuffer.spp as f32)
            };
            image.put_pixel(x, y, Rgba([c.x, c.y, c.z, 1.0]));
            coverage[y as usize * width as usize + x as usize] = covered;
        }
    }
    (image, coverage)
}
