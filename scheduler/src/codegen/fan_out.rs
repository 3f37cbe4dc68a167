//! Checked mode's per-item fan-out check
//! ([`CompileOptions::checked`](crate::CompileOptions::checked)): every
//! `enqueue_<Target>` counts one for the calling item (its slot in the
//! workgroup) and target, in workgroup memory; when the item's body call is
//! over, the item's first thread compares each count with the connection's
//! fan-out, records a violation in the procedure's control words (the first
//! item over: its ticket, the target, its count) and sets the count back to
//! zero. Without checked mode none of it is generated, and the run checks
//! only that each batch stays within its staging room.

use crate::codegen::module::{Constant, Function, Global};
use crate::plan::fan_out::{COUNT, ITEM, ITEMS, TARGET, WORDS, first_word};
use crate::plan::{Plan, QueuePlan};

/// The workgroup array of counts: one word per item slot and queue.
const COUNTS: &str = "sched_wg_fan_out";
/// The private variable holding the running item's slot, for the enqueues.
const SLOT: &str = "sched_fan_out_slot";

/// Where the check's control words start.
pub(crate) fn constants(plan: &Plan) -> Vec<Constant> {
    vec![Constant::u32(
        "SCHED_CTRL_FAN_OUT",
        first_word(plan),
        format!(
            "Checked mode: first control word of the per-item fan-out check ({WORDS} per procedure)."
        ),
    )]
}

/// The counts and the running item's slot.
pub(crate) fn globals(plan: &Plan) -> Vec<Global> {
    vec![
        Global {
            attributes: String::new(),
            space: "workgroup".into(),
            name: COUNTS.into(),
            ty: format!(
                "array<atomic<u32>, {}>",
                plan.workgroup_size as usize * plan.queues.len()
            ),
            doc: "Checked mode: enqueues of the item in slot s into queue q, at s * SCHED_NUM_QUEUES + q.".into(),
        },
        Global {
            attributes: String::new(),
            space: "private".into(),
            name: SLOT.into(),
            ty: "u32".into(),
            doc: "Checked mode: the slot of the item this thread runs, for the enqueues' counts."
                .into(),
        },
    ]
}

/// The count an enqueue adds, and the recorder of a violation.
pub(crate) fn functions() -> Vec<Function> {
    let mut count = Function::new("sched_fan_out_count")
        .doc("Checked mode: counts one enqueue into queue `q` for the calling item.")
        .param("q", "u32");
    count.line(format!(
        "atomicAdd(&{COUNTS}[{SLOT} * SCHED_NUM_QUEUES + q], 1u);"
    ));
    let mut record = Function::new("sched_record_fan_out")
        .doc("Checked mode: item `ticket` of procedure `p` enqueued `count` items into queue")
        .doc("`q`, over the fan-out; the first such item is recorded.")
        .param("p", "u32")
        .param("ticket", "u32")
        .param("q", "u32")
        .param("count", "u32");
    record.line(format!("let word = SCHED_CTRL_FAN_OUT + {WORDS}u * p;"));
    record.line(format!(
        "if (atomicAdd(&sched_control[word + {ITEMS}u], 1u) == 0u) {{"
    ));
    record.line(format!(
        "    atomicStore(&sched_control[word + {ITEM}u], ticket);"
    ));
    record.line(format!(
        "    atomicStore(&sched_control[word + {TARGET}u], q);"
    ));
    record.line(format!(
        "    atomicStore(&sched_control[word + {COUNT}u], count);"
    ));
    record.line("}");
    vec![count, record]
}

/// The runner's line that tells the enqueues which item is running.
pub(crate) fn slot_line() -> String {
    format!("{SLOT} = slot; // checked mode: enqueues count for this item")
}

/// The runner's check of the items of chunk `chunk` (a WGSL expression) of
/// queue `q`'s batch: their first threads compare and reset the counts. It
/// runs after a barrier that ends the chunk's body call.
pub(crate) fn check_lines(plan: &Plan, q: usize, queue: &QueuePlan, chunk: &str) -> Vec<String> {
    let n = plan.queues.len();
    let mut lines = vec![
        "// Checked mode: each item's enqueues against the fan-outs; the counts".to_owned(),
        "// start again at zero.".to_owned(),
        "if (thread == 0u) {".to_owned(),
        format!(
            "    let ticket = first + {chunk} * {}u + slot;",
            queue.items_per_workgroup
        ),
    ];
    for &(t, fan_out) in &queue.targets {
        lines.push(format!(
            "    let to_{t} = atomicExchange(&{COUNTS}[slot * {n}u + {t}u], 0u); // {}",
            plan.queues[t].name
        ));
        lines.push(format!("    if (to_{t} > {fan_out}u) {{"));
        lines.push(format!(
            "        sched_record_fan_out({q}u, ticket, {t}u, to_{t});"
        ));
        lines.push("    }".to_owned());
    }
    lines.push("}".to_owned());
    lines
}
