//! How a run executes the compiled graph: the persistent megakernel or
//! kernel-by-kernel rounds.

use std::fmt;

/// Default number of rounds encoded between two checks of the done flag.
pub const DEFAULT_ROUNDS_PER_BATCH: u32 = 8;

/// The execution strategy of one run. Both run the same compiled module and
/// give the same per-procedure counts (docs/scheduler.md, "Strategies").
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Strategy {
    /// Persistent workgroups pick batches from any queue until no work is
    /// left (Whippletree's megakernel). The host dispatches again only when an
    /// iteration budget ends a dispatch early.
    #[default]
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

    /// A short name: `megakernel` or `rounds`.
    pub const fn name(&self) -> &'static str {
        match self {
            Self::Megakernel => "megakernel",
            Self::Rounds { .. } => "rounds",
        }
    }
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Megakernel => f.write_str("megakernel"),
            Self::Rounds { rounds_per_batch } => write!(f, "rounds ({rounds_per_batch} per batch)"),
        }
    }
}
