//! Driver quirks: behaviours of particular drivers that the scheduler works
//! around, decided once per adapter from its driver name (as wgpu-hal's
//! `Workarounds` are) and applied by the executor; libraries built on the
//! scheduler take their per-driver defaults from here too (the Reyes
//! renderer's workgroups, chunks per batch and first iteration budget).
//! Nothing else in the crate asks what kind of adapter it runs on. docs/scheduler.md ("Driver
//! quirks") lists each quirk, what it costs elsewhere and the test that
//! shows it.

/// llvmpipe's loop budget, and the defaults that keep every invocation of
/// the megakernel within it (docs/scheduler.md, "Loop limits").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoopBudget {
    /// Iterations the driver allows all the loops nested in an invocation's
    /// outermost loop together; past it, they all end early.
    pub driver_iterations: u32,
    /// Default iteration budget: batches after which a workgroup leaves
    /// the persistent loop and the host dispatches again. Leaving after 64
    /// batches starts fresh invocations often enough for bodies whose loops
    /// run up to ~800 iterations per batch.
    pub batches: u32,
    /// The default budget also stops at this many chunks (batches times
    /// chunks per batch), because each chunk runs the bodies' loops once
    /// more: 64 batches of up to 4 chunks, 16 of 16, 4 of 64.
    pub chunks: u32,
    /// Spin-wait iterations after which a workgroup leaves at its next
    /// batch boundary. Each makes 64 checks; together with the budget they
    /// leave an invocation roughly 50,000 iterations for the bodies.
    pub spin_limit: u32,
    /// Batches per dispatch for graphs whose bodies run long loops of their
    /// own (a rasterizer's sample loops: hundreds to thousands of iterations
    /// per item), which share the same budget. Measured with the Reyes
    /// renderer: at 64 batches per dispatch the rasterization loops of
    /// DiceShadeSample were cut in a 256-workgroup teapot run (counted by
    /// the renderer's `STAT_LOOPS_CUT` and reported through
    /// [`Retry::check_loops`](crate::Retry::check_loops)); 16 left room in
    /// every uncontended run, at the cost of a few more dispatches.
    pub long_body_batches: u32,
}

/// How a driver that runs each workgroup on a CPU thread (llvmpipe) wants
/// the megakernel shaped (docs/scheduler.md, "Driver quirks").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CpuWorkgroups {
    /// Chunks per batch ([`CompileOptions::chunks_per_batch`](crate::CompileOptions::chunks_per_batch))
    /// worth compiling for. llvmpipe runs every part of the megakernel for
    /// every group of 8 lanes, whichever procedure the batch belongs to, so
    /// larger batches share that cost among more items: the default Reyes
    /// teapot frame takes about 1.5 s with 4 chunks against 2.4 s with 1
    /// (docs/performance.md, "Chunks per batch"). Graphs whose bodies loop
    /// long (motion blur, depth of field in the renderer) keep 1: 4 chunks
    /// per batch ran them into the loop limit.
    pub chunks_per_batch: u32,
    /// The most chunks per batch worth compiling for. The megakernel's
    /// workgroup staging grows with the chunk count, and so does llvmpipe's
    /// compile of it (measured on a 2-core VM, shader cache cold, the Reyes
    /// megakernel at 64 x 48): 96 s at 2 chunks, 324 s at 8, and the 64
    /// chunks the scheduler allows ran past 400 s at 4.2 GB.
    pub max_chunks_per_batch: u32,
    /// Whether [`Strategy::Auto`](crate::Strategy::Auto) runs Rounds here
    /// although persistent workgroups are safe: Rounds are the faster
    /// strategy on this driver. On llvmpipe every megakernel batch runs all of
    /// the megakernel's code for every 8 lanes and each workgroup is a
    /// coroutine per barrier, while a round kernel holds one procedure and
    /// the barrier-free ones run as plain loops; with 2 CPU threads there are
    /// no idle compute units for persistent workgroups to fill. Measured side
    /// by side (docs/performance.md, "Strategies"): Rounds at the default 256
    /// workgroups were as fast as or faster than the megakernel on the spawn
    /// tree and 1.3x faster on the Mandelbrot set.
    pub auto_rounds: bool,
}

