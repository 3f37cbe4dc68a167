//! [`RenderError`]: why a frame could not be rendered.

use scheduler::{CompileError, DeviceError, RunError};

use super::loop_limit::LoopLimitError;

/// Why a frame could not be rendered.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No device with the features the renderer needs could be created.
    #[error(
        "could not create a GPU device with 64-bit integer atomics (SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX, needed for the depth test): {0}"
    )]
    Device(#[source] DeviceError),
    /// The device lacks features the renderer needs.
    #[error(
        "the GPU device lacks {missing:?}; the Reyes renderer needs 64-bit integers and 64-bit atomicMin for its depth test (create the device with reyes::gpu::create_gpu)"
    )]
    MissingFeatures {
        /// The features that are missing.
        missing: wgpu::Features,
    },
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
    /// The megakernel did not compile with the scene's user displacement
    /// function (most likely an error in that function).
    #[error(
        "the user displacement function (WGSL defining `fn displacement_user(u: f32, v: f32) -> f32`) does not compile into the megakernel: {0}"
    )]
    UserDisplacement(#[source] CompileError),
    /// The scene's user displacement function fails the checks made on its
    /// own source (syntax, a name of the renderer's, module variables,
    /// barriers), at its own line.
    #[error("the user displacement function is refused: {0}")]
    UserFunction(#[from] crate::displacement::user_wgsl::UserWgslError),
    /// Objects use different user displacement functions; the megakernel
    /// holds one.
    #[error(
        "objects {first} and {other} use different user displacement functions; a scene may use one (it is compiled into the megakernel)"
    )]
    ConflictingUserDisplacement {
        /// The first object with a user function.
        first: usize,
        /// An object whose function differs.
        other: usize,
    },
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
}
