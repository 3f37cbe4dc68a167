//! Driver quirks: behaviours of particular drivers that the scheduler works
//! around, decided once per adapter from its driver name (as wgpu-hal's
//! `Workarounds` are) and applied by the executor. Nothing else in the
//! crate asks what kind of adapter it runs on. docs/scheduler.md ("Driver
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
}

/// llvmpipe (Mesa's CPU driver, behind lavapipe), measured on Mesa 22.3.6.
const LLVMPIPE_LOOP_BUDGET: LoopBudget = LoopBudget {
    driver_iterations: 65_535,
    batches: 64,
    chunks: 256,
    spin_limit: 8192,
};

/// What the scheduler works around on one adapter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Quirks {
    /// `Some` on drivers that cap the loops of an invocation (llvmpipe):
    /// the megakernel then runs with a default iteration budget and spin
    /// limit, and a cut loop is reported as
    /// [`RunError::LoopLimit`](crate::RunError::LoopLimit).
    pub loop_budget: Option<LoopBudget>,
}

impl Quirks {
    /// The quirks of the adapter `info` describes, from its driver name:
    /// llvmpipe (`driver` on Vulkan, `name` on GL) caps loops. Other CPU
    /// drivers (WARP, SwiftShader) are not assumed to.
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        let llvmpipe = info.driver.eq_ignore_ascii_case("llvmpipe")
            || info.name.to_ascii_lowercase().starts_with("llvmpipe");
        Self {
            loop_budget: llvmpipe.then_some(LLVMPIPE_LOOP_BUDGET),
        }
    }

    /// The quirks of the adapter behind `device`.
    pub fn of_device(device: &wgpu::Device) -> Self {
        Self::of(&device.adapter_info())
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

    /// Spin-wait iterations after which a workgroup leaves (`u32::MAX`:
    /// never).
    pub fn spin_limit(&self) -> u32 {
        self.loop_budget
            .map_or(u32::MAX, |budget| budget.spin_limit)
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
            assert_eq!(quirks, Quirks::default(), "{}", other.name);
            assert_eq!(quirks.default_iteration_budget(4), None);
            assert_eq!(quirks.spin_limit(), u32::MAX);
        }
    }
}
