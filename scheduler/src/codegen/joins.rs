//! The WGSL of joins ([`Graph::join`](crate::Graph::join)), generated only
//! for a graph that declares them: the pool of join records in the control
//! buffer, `join_open_<Continuation>` for the bodies, the tagging of every
//! enqueued item with the join it counts towards, and the releases and
//! fires after each body call. docs/scheduler.md ("Joins") argues the
//! protocol; `plan::joins` holds its numbers.

use std::collections::BTreeMap;

use crate::codegen::codec;
use crate::codegen::module::{Constant, Function, Global};
use crate::naming::{join_continue_name, join_open_name, join_store_name};
use crate::plan::joins::{
    self, CAPACITY, FIRED, KIND, KIND_WORDS, KINDS, NEXT, OPENED, PARENT, PAYLOAD, PENDING,
};
use crate::plan::layout::{ItemLayout, PACKET_WORDS};
use crate::plan::{Plan, QueuePlan};

/// Whether `plan` has joins: everything else here is empty without.
pub(crate) fn any(plan: &Plan) -> bool {
    !plan.joins.is_empty()
}

/// Control words of the trace, which lie between the markers and the pool.
fn trace_words(plan: &Plan) -> u32 {
    plan.trace.map_or(0, |trace| {
        crate::codegen::trace::HEADER_WORDS
            + trace.capacity * crate::codegen::trace::record_words(plan.queues.len())
    })
}

pub(crate) fn constants(plan: &Plan) -> Vec<Constant> {
    if !any(plan) {
        return Vec::new();
    }
    let first = joins::first_word(plan);
    vec![
        Constant::u32(
            "SCHED_CTRL_JOIN_CAPACITY",
            first + CAPACITY,
            "Control word: records the join pool holds (written by the host).",
        ),
        Constant::u32(
            "SCHED_CTRL_JOIN_NEXT",
            first + NEXT,
            "Control word: join records asked for (every join_open call, granted or not).",
        ),
        Constant::u32(
            "SCHED_CTRL_JOIN_KINDS",
            first + KINDS,
            "Control word of the first continuation's counters: joins opened, then fired, per continuation.",
        ),
        Constant::u32(
            "SCHED_JOIN_RECORD_WORDS",
            joins::record_words(plan),
            "Words per join record: references outstanding, the join it runs under + 1, its kind, then the record item.",
        ),
        Constant::u32(
            "SCHED_JOIN_TRACE_WORDS",
            trace_words(plan),
            "Control words of the trace between the range markers and the join pool.",
        ),
    ]
}

fn private(name: &str, ty: &str, doc: &str) -> Global {
    Global {
        attributes: String::new(),
        space: "private".to_owned(),
        name: name.to_owned(),
        ty: ty.to_owned(),
        doc: doc.to_owned(),
    }
}

pub(crate) fn globals(plan: &Plan) -> Vec<Global> {
    if !any(plan) {
        return Vec::new();
    }
    vec![
        private(
            "sched_join_item",
            "u32",
            "Joins: the join the thread's item runs under, plus 1 (0: none).",
        ),
        private(
            "sched_join_opened",
            "u32",
            "Joins: the join this thread opened for its item, plus 1 (0: none).",
        ),
        private(
            "sched_join_fire",
            "vec2<u32>",
            "Joins: the joins this thread's releases brought to zero, plus 1: the item's, the opened one's.",
        ),
    ]
}

