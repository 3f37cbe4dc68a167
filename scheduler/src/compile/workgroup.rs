//! Workgroup memory, measured on the validated module: every
//! `var<workgroup>` it declares, the scheduler's, the shared scratch and the
//! library's alike, so a variable added anywhere is counted.

use naga::{AddressSpace, Module};

use crate::CompileError;
use crate::compile::plan::Plan;

/// WebGPU counts each workgroup variable as its size rounded up to 16 bytes
/// (the rule behind `maxComputeWorkgroupStorageSize`).
const VARIABLE_GRANULE: u32 = 16;

/// Workgroup bytes of `module`: every workgroup variable, each rounded up as
/// WebGPU counts it. All of them, not only those an entry point uses: the
/// megakernel reaches every body, and scratch a procedure declares counts
/// even before its body uses it.
pub(crate) fn bytes(module: &Module) -> u32 {
    module
        .global_variables
        .iter()
        .filter(|(_, var)| var.space == AddressSpace::WorkGroup)
        .map(|(_, var)| {
            module.types[var.ty]
                .inner
                .size(module.to_ctx())
                .next_multiple_of(VARIABLE_GRANULE)
        })
        .fold(0u32, u32::saturating_add)
}

/// The module's workgroup bytes. Fails with [`CompileError::ScratchTooLarge`]
/// beyond `limit`, naming the procedure with the largest scratch (the part of
/// the need a graph usually controls).
pub(crate) fn check(module: &Module, plan: &Plan, limit: u32) -> Result<u32, CompileError> {
    let needed = bytes(module);
    if needed <= limit {
        return Ok(needed);
    }
    let largest = plan
        .queues
        .iter()
        .max_by_key(|q| q.scratch_words.saturating_mul(q.items_per_workgroup))
        .expect("a compiled graph has at least one procedure");
    let per_item = largest.scratch_words * 4;
    Err(CompileError::ScratchTooLarge {
        procedure: largest.name.clone(),
        per_item,
        items: largest.items_per_workgroup,
        internal: needed.saturating_sub(per_item.saturating_mul(largest.items_per_workgroup)),
        needed,
        limit,
    })
}
