//! Render statistics, shared by the CPU reference and the GPU renderer so the
//! two can be compared field by field.

use serde::{Deserialize, Serialize};

/// Counters collected during one frame. See `docs/reyes.md` for the precise
/// definitions; every counter counts the same events on the CPU and the GPU.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RenderStats {
    /// Patches handed to the pipeline (all objects' patches).
    pub input_patches: u64,
    /// Split operations (one per split parent; each produces two children).
    pub splits: u64,
    /// Patches (input or split children) rejected because all 16 control
    /// points are outside the same clip plane.
    pub culled_patches: u64,
    /// Patches dropped because they still needed a split at `max_split_depth`.
    pub depth_guard_drops: u64,
    /// Pieces diced into a grid.
    pub grids_diced: u64,
    /// Micropolygons produced: the sum of every grid's `nu * nv` (225 per
    /// grid with fixed dicing).
    pub micropolygons: u64,
    /// Grids diced by each dice procedure, in `crate::dicing::GridClass::ALL`
    /// order (small: 16 threads, medium: 64, large: 256).
    #[serde(default)]
    pub grids_by_class: [u64; 3],
    /// Threads the dice procedures ran their grids with: each grid counts
    /// its class's threads per item.
    #[serde(default)]
    pub dice_threads: u64,
    /// Sample positions tested against a micropolygon (bbox mode: every sample
    /// of every pixel in each triangle's clamped bounding box; nearest mode:
    /// one per micropolygon).
    pub samples_tested: u64,
    /// Sample tests that hit (a key was offered to the framebuffer).
    pub samples_hit: u64,
    /// Samples that a box's loop reached but skipped without a test:
    /// Interleave UVT's tile lookups and INTERVAL's pixels whose sample
    /// lies in a stratum outside the box (or off the image). The other
    /// modes loop over the box's strata only and skip none. Fatahalian et
    /// al. count these as tests; see [`Self::sample_lookup_efficiency`].
    #[serde(default)]
    pub samples_skipped: u64,
    /// Largest side, in pixels, of any micropolygon's screen bounding box
    /// (after displacement).
    pub largest_micropolygon_px: f32,
    /// Displaced grid points that moved further than their object's
    /// displacement bound (0 when every bound holds; see `docs/reyes.md`).
    #[serde(default)]
    pub displacement_bound_exceeded: u64,
    /// Grid points whose position the displacement turned infinite or NaN
    /// (height times scale beyond `f32`, or a user function returning NaN
    /// or infinity), counted once per diced point (see
    /// `crate::nonfinite`; 0 in a healthy frame).
    #[serde(default)]
    pub non_finite_displacement: u64,
    /// Grid points whose position the object's transform turned infinite or
    /// NaN (the shutter-close motion, or a placement near the `f32` limit),
    /// counted once per diced point (see `crate::nonfinite`).
    #[serde(default)]
    pub non_finite_transform: u64,
    /// Grid points with a finite world position whose clip or pixel
    /// position (at open or close) is infinite or NaN, counted once per
    /// diced point (see `crate::nonfinite`).
    #[serde(default)]
    pub non_finite_camera: u64,
    /// Grids that Adaptive sampling (or Interleave UVT itself) sampled
    /// with Interleave UVT.
    #[serde(default)]
    pub interleave_grids: u64,
    /// Wall-clock time of the frame in milliseconds, when measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame_time_ms: Option<f64>,
    /// A frame with automatic shadows: its passes in the order they ran,
    /// each depth pass from a light, then the frame itself (`"frame"`),
    /// with their own counts. The counters above are the frame's own
    /// (without the depth passes). Empty for a frame of one pass.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub passes: Vec<PassStats>,
}

/// One pass of a frame with automatic shadows ([`RenderStats::passes`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PassStats {
    /// What the pass renders: `"frame"`, or a depth pass's name
    /// (`crate::prepare::DepthPass::name`).
    pub name: String,
    /// Its image's width in pixels (a map's in texels).
    pub width: u32,
    /// Its image's height.
    pub height: u32,
    /// Micropolygons it produced.
    pub micropolygons: u64,
    /// Its time in milliseconds, measured as the renderer measures
    /// [`RenderStats::frame_time_ms`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame_time_ms: Option<f64>,
}

impl PassStats {
    /// The pass `name` of an image `width x height` with its counters.
    pub fn of(name: impl Into<String>, width: u32, height: u32, stats: &RenderStats) -> Self {
        PassStats {
            name: name.into(),
            width,
            height,
            micropolygons: stats.micropolygons,
            frame_time_ms: stats.frame_time_ms,
        }
    }
}

impl RenderStats {
    /// Thread utilization of the dice procedures: the share of their
    /// threads that rasterize a micropolygon (`micropolygons /
    /// dice_threads`; 0 when nothing was diced).
    pub fn thread_utilization(&self) -> f64 {
        if self.dice_threads == 0 {
            0.0
        } else {
            self.micropolygons as f64 / self.dice_threads as f64
        }
    }

    /// Micropolygons per sample hit (0 when no sample was hit).
    pub fn micropolygons_per_hit(&self) -> f64 {
        if self.samples_hit == 0 {
            0.0
        } else {
            self.micropolygons as f64 / self.samples_hit as f64
        }
    }

    /// Sample test efficiency: samples hit per sample tested (0 when none
    /// was tested).
    pub fn sample_test_efficiency(&self) -> f64 {
        if self.samples_tested == 0 {
            0.0
        } else {
            self.samples_hit as f64 / self.samples_tested as f64
        }
    }

    /// Samples hit per sample looked up, tested or skipped: the sample test
    /// efficiency as Fatahalian et al. count it, whose rasterizers test
    /// every sample their loops reach (0 when none was looked up).
    pub fn sample_lookup_efficiency(&self) -> f64 {
        let looked_up = self.samples_tested + self.samples_skipped;
        if looked_up == 0 {
            0.0
        } else {
            self.samples_hit as f64 / looked_up as f64
        }
    }
}
