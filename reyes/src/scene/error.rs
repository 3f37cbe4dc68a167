//! Why a scene is refused: [`SceneError`], and the helpers that build the
//! two most common kinds ([`finite`], [`invalid`]).

use std::path::PathBuf;

use glam::Vec3;

use crate::displacement::DisplacementError;
use crate::input::InputError;
use crate::load::LoadError;

#[cfg(doc)]
use super::CameraDesc;
use super::framing::FramingError;

/// Why a scene could not be loaded or is invalid.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The scene file could not be opened or read (missing, no permission, ...).
    #[error("cannot read scene file {}: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The scene file was refused before parsing: not a regular file, larger
    /// than the scene cap, or not UTF-8 (see `crate::input`).
    #[error(transparent)]
    Input(InputError),
    /// The text is not valid TOML or does not match the scene format.
    #[error("{}{}: {message}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default(), line.map(|l| format!("line {l}")).unwrap_or_else(|| "scene".to_string()))]
    Parse {
        /// The scene file, when parsing a file.
        path: Option<PathBuf>,
        /// 1-based line of the error, when the parser knows it.
        line: Option<usize>,
        /// The TOML/serde message.
        message: String,
    },
    /// Width or height is zero.
    #[error("invalid resolution {width}x{height}: width and height must be > 0")]
    InvalidResolution {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// `spp` is not one of the supported perfect squares.
    #[error(
        "spp = {spp} is not supported: use a perfect square k * k with k = 1 to 16 (1, 4, 9, ..., 225 or 256; the samples form a k x k grid)"
    )]
    InvalidSpp {
        /// Requested samples per pixel.
        spp: u32,
    },
    /// `interleave_permutations` is 0 or above
    /// 256 (`crate::uvt::MAX_INTERLEAVE_PERMUTATIONS`).
    #[error(
        "interleave_permutations = {permutations} is not supported: use 1 to {} (Interleave UVT's permutations of a tile's pixels; 1 repeats one pattern in every tile)",
        crate::uvt::MAX_INTERLEAVE_PERMUTATIONS
    )]
    InvalidInterleavePermutations {
        /// Requested number of permutations.
        permutations: u32,
    },
    /// A number is NaN or infinite.
    #[error("{field} must be finite")]
    NonFinite {
        /// The field, e.g. `objects[0].transform.translate`.
        field: String,
    },
    /// The camera cannot produce a projection.
    #[error("invalid camera: {reason}")]
    InvalidCamera {
        /// What is wrong.
        reason: String,
    },
    /// Any other out-of-range value.
    #[error("invalid {field}: {reason}")]
    InvalidValue {
        /// The field.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// An object's model could not be loaded.
    #[error("object {index} (model {model:?}): {source}")]
    Model {
        /// Index of the object in `objects`.
        index: usize,
        /// The object's `model` string.
        model: String,
        /// Why loading failed.
        #[source]
        source: LoadError,
    },
    /// An object's surface shader could not be loaded or checked, or the
    /// scene's values do not fit its parameters.
    #[error("object {index}: surface shader {}: {source}", file.display())]
    SurfaceShader {
        /// Index of the object in `objects`.
        index: usize,
        /// The shader file.
        file: PathBuf,
        /// Why.
        #[source]
        source: crate::surface_shader::SurfaceShaderError,
    },
    /// An object's displacement could not be prepared (its height map could
    /// not be read, or its bound is too small for its source).
    #[error(
        "object {index} (displacement source {:?}): {source}",
        crate::input::excerpt(displacement)
    )]
    Displacement {
        /// Index of the object in `objects`.
        index: usize,
        /// The object's displacement `source` string.
        displacement: String,
        /// Why preparing failed.
        #[source]
        source: DisplacementError,
    },
    /// The scene has no camera and its objects cannot be framed
    /// automatically ([`CameraDesc::try_framing_points`]).
    #[error(
        "{} ({} to {}) {source}",
        if *objects == 1 { "the model's bounds".to_string() } else { format!("the bounds of the scene's {objects} models") },
        format_point(source.bounds().0),
        format_point(source.bounds().1)
    )]
    Framing {
        /// Number of objects framed together.
        objects: usize,
        /// Why framing fails.
        #[source]
        source: FramingError,
    },
    /// An object's transform maps its model's points (at shutter open or
    /// close) beyond `f32`: the product of the transform and the model's
    /// coordinates overflows.
    #[error(
        "objects[{index}].{field} maps model {model:?} beyond f32 range (the transformed control points are not finite: scale times the model's coordinates, plus translate, overflows); scale the model down"
    )]
    TransformOverflow {
        /// Index of the object.
        index: usize,
        /// `transform` or `transform_close`.
        field: &'static str,
        /// The object's `model` string.
        model: String,
    },
    /// A light's shadow map could not be read, or is not a shadow map.
    #[error("lights[{light}] ({kind} light): shadow map {}: {source}", path.display())]
    ShadowMap {
        /// Index of the light in the scene's `lights`.
        light: usize,
        /// The light's kind (`spot`, `distant`, `point`).
        kind: &'static str,
        /// The map's path as the scene names it, resolved against the
        /// scene's directory.
        path: PathBuf,
        /// Why.
        #[source]
        source: crate::shadow::ShadowFileError,
    },
    /// A prepared scene was given a different number of models than objects.
    #[error("the scene has {objects} objects but {models} models were given")]
    ModelCountMismatch {
        /// Number of objects in the scene.
        objects: usize,
        /// Number of models given.
        models: usize,
    },
    /// A model's texture coordinates do not fit its patches
    /// ([`crate::model::Model::st_problem`]).
    #[error("objects[{index}]: model {model:?}: {reason}")]
    InvalidSt {
        /// Index of the object.
        index: usize,
        /// The object's `model` string.
        model: String,
        /// What is wrong.
        reason: String,
    },
}

/// A point in short scientific notation, e.g. `[1e19, -2.5e-30, 0e0]`.
pub fn format_point(p: Vec3) -> String {
    format!("[{:e}, {:e}, {:e}]", p.x, p.y, p.z)
}

pub(super) fn finite<const N: usize>(field: &str, values: [f32; N]) -> Result<(), SceneError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SceneError::NonFinite {
            field: field.to_string(),
        })
    }
}

/// A linear RGB colour: finite, and no channel below 0 (above 1 is light
/// brighter than white, which an EXR keeps).
pub(super) fn colour(field: &str, value: glam::Vec3) -> Result<(), SceneError> {
    finite(field, value.to_array())?;
    if value.min_element() < 0.0 {
        return Err(invalid(
            field,
            &format!(
                "{} is out of range: every channel must be >= 0 (linear RGB)",
                format_point(value)
            ),
        ));
    }
    Ok(())
}

pub(super) fn invalid(field: &str, reason: &str) -> SceneError {
    SceneError::InvalidValue {
        field: field.to_string(),
        reason: reason.to_string(),
    }
}