/// llvmpipe's shaping of the megakernel, measured on Mesa 22.3.6.
const LLVMPIPE_WORKGROUPS: CpuWorkgroups = CpuWorkgroups {
    chunks_per_batch: 4,
    max_chunks_per_batch: 4,
    auto_rounds: true,
};

/// llvmpipe (Mesa's CPU driver, behind lavapipe), measured on Mesa 22.3.6.
const LLVMPIPE_LOOP_BUDGET: LoopBudget = LoopBudget {
    driver_iterations: 65_535,
    batches: 64,
    chunks: 256,
    spin_limit: 8192,
    long_body_batches: 16,
};

/// Spin-wait iterations after which a workgroup leaves, on drivers without a
/// loop budget of their own: a wait or an idle workgroup never holds a
/// dispatch for ever, and the host dispatches again while work is
/// outstanding (docs/scheduler.md, "Progress").
pub const DEFAULT_SPIN_LIMIT: u32 = 1 << 16;

/// Whether persistent workgroups (the megakernel) are known to be safe on a
/// platform, and why: [`Strategy::Auto`](crate::Strategy::Auto) runs the
/// megakernel only where they are (docs/scheduler.md, "Driver quirks").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PersistentThreads {
    /// The platform, in words.
    pub platform: &'static str,
    /// Whether the megakernel is known to be safe there.
    pub safe: bool,
    /// Why.
    pub reason: &'static str,
}

/// One row of [`PERSISTENT_THREADS`]: the adapters it covers and its verdict.
struct Platform {
    covers: fn(&wgpu::AdapterInfo) -> bool,
    verdict: PersistentThreads,
}

/// PCI vendor ids of the discrete GPUs known to run persistent workgroups.
const NVIDIA: u32 = 0x10de;
const AMD: u32 = 0x1002;

/// Where persistent workgroups are known to be safe, first match wins. A
/// platform not listed gets Rounds, which needs no forward-progress guarantee
/// at all.
const PERSISTENT_THREADS: &[Platform] = &[
    Platform {
        covers: is_llvmpipe,
        verdict: PersistentThreads {
            platform: "llvmpipe (lavapipe)",
            safe: true,
            reason: "each workgroup runs on a CPU thread that the operating system schedules preemptively, so every launched workgroup runs in turn; the megakernel launches one per CPU thread (`Quirks::megakernel_workgroups`) and the loop budget bounds every wait",
        },
    },
    Platform {
        covers: |info| info.backend == wgpu::Backend::Metal,
        verdict: PersistentThreads {
            platform: "Metal",
            safe: false,
            reason: "Metal gives no forward-progress guarantee between threadgroups, and persistent-thread kernels have been reported to lose the device on macOS",
        },
    },
    Platform {
        covers: |info| info.device_type == wgpu::DeviceType::IntegratedGpu,
        verdict: PersistentThreads {
            platform: "integrated GPUs",
            safe: false,
            reason: "some (AMD integrated GPUs among them) have been reported to lose the device under persistent-thread kernels, and they share the display's watchdog",
        },
    },
    Platform {
        covers: |info| {
            info.device_type == wgpu::DeviceType::DiscreteGpu
                && matches!(info.backend, wgpu::Backend::Vulkan | wgpu::Backend::Dx12)
                && matches!(info.vendor, NVIDIA | AMD)
        },
        verdict: PersistentThreads {
            platform: "NVIDIA and AMD discrete GPUs on Vulkan or DX12",
            safe: true,
            reason: "their hardware schedulers run a resident workgroup until it ends, and workgroups beyond residency start as others leave; the protocol waits only on running workgroups (docs/scheduler.md, \"Progress\"), and every wait is bounded by the spin limit",
        },
    },
];

/// The verdict for adapters no row of [`PERSISTENT_THREADS`] covers.
const UNKNOWN_PLATFORM: PersistentThreads = PersistentThreads {
    platform: "other adapters",
    safe: false,
    reason: "no forward progress between workgroups is known; Rounds needs none (vkd3d-proton emulates D3D12 work graphs level by level for the same reason)",
};

