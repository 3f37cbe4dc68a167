//! Tracing ([`CompileOptions::trace`](crate::CompileOptions::trace)): the
//! layout of the trace, which the host reads back, and the WGSL that fills
//! it. Nothing here is generated for an untraced module.
//!
//! The trace lies in `sched_control`, after the last queue's range markers
//! (a traced module binds no other buffer, and the host's clearing of the
//! markers before a run clears it too): [`HEADER_WORDS`] words, then up to
//! the capacity records of [`record_words`] words, one per batch:
//!
//! - header word [`CLOCK`]: the logical clock, the number of batches begun;
//! - header word [`SUBMISSION`]: the host's submission counter, written before
//!   each submission;
//! - a record: the begin and end ticks, the workgroup, the queue, the items
//!   taken, the first ticket, the submission, the round (Rounds strategy, else
//!   0), then the fill of every queue when the batch began.
//!
//! A batch takes its tick with one `atomicAdd` on the clock; the tick is also
//! its record's index, so the first `capacity` batches are kept and every
//! later one is counted by the clock alone. Its end tick is the clock read
//! (not advanced) when the batch ends: the batches begun meanwhile.

use crate::codegen::module::{Constant, Function, Global};
use crate::plan::Plan;

/// Words before the first record.
pub(crate) const HEADER_WORDS: u32 = 4;
/// Header word: the logical clock.
pub(crate) const CLOCK: u32 = 0;
/// Header word: the submission counter.
pub(crate) const SUBMISSION: u32 = 1;

/// Record words, in order, before the fills.
pub(crate) const FIELDS: [&str; 8] = [
    "begin",
    "end",
    "workgroup",
    "queue",
    "items",
    "first",
    "submission",
    "round",
];

/// Words of one record in a module of `queues` queues.
pub(crate) fn record_words(queues: usize) -> u32 {
    (FIELDS.len() + queues) as u32
}

/// "No record": the batch's tick was beyond the capacity.
const NO_RECORD: &str = "0xffffffffu";

/// The private variable that holds the workgroup index for the records.
const WORKGROUP: &str = "sched_trace_workgroup";

/// The constants of a traced module (none without tracing).
pub(crate) fn constants(plan: &Plan) -> Vec<Constant> {
    let Some(trace) = plan.trace else {
        return Vec::new();
    };
    let constant = Constant::u32;
    vec![
        constant(
            "SCHED_TRACE_CAPACITY",
            trace.capacity,
            "Tracing: records the trace buffer holds (the first batches of a run).",
        ),
        constant(
            "SCHED_TRACE_RECORD_WORDS",
            record_words(plan.queues.len()),
            "Tracing: words of one record.",
        ),
    ]
}

/// The private state of a traced module.
pub(crate) fn globals(plan: &Plan) -> Vec<Global> {
    if plan.trace.is_none() {
        return Vec::new();
    }
    vec![Global {
        attributes: String::new(),
        space: "private".to_owned(),
        name: WORKGROUP.to_owned(),
        ty: "u32".to_owned(),
        doc: "Tracing: this workgroup's index, for its records.".to_owned(),
    }]
}

/// `sched_trace_base`, `sched_trace_begin` and `sched_trace_end` (none
/// without tracing). Straight line code: a loop here would spend llvmpipe's
/// loop budget of the persistent loop (docs/scheduler.md, "Loop limits").
pub(crate) fn functions(plan: &Plan) -> Vec<Function> {
    if plan.trace.is_none() {
        return Vec::new();
    }
    let word = |field: &str| FIELDS.iter().position(|f| *f == field).unwrap_or(0);
    let store = |field: &str, value: &str| {
        format!(
            "atomicStore(&sched_control[at + {}u], {value});",
            word(field)
        )
    };
    let mut base = Function::new("sched_trace_base")
        .doc("Tracing: the first word of the trace in sched_control, after the last queue's markers.")
        .returns("u32");
    base.line("let last = SCHED_NUM_QUEUES - 1u;");
    base.line("return sched_config[last].z + 2u * sched_capacity(last);");

    let mut begin = Function::new("sched_trace_begin")
        .doc("Tracing, thread 0 only: records a batch of `count` items of queue `q` from ticket `first`. Returns its record (its tick), or none beyond the capacity.")
        .param("q", "u32")
        .param("first", "u32")
        .param("count", "u32")
        .returns("u32");
    begin.line("let base = sched_trace_base();");
    begin.line(format!(
        "let tick = atomicAdd(&sched_control[base + {CLOCK}u], 1u);"
    ));
    begin.line("if (tick >= SCHED_TRACE_CAPACITY) {");
    begin.line(format!("    return {NO_RECORD};"));
    begin.line("}");
    begin.line(format!(
        "let at = base + {HEADER_WORDS}u + tick * SCHED_TRACE_RECORD_WORDS;"
    ));
    begin.line("var round = 0u;");
    begin.line("if (sched_rounds) {");
    begin.line("    round = atomicLoad(&sched_control[SCHED_CTRL_ROUNDS]);");
    begin.line("}");
    for (field, value) in [
        ("begin", "tick".to_owned()),
        ("end", "tick + 1u".to_owned()),
        ("workgroup", WORKGROUP.to_owned()),
        ("queue", "q".to_owned()),
        ("items", "count".to_owned()),
        ("first", "first".to_owned()),
        (
            "submission",
            format!("atomicLoad(&sched_control[base + {SUBMISSION}u])"),
        ),
        ("round", "round".to_owned()),
    ] {
        begin.line(store(field, &value));
    }
    begin.line("// The fill of every queue: items reserved and not yet claimed.");
    for (q, queue) in plan.queues.iter().enumerate() {
        begin.line(format!(
            "atomicStore(&sched_control[at + {}u], atomicLoad(&sched_control[sched_ctrl({q}u, SCHED_Q_FILL)])); // {}",
            FIELDS.len() + q,
            queue.name
        ));
    }
    begin.line("return tick;");

    let mut end = Function::new("sched_trace_end")
        .doc("Tracing, thread 0 only: the end tick of `record` (from sched_trace_begin): the clock now.")
        .param("record", "u32");
    end.line(format!("if (record != {NO_RECORD}) {{"));
    end.line("    let base = sched_trace_base();");
    end.line(format!(
        "    let at = base + {HEADER_WORDS}u + record * SCHED_TRACE_RECORD_WORDS;"
    ));
    end.line(format!(
        "    {}",
        store(
            "end",
            &format!("atomicLoad(&sched_control[base + {CLOCK}u])")
        )
    ));
    end.line("}");
    vec![base, begin, end]
}

/// The runner's first lines: thread 0 records the batch.
pub(crate) fn runner_begin(plan: &Plan, q: usize) -> Vec<String> {
    if plan.trace.is_none() {
        return Vec::new();
    }
    vec![
        "// Tracing: thread 0 records the batch.".to_owned(),
        format!("var trace_record = {NO_RECORD};"),
        "if (lid == 0u) {".to_owned(),
        format!("    trace_record = sched_trace_begin({q}u, first, count);"),
        "}".to_owned(),
    ]
}

/// The runner's line, for thread 0, when the batch is over.
pub(crate) fn runner_end(plan: &Plan) -> Option<String> {
    plan.trace
        .map(|_| "    sched_trace_end(trace_record);".to_owned())
}

/// An entry point's line that names the workgroup for the records.
pub(crate) fn entry_lines(plan: &Plan) -> Option<String> {
    plan.trace.map(|_| format!("{WORKGROUP} = workgroup.x;"))
}
