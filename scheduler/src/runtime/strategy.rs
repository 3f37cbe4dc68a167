//! How a run executes the compiled graph: the persistent megakernel or
//! kernel-by-kernel rounds.

use std::fmt;

use crate::Quirks;

/// Default number of rounds encoded between two checks of the done flag.
pub const DEFAULT_ROUNDS_PER_BATCH: u32 = 8;

/// The execution strategy of one run. Both run the same compiled module and
/// give the same per-procedure counts (docs/scheduler.md, "Strategies").
/// [`Strategy::Auto`], the default, picks one of them per adapter.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Strategy {
    /// The megakernel where persistent workgroups are known to be safe on the
    /// adapter ([`Quirks::persistent_threads`](crate::Quirks::persistent_threads))
    /// and Rounds are not faster on its driver (they are on llvmpipe), Rounds
    /// with [`DEFAULT_ROUNDS_PER_BATCH`] elsewhere ([`Quirks::rounds_faster`](crate::Quirks::rounds_faster)).
    /// Resolved when a run starts ([`Strategy::resolve`]); reports name the
    /// strategy that ran.
    #[default]
    Auto,
    /// Persistent workgroups pick batches from any queue until no work is
    /// left (Whippletree's megakernel). The host dispatches again only when an
    /// iteration budget ends a dispatch early.
    Megakernel,
    /// Kernel-by-kernel: each round dispatches every procedure's own entry
    /// point over exactly the items queued when the round started; children go
    /// to the next round. Dispatch sizes come from a prepare kernel through
    /// indirect dispatches, and no workgroup ever waits on another, so this is
    /// the portable fallback where persistent threads are unsafe.
    Rounds {
        /// Rounds encoded per submission; the host reads the done flag after
        /// each batch, so extra rounds at the end are empty dispatches.
        rounds_per_batch: u32,
    },
}

impl Strategy {
    /// Rounds with [`DEFAULT_ROUNDS_PER_BATCH`].
    pub const fn rounds() -> Self {
        Self::Rounds {
            rounds_per_batch: DEFAULT_ROUNDS_PER_BATCH,
        }
    }

    /// The strategy that runs on an adapter with `quirks`: `Auto` becomes the
    /// megakernel where persistent workgroups are known to be safe
    /// ([`Quirks::persistent_threads`](crate::Quirks::persistent_threads)) and
    /// Rounds are not faster ([`Quirks::rounds_faster`]), else
    /// [`Strategy::rounds`]; the others are returned as they are.
    pub fn resolve(self, quirks: &Quirks) -> Self {
        match self {
            Self::Auto if quirks.persistent_threads.safe && !quirks.rounds_faster() => {
                Self::Megakernel
            }
            Self::Auto => Self::rounds(),
            chosen => chosen,
        }
    }

    /// A short name: `auto`, `megakernel` or `rounds`.
    pub const fn name(&self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Megakernel => "megakernel",
            Self::Rounds { .. } => "rounds",
        }
    }
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Auto => f.write_str("auto"),
            Self::Megakernel => f.write_str("megakernel"),
            Self::Rounds { rounds_per_batch } => write!(f, "rounds ({rounds_per_batch} per batch)"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_strategy_round_trips_through_serde_and_has_a_name() {
        for strategy in [Strategy::Auto, Strategy::Megakernel, Strategy::rounds()] {
            let json = serde_json::to_string(&strategy).unwrap();
            let back: Strategy = serde_json::from_str(&json).unwrap();
            assert_eq!(back, strategy, "{json}");
            assert!(strategy.to_string().starts_with(strategy.name()));
        }
        assert_eq!(
            serde_json::to_string(&Strategy::Auto).unwrap(),
            r#"{"kind":"auto"}"#
        );
        assert_eq!(Strategy::default(), Strategy::Auto);
    }

    fn adapter(
        name: &str,
        vendor: u32,
        device_type: wgpu::DeviceType,
        backend: wgpu::Backend,
    ) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: name.into(),
            vendor,
            ..wgpu::AdapterInfo::new(device_type, backend)
        }
    }

    #[test]
    fn auto_runs_the_megakernel_only_where_persistent_workgroups_are_known_safe_and_faster() {
        use wgpu::{Backend, DeviceType};
        const NVIDIA: u32 = 0x10de;
        const AMD: u32 = 0x1002;
        let lavapipe = wgpu::AdapterInfo {
            driver: "llvmpipe".into(),
            ..adapter(
                "llvmpipe (LLVM 15.0.6, 256 bits)",
                0x10005,
                DeviceType::Cpu,
                Backend::Vulkan,
            )
        };
        let swiftshader = wgpu::AdapterInfo {
            driver: "SwiftShader driver".into(),
            ..adapter(
                "SwiftShader Device",
                0x1ae0,
                DeviceType::Cpu,
                Backend::Vulkan,
            )
        };
        let megakernel = Strategy::Megakernel;
        let rounds = Strategy::rounds();
        let cases = [
            // Persistent workgroups are safe on llvmpipe, but Rounds are faster.
            (lavapipe, rounds),
            (
                adapter(
                    "NVIDIA H200",
                    NVIDIA,
                    DeviceType::DiscreteGpu,
                    Backend::Vulkan,
                ),
                megakernel,
            ),
            (
                adapter(
                    "AMD Radeon RX 7900",
                    AMD,
                    DeviceType::DiscreteGpu,
                    Backend::Dx12,
                ),
                megakernel,
            ),
            // The same GPUs elsewhere, and every other platform: Rounds.
            (
                adapter("NVIDIA H200", NVIDIA, DeviceType::DiscreteGpu, Backend::Gl),
                rounds,
            ),
            (
                adapter(
                    "AMD Radeon Pro",
                    AMD,
                    DeviceType::DiscreteGpu,
                    Backend::Metal,
                ),
                rounds,
            ),
            (
                adapter("Apple M2", 0, DeviceType::IntegratedGpu, Backend::Metal),
                rounds,
            ),
            (
                adapter(
                    "AMD Radeon 780M",
                    AMD,
                    DeviceType::IntegratedGpu,
                    Backend::Vulkan,
                ),
                rounds,
            ),
            (
                adapter(
                    "Intel Arc A770",
                    0x8086,
                    DeviceType::DiscreteGpu,
                    Backend::Vulkan,
                ),
                rounds,
            ),
            (swiftshader, rounds),
            (
                adapter(
                    "Microsoft Basic Render Driver",
                    0x1414,
                    DeviceType::Cpu,
                    Backend::Dx12,
                ),
                rounds,
            ),
        ];
        for (adapter, expected) in cases {
            let quirks = Quirks::of(&adapter);
            assert_eq!(
                Strategy::Auto.resolve(&quirks),
                expected,
                "{} on {:?}: {:?}",
                adapter.name,
                adapter.backend,
                quirks.persistent_threads
            );
            // An explicit strategy is never changed.
            assert_eq!(Strategy::Megakernel.resolve(&quirks), Strategy::Megakernel);
            assert_eq!(Strategy::rounds().resolve(&quirks), Strategy::rounds());
        }
        // Every row says why.
        assert!(Quirks::persistent_threads_table().all(|row| !row.reason.is_empty()));
    }
}
