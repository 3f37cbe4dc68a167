//! The patch budget: how many bicubic patches one scene may bring into
//! memory, counted before they are made.
//!
//! A few bytes of input can ask for many patches: a RIB quadric becomes up
//! to 64 x 64 of them, a polygon a fan of them, a model file declares its
//! count in its first line. Every producer estimates what a request (a RIB
//! request, a model file) will make and takes it from one [`PatchBudget`]
//! per scene *before* making it, so a scene is refused at the request that
//! would pass the budget, whether that request is one large one or the
//! 4,097th modest one. [`DEFAULT_MAX_PATCHES`] is the default; the CLI's
//! `--max-patches` changes it for the process ([`set_max_patches`]).
//!
//! Memory: a patch is [`PATCH_BYTES`] bytes of control points. Reading and
//! preparing a scene holds at most a few copies of them at once (the
//! reader's, the scene's models, the prepared world-space patches), so its
//! peak memory stays within [`MEMORY_MULTIPLE`] times the budget's bytes,
//! plus the input text and the process's base (see `docs/reyes.md`, "Patch
//! budget").

use std::sync::atomic::{AtomicU64, Ordering};

/// The default budget: 2^20 patches (192 MiB of control points), several
/// times the largest scenes in `docs/scenes` and the gallery, and small
/// enough that a refused scene stays within a gigabyte.
pub const DEFAULT_MAX_PATCHES: u64 = 1 << 20;

/// The bytes of one patch's control points (16 `f32` points).
pub const PATCH_BYTES: u64 = std::mem::size_of::<crate::model::Patch>() as u64;

/// How many times the budget's bytes reading and preparing a scene may
/// hold at once (documented, and measured by the tests).
pub const MEMORY_MULTIPLE: u64 = 3;

/// The process-wide budget. A global, as the input caps
/// (`crate::input::set_limits`), because models are read deep inside
/// [`crate::scene::Scene::load_models`], which a command line sets up once.
static MAX_PATCHES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_PATCHES);

/// Sets the budget of every later scene, for the whole process (the CLI's
/// `--max-patches`).
pub fn set_max_patches(patches: u64) {
    MAX_PATCHES.store(patches, Ordering::Relaxed);
}

/// The budget in force ([`DEFAULT_MAX_PATCHES`] unless
/// [`set_max_patches`] was called).
pub fn max_patches() -> u64 {
    MAX_PATCHES.load(Ordering::Relaxed)
}

/// The patches one scene has taken, and its limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PatchBudget {
    limit: u64,
    used: u64,
}

impl PatchBudget {
    /// A budget of `limit` patches, none taken.
    pub fn new(limit: u64) -> PatchBudget {
        PatchBudget { limit, used: 0 }
    }

    /// A budget of [`max_patches`] patches, none taken.
    pub fn from_setting() -> PatchBudget {
        PatchBudget::new(max_patches())
    }

    /// The patches taken so far.
    pub fn used(&self) -> u64 {
        self.used
    }

    /// The limit.
    pub fn limit(&self) -> u64 {
        self.limit
    }

    /// Takes `patches` (an estimate made before making them), or says by
    /// how much they would pass the limit; nothing is taken then.
    pub fn take(&mut self, patches: u64) -> Result<(), BudgetExceeded> {
        match self.used.checked_add(patches) {
            Some(total) if total <= self.limit => {
                self.used = total;
                Ok(())
            }
            _ => Err(BudgetExceeded {
                patches,
                used: self.used,
                limit: self.limit,
            }),
        }
    }

    /// Gives back `patches` taken by an estimate that made fewer.
    pub fn give_back(&mut self, patches: u64) {
        self.used = self.used.saturating_sub(patches);
    }

    /// The patches still free.
    pub fn remaining(&self) -> u64 {
        self.limit.saturating_sub(self.used)
    }

    /// The refusal of a request for `patches` more than
    /// [`PatchBudget::remaining`] (what [`PatchBudget::take`] returns for
    /// it), for a producer that learns it would pass the budget before it
    /// knows by how much.
    pub fn refusal(&self, patches: u64) -> BudgetExceeded {
        BudgetExceeded {
            patches,
            used: self.used,
            limit: self.limit,
        }
    }
}

/// A request that would pass the patch budget.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "{patches} patches ({}) would bring the scene to {} patches, over the budget of {limit} ({}); raise it with --max-patches",
    mib(*patches),
    used.saturating_add(*patches),
    mib(*limit)
)]
pub struct BudgetExceeded {
    /// The patches the request would make.
    pub patches: u64,
    /// The patches the scene had before it.
    pub used: u64,
    /// The budget.
    pub limit: u64,
}

/// The control points of `patches` patches, in MiB, for messages.
fn mib(patches: u64) -> String {
    let bytes = patches as f64 * PATCH_BYTES as f64;
    format!("{:.1} MiB", bytes / f64::from(1u32 << 20))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_patch_is_sixteen_f32_points() {
        assert_eq!(PATCH_BYTES, 16 * 3 * 4);
    }

    #[test]
    fn the_budget_refuses_the_request_that_passes_it_and_takes_nothing() {
        let mut budget = PatchBudget::new(10);
        assert!(budget.take(6).is_ok());
        assert!(budget.take(4).is_ok());
        let error = budget.take(1).unwrap_err();
        assert_eq!(
            error,
            BudgetExceeded {
                patches: 1,
                used: 10,
                limit: 10
            }
        );
        assert_eq!(budget.used(), 10);
        assert!(budget.take(u64::MAX).is_err());
        budget.give_back(3);
        assert_eq!(budget.used(), 7);
        let text = PatchBudget::new(4).take(4096).unwrap_err().to_string();
        assert_eq!(
            text,
            "4096 patches (0.8 MiB) would bring the scene to 4096 patches, over the budget of 4 (0.0 MiB); raise it with --max-patches"
        );
    }
}