/// The join functions: the pool's addressing, the bodies' `join_open_*`,
/// the tagging, releasing and firing.
pub(crate) fn functions(
    plan: &Plan,
    items: &BTreeMap<String, (String, ItemLayout)>,
) -> Vec<Function> {
    if !any(plan) {
        return Vec::new();
    }
    let mut functions = Vec::new();

    let mut base = Function::new("sched_join_base")
        .doc("Joins: the first word of the join pool in sched_control, after the markers (and the trace).")
        .returns("u32");
    base.line("let last = SCHED_NUM_QUEUES - 1u;");
    base.line("return sched_config[last].z + 2u * sched_capacity(last) + SCHED_JOIN_TRACE_WORDS;");
    functions.push(base);

    let mut record = Function::new("sched_join_record")
        .doc("Joins: the first control word of record `join`.")
        .param("join", "u32")
        .returns("u32");
    record.line("return sched_join_base() + join * SCHED_JOIN_RECORD_WORDS;");
    functions.push(record);

    let mut current = Function::new("sched_join_current")
        .doc("Joins: the join this thread's enqueues count towards, plus 1: the one it opened, else its item's.")
        .returns("u32");
    current.line("if (sched_join_opened != 0u) {");
    current.line("    return sched_join_opened;");
    current.line("}");
    current.line("return sched_join_item;");
    functions.push(current);

    let mut add = Function::new("sched_join_add_child")
        .doc("Joins, before an enqueue: the child holds a reference on the join it counts towards until it finishes. Counted before staging, so a child lost to an overflow keeps its join from firing.");
    add.line("let join = sched_join_current();");
    add.line("if (join != 0u) {");
    add.line(format!(
        "    atomicAdd(&sched_control[sched_join_record(join - 1u) + {PENDING}u], 1u);"
    ));
    add.line("}");
    functions.push(add);

    let mut tag = Function::new("sched_join_tag")
        .doc("Joins: writes `join` (plus 1) into the staged item's join word, staging word `word`, which shares a packet with the item or has its own.")
        .param("word", "u32")
        .param("join", "u32");
    tag.line("var packet = sched_staging_load4(word & ~3u);");
    tag.line("packet[word & 3u] = join;");
    tag.line("sched_staging_store4(word & ~3u, packet);");
    functions.push(tag);

    let mut release = Function::new("sched_join_release")
        .doc("Joins: drops one reference on `join` (plus 1); true when it was the last. The caller's storageBarrier before it is the release of the writes that precede.")
        .param("join", "u32")
        .returns("bool");
    release.line(format!(
        "return atomicSub(&sched_control[sched_join_record(join - 1u) + {PENDING}u], 1u) == 1u;"
    ));
    functions.push(release);

    let mut finish = Function::new("sched_join_finish")
        .doc("Joins, all threads after a body call: the item (`item_done`, one thread per item) drops its reference on the join it runs under, and the thread that opened a join drops the opener's; the joins brought to zero are kept in sched_join_fire.")
        .param("item_done", "bool");
    finish.line("sched_join_fire = vec2<u32>();");
    finish.line("if (item_done && sched_join_item != 0u && sched_join_release(sched_join_item)) {");
    finish.line("    sched_join_fire.x = sched_join_item;");
    finish.line("}");
    finish.line("if (sched_join_opened != 0u && sched_join_release(sched_join_opened)) {");
    finish.line("    sched_join_fire.y = sched_join_opened;");
    finish.line("}");
    finish.line("sched_join_opened = 0u;");
    functions.push(finish);

    let mut fire_staged = Function::new("sched_join_fire_staged")
        .doc("Joins, all threads after the storageBarrier (acquire) that follows sched_join_finish: enqueue the continuations of the joins this thread brought to zero.");
    fire_staged.line("if (sched_join_fire.x != 0u) {");
    fire_staged.line("    sched_join_fire_one(sched_join_fire.x - 1u);");
    fire_staged.line("}");
    fire_staged.line("if (sched_join_fire.y != 0u) {");
    fire_staged.line("    sched_join_fire_one(sched_join_fire.y - 1u);");
    fire_staged.line("}");
    functions.push(fire_staged);

    let mut fire = Function::new("sched_join_fire_one")
        .doc("Joins: stages the record of `join`, whose last reference is gone, for its continuation, under the join its opener ran under.")
        .param("join", "u32");
    fire.line("let at = sched_join_record(join);");
    fire.line(format!(
        "let parent = atomicLoad(&sched_control[at + {PARENT}u]);"
    ));
    fire.line(format!(
        "let kind = atomicLoad(&sched_control[at + {KIND}u]);"
    ));
    fire.line(format!(
        "atomicAdd(&sched_control[SCHED_CTRL_JOIN_KINDS + kind * {KIND_WORDS}u + {FIRED}u], 1u);"
    ));
    fire.line("switch kind {");
    for (k, join) in plan.joins.iter().enumerate() {
        let queue = &plan.queues[join.continuation];
        fire.line(format!(
            "    case {k}u: {{ {}(at + {PAYLOAD}u, parent); }}",
            join_continue_name(&queue.name)
        ));
    }
    fire.line("    default: {}");
    fire.line("}");
    functions.push(fire);

    for join in &plan.joins {
        functions.push(continue_function(plan, join.continuation));
    }
    let mut stored: Vec<&str> = Vec::new();
    for join in &plan.joins {
        let item = plan.queues[join.continuation].item.as_str();
        if !stored.contains(&item) {
            stored.push(item);
            functions.push(codec::join_store_function(item, &items[item].1));
        }
    }
    for (k, join) in plan.joins.iter().enumerate() {
        functions.push(open_function(plan, k, join.continuation));
    }
    functions
}

