//! [`RenderError`]: why a frame could not be rendered.

use scheduler::{CompileError, DeviceError, RunError};

use super::loop_limit::LoopLimitError;

/// Why a frame could not be rendered.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No GPU device could be created.
    #[error("could not create a GPU device: {0}")]
    Device(#[source] DeviceError),
    /// More chunks per batch than llvmpipe compiles in reasonable time
    /// ([`scheduler::Quirks::max_chunks_per_batch`]).
    #[error(
        "{chunks} chunks per batch: llvmpipe would compile that megakernel for many minutes (its compile grows with the chunk count); at most {max} are accepted on this driver"
    )]
    TooManyChunks {
        /// Chunks per batch asked for.
        chunks: u32,
        /// The most accepted on this driver.
        max: u32,
    },
    /// The image is too large for the device's buffers.
    #[error(
        "{width}x{height} at {spp} spp needs a {needed}-byte {what} but the device allows at most {limit} bytes per buffer; lower the resolution or spp"
    )]
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Samples per pixel.
        spp: u32,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// The scene's height maps and textures do not fit into one device
    /// buffer.
    #[error(
        "the scene's height maps, textures, time/lens tables, patches and shader parameters need {needed} bytes but the device allows at most {limit} bytes per buffer; use fewer or smaller height maps or textures, or fewer patches"
    )]
    HeightMapsTooLarge {
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// A queue of split patches or grids needs more items than the device's
    /// buffers hold: the shading rate makes too many of them.
    #[error(transparent)]
    ShadingRateTooSmall(Box<ShadingRateTooSmall>),
    /// A pass of the frame needs more workgroups than the device
    /// dispatches, even spread over two dimensions.
    #[error(
        "the {pass} pass of a {width}x{height} frame needs {workgroups} workgroups, more than the device dispatches ({limit} per dimension, {limit}x{limit} in all); lower the resolution or spp"
    )]
    TooManyWorkgroups {
        /// The pass.
        pass: &'static str,
        /// The frame's width.
        width: u32,
        /// Its height.
        height: u32,
        /// The workgroups the pass needs.
        workgroups: u64,
        /// The device's limit per dimension.
        limit: u32,
    },
    /// The megakernel did not compile (a bug in the renderer's WGSL).
    #[error("the Reyes megakernel did not compile: {0}")]
    Compile(#[from] CompileError),
    /// The scheduler could not run the megakernel (after its retries, up to
    /// `super::renderer::RENDER_ATTEMPTS` attempts, when a queue
    /// overflowed).
    #[error("the Reyes megakernel failed: {error}{advice}", error = .0, advice = run_advice(.0))]
    Run(#[from] RunError),
    /// llvmpipe's loop limit still cut loops short after the scheduler's
    /// retries with smaller iteration budgets, so samples would be missing. The error
    /// gives the facts (workgroups, iteration budget, attempts) and advice
    /// that follows from the frame's configuration ([`LoopLimitError`]).
    #[error(transparent)]
    LoopLimit(Box<LoopLimitError>),
    /// Not even one input patch fits the Bound queue next to the smallest
    /// work queues in one device buffer.
    #[error(
        "the scheduler's queues need {needed} bytes for one input patch next to the split and dice queues at their smallest ({work_capacity} items each), but the device allows at most {limit} bytes per buffer: 0 of the {patches} patches fit per batch"
    )]
    NoBatchFits {
        /// Input patches of the scene.
        patches: usize,
        /// Capacity of each work queue, in items.
        work_capacity: u32,
        /// Bytes of the queues for one input patch.
        needed: u64,
        /// Bytes allowed per buffer.
        limit: u64,
    },
    /// The input patches (which the megakernel reads from one device buffer
    /// whatever the batches) do not fit the device next to the height maps.
    #[error(
        "the scene's {patches} input patches need {needed} bytes next to the height maps and time/lens tables, but the device allows at most {limit} bytes per buffer: {fit} patches fit; use a model with fewer patches"
    )]
    TooManyPatches {
        /// Input patches of the scene.
        patches: usize,
        /// Patches that would fit.
        fit: u64,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
}

