//! Writing the depth output ([`crate::depth`]) and shadow maps: a
//! single-channel OpenEXR file whose channel `Z` holds each pixel's
//! camera-space depth as a 32-bit float (+inf where no surface is), with
//! the camera's matrices as attributes ([`crate::shadow::file`]).

use std::io::Write as _;
use std::path::Path;

use image::Rgba32FImage;

use super::staged::Staged;
use super::{ImageFormat, OutputError, OutputKind, OutputPlan, single_output};
use crate::camera::Camera;
use crate::shadow::{ShadowFileError, ShadowMap};
use crate::stats::RenderStats;

/// The name of the depth channel.
pub const DEPTH_CHANNEL: &str = crate::shadow::file::DEPTH_CHANNEL;

/// Encodes the depth channel of `depths` (a depth resolve's image, the
/// depth in its red channel) seen through `camera` as a single-channel
/// float EXR with the camera's matrices ([`crate::shadow::file`]) into a
/// temporary file beside `path`.
pub(super) fn stage_depth(
    depths: &Rgba32FImage,
    camera: &Camera,
    path: &Path,
) -> Result<Staged, OutputError> {
    let map = ShadowMap::from_camera(camera, crate::depth::depths(depths));
    stage_map(&map, "depth", path)
}

/// Encodes `map`, marked as `kind`, into a temporary file beside `path`.
fn stage_map(map: &ShadowMap, kind: &str, path: &Path) -> Result<Staged, OutputError> {
    let bytes = crate::shadow::file::encode(map, kind).map_err(|e| OutputError::Write {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    })?;
    Staged::write(path, |writer| {
        writer
            .write_all(&bytes)
            .map_err(|source| OutputError::Write {
                path: path.to_path_buf(),
                source,
            })
    })
}

impl OutputPlan {
    /// [`OutputError::DepthNeedsExr`] unless the image is an EXR: the check
    /// before a depth frame renders.
    pub fn check_depth(&self) -> Result<(), OutputError> {
        match self.image.1 {
            ImageFormat::Exr => Ok(()),
            ImageFormat::Png => Err(OutputError::DepthNeedsExr {
                path: self.image.0.clone(),
            }),
        }
    }

    /// Writes a depth frame ([`crate::Aov::Z`]) as [`OutputPlan::write`]
    /// writes an image: `depths` (a depth resolve's image) as a
    /// single-channel float EXR (channel [`DEPTH_CHANNEL`]), and the
    /// statistics, all or nothing.
    pub fn write_depth(
        &self,
        depths: &Rgba32FImage,
        camera: &Camera,
        stats: &RenderStats,
    ) -> Result<(), OutputError> {
        self.write_depth_map(
            &ShadowMap::from_camera(camera, crate::depth::depths(depths)),
            stats,
        )
    }

    /// [`OutputPlan::write_depth`] of a depth frame already made a map
    /// (its camera's matrices possibly relative to another world space).
    pub fn write_depth_map(&self, map: &ShadowMap, stats: &RenderStats) -> Result<(), OutputError> {
        self.check_depth()?;
        let staged_image = stage_map(map, "depth", &self.image.0)?;
        let staged_stats = self.stage_stats(stats)?;
        staged_image.commit()?;
        staged_stats.map(Staged::commit).transpose()?;
        Ok(())
    }
}

/// Writes a depth resolve's image (e.g. [`crate::GpuRendered::linear`] of a
/// [`crate::Aov::Z`] frame) seen through `camera` (the frame's) as a
/// single-channel float EXR (channel [`DEPTH_CHANNEL`]) with the camera's
/// matrices, whatever the extension, but `.png` is
/// [`OutputError::DepthNeedsExr`] (see [`OutputKind::Depth`]); the path is
/// checked and written as [`super::write_image`] does.
pub fn write_depth(
    depths: &Rgba32FImage,
    camera: &Camera,
    path: impl AsRef<Path>,
) -> Result<(), OutputError> {
    let file = single_output(OutputKind::Depth, "depth image", path.as_ref())?;
    stage_depth(depths, camera, &file)?.commit()
}

/// Writes `map` to `path` as a shadow map ([`crate::shadow::file`]), through
/// a temporary file renamed into place; the path is checked as a depth
/// image's.
pub fn write_shadow_map(map: &ShadowMap, path: impl AsRef<Path>) -> Result<(), OutputError> {
    let file = single_output(OutputKind::Depth, "shadow map", path.as_ref())?;
    stage_map(map, "shadow", &file)?.commit()
}

/// Why `MakeShadow` failed.
#[derive(Debug, thiserror::Error)]
pub enum MakeShadowError {
    /// The picture is not a depth image with its camera.
    #[error(transparent)]
    Picture(#[from] ShadowFileError),
    /// The map could not be written.
    #[error(transparent)]
    Write(#[from] OutputError),
}

/// RIB `MakeShadow picturename texturename`: reads the depth image
/// `picture` (as a frame with Display mode `"z"` writes it) and writes it
/// to `shadow` as a shadow map. A picture that is not a depth image with
/// its camera is [`ShadowFileError::WrongKind`]; nothing is written then.
pub fn make_shadow(picture: &Path, shadow: &Path) -> Result<ShadowMap, MakeShadowError> {
    let map = crate::shadow::read_shadow_map(picture)?;
    write_shadow_map(&map, shadow)?;
    Ok(map)
}

/// A depth image read back: `width * height` depths, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The depths (+inf where no surface is).
    pub depths: Vec<f32>,
}

/// Why a depth file could not be read.
#[derive(Debug, thiserror::Error)]
#[error("{}: not a depth image (a float EXR with a channel {DEPTH_CHANNEL}): {reason}", path.display())]
pub struct ReadDepthError {
    /// The file.
    pub path: std::path::PathBuf,
    /// What went wrong.
    pub reason: String,
}

/// Reads the channel [`DEPTH_CHANNEL`] of the first layer of the EXR file
/// at `path`, as the depth output writes it ([`super::OutputPlan::write_depth`]).
pub fn read_depth(path: &Path) -> Result<DepthImage, ReadDepthError> {
    let layer = crate::shadow::file::read_depth_layer(path).map_err(|e| ReadDepthError {
        path: path.to_path_buf(),
        reason: match e {
            ShadowFileError::Read { reason, .. } | ShadowFileError::WrongKind { reason, .. } => {
                reason
            }
            other => other.to_string(),
        },
    })?;
    Ok(DepthImage {
        width: layer.width,
        height: layer.height,
        depths: layer.depths,
    })
}
