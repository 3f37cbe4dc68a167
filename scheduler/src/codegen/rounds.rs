//! The Rounds strategy's entry points: the prepare kernel, and per procedure
//! a round kernel with a batch function of its own.
//!
//! A round kernel runs only items that were complete before its dispatch
//! began, and the items it enqueues are read only after it ended, so the
//! batch function leaves out what the megakernel's runner needs to share
//! queues with running workgroups: the acquire and release fences around the
//! slots it reads, the released range and the publication of the slots it
//! writes. llvmpipe (lavapipe) suspends every thread of a workgroup at each
//! barrier, so the barriers saved are most of the scheduler's cost per batch
//! there.

use crate::codegen::module::Function;
use crate::codegen::{joins, kernels, trace};
use crate::graph::Procedure;
use crate::naming::{PREPARE_ENTRY_POINT, round_entry_point, round_runner_name};
use crate::plan::{Plan, QueuePlan};

/// The Rounds functions of `plan`, in module order: the prepare kernel, then
/// per procedure its batch function and its round kernel.
pub(crate) fn functions(plan: &Plan, procedures: &[Procedure], library: &str) -> Vec<Function> {
    let mut functions = vec![prepare_entry_point()];
    for ((q, queue), procedure) in plan.queues.iter().enumerate().zip(procedures) {
        let free = barrier_free(plan, queue, procedure, library);
        functions.push(round_runner(plan, q, queue, free));
        functions.push(round_entry(plan, q, queue, free));
    }
    functions
}

/// Whether a procedure's round kernel can do without any barrier: it
/// enqueues nothing (no flush), shares nothing between threads (no scratch,
/// no item-wide helpers), and neither its body nor the graph's library
/// synchronizes or declares workgroup memory (a plain text test, which errs
/// on the side of barriers). llvmpipe compiles a kernel without barriers
/// into a plain loop over the workgroup's SIMD groups instead of coroutines
/// that keep the loop state of bodies in memory (docs/performance.md).
fn barrier_free(plan: &Plan, queue: &QueuePlan, procedure: &Procedure, library: &str) -> bool {
    let synchronizes = |text: &str| {
        ["Barrier", "workgroupUniformLoad", "workgroup>"]
            .iter()
            .any(|word| text.contains(word))
    };
    queue.targets.is_empty()
        && queue.scratch_words == 0
        && procedure.scratch_type.is_none()
        && !plan.item_helpers
        && !synchronizes(&procedure.body)
        && !synchronizes(library)
}

/// The prepare kernel: one thread retires the round that ran and sizes the
/// next one for every queue.
fn prepare_entry_point() -> Function {
    let mut f = Function::new(PREPARE_ENTRY_POINT)
        .doc("Rounds strategy: between two rounds, retire the round that ran and size the next one's indirect dispatches.");
    f.attributes.push("@compute @workgroup_size(1)".to_owned());
    f.line("var items = 0u;");
    f.line("for (var q = 0u; q < SCHED_NUM_QUEUES; q += 1u) {");
    f.line("    items += sched_prepare_queue(q);");
    f.line("}");
    f.line("if (items > 0u) {");
    f.line("    atomicAdd(&sched_control[SCHED_CTRL_ROUNDS], 1u);");
    f.line("}");
    f
}

/// One batch of a procedure inside a round: decode, run the body, flush the
/// children into their queues. Between two batches of one workgroup the
/// round kernel puts the barriers (scratch and staging are reused).
/// `barrier_free`: see [`barrier_free`].
fn round_runner(plan: &Plan, q: usize, queue: &QueuePlan, barrier_free: bool) -> Function {
    let per_chunk = queue.items_per_workgroup;
    let mut f = Function::new(round_runner_name(&queue.name))
        .doc(format!(
            "Rounds strategy: runs one batch of `{}` (`count` items from ticket `first`), then copies its children into their queues.",
            queue.name
        ))
        .param("lid", "u32")
        .param("first", "u32")
        .param("count", "u32");
    let count_fan_out = kernels::batch_prologue(&mut f, plan, q, queue);
    f.line("// The slots were written before this dispatch began: no fence needed.");
    let call = |chunk: &str| {
        kernels::body_call_lines(
            plan,
            q,
            queue,
            chunk,
            Some(joins::Finish::OrderedByDispatch),
        )
    };
    if plan.chunks_per_batch == 1 {
        for line in call("0u") {
            f.line(line);
        }
    } else {
        f.line(format!(
            "// One body call per chunk of {per_chunk} items; `count` is uniform, so is the loop."
        ));
        f.line("var chunk = 0u;");
        f.line(format!(
            "for (; chunk * {per_chunk}u < count; chunk += 1u) {{"
        ));
        if !barrier_free {
            f.line("    // The previous call is over in every thread before this one reuses");
            f.line("    // scratch and the body's workgroup variables.");
            f.line("    workgroupBarrier();");
        }
        if count_fan_out {
            for line in kernels::fan_out_chunk_lines(plan, q, queue) {
                f.line(line);
            }
        }
        for line in call("chunk") {
            f.line(format!("    {line}"));
        }
        f.line("}");
        f.line(format!(
            "sched_check_left_in_step(chunk * {per_chunk}u >= count);"
        ));
    }
    if !queue.targets.is_empty() {
        round_flush_lines(&mut f, plan, q, queue);
    }
    f.line("if (lid == 0u) {");
    if let Some(line) = trace::runner_end(plan) {
        f.line(line);
    }
    f.line(format!(
        "    atomicAdd(&sched_control[sched_ctrl({q}u, SCHED_Q_EXECUTED)], count);"
    ));
    f.line("    atomicSub(&sched_control[SCHED_CTRL_PENDING], count);");
    f.line("}");
    f
}

