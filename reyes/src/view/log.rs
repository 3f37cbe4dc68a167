//! `--log-json`: what the viewer rendered, for tests and measurements.

use serde::Serialize;

use super::worker::{Frame, Quality};
use crate::camera::Camera;

/// A camera pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CameraRecord {
    /// Eye position.
    pub eye: [f32; 3],
    /// Point looked at.
    pub target: [f32; 3],
    /// Up direction.
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_degrees: f32,
}

impl CameraRecord {
    /// The pose of `camera`.
    pub fn of(camera: &Camera) -> CameraRecord {
        CameraRecord {
            eye: camera.eye.to_array(),
            target: camera.target.to_array(),
            up: camera.up.to_array(),
            fov_degrees: camera.fov_y_radians.to_degrees(),
        }
    }
}

/// One frame the worker delivered.
#[derive(Debug, Clone, Serialize)]
pub struct FrameRecord {
    /// The view change it renders (0: the initial view).
    pub generation: u64,
    /// The newest view change when it arrived.
    pub current_generation: u64,
    /// `true` for a refined frame, `false` for a preview.
    pub full: bool,
    /// Its size in pixels.
    pub width: u32,
    /// Its size in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Its camera.
    pub camera: CameraRecord,
    /// Megakernel time on the GPU, when measured.
    pub gpu_ms: Option<f64>,
    /// Wall time of the frame in the render worker.
    pub wall_ms: f64,
    /// Micropolygons.
    pub micropolygons: u64,
    /// Samples tested.
    pub samples_tested: u64,
    /// Samples hit.
    pub samples_hit: u64,
}

impl FrameRecord {
    /// The record of `frame`, arriving when the view is at `current`.
    pub fn of(frame: &Frame, current: u64) -> FrameRecord {
        let (width, height) = frame.image.dimensions();
        FrameRecord {
            generation: frame.spec.generation,
            current_generation: current,
            full: frame.spec.quality == Quality::Full,
            width,
            height,
            spp: match frame.spec.quality {
                Quality::Preview => 1,
                Quality::Full => frame.spec.settings.spp,
            },
            camera: CameraRecord::of(&frame.spec.camera),
            gpu_ms: frame.gpu_ms,
            wall_ms: frame.wall_ms,
            micropolygons: frame.stats.micropolygons,
            samples_tested: frame.stats.samples_tested,
            samples_hit: frame.stats.samples_hit,
        }
    }
}

/// The whole session.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ViewLog {
    /// The adapter's description.
    pub adapter: String,
    /// The scene's camera.
    pub initial_camera: Option<CameraRecord>,
    /// The camera when `--frames` ended the viewer.
    pub final_camera: Option<CameraRecord>,
    /// Every frame delivered, in order.
    pub frames: Vec<FrameRecord>,
}
