//! Options that make compilation independent of the machine it runs on.

/// How a workgroup chooses the next queue to pop from.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Policy {
    /// Take work from the highest-priority non-empty queue (ties: declaration
    /// order). Giving leaves higher priority than their producers works the
    /// graph depth-first and keeps queues small.
    #[default]
    Priority,
    /// Ignore priorities: each workgroup starts its scan at a queue that rotates
    /// with the workgroup index and iteration.
    RoundRobin,
}

/// What a graph is compiled for. The generated WGSL depends only on the graph
/// and these options, never on the adapter it later runs on.
#[derive(Clone, Debug)]
pub struct CompileOptions {
    /// Threads per workgroup (a power of two).
    pub workgroup_size: u32,
    /// Queue selection policy.
    pub policy: Policy,
    /// Limits the module must respect (workgroup memory, bindings, sizes).
    pub limits: wgpu::Limits,
    /// Features the module may use (passed to naga validation as capabilities).
    pub features: wgpu::Features,
    /// Chunks per batch, from 1 to [`MAX_CHUNKS_PER_BATCH`]. A chunk is one
    /// workgroup-full of items (workgroup size / threads per item). A batch
    /// claims up to this many chunks at once and runs the body once per chunk,
    /// so the per-batch work (claiming, reserving and publishing children,
    /// releasing slots) is shared by more items. Fewer chunks keep batches
    /// small, so that more workgroups share a short queue. Default 1; on
    /// llvmpipe 4 is markedly faster (docs/performance.md, "Chunks per batch"),
    /// which [`CompileOptions::for_adapter`] takes.
    pub chunks_per_batch: u32,
    /// Checked mode: every index into a runtime-sized array resource made by
    /// a body or the library is compared with the bound buffer's length, and
    /// a run with a violation fails with
    /// [`RunError::OutOfBounds`](crate::RunError::OutOfBounds). Costs a
    /// branch per access (docs/scheduler.md, "Checked mode"). Without it,
    /// such an access is undefined behaviour.
    pub checked: bool,
    /// Specialization: fold every `if` whose condition is a constant
    /// expression (graph constants make a caller's switches constant) and
    /// drop the functions no entry point reaches any more, so the driver
    /// compiles only what can run (docs/scheduler.md, "Specialization").
    /// Default on; off keeps the module as generated, for debugging.
    pub specialize: bool,
    /// Tracing: every batch is recorded (workgroup, procedure, items, a
    /// logical timestamp, the queue fills) into a buffer of this many
    /// records, read back into [`RunReport::trace`](crate::RunReport::trace)
    /// (docs/scheduler.md, "Seeing a run"). Default off: the module then
    /// holds no trace code and no buffer is allocated.
    pub trace: Option<TraceOptions>,
}

/// How a traced run records its batches ([`CompileOptions::trace`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TraceOptions {
    /// Records the trace buffer holds. The first `capacity` batches of a run
    /// are kept; the later ones are counted as
    /// [`Trace::dropped`](crate::Trace::dropped).
    pub capacity: u32,
}

impl Default for TraceOptions {
    /// 65536 records.
    fn default() -> Self {
        Self { capacity: 1 << 16 }
    }
}

/// Largest [`CompileOptions::chunks_per_batch`]. Staging memory grows with it
/// (each workgroup stages up to a whole batch's children).
pub const MAX_CHUNKS_PER_BATCH: u32 = 64;

impl Default for CompileOptions {
    /// 256 threads, priority policy, WebGPU default limits, no features, one
    /// chunk per batch, specialized.
    fn default() -> Self {
        Self {
            workgroup_size: 256,
            policy: Policy::Priority,
            limits: wgpu::Limits::default(),
            features: wgpu::Features::empty(),
            chunks_per_batch: 1,
            checked: false,
            specialize: true,
            trace: None,
        }
    }
}

impl CompileOptions {
    /// These options in checked mode ([`CompileOptions::checked`]).
    pub fn checked(self) -> Self {
        Self {
            checked: true,
            ..self
        }
    }

    /// Default options with the chunks per batch worth compiling for on the
    /// adapter `info` describes ([`Quirks::chunks_per_batch`](crate::Quirks::chunks_per_batch):
    /// 4 on llvmpipe, 1 elsewhere). The generated WGSL still depends only on
    /// the options: the adapter is named here, explicitly, and the same
    /// adapter gives the same module. Set fields afterwards to override.
    pub fn for_adapter(info: &wgpu::AdapterInfo) -> Self {
        Self {
            chunks_per_batch: crate::Quirks::of(info).chunks_per_batch(),
            ..Self::default()
        }
    }

    /// These options with tracing on ([`CompileOptions::trace`]).
    pub fn traced(self, trace: TraceOptions) -> Self {
        Self {
            trace: Some(trace),
            ..self
        }
    }

    /// Default options with the given features enabled.
    pub fn with_features(features: wgpu::Features) -> Self {
        Self {
            features,
            ..Self::default()
        }
    }
}

/// The optional features the generated megakernel can use, restricted to those
/// `device` has. Pass the result to [`CompileOptions::with_features`] (combined
/// with your own). It is explicit on purpose: the same features give the same
/// WGSL on every machine.
///
/// Today this is `MEMORY_DECORATION_COHERENT`: queue payloads are then plain
/// `@coherent` loads and stores instead of atomics (faster; see
/// docs/scheduler.md, "Hand-off").
pub fn recommended_features(device: &wgpu::Device) -> wgpu::Features {
    device.features() & wgpu::Features::MEMORY_DECORATION_COHERENT
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_for_an_adapter_take_its_chunks_per_batch() {
        let lavapipe = wgpu::AdapterInfo {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            driver: "llvmpipe".into(),
            ..wgpu::AdapterInfo::new(wgpu::DeviceType::Cpu, wgpu::Backend::Vulkan)
        };
        assert_eq!(CompileOptions::for_adapter(&lavapipe).chunks_per_batch, 4);
        let gpu = wgpu::AdapterInfo::new(wgpu::DeviceType::DiscreteGpu, wgpu::Backend::Vulkan);
        assert_eq!(CompileOptions::for_adapter(&gpu).chunks_per_batch, 1);
        assert!(CompileOptions::for_adapter(&gpu).specialize);
    }
}
