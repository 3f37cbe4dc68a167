//! The module-scope variables of the generated module: the bindings of the
//! binding table, then the workgroup and private state of the runtime.

use crate::codegen::bindings::{self, Shape};
use crate::codegen::module::Global;
use crate::plan::Plan;

/// The workgroup array that holds every procedure's scratch.
pub(crate) const SCRATCH: &str = "sched_wg_scratch";

/// What the globals depend on besides the plan.
pub(crate) fn shape(plan: &Plan) -> Shape {
    Shape {
        queues: plan.queues.len(),
        coherent: plan
            .features
            .contains(wgpu::Features::MEMORY_DECORATION_COHERENT),
    }
}

fn state(space: &str, name: &str, ty: String, doc: &str) -> Global {
    Global {
        attributes: String::new(),
        space: space.to_owned(),
        name: name.to_owned(),
        ty,
        doc: doc.to_owned(),
    }
}

/// Every module-scope variable, in declaration order.
pub(crate) fn globals(plan: &Plan) -> Vec<Global> {
    let n = plan.queues.len();
    let mut globals: Vec<Global> = bindings::declarations(shape(plan), &plan.resources)
        .into_iter()
        .map(|d| Global {
            attributes: d.attributes(),
            space: d.kind.address_space().to_owned(),
            name: d.name,
            ty: d.ty,
            doc: d.doc,
        })
        .collect();
    globals.extend([
        state(
            "workgroup",
            "sched_wg_pick",
            "vec4<u32>".into(),
            "The batch thread 0 picked, broadcast with workgroupUniformLoad.",
        ),
        state(
            "workgroup",
            "sched_wg_flushes",
            "array<vec2<u32>, SCHED_MAX_TARGETS>".into(),
            "First ticket and count of the flush into each target of the running batch.",
        ),
        state(
            "workgroup",
            "sched_wg_staged",
            format!("array<atomic<u32>, {n}>"),
            "Items staged per queue in this batch.",
        ),
        state(
            "workgroup",
            SCRATCH,
            format!("array<u32, {}>", plan.scratch_words.max(1)),
            "Scratch shared by all procedures, sized by the largest.",
        ),
        state(
            "private",
            "sched_spins",
            "u32".into(),
            "Spin-wait iterations of this invocation (thread 0), for the spin limit.",
        ),
        state(
            "private",
            "sched_rounds",
            "bool".into(),
            "Whether a Rounds entry point runs (no waiting on other workgroups).",
        ),
        state(
            "private",
            "sched_wg_base",
            "u32".into(),
            "First word of this workgroup's region of the staging buffer.",
        ),
        state(
            "private",
            "sched_scratch_stride",
            "u32".into(),
            "Scratch words per item of the running procedure.",
        ),
    ]);
    globals
}
