//! The result of a checked run, shared by the workloads whose result is a
//! list of disagreements with their CPU reference.

use scheduler::RunReport;

/// A checked run: the report and every disagreement with the CPU (none when
/// the run is correct).
#[derive(Debug)]
pub struct Checked {
    /// The scheduler's report of the run.
    pub report: RunReport,
    /// Every disagreement with the CPU, empty when the run is correct.
    pub mismatches: Vec<String>,
    /// A human-readable summary of the result.
    pub summary: String,
}
