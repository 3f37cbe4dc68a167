//! Why a displacement source could not be prepared.

use std::path::PathBuf;

use crate::input::{InputError, excerpt};

/// A path for an error message, cut to a bounded length (a scene may name
/// any string as its source).
fn shown(path: &std::path::Path) -> String {
    excerpt(&path.display().to_string())
}

/// Errors found while preparing an object's displacement (reading its height
/// map, checking its bound). Scene-level value errors (NaN, negative bound,
/// ...) are [`crate::scene::SceneError`]s found by [`crate::scene::Scene::validate`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DisplacementError {
    /// The height-map file could not be opened or read (missing, no permission, ...).
    #[error("cannot read height map {}: {source}", shown(path))]
    Io {
        /// The PNG file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The height-map file was refused before decoding: not a regular file,
    /// or larger than the height-map cap (never [`InputError::Io`], which
    /// becomes [`DisplacementError::Io`]).
    #[error(transparent)]
    Input(InputError),
    /// The file is not a PNG the `image` crate can decode.
    #[error("height map {} is not a valid PNG: {source}", shown(path))]
    Decode {
        /// The PNG file.
        path: PathBuf,
        /// The decoder's error.
        #[source]
        source: image::ImageError,
    },
    /// The image has colour (or alpha) channels: a height map has one grey channel.
    #[error(
        "height map {} is a {color} image; height maps must be 8- or 16-bit greyscale PNGs without alpha",
        shown(path)
    )]
    NotGrey {
        /// The PNG file.
        path: PathBuf,
        /// The image's colour type, e.g. `Rgb8`.
        color: String,
    },
    /// The image is larger than `crate::params::MAX_HEIGHT_MAP_SIDE` on a
    /// side (found from the PNG header, before anything is decoded).
    #[error(
        "height map {} is {width}x{height}; at most {max}x{max} texels are supported",
        shown(path)
    )]
    TooLarge {
        /// The PNG file.
        path: PathBuf,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Largest accepted side.
        max: u32,
    },
    /// The declared bound is smaller than the largest displacement the source
    /// can produce, so culling could discard visible surface.
    #[error(
        "displacement bound {bound} is smaller than |scale| * max height = {needed}; displaced points could leave the bound and be culled (raise `bound`, or leave it out: the default is exactly |scale| * max height)"
    )]
    BoundTooSmall {
        /// The declared bound.
        bound: f32,
        /// `|scale| * max height` of the source.
        needed: f32,
    },
    /// The displacement shader cannot be loaded or checked, or the scene's
    /// values do not fit its parameters.
    #[error("displacement shader {}: {source}", shown(file))]
    Shader {
        /// The shader file.
        file: PathBuf,
        /// Why (boxed: it is large, and rare).
        #[source]
        source: Box<crate::surface_shader::SurfaceShaderError>,
    },
}

impl From<InputError> for DisplacementError {
    /// Plain I/O failures keep their long-standing [`DisplacementError::Io`]
    /// variant; refusals become [`DisplacementError::Input`].
    fn from(error: InputError) -> DisplacementError {
        match error {
            InputError::Io { path, source, .. } => DisplacementError::Io { path, source },
            other => DisplacementError::Input(other),
        }
    }
}