/// The flush of a batch inside a round: thread 0 reserves slots in each
/// target queue, every thread copies staged items into them. The slots are
/// free (the prepare kernel released the previous round's) and nobody reads
/// them before the next round, so neither a fence before the copies nor a
/// publication after them is needed.
fn round_flush_lines(f: &mut Function, plan: &Plan, q: usize, queue: &QueuePlan) {
    f.line("// Every thread's staging is done: the counts (workgroup memory) and the");
    f.line("// staged items (storage) are complete.");
    f.line("workgroupBarrier();");
    f.line("storageBarrier();");
    kernels::reserve_and_copy_lines(f, plan, q, queue, "workgroupUniformLoad(&sched_wg_flushes)");
}

/// One procedure's round kernel: workgroups stride over the batches of the
/// round's items; nobody waits on another workgroup. Without barriers
/// (`barrier_free`), every thread reads the round's range itself.
fn round_entry(plan: &Plan, q: usize, queue: &QueuePlan, barrier_free: bool) -> Function {
    let mut f = Function::new(round_entry_point(&queue.name))
        .doc(format!(
            "Rounds strategy: runs the `{}` items queued before this round, children go to the next round.",
            queue.name
        ))
        .param("@builtin(local_invocation_index) lid", "u32")
        .param("@builtin(workgroup_id) workgroup", "vec3<u32>")
        .param("@builtin(num_workgroups) groups", "vec3<u32>");
    f.attributes
        .push(format!("@compute @workgroup_size({})", plan.workgroup_size));
    f.line("sched_rounds = true;");
    f.line("sched_wg_base = workgroup.x * SCHED_WORKGROUP_WORDS;");
    if let Some(line) = trace::entry_lines(plan) {
        f.line(line);
    }
    if barrier_free {
        f.line("// No barrier anywhere: every thread reads the range.");
        f.line(format!("let range = sched_round_range({q}u);"));
    } else {
        f.line("if (lid == 0u) {");
        f.line(format!(
            "    sched_wg_pick = vec4<u32>(sched_round_range({q}u), 0u, 0u);"
        ));
        f.line("}");
        f.line("let range = workgroupUniformLoad(&sched_wg_pick).xy;");
    }
    f.line(format!("let per = {}u;", queue.items_per_batch));
    f.line("// Grid-stride over batches: the dispatch size may be clamped.");
    f.line("var batch = workgroup.x;");
    f.line("for (; batch * per < range.y; batch += groups.x) {");
    if !barrier_free {
        f.line("    if (batch != workgroup.x) {");
        f.line("        // The previous batch is over in every thread before this one reuses");
        f.line("        // scratch and the body's workgroup variables.");
        f.line("        workgroupBarrier();");
        if !queue.targets.is_empty() {
            f.line("        // Its copies have read the staging area.");
            f.line("        storageBarrier();");
        }
        f.line("    }");
    }
    f.line(format!(
        "    {}(lid, range.x + batch * per, min(per, range.y - batch * per));",
        round_runner_name(&queue.name)
    ));
    f.line("}");
    f.line("// A driver that cut a loop short (llvmpipe's loop limit) may have");
    f.line("// skipped items or part of a body: flag it so the run fails loudly.");
    f.line("sched_check_left_in_step(batch * per >= range.y);");
    f
}
