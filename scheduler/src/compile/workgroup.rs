//! Workgroup memory, measured on the validated module: every
//! `var<workgroup>` it declares, the scheduler's, the shared scratch and the
//! library's alike, so a variable added anywhere is counted.

use naga::{AddressSpace, Module};

use crate::CompileError;
use crate::naming::scratch_name;
use crate::plan::Plan;

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

/// Bytes of the workgroup variable `name` as WebGPU counts it, 0 if absent.
fn variable_bytes(module: &Module, name: &str) -> u32 {
    module
        .global_variables
        .iter()
        .find(|(_, var)| var.space == AddressSpace::WorkGroup && var.name.as_deref() == Some(name))
        .map_or(0, |(_, var)| {
            module.types[var.ty]
                .inner
                .size(module.to_ctx())
                .next_multiple_of(VARIABLE_GRANULE)
        })
}

/// The module's workgroup bytes. Fails with [`CompileError::ScratchTooLarge`]
/// beyond `limit`, naming the procedure with the largest scratch (the part of
/// the need a graph usually controls): its untyped words plus its typed
/// scratch, measured on the module.
pub(crate) fn check(module: &Module, plan: &Plan, limit: u32) -> Result<u32, CompileError> {
    let needed = bytes(module);
    if needed <= limit {
        return Ok(needed);
    }
    let (largest, per_item) = plan
        .queues
        .iter()
        .map(|q| {
            let typed = variable_bytes(module, &scratch_name(&q.name)) / q.items_per_workgroup;
            (q, q.scratch_words * 4 + typed)
        })
        .max_by_key(|&(q, per_item)| per_item.saturating_mul(q.items_per_workgroup))
        .expect("a compiled graph has at least one procedure");
    Err(CompileError::ScratchTooLarge {
        procedure: largest.name.clone(),
        per_item,
        items: largest.items_per_workgroup,
        internal: needed.saturating_sub(per_item.saturating_mul(largest.items_per_workgroup)),
        needed,
        limit,
    })
}
