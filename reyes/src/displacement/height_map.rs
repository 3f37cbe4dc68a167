//! Grey height maps: PNG decoding and the bilinear, wrap-around lookup that
//! the GPU repeats operation for operation (`height_image` in
//! `shaders/reyes/displacement.wgsl`).

use std::io::Cursor;
use std::path::Path;
use std::sync::{Arc, OnceLock};

use image::{ColorType, DynamicImage, ImageDecoder, ImageFormat, ImageReader};

use super::error::DisplacementError;
use crate::input::{self, InputKind};
use crate::params::MAX_HEIGHT_MAP_SIDE;

/// The eight bytes every PNG file starts with.
const PNG_SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";

/// The width and height a PNG's header declares, read from the IHDR chunk
/// (which the format requires to come first), without decoding anything.
/// `None` when `bytes` does not start like a PNG; the decoder then says why.
fn png_header_size(bytes: &[u8]) -> Option<(u32, u32)> {
    // Signature (8), IHDR length (4), "IHDR" (4), width (4), height (4).
    let header = bytes.get(..24)?;
    if &header[..8] != PNG_SIGNATURE || &header[12..16] != b"IHDR" {
        return None;
    }
    let be = |at: usize| {
        u32::from_be_bytes([header[at], header[at + 1], header[at + 2], header[at + 3]])
    };
    Some((be(16), be(20)))
}

/// The embedded `bumps.png`: a tileable 512 x 512 8-bit grey height map
/// (sines plus a 16 x 16 grid of round bumps). It was made for this project
/// and is free to redistribute (see "Heights" in `docs/reyes.md`).
const BUMPS_PNG: &[u8] = include_bytes!("../../assets/bumps.png");

/// A height map: `width x height` texels in `[0, 1]`, row-major, top row
/// first. Texel `(i, j)` has its centre at `u = (i + 0.5) / width`,
/// `v = (j + 0.5) / height`; the map repeats in both directions.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    /// Width in texels (> 0).
    pub width: u32,
    /// Height in texels (> 0).
    pub height: u32,
    /// `width * height` heights in `[0, 1]`, `texels[j * width + i]`.
    pub texels: Vec<f32>,
    /// The largest texel: no bilinear sample exceeds it.
    pub max_height: f32,
}

impl HeightMap {
    /// The embedded bumps map, decoded once per process.
    pub fn bumps() -> Arc<HeightMap> {
        static BUMPS: OnceLock<Arc<HeightMap>> = OnceLock::new();
        BUMPS
            .get_or_init(|| {
                // The embedded file is checked by the tests; failing here is a build defect.
                let map = HeightMap::decode(BUMPS_PNG, Path::new("<embedded bumps.png>"))
                    .expect("the embedded bumps.png is an 8-bit grey PNG");
                Arc::new(map)
            })
            .clone()
    }

    /// Reads and decodes a greyscale PNG (8 or 16 bits, no alpha). The file
    /// is read through `crate::input`: a regular file of at most the
    /// height-map cap ([`InputKind::HeightMap`]`.limit()`, 64 MiB by
    /// default), else [`DisplacementError::Input`].
    pub fn load(path: &Path) -> Result<HeightMap, DisplacementError> {
        HeightMap::load_with_limit(path, InputKind::HeightMap.limit())
    }

    /// [`HeightMap::load`] with an explicit file-size cap in bytes instead of
    /// the process-wide one.
    pub fn load_with_limit(path: &Path, limit: u64) -> Result<HeightMap, DisplacementError> {
        let bytes = input::read_input(path, InputKind::HeightMap, limit)?;
        HeightMap::decode(&bytes, path)
    }