/// What to do about a failed run, where the scheduler's message cannot say
/// it: its timeout is the renderer's option.
/// What [`RenderError::ShadingRateTooSmall`] says: the queue that does not
/// fit, the patches whose pieces filled it, the rate they were diced at and
/// the smallest rate that fits.
#[derive(Debug, thiserror::Error)]
#[error(
    "the shading rate {rate} makes too many pieces: queue `{procedure}` needs {needed} items (the split patches and grids that {patches} input patch(es) make at that rate) but at most {max} fit the device's storage buffer limits next to the other queues; {advice}",
    advice = self.advice()
)]
pub struct ShadingRateTooSmall {
    /// The queue that does not fit.
    pub procedure: String,
    /// The items it was measured to need.
    pub needed: u64,
    /// The most the device holds.
    pub max: u32,
    /// The input patches of the run (one batch).
    pub patches: u32,
    /// The smallest shading rate of the scene (pixels per micropolygon).
    pub rate: f32,
    /// The smallest rate that should fit: the pieces of a surface grow as
    /// the inverse of the rate (a grid holds a fixed number of micropolygons
    /// of `rate` pixels each), so `rate * needed / max`; `None` when the
    /// device holds none.
    pub smallest: Option<f32>,
}

impl ShadingRateTooSmall {
    /// The error for queue `procedure` of a run of `patches` input patches
    /// of `scene`.
    pub fn new(
        scene: &crate::prepare::PreparedScene,
        procedure: String,
        needed: u64,
        max: u32,
        patches: u32,
    ) -> Self {
        let rate = scene
            .objects
            .iter()
            .map(|o| scene.object_dicing(o).shading_rate())
            .fold(scene.dicing.shading_rate(), f32::min);
        let smallest = (max > 0).then(|| {
            let scale = needed as f64 / f64::from(max);
            // Two significant digits, rounded up, so the rate named fits.
            let raw = f64::from(rate) * scale.max(1.0);
            let step = 10f64.powf(raw.log10().floor() - 1.0);
            ((raw / step).ceil() * step) as f32
        });
        Self {
            procedure,
            needed,
            max,
            patches,
            rate,
            smallest,
        }
    }

    fn advice(&self) -> String {
        match self.smallest {
            Some(rate) => format!(
                "the smallest shading rate that fits is about {rate} (--shading-rate, `shading_rate`, RIB `ShadingRate`)"
            ),
            None => "raise the shading rate (--shading-rate, `shading_rate`, RIB `ShadingRate`) or use a device with larger buffers".to_owned(),
        }
    }
}

fn run_advice(error: &RunError) -> &'static str {
    match error {
        RunError::Timeout { .. } => {
            "; if the frame only needs longer (a cold shader cache, a large frame on a software adapter), raise the limit: --timeout SECONDS (GpuOptions::timeout)"
        }
        _ => "",
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn a_timeout_names_the_option_that_raises_it() {
        let error = RenderError::Run(RunError::Timeout {
            limit: Duration::from_secs(3),
            report: None,
            also: Vec::new(),
        });
        let text = error.to_string();
        assert!(text.contains("did not finish within 3s"), "{text}");
        assert!(text.contains("--timeout SECONDS"), "{text}");
        let other = RenderError::Run(RunError::Gpu("lost".into()));
        assert!(!other.to_string().contains("--timeout"), "{other}");
    }

    /// D24: the message names what is too large and the smallest rate that
    /// fits (it said `queue Bound needs 0 items but at most 0 fit`).
    #[test]
    fn a_too_small_shading_rate_names_the_rate_that_fits() {
        let error = ShadingRateTooSmall {
            procedure: "DiceShadeSample256".into(),
            needed: 3_000_000,
            max: 1 << 20,
            patches: 32,
            rate: 0.01,
            smallest: Some(0.029),
        };
        let text = RenderError::ShadingRateTooSmall(Box::new(error)).to_string();
        assert!(
            text.contains("the shading rate 0.01 makes too many pieces")
                && text.contains("queue `DiceShadeSample256` needs 3000000 items")
                && text.contains("32 input patch(es)")
                && text.contains("at most 1048576 fit")
                && text.contains("the smallest shading rate that fits is about 0.029"),
            "{text}"
        );
    }

    #[test]
    fn the_smallest_rate_scales_with_the_need_and_rounds_up() {
        let scene = crate::prepare::PreparedScene::new(
            &crate::scene::Scene {
                shading_rate: 0.01,
                ..crate::scene::Scene::default()
            },
            &[],
        )
        .expect("an empty scene prepares");
        let error = ShadingRateTooSmall::new(&scene, "SplitU".into(), 3_000_000, 1 << 20, 4);
        // 0.01 * 3e6 / 2^20 = 0.0286..., up to two digits.
        assert_eq!(error.smallest, Some(0.029));
        assert!(error.smallest.unwrap() * (1 << 20) as f32 >= 0.01 * 3e6);
        let none = ShadingRateTooSmall::new(&scene, "SplitU".into(), 10, 0, 4);
        assert_eq!(none.smallest, None);
        assert!(
            none.to_string().contains("raise the shading rate"),
            "{none}"
        );
    }
}