/// `sched_join_continue_<C>`: copies a fired record into the staging of the
/// continuation `c`, packet by packet, and tags it with `parent`.
fn continue_function(plan: &Plan, c: usize) -> Function {
    let queue = &plan.queues[c];
    let mut f = Function::new(join_continue_name(&queue.name))
        .doc(format!(
            "Joins: stages the record at control word `at` for `{}`, under join `parent` (plus 1).",
            queue.name
        ))
        .param("at", "u32")
        .param("parent", "u32");
    f.line(format!(
        "let base = sched_stage({c}u, {}u, {}u);",
        queue.stage_offset, queue.stage_capacity
    ));
    f.line("if (base != 0xffffffffu) {");
    for w in (0..queue.slot_words).step_by(PACKET_WORDS as usize) {
        f.line(format!("    sched_staging_store4(base + {w}u, vec4<u32>("));
        for c in 0..PACKET_WORDS {
            let comma = if c + 1 < PACKET_WORDS { "," } else { "" };
            f.line(format!(
                "        atomicLoad(&sched_control[at + {}u]){comma}",
                w + c
            ));
        }
        f.line("    ));");
    }
    f.line(format!(
        "    sched_join_tag(base + {}u, parent);",
        joins::join_word(queue)
    ));
    f.line("}");
    f
}

/// `join_open_<C>`, the bodies' call: takes a record from the pool, holds
/// the join the item runs under, and makes the new join the one the
/// thread's enqueues count towards.
fn open_function(plan: &Plan, k: usize, c: usize) -> Function {
    let queue = &plan.queues[c];
    let mut f = Function::new(join_open_name(&queue.name))
        .doc(format!(
            "Opens a join whose continuation `{}` receives `record` once every child enqueued by this thread from now on (and their children) has finished. False when this thread already opened one for its item, or the pool is full (the run then fails with the need measured).",
            queue.name
        ))
        .param("record", &queue.item)
        .returns("bool");
    f.line("if (sched_join_opened != 0u) {");
    f.line("    return false;");
    f.line("}");
    f.line("let join = atomicAdd(&sched_control[SCHED_CTRL_JOIN_NEXT], 1u);");
    f.line("if (join >= atomicLoad(&sched_control[SCHED_CTRL_JOIN_CAPACITY])) {");
    f.line("    return false;");
    f.line("}");
    f.line("let at = sched_join_record(join);");
    f.line("// The opener's own reference, dropped when its body call ends.");
    f.line(format!("atomicStore(&sched_control[at + {PENDING}u], 1u);"));
    f.line(format!(
        "atomicStore(&sched_control[at + {PARENT}u], sched_join_item);"
    ));
    f.line(format!("atomicStore(&sched_control[at + {KIND}u], {k}u);"));
    f.line(format!(
        "{}(at + {PAYLOAD}u, record);",
        join_store_name(&queue.item)
    ));
    f.line("if (sched_join_item != 0u) {");
    f.line("    // The new join holds the one its opener runs under; its continuation");
    f.line("    // inherits that reference and drops it when it finishes.");
    f.line(format!(
        "    atomicAdd(&sched_control[sched_join_record(sched_join_item - 1u) + {PENDING}u], 1u);"
    ));
    f.line("}");
    f.line(format!(
        "atomicAdd(&sched_control[SCHED_CTRL_JOIN_KINDS + {}u], 1u);",
        k as u32 * KIND_WORDS + OPENED
    ));
    f.line("sched_join_opened = join + 1u;");
    f.line("return true;");
    f
}