    /// Decodes PNG bytes; `path` only names the image in errors.
    ///
    /// The size and colour type come from the header and are checked before
    /// any pixel is decoded, so a header claiming 60000 x 60000 texels is a
    /// [`DisplacementError::TooLarge`], not a decoder memory error, and a
    /// 20000 x 20000 map is refused without decoding 400 MB first.
    pub fn decode(bytes: &[u8], path: &Path) -> Result<HeightMap, DisplacementError> {
        let too_large = |width, height| DisplacementError::TooLarge {
            path: path.to_path_buf(),
            width,
            height,
            max: MAX_HEIGHT_MAP_SIDE,
        };
        let fits = |width, height| width <= MAX_HEIGHT_MAP_SIDE && height <= MAX_HEIGHT_MAP_SIDE;
        // Before the decoder: it reserves buffers from the header's size and
        // would fail on a huge one with a memory error of its own.
        match png_header_size(bytes) {
            Some((width, height)) if !fits(width, height) => return Err(too_large(width, height)),
            _ => {}
        }
        let decode_error = |source| DisplacementError::Decode {
            path: path.to_path_buf(),
            source,
        };
        let mut reader = ImageReader::with_format(Cursor::new(bytes), ImageFormat::Png);
        // A second guard on the size, in the decoder itself.
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_HEIGHT_MAP_SIDE);
        limits.max_image_height = Some(MAX_HEIGHT_MAP_SIDE);
        reader.limits(limits);
        let decoder = reader.into_decoder().map_err(decode_error)?;
        let (width, height) = decoder.dimensions();
        if !fits(width, height) {
            return Err(too_large(width, height));
        }
        let color = decoder.color_type();
        if !matches!(color, ColorType::L8 | ColorType::L16) {
            return Err(DisplacementError::NotGrey {
                path: path.to_path_buf(),
                color: format!("{color:?}"),
            });
        }
        let image = DynamicImage::from_decoder(decoder).map_err(decode_error)?;
        // Converted on the host once: the GPU receives these exact f32 values.
        let texels: Vec<f32> = match &image {
            DynamicImage::ImageLuma8(grey) => grey
                .as_raw()
                .iter()
                .map(|&t| f32::from(t) / 255.0)
                .collect(),
            DynamicImage::ImageLuma16(grey) => grey
                .as_raw()
                .iter()
                .map(|&t| f32::from(t) / 65535.0)
                .collect(),
            other => {
                return Err(DisplacementError::NotGrey {
                    path: path.to_path_buf(),
                    color: format!("{:?}", other.color()),
                });
            }
        };
        let max_height = texels.iter().copied().fold(0.0, f32::max);
        Ok(HeightMap {
            width,
            height,
            texels,
            max_height,
        })
    }

    fn texel(&self, i: u32, j: u32) -> f32 {
        self.texels[(j * self.width + i) as usize]
    }

    /// Bilinear height at `(u, v)`, wrapping around in both directions.
    ///
    /// `x = u * width - 0.5` (likewise `y`); the four texels around `(x, y)`
    /// are blended with `fx = x - floor(x)`, `fy = y - floor(y)`:
    /// `top = t00 + (t10 - t00) * fx`, `bottom = t01 + (t11 - t01) * fx`,
    /// `h = top + (bottom - top) * fy`. Texel indices wrap with integer
    /// arithmetic, so both implementations pick the same texels.
    pub fn sample(&self, u: f32, v: f32) -> f32 {
        let x = u * self.width as f32 - 0.5;
        let y = v * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // |x| < 2^23 for the accepted tiling and map sizes, so the casts are exact.
        let (i0, j0) = (wrap(x0 as i32, self.width), wrap(y0 as i32, self.height));
        let (i1, j1) = ((i0 + 1) % self.width, (j0 + 1) % self.height);
        let top = self.texel(i0, j0) + (self.texel(i1, j0) - self.texel(i0, j0)) * fx;
        let bottom = self.texel(i0, j1) + (self.texel(i1, j1) - self.texel(i0, j1)) * fx;
        top + (bottom - top) * fy
    }
}

/// `i` modulo `n`, in `0..n` also for negative `i`.
fn wrap(i: i32, n: u32) -> u32 {
    let n = n.cast_signed();
    (((i % n) + n) % n) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(width: u32, height: u32, texels: Vec<f32>) -> HeightMap {
        let max_height = texels.iter().copied().fold(0.0, f32::max);
        HeightMap {
            width,
            height,
            texels,
            max_height,
        }
    }

    #[test]
    fn bumps_decodes() {
        let bumps = HeightMap::bumps();
        assert_eq!((bumps.width, bumps.height), (512, 512));
        assert!(bumps.max_height > 0.5 && bumps.max_height <= 1.0);
    }

    #[test]
    fn texel_centres_are_exact_and_wrap() {
        let m = map(2, 2, vec![0.0, 1.0, 0.25, 0.5]);
        assert_eq!(m.sample(0.25, 0.25), 0.0);
        assert_eq!(m.sample(0.75, 0.25), 1.0);
        assert_eq!(m.sample(0.25, 0.75), 0.25);
        // One period later and earlier: the same texels.
        assert_eq!(m.sample(1.25, 0.25), 0.0);
        assert_eq!(m.sample(-0.25, 0.25), 1.0);
        // Half-way between texel 1 and (wrapped) texel 0 of the top row.
        assert_eq!(m.sample(1.0, 0.25), 0.5);
        // The wrap makes u = 0 and u = 1 identical (seams match).
        for v in [0.0, 0.3, 0.9] {
            assert_eq!(m.sample(0.0, v), m.sample(1.0, v));
        }
    }

    #[test]
    fn samples_stay_within_the_texel_range() {
        let bumps = HeightMap::bumps();
        for k in 0..1000 {
            let u = k as f32 * 0.0137;
            let v = k as f32 * 0.0291;
            let h = bumps.sample(u, v);
            assert!((0.0..=bumps.max_height * (1.0 + 1e-6)).contains(&h), "{h}");
        }
    }
}
