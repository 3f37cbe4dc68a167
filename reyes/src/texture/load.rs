//! Reading and decoding texture files into linear RGBA.
//!
//! The file is read through `crate::input` (a regular file under the
//! texture cap), its format is recognised from its first bytes (PNG,
//! OpenEXR or TIFF, whatever the extension says), and its header is read
//! and judged (size, budget) before a single pixel is decoded.

use std::io::Cursor;
use std::path::Path;

use glam::Vec4;
use image::{ColorType, DynamicImage, ImageDecoder, ImageFormat, ImageReader};

use super::error::TextureError;
use super::{ColorSpace, MAX_TEXTURE_SIDE};
use crate::color::srgb_to_linear;
use crate::input::{self, InputKind};

/// Most bytes a decoder may allocate (image's `Limits::max_alloc`): the
/// largest accepted image, 16384 x 16384 RGBA of 32-bit floats, is 4 GiB.
/// The budget, checked first from the header, normally refuses far less.
const MAX_DECODE_BYTES: u64 = 4 << 30;

/// A decoded image: linear RGBA, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LinearImage {
    /// Width in texels (> 0).
    pub(super) width: u32,
    /// Height in texels (> 0).
    pub(super) height: u32,
    /// `width * height` texels, `texels[y * width + x]`.
    pub(super) texels: Vec<Vec4>,
}

/// How a source stores a channel: decides what [`ColorSpace::Auto`] means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Depth {
    /// 8-bit integers: sRGB-encoded unless told otherwise.
    Eight,
    /// 16-bit integers: linear unless told otherwise.
    Sixteen,
    /// Half or single floats: linear unless told otherwise.
    Float,
}

impl Depth {
    fn of(color: ColorType) -> Depth {
        match color.bytes_per_pixel() / color.channel_count().max(1) {
            1 => Depth::Eight,
            2 => Depth::Sixteen,
            _ => Depth::Float,
        }
    }
}

/// The bytes of the texture file at `path` (at most the texture cap).
pub(super) fn read(path: &Path) -> Result<Vec<u8>, TextureError> {
    input::read_input(path, InputKind::Texture, InputKind::Texture.limit())
        .map_err(TextureError::from_input)
}

/// Decodes `bytes` (the file at `path`, which only names it in errors) to
/// linear RGBA in `color_space`, and returns the colour space it resolved
/// [`ColorSpace::Auto`] to.
///
/// `admit(width, height)` is called once the header is read and before the
/// pixels are decoded: its error (the budget) ends the load there. Sides
/// over [`MAX_TEXTURE_SIDE`] are refused before it.
pub(super) fn decode(
    bytes: &[u8],
    path: &Path,
    color_space: ColorSpace,
    admit: impl FnOnce(u32, u32) -> Result<(), TextureError>,
) -> Result<(LinearImage, ColorSpace), TextureError> {
    let decode_error = |message: String| TextureError::Decode {
        path: path.to_path_buf(),
        message,
    };
    let reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| decode_error(e.to_string()))?;
    match reader.format() {
        Some(ImageFormat::Png | ImageFormat::OpenExr | ImageFormat::Tiff) => {}
        Some(other) => {
            return Err(decode_error(format!(
                "{other:?} images are not read; textures are PNG, OpenEXR or TIFF files"
            )));
        }
        None => {
            return Err(decode_error(
                "not a PNG, OpenEXR or TIFF file (unrecognised first bytes)".to_string(),
            ));
        }
    }
    // Reading the header allocates nothing in proportion to the image, so
    // the decoder is made without size limits and the size is judged here,
    // with an error that says it.
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    let mut reader = reader;
    reader.limits(limits.clone());
    let mut decoder = reader
        .into_decoder()
        .map_err(|e| decode_error(e.to_string()))?;
    let (width, height) = decoder.dimensions();
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(TextureError::TooLarge {
            path: path.to_path_buf(),
            width,
            height,
            max: MAX_TEXTURE_SIDE,
        });
    }
    if width == 0 || height == 0 {
        return Err(decode_error(format!("the image is {width}x{height}")));
    }
    admit(width, height)?;
    // A second guard on the size, in the decoder itself.
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    decoder
        .set_limits(limits)
        .map_err(|e| decode_error(e.to_string()))?;
    let depth = Depth::of(decoder.color_type());
    let image = DynamicImage::from_decoder(decoder).map_err(|e| decode_error(e.to_string()))?;
    let resolved = match (color_space, depth) {
        (ColorSpace::Auto, Depth::Eight) => ColorSpace::Srgb,
        (ColorSpace::Auto, Depth::Sixteen | Depth::Float) => ColorSpace::Linear,
        (explicit, _) => explicit,
    };
    let texels = linear_texels(&image, depth, resolved);
    if let Some(at) = texels.iter().position(|t| !t.is_finite()) {
        return Err(TextureError::NonFinite {
            path: path.to_path_buf(),
            x: (at % width as usize) as u32,
            y: (at / width as usize) as u32,
        });
    }
    Ok((
        LinearImage {
            width,
            height,
            texels,
        },
        resolved,
    ))
}

/// The texels of `image` as RGBA in `[0, 1]` (integers) or as stored
/// (floats), grey replicated to RGB and a missing alpha 1, with the sRGB
/// transfer function undone on R, G and B when `color_space` is sRGB.
fn linear_texels(image: &DynamicImage, depth: Depth, color_space: ColorSpace) -> Vec<Vec4> {
    let mut texels: Vec<Vec4> = match depth {
        Depth::Eight => image
            .to_rgba8()
            .pixels()
            .map(|p| Vec4::from_array(p.0.map(|c| f32::from(c) / 255.0)))
            .collect(),
        Depth::Sixteen => image
            .to_rgba16()
            .pixels()
            .map(|p| Vec4::from_array(p.0.map(|c| f32::from(c) / 65535.0)))
            .collect(),
        Depth::Float => image
            .to_rgba32f()
            .pixels()
            .map(|p| Vec4::from_array(p.0))
            .collect(),
    };
    if color_space == ColorSpace::Srgb {
        for t in &mut texels {
            // Alpha is coverage, never encoded.
            *t = Vec4::new(
                srgb_to_linear(t.x),
                srgb_to_linear(t.y),
                srgb_to_linear(t.z),
                t.w,
            );
        }
    }
    texels
}
