//! Shadow-map files: a single-channel float OpenEXR image (channel `Z`,
//! camera-space depth, +inf where the light sees nothing) carrying the
//! light's matrices as OpenEXR's standard attributes `worldToCamera` and
//! `worldToNDC` (here the world-to-clip matrix, whose `x / w` and `y / w`
//! run over [-1, 1] across the image, y up), stored as OpenEXR stores
//! matrices (row vectors, translation in the last row: glam's column-major
//! array). The depth output writes the same layout ([`crate::output`]), so
//! a frame rendered from a light is already a map;
//! [`crate::output::make_shadow`] checks it and marks it as one.

use std::path::{Path, PathBuf};

use exr::meta::attribute::{AttributeValue, Text};
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes,
    ReadChannels as _, ReadLayers as _, WritableImage as _,
};
use glam::Mat4;

use super::ShadowMap;

/// The channel of the depths.
pub const DEPTH_CHANNEL: &str = "Z";
/// The attribute of the world-to-camera matrix (OpenEXR's standard name).
pub const WORLD_TO_CAMERA: &str = "worldToCamera";
/// The attribute of the world-to-clip matrix (OpenEXR's standard name for
/// the world-to-NDC matrix).
pub const WORLD_TO_NDC: &str = "worldToNDC";
/// The attribute naming what the file is: `"depth"` as the depth output
/// writes it, `"shadow"` once [`crate::output::make_shadow`] made it a map.
pub const MAP_KIND: &str = "reyesMapKind";

/// Why a shadow map or a depth image could not be read, made or written.
#[derive(Debug, thiserror::Error)]
pub enum ShadowFileError {
    /// The file could not be read as an EXR image.
    #[error("{}: cannot read it as a depth image or shadow map: {reason}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// What the EXR reader said.
        reason: String,
    },
    /// The file is an image, but not a depth image with a light's
    /// projection.
    #[error("{}: not a depth image with its camera (a float EXR with channel Z and the attributes worldToCamera and worldToNDC, as a frame with Display mode \"z\" writes): {reason}", path.display())]
    WrongKind {
        /// The file.
        path: PathBuf,
        /// What is missing or wrong.
        reason: String,
    },
    /// The map could not be written.
    #[error("{}: cannot write the shadow map: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
}

/// The EXR bytes of `map`, marked as `kind` (`"depth"` or `"shadow"`).
pub fn encode(map: &ShadowMap, kind: &str) -> Result<Vec<u8>, String> {
    let size = (map.width as usize, map.height as usize);
    let channel = AnyChannel::new(DEPTH_CHANNEL, FlatSamples::F32(map.depths.clone()));
    let mut attributes = LayerAttributes {
        world_to_camera: Some(map.world_to_camera.to_cols_array()),
        world_to_normalized_device: Some(map.world_to_clip.to_cols_array()),
        ..LayerAttributes::default()
    };
    attributes
        .other
        .insert(Text::from(MAP_KIND), AttributeValue::Text(Text::from(kind)));
    let layer = Layer::new(
        size,
        attributes,
        // Scan lines, which every EXR reader takes; ZIP keeps floats exact.
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(vec![channel].into()),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

/// Reads a shadow map, or a depth image with its camera (the depth output
/// of a frame), from `path`.
pub fn read_shadow_map(path: &Path) -> Result<ShadowMap, ShadowFileError> {
    let wrong = |reason: String| ShadowFileError::WrongKind {
        path: path.to_path_buf(),
        reason,
    };
    let DepthLayer {
        width,
        height,
        depths,
        attributes,
    } = read_depth_layer(path)?;
    let matrix = |name: &str, value: Option<exr::meta::attribute::Matrix4x4>| {
        value
            .map(|m| Mat4::from_cols_array(&m))
            .ok_or_else(|| wrong(format!("it has no attribute {name}")))
    };
    let map = ShadowMap {
        width,
        height,
        depths,
        world_to_camera: matrix(WORLD_TO_CAMERA, attributes.world_to_camera)?,
        world_to_clip: matrix(WORLD_TO_NDC, attributes.world_to_normalized_device)?,
    };
    if let Some(reason) = map.problem() {
        return Err(wrong(reason));
    }
    Ok(map)
}

/// The channel [`DEPTH_CHANNEL`] of the first layer of an EXR file, with
/// the layer's size and attributes.
#[derive(Debug)]
pub struct DepthLayer {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// The depths, row-major.
    pub depths: Vec<f32>,
    /// The layer's attributes (the matrices among them).
    pub attributes: LayerAttributes,
}

/// Reads the channel [`DEPTH_CHANNEL`] (32-bit float) of the first layer of
/// the EXR file at `path`: [`ShadowFileError::Read`] when it is no EXR,
/// [`ShadowFileError::WrongKind`] when it has no such channel.
pub fn read_depth_layer(path: &Path) -> Result<DepthLayer, ShadowFileError> {
    let wrong = |reason: String| ShadowFileError::WrongKind {
        path: path.to_path_buf(),
        reason,
    };
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| ShadowFileError::Read {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
    let layer = image.layer_data;
    let channel = layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == DEPTH_CHANNEL)
        .ok_or_else(|| {
            let names: Vec<String> = layer
                .channel_data
                .list
                .iter()
                .map(|c| c.name.to_string())
                .collect();
            wrong(format!(
                "it has no channel {DEPTH_CHANNEL} (its channels: {})",
                names.join(", ")
            ))
        })?;
    let depths = match &channel.sample_data {
        FlatSamples::F32(samples) => samples.clone(),
        _ => {
            return Err(wrong(format!(
                "channel {DEPTH_CHANNEL} is not 32-bit float"
            )));
        }
    };
    Ok(DepthLayer {
        width: layer.size.0 as u32,
        height: layer.size.1 as u32,
        depths,
        attributes: layer.attributes,
    })
}
