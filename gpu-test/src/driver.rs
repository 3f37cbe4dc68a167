//! Outcomes that depend on the driver and are valid either way: a test
//! asks which one to check here, so that no test decides from adapter names
//! itself.

use scheduler::{Gpu, Quirks};

/// What the adapter behind `gpu` is expected to do where drivers differ
/// legitimately.
pub fn expect(gpu: &Gpu) -> DriverBehaviour {
    DriverBehaviour {
        quirks: Quirks::of(&gpu.adapter.get_info()),
    }
}

/// The driver-dependent behaviours of one adapter, from its
/// [`scheduler::Quirks`].
#[derive(Clone, Copy, Debug)]
pub struct DriverBehaviour {
    quirks: Quirks,
}

impl DriverBehaviour {
    /// Whether the driver caps the loops of an invocation (llvmpipe): only
    /// there can a run end in a loop limit, and only there does the
    /// scheduler default to an iteration budget.
    pub fn loops_capped(&self) -> bool {
        self.quirks.caps_loops()
    }

    /// The quirks the scheduler applies on this adapter.
    pub fn quirks(&self) -> Quirks {
        self.quirks
    }
}