/// The lines of `enqueue_<queue>` after staging at `base`, in a graph with
/// joins: the join word of the staged item.
pub(crate) fn enqueue_tag_line(queue: &QueuePlan) -> String {
    format!(
        "    sched_join_tag(base + {}u, sched_join_current());",
        joins::join_word(queue)
    )
}

/// In a batch, where the thread's item is decoded (`valid` and the slot
/// `at` known): which join it runs under. Lines of the decode block, and
/// the reset before it.
pub(crate) fn decode_lines(q: usize, queue: &QueuePlan) -> (String, String) {
    let word = joins::join_word(queue);
    let packet = word / PACKET_WORDS * PACKET_WORDS;
    let component = ["x", "y", "z", "w"][(word % PACKET_WORDS) as usize];
    (
        "sched_join_item = 0u;".to_owned(),
        format!(
            "    sched_join_item = sched_payload_load4(sched_slot_word({q}u, first + at) + {packet}u).{component};"
        ),
    )
}

/// Where the joins of a body call are released and fired.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Finish {
    /// Right after the call, between two fences of their own (the
    /// megakernel's batches of several chunks).
    Fenced,
    /// After a fence the batch passes anyway (the megakernel's one-chunk
    /// batch: `sched_receive_done`'s), so only the acquire fence is added.
    AfterReleaseFence,
    /// Without fences: under Rounds a continuation runs in a later dispatch
    /// than every write it reads, and a record is read in the round that
    /// opened it only by its opener's own thread.
    OrderedByDispatch,
}

/// After a body call, all threads: release the item's and the opened
/// joins, then fire those brought to zero, with the fences `finish` needs.
pub(crate) fn finish_lines(finish: Finish) -> Vec<String> {
    let mut lines = Vec::new();
    match finish {
        Finish::Fenced => {
            lines.push(
                "// Joins. Release: the item's writes (every thread's) are complete before"
                    .to_owned(),
            );
            lines.push("// its references are dropped.".to_owned());
            lines.push("storageBarrier();".to_owned());
        }
        Finish::AfterReleaseFence => {
            lines.push(
                "// Joins. The fence above released the item's writes (every thread's).".to_owned(),
            );
        }
        Finish::OrderedByDispatch => {
            lines.push(
                "// Joins. A continuation runs in a later round than every write it reads:"
                    .to_owned(),
            );
            lines.push("// the dispatches order them, so no fence is needed.".to_owned());
        }
    }
    lines.push("sched_join_finish(valid && thread == 0u);".to_owned());
    if finish != Finish::OrderedByDispatch {
        lines.push(
            "// Acquire: the writes of every child of a join brought to zero, and its".to_owned(),
        );
        lines.push("// record, are visible before the continuation is staged.".to_owned());
        lines.push("storageBarrier();".to_owned());
    }
    lines.push("sched_join_fire_staged();".to_owned());
    lines
}