/// Whether `info` describes llvmpipe: `driver` on Vulkan, `name` on GL.
fn is_llvmpipe(info: &wgpu::AdapterInfo) -> bool {
    info.driver.eq_ignore_ascii_case("llvmpipe")
        || info.name.to_ascii_lowercase().starts_with("llvmpipe")
}

/// What the scheduler works around on one adapter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Quirks {
    /// `Some` on drivers that cap the loops of an invocation (llvmpipe):
    /// the megakernel then runs with a default iteration budget and spin
    /// limit, and a cut loop is reported as
    /// [`RunError::LoopLimit`](crate::RunError::LoopLimit).
    pub loop_budget: Option<LoopBudget>,
    /// `Some` on drivers that run each workgroup on a CPU thread
    /// (llvmpipe): see [`Quirks::megakernel_workgroups`] and
    /// [`CpuWorkgroups`].
    pub cpu_workgroups: Option<CpuWorkgroups>,
    /// Whether persistent workgroups are known to be safe here, and why
    /// ([`Strategy::Auto`](crate::Strategy::Auto) takes the megakernel only
    /// where they are).
    pub persistent_threads: PersistentThreads,
}

impl Quirks {
    /// The quirks of the adapter `info` describes, from its driver name:
    /// llvmpipe (`driver` on Vulkan, `name` on GL) caps loops. Other CPU
    /// drivers (WARP, SwiftShader) are not assumed to.
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        let llvmpipe = is_llvmpipe(info);
        Self {
            loop_budget: llvmpipe.then_some(LLVMPIPE_LOOP_BUDGET),
            cpu_workgroups: llvmpipe.then_some(LLVMPIPE_WORKGROUPS),
            persistent_threads: PERSISTENT_THREADS
                .iter()
                .find(|platform| (platform.covers)(info))
                .map_or(UNKNOWN_PLATFORM, |platform| platform.verdict),
        }
    }

    /// Every row of the table [`Strategy::Auto`](crate::Strategy::Auto)
    /// decides by, in the order it is searched, then the verdict for
    /// adapters none covers.
    pub fn persistent_threads_table() -> impl Iterator<Item = PersistentThreads> {
        PERSISTENT_THREADS
            .iter()
            .map(|platform| platform.verdict)
            .chain([UNKNOWN_PLATFORM])
    }

    /// The quirks of the adapter behind `device`.
    pub fn of_device(device: &wgpu::Device) -> Self {
        Self::of(&device.adapter_info())
    }

    /// Whether Rounds are the faster strategy on this driver although
    /// persistent workgroups are safe ([`CpuWorkgroups::auto_rounds`]):
    /// [`Strategy::Auto`](crate::Strategy::Auto) then runs Rounds.
    pub fn rounds_faster(&self) -> bool {
        self.cpu_workgroups.is_some_and(|cpu| cpu.auto_rounds)
    }

    /// Whether the driver caps the loops of an invocation.
    pub fn caps_loops(&self) -> bool {
        self.loop_budget.is_some()
    }

    /// The iteration budget a run gets when its configuration names none:
    /// `None` (no budget) unless the driver caps loops.
    pub fn default_iteration_budget(&self, chunks_per_batch: u32) -> Option<u32> {
        self.loop_budget.map(|budget| {
            budget
                .batches
                .min(budget.chunks / chunks_per_batch.max(1))
                .max(1)
        })
    }

    /// The iteration budget of a first attempt for graphs whose bodies run
    /// long loops of their own ([`LoopBudget::long_body_batches`], within the
    /// same chunk cap as [`Quirks::default_iteration_budget`]): `None` (no
    /// budget) unless the driver caps loops.
    pub fn long_body_iteration_budget(&self, chunks_per_batch: u32) -> Option<u32> {
        self.loop_budget.map(|budget| {
            budget
                .long_body_batches
                .min(budget.chunks / chunks_per_batch.max(1))
                .max(1)
        })
    }

    /// Persistent workgroups for the megakernel: one per CPU thread on
    /// drivers that run each workgroup on one (llvmpipe), so that all of
    /// them run at once; `None` (the scheduler's default) elsewhere.
    /// llvmpipe runs only as many workgroups at a time as it has threads; a
    /// workgroup polling for work that a descheduled workgroup is producing
    /// spends the shared loop budget until the bodies' own loops get cut.
    /// With 256 or 16 workgroups that happened in 800x600 and 1920x1080
    /// Reyes teapot frames even at 4 batches per dispatch. Rounds keep the
    /// scheduler's default: each of their workgroups strides over a round's
    /// batches within one budget.
    pub fn megakernel_workgroups(&self) -> Option<u32> {
        self.cpu_workgroups
            .map(|_| std::thread::available_parallelism().map_or(2, |n| n.get().min(64) as u32))
    }

    /// Chunks per batch worth compiling for on this driver
    /// ([`CpuWorkgroups::chunks_per_batch`]; 1 elsewhere).
    pub fn chunks_per_batch(&self) -> u32 {
        self.cpu_workgroups.map_or(1, |cpu| cpu.chunks_per_batch)
    }

    /// The most chunks per batch this driver compiles in reasonable time
    /// ([`CpuWorkgroups::max_chunks_per_batch`]; `None`: no limit beyond the
    /// scheduler's).
    pub fn max_chunks_per_batch(&self) -> Option<u32> {
        self.cpu_workgroups.map(|cpu| cpu.max_chunks_per_batch)
    }

    /// Spin-wait iterations (waits for free slots and idle picks) after
    /// which a workgroup leaves at its next batch boundary: the loop
    /// budget's on drivers that cap loops, [`DEFAULT_SPIN_LIMIT`]
    /// elsewhere. Every wait is bounded on every adapter.
    pub fn spin_limit(&self) -> u32 {
        self.loop_budget
            .map_or(DEFAULT_SPIN_LIMIT, |budget| budget.spin_limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(name: &str, driver: &str, device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: name.into(),
            driver: driver.into(),
            device_type,
            ..wgpu::AdapterInfo::new(device_type, wgpu::Backend::Vulkan)
        }
    }

    #[test]
    fn llvmpipe_caps_loops_and_other_drivers_do_not() {
        let lavapipe = Quirks::of(&info(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            "llvmpipe",
            wgpu::DeviceType::Cpu,
        ));
        assert!(lavapipe.caps_loops());
        assert_eq!(lavapipe.default_iteration_budget(1), Some(64));
        assert_eq!(lavapipe.default_iteration_budget(16), Some(16));
        assert_eq!(lavapipe.default_iteration_budget(1024), Some(1));
        assert_eq!(lavapipe.spin_limit(), 8192);
        assert_eq!(lavapipe.long_body_iteration_budget(4), Some(16));
        assert_eq!(lavapipe.long_body_iteration_budget(64), Some(4));
        assert_eq!(lavapipe.chunks_per_batch(), 4);
        assert_eq!(lavapipe.max_chunks_per_batch(), Some(4));
        assert!(lavapipe.megakernel_workgroups().is_some_and(|n| n >= 1));
        let gl = Quirks::of(&info("llvmpipe (LLVM 15)", "", wgpu::DeviceType::Cpu));
        assert!(gl.caps_loops());
        for other in [
            info("NVIDIA H200", "NVIDIA", wgpu::DeviceType::DiscreteGpu),
            info(
                "SwiftShader Device",
                "SwiftShader driver",
                wgpu::DeviceType::Cpu,
            ),
            info("Microsoft Basic Render Driver", "", wgpu::DeviceType::Cpu),
        ] {
            let quirks = Quirks::of(&other);
            assert_eq!(quirks.loop_budget, None, "{}", other.name);
            assert_eq!(quirks.cpu_workgroups, None, "{}", other.name);
            assert_eq!(quirks.default_iteration_budget(4), None);
            assert_eq!(quirks.spin_limit(), DEFAULT_SPIN_LIMIT);
            assert_eq!(quirks.long_body_iteration_budget(4), None);
            assert_eq!(quirks.megakernel_workgroups(), None);
            assert_eq!(quirks.chunks_per_batch(), 1);
            assert_eq!(quirks.max_chunks_per_batch(), None);
        }
    }
}
