//! Defaults for CPU adapters (llvmpipe behind lavapipe), whose driver caps
//! the loop iterations of an invocation, and how the renderer tells them
//! apart.

use scheduler::Gpu;

use super::options::GpuOptions;

/// Iteration budget on CPU adapters (llvmpipe). llvmpipe ends loops once an
/// invocation has run 65535 loop iterations, counted across all loops and
/// all their runs (the scheduler's queue waits included). With the
/// scheduler's CPU default of 64 batches per dispatch the rasterization
/// loops of DiceShadeSample were cut in a 256-workgroup teapot run (detected
/// through `STAT_LOOPS_CUT`); 16 batches per dispatch left room in every
/// uncontended run, at the cost of a few more dispatches.
pub const CPU_ITERATION_BUDGET: u32 = 16;
/// Persistent workgroups on CPU adapters: one per CPU thread, so that all
/// of them run at once. llvmpipe runs only as many workgroups at a time as it
/// has threads; a workgroup polling for work that a descheduled workgroup is
/// producing spends llvmpipe's shared loop budget (see
/// [`CPU_ITERATION_BUDGET`]) until the body's own loops get cut. With 256 or
/// 16 workgroups that happened in 800x600 and 1920x1080 teapot frames even at
/// 4 batches per dispatch.
pub fn cpu_workgroups() -> u32 {
    std::thread::available_parallelism().map_or(2, |n| n.get().min(64) as u32)
}
/// Chunks per batch on CPU adapters ([`scheduler::CompileOptions::chunks_per_batch`])
/// for frames without motion blur or depth of field. llvmpipe runs every part
/// of the megakernel for every group of 8 lanes, whichever procedure the batch
/// belongs to, so larger batches share that cost among more items: the
/// default teapot frame takes about 1.5 s with 4 chunks against 2.4 s with 1
/// (docs/performance.md, "Chunks per batch"). Frames that sample time or
/// lens keep 1: their rasterization loops are long enough that 4 chunks per
/// batch ran into llvmpipe's loop limit (see [`CPU_ITERATION_BUDGET`]), and
/// the bookkeeping is a small share of their time.
pub const CPU_CHUNKS_PER_BATCH: u32 = 4;
/// Iteration budget of the one retry after llvmpipe cut loops short. The
/// loop counter llvmpipe keeps is shared by all loops of an invocation,
/// including the scheduler's queue waits, which grow when other work
/// competes for the CPU; fewer batches per dispatch leave more headroom.
pub const CPU_RETRY_ITERATION_BUDGET: u32 = 1;

/// The most chunks per batch the renderer compiles for on llvmpipe. The
/// megakernel's workgroup staging grows with the chunk count, and so does
/// llvmpipe's compile of it (measured on the 2-core VM, shader cache cold,
/// `reyes render --chunks N --width 64 --height 48`): 96 s at 2 chunks,
/// 324 s at 8, and the 64 chunks the scheduler allows ran past 400 s
/// at 4.2 GB. Above this, [`super::GpuRenderer::new`] refuses with
/// [`super::RenderError::TooManyChunks`] instead of appearing to hang.
pub const CPU_MAX_CHUNKS_PER_BATCH: u32 = 4;

/// Whether `gpu`'s driver caps the loops of an invocation (llvmpipe behind
/// lavapipe), as the scheduler's [`scheduler::Quirks`] decide.
pub(super) fn is_cpu(gpu: &Gpu) -> bool {
    scheduler::Quirks::of(&gpu.adapter.get_info()).caps_loops()
}

/// The chunks per batch `options` ask for on `gpu`, for a frame that samples
/// time or lens (`blurred`) or not.
pub(super) fn chunks_per_batch(gpu: &Gpu, options: &GpuOptions, blurred: bool) -> u32 {
    options
        .chunks_per_batch
        .unwrap_or(if is_cpu(gpu) && !blurred {
            CPU_CHUNKS_PER_BATCH
        } else {
            1
        })
}
