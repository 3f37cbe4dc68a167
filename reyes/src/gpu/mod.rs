//! The GPU renderer: the Reyes pipeline as one scheduler megakernel.
//!
//! * `graph`: the procedure graph (Bound, SplitU, SplitV,
//!   DiceShadeSample) and its WGSL (`shaders/reyes/`);
//! * `abi`: the codes the WGSL and the host agree on (statistics words,
//!   mode codes), below the data layouts and the graph;
//! * `buffers`: the frame uniform, scene buffers, framebuffer and statistics;
//!   the lights' layout is `lights`;
//! * `shadow_maps`: the shadow maps' table and depths in the texel
//!   buffer, and the shadow lookup's WGSL;
//! * `objects`: the per-object table (albedo, displacement) and the
//!   height-map texels' layout;
//! * `loop_limit`: [`LoopLimitError`], the advice when llvmpipe's loop
//!   limit still cut loops short after the scheduler's retries;
//! * `resolve`: the clear and resolve passes (a plain compute shader);
//! * `renderer`: [`GpuRenderer`], which runs a frame and returns the image
//!   and [`crate::stats::RenderStats`]; its options and results, its error,
//!   the screen tiles and the batches of input patches are private modules
//!   beside it, re-exported from `renderer`. Per-driver defaults come from
//!   [`scheduler::Quirks`].
//!
//! ```no_run
//! use reyes::gpu::{GpuRenderer, GpuOptions};
//! use reyes::{prepare::PreparedScene, scene::Scene};
//!
//! let gpu = reyes::gpu::create_gpu()?;
//! let mut renderer = GpuRenderer::new(&gpu, GpuOptions::default())?;
//! let scene = PreparedScene::load(&Scene::default_teapot())?;
//! let rendered = renderer.render(&scene)?;
//! reyes::output::write_png(&rendered.image, "teapot.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

internal_modules! {
    abi;
    buffers;
    graph;
    loop_limit;
    objects;
    renderer;
    resolve;
    shadow_maps;
}

mod batches;
mod counters;
mod frame_uniform;
mod lights;
mod options;
mod patch_item;
mod pipeline_cache;
mod render_error;
mod shared_constants;
mod tiles;
mod variant;

pub use buffers::patch_store_bytes;
pub use loop_limit::{LoopLimitContext, LoopLimitError, LoopLimitHint};
pub use pipeline_cache::{
    CACHE_DIR_ENV, PipelineInfo, default_pipeline_cache_dir, pipeline_cache_dir,
};
pub use renderer::{DEFAULT_RENDER_TIMEOUT, GpuOptions, GpuRendered, GpuRenderer, RenderError};
pub use variant::{DepthTest, KernelVariant};

/// Creates a device for the renderer, with 64-bit atomics where the
/// adapter has them (`graph::WIDE_ATOMICS`: the depth test then takes one
/// pass instead of two, [`DepthTest`]).
pub fn create_gpu() -> Result<scheduler::Gpu, RenderError> {
    scheduler::Gpu::new(&scheduler::DeviceRequest {
        optional_features: graph::WIDE_ATOMICS,
        ..Default::default()
    })
    .map_err(RenderError::Device)
}
