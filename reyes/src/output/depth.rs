//! Writing the depth output ([`crate::depth`]): a single-channel OpenEXR
//! file whose channel `Z` holds each pixel's camera-space depth as a 32-bit
//! float (+inf where no surface is), the layout shadow-map tools read.

use std::io::Write as _;
use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, WritableImage,
};
use image::Rgba32FImage;

use super::staged::Staged;
use super::{ImageFormat, OutputError, OutputKind, OutputPlan, single_output};
use crate::stats::RenderStats;

/// The name of the depth channel.
pub const DEPTH_CHANNEL: &str = "Z";

/// Encodes the depth channel of `depths` (a depth resolve's image, the
/// depth in its red channel) as a single-channel float EXR into a
/// temporary file beside `path`.
pub(super) fn stage_depth(depths: &Rgba32FImage, path: &Path) -> Result<Staged, OutputError> {
    let size = (depths.width() as usize, depths.height() as usize);
    let samples: Vec<f32> = crate::depth::depths(depths);
    let channel = AnyChannel::new(DEPTH_CHANNEL, FlatSamples::F32(samples));
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        // Scan lines, which every EXR reader takes; ZIP keeps floats exact.
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(vec![channel].into()),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| OutputError::Write {
            path: path.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        })?;
    Staged::write(path, |writer| {
        writer
            .write_all(bytes.get_ref())
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
        stats: &RenderStats,
    ) -> Result<(), OutputError> {
        self.check_depth()?;
        let staged_image = stage_depth(depths, &self.image.0)?;
        let staged_stats = self.stage_stats(stats)?;
        staged_image.commit()?;
        staged_stats.map(Staged::commit).transpose()?;
        Ok(())
    }
}

/// Writes a depth resolve's image (e.g. [`crate::GpuRendered::linear`] of a
/// [`crate::Aov::Z`] frame) as a single-channel float EXR (channel
/// [`DEPTH_CHANNEL`]) whatever the extension, but `.png` is
/// [`OutputError::DepthNeedsExr`] (see [`OutputKind::Depth`]); the path is
/// checked and written as [`super::write_image`] does.
pub fn write_depth(depths: &Rgba32FImage, path: impl AsRef<Path>) -> Result<(), OutputError> {
    let file = single_output(OutputKind::Depth, "depth image", path.as_ref())?;
    stage_depth(depths, &file)?.commit()
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
    use exr::prelude::{ReadChannels as _, ReadLayers as _, read};
    let error = |reason: String| ReadDepthError {
        path: path.to_path_buf(),
        reason,
    };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| error(e.to_string()))?;
    let layer = image.layer_data;
    let channel = layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == DEPTH_CHANNEL)
        .ok_or_else(|| error(format!("it has no channel {DEPTH_CHANNEL}")))?;
    let depths = match &channel.sample_data {
        FlatSamples::F32(samples) => samples.clone(),
        _ => return Err(error("the channel is not 32-bit float".into())),
    };
    Ok(DepthImage {
        width: layer.size.0 as u32,
        height: layer.size.1 as u32,
        depths,
    })
}
