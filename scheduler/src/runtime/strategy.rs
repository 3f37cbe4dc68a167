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
    /// adapter ([`Quirks::persistent_threads`](crate::Quirks::persistent_threads)),
    /// Rounds with [`DEFAULT_ROUNDS_PER_BATCH`] elsewhere. Resolved when a run
    /// starts ([`Strategy::resolve`]); reports name the strategy that ran.
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
    /// megakernel where persistent workgroups are known to be safe and
    /// [`Strategy::rounds`] elsewhere; the others are returned as they are.
    pub fn resolve(self, quirks: &Quirks) -> Self {
        match self {
            Self::Auto if quirks.persistent_threads.safe => Self::Megakernel,
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
}
