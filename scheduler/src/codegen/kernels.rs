//! The generated functions around the procedure bodies: item copies, payload
//! access, the queue policy, the runners and the entry points.

use crate::Policy;
use crate::codegen::module::Function;
use crate::codegen::{checked, fan_out, helpers, joins, trace};
use crate::naming::{ENTRY_POINT, body_name, copy_out_name, decode_name, runner_name};
use crate::plan::layout::PACKET_WORDS;
use crate::plan::{Plan, QueuePlan};

/// Straight-line packet copy from the workgroup's region of the staging buffer
/// into a queue slot. It is written out word by word on purpose: a loop here
/// could be cut short by llvmpipe's loop limiter (docs/scheduler.md, "Loop
/// limits"), publishing half-copied items.
pub(crate) fn copy_out_function(queue: &QueuePlan) -> Function {
    let mut copy_out = Function::new(copy_out_name(&queue.name))
        .doc(format!(
            "Copies one staged `{}` at `source` into queue slot word `slot`.",
            queue.item
        ))
        .param("source", "u32")
        .param("slot", "u32");
    for w in (0..queue.slot_words).step_by(PACKET_WORDS as usize) {
        copy_out.line(format!(
            "sched_payload_store4(slot + {w}u, sched_staging_load4(source + {w}u));"
        ));
    }
    copy_out
}

/// Access to queue payload words. With coherent memory they are plain loads
/// and stores; otherwise relaxed atomics, which are always coherent. Either
/// way the runtime orders them with device-scope fences (storageBarrier).
pub(crate) fn payload_functions(coherent: bool) -> [Function; 2] {
    let mut load = Function::new("sched_payload_load4")
        .doc("Reads the packet of a queue slot at word `word` (a multiple of 4).")
        .param("word", "u32")
        .returns("vec4<u32>");
    let mut store = Function::new("sched_payload_store4")
        .doc("Writes the packet of a queue slot at word `word` (a multiple of 4).")
        .param("word", "u32")
        .param("value", "vec4<u32>");
    if coherent {
        load.line("return sched_queue_words[word / 4u];");
        store.line("sched_queue_words[word / 4u] = value;");
    } else {
        load.line("return vec4<u32>(");
        for c in 0..4 {
            let comma = if c < 3 { "," } else { "" };
            load.line(format!(
                "    atomicLoad(&sched_queue_words[word + {c}u]){comma}"
            ));
        }
        load.line(");");
        for (c, component) in ["x", "y", "z", "w"].iter().enumerate() {
            store.line(format!(
                "atomicStore(&sched_queue_words[word + {c}u], value.{component});"
            ));
        }
    }
    [load, store]
}

pub(crate) fn policy_function(policy: Policy) -> Function {
    let mut f = Function::new("sched_policy_start")
        .doc("Index into sched_queue_order where this workgroup's scan starts.")
        .param("workgroup", "u32")
        .param("iteration", "u32")
        .returns("u32");
    match policy {
        Policy::Priority => f.line("return 0u;"),
        Policy::RoundRobin => f.line("return (workgroup + iteration) % SCHED_NUM_QUEUES;"),
    }
    f
}

pub(crate) fn runner(plan: &Plan, q: usize, queue: &QueuePlan) -> Function {
    let mut f = Function::new(runner_name(&queue.name))
        .doc(format!("Runs one batch of `{}`: receive the items, run the body on every thread, publish the children.", queue.name))
        .param("lid", "u32")
        .param("first", "u32")
        .param("count", "u32");
    let per_chunk = queue.items_per_workgroup;
    let count_fan_out = batch_prologue(&mut f, plan, q, queue);
    f.line("// Acquire: the reads below come after the claim saw `published`.");
    f.line("storageBarrier();");
    // The body's call on one chunk; `chunk` is its index within the batch.
    // A batch of one chunk finishes its joins after `sched_receive_done`,
    // whose fence releases the items' writes.
    let single = plan.chunks_per_batch == 1;
    let call = |chunk: &str| {
        let finish = (!single).then_some(joins::Finish::Fenced);
        let mut lines = body_call_lines(plan, q, queue, chunk, finish);
        lines.splice(
            2..2,
            [
                "// Every thread decodes its item straight from the slot, without loops".to_owned(),
                "// (docs/scheduler.md, \"Loop limits\").".to_owned(),
            ],
        );
        lines
    };
    if plan.chunks_per_batch == 1 {
        // A single chunk needs no loop, which llvmpipe runs markedly faster.
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
        f.line("    // The previous call is over in every thread before this one reuses");
        f.line("    // scratch and the body's workgroup variables.");
        f.line("    workgroupBarrier();");
        if count_fan_out {
            for line in fan_out_chunk_lines(plan, q, queue) {
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
    f.line("// Every item was read: release the slots.");
    f.line(format!("sched_receive_done(lid, {q}u, first, count);"));
    if single && joins::any(plan) {
        for line in joins::finish_lines(joins::Finish::AfterReleaseFence) {
            f.line(line);
        }
    }
    if !queue.targets.is_empty() {
        flush_lines(&mut f, plan, q, queue);
    }
    f.line("if (lid == 0u) {");
    if let Some(line) = trace::runner_end(plan) {
        f.line(line);
    }
    f.line(format!(
        "    atomicAdd(&sched_control[sched_ctrl({q}u, SCHED_Q_EXECUTED)], count);"
    ));
    f.line("    // Children were counted by the flushes above, so outstanding work");
    f.line("    // never reaches zero while any of them exists.");
    f.line("    atomicSub(&sched_control[SCHED_CTRL_PENDING], count);");
    f.line("}");
    f
}

/// The flush of a batch into all its procedure's targets: thread 0 reserves
/// slots in each target queue, every thread copies staged items into them,
/// thread 0 publishes them, with one set of barriers for all targets
/// (`sched_flush_begin` in the runtime says why).
fn flush_lines(f: &mut Function, plan: &Plan, q: usize, queue: &QueuePlan) {
    f.line("// Publish the items staged for the targets: thread 0 reserves their");
    f.line("// slots, every thread copies, thread 0 publishes.");
    f.line("sched_flush_begin();");
    reserve_and_copy_lines(f, plan, q, queue, "sched_flush_share()");
    f.line("// Release: the copies are complete before `published` covers them.");
    f.line("storageBarrier();");
    f.line("if (lid == 0u) {");
    for (i, &(t, _)) in queue.targets.iter().enumerate() {
        f.line(format!("    sched_publish({t}u, flushes[{i}]);"));
    }
    f.line("}");
}

pub(crate) fn entry_point(plan: &Plan) -> Function {
    let mut f = Function::new(ENTRY_POINT)
        .doc("Persistent workgroups: pick a batch, run it, until no work is left or the iteration budget is spent.")
        .param("@builtin(local_invocation_index) lid", "u32")
        .param("@builtin(workgroup_id) workgroup", "vec3<u32>");
    f.attributes
        .push(format!("@compute @workgroup_size({})", plan.workgroup_size));
    f.line("sched_wg_base = workgroup.x * SCHED_WORKGROUP_WORDS;");
    if let Some(line) = trace::entry_lines(plan) {
        f.line(line);
    }
    f.line("let budget = sched_config[SCHED_NUM_QUEUES].x;");
    f.line("var iteration = 0u;");
    f.line("var finished = false;");
    f.line("for (; iteration < budget; iteration += 1u) {");
    f.line("    if (lid == 0u) {");
    f.line("        sched_wg_pick = sched_pick(workgroup.x, iteration);");
    f.line("    }");
    f.line("    let pick = workgroupUniformLoad(&sched_wg_pick);");
    f.line("    if (pick.x == SCHED_EXIT) {");
    f.line("        finished = true;");
    f.line("        break;");
    f.line("    }");
    f.line("    switch pick.x {");
    for (q, queue) in plan.queues.iter().enumerate() {
        f.line(format!(
            "        case {q}u: {{ {}(lid, pick.y, pick.z); }}",
            runner_name(&queue.name)
        ));
    }
    f.line("        default: {}");
    f.line("    }");
    f.line("}");
    f.line("sched_check_left_in_step(finished || iteration >= budget);");
    f
}

/// Inside a batch's chunk loop, before the body's call on chunk `chunk`:
/// checked mode's per-item fan-out check of the previous chunk's items.
pub(crate) fn fan_out_chunk_lines(plan: &Plan, q: usize, queue: &QueuePlan) -> Vec<String> {
    let mut lines = vec!["    if (chunk > 0u) {".to_owned()];
    for line in fan_out::check_lines(plan, q, queue, "(chunk - 1u)") {
        lines.push(format!("        {line}"));
    }
    lines.push("    }".to_owned());
    if queue.threads_per_item > 1 {
        lines.push("    // The item's other threads see its counts at zero.".to_owned());
        lines.push("    workgroupBarrier();".to_owned());
    }
    lines
}

/// The part of a flush both strategies share, after the barrier that ends
/// the batch's staging: checked mode's fan-out check of the last chunk,
/// thread 0's reservations in every target, shared as `flushes` by `share`
/// (a WGSL expression), and every thread's copies from staging into the
/// reserved slots.
pub(crate) fn reserve_and_copy_lines(
    f: &mut Function,
    plan: &Plan,
    q: usize,
    queue: &QueuePlan,
    share: &str,
) {
    if crate::plan::fan_out::checked(plan) {
        let last = if plan.chunks_per_batch == 1 {
            "0u"
        } else {
            "(chunk - 1u)"
        };
        for line in fan_out::check_lines(plan, q, queue, last) {
            f.line(line);
        }
    }
    f.line("if (lid == 0u) {");
    for (i, &(t, _)) in queue.targets.iter().enumerate() {
        let target = &plan.queues[t];
        f.line(format!(
            "    sched_wg_flushes[{i}] = sched_reserve({t}u, {}u); // {}",
            target.stage_capacity, target.name
        ));
    }
    f.line("}");
    f.line(format!("let flushes = {share};"));
    for (i, &(t, _)) in queue.targets.iter().enumerate() {
        let target = &plan.queues[t];
        f.line(format!("// The items staged for `{}`.", target.name));
        let per_thread = target.stage_capacity.div_ceil(plan.workgroup_size);
        for j in 0..per_thread {
            let k = if j == 0 {
                "lid".to_owned()
            } else {
                format!("lid + {}u", j * plan.workgroup_size)
            };
            f.line(format!("if ({k} < flushes[{i}].y) {{"));
            f.line(format!(
                "    {}(sched_stage_word({}u, {}u, {k}), sched_slot_word({t}u, flushes[{i}].x + {k}));",
                copy_out_name(&target.name),
                target.stage_offset,
                target.slot_words
            ));
            f.line("}");
        }
    }
}

/// The first lines of a batch function under either strategy: the thread's
/// slot and thread within its item, the scratch stride, and what tracing,
/// checked mode and the item-wide helpers need. Returns whether the batch
/// counts its items' enqueues (checked mode's per-item fan-out check).
pub(crate) fn batch_prologue(f: &mut Function, plan: &Plan, q: usize, queue: &QueuePlan) -> bool {
    let tpi = queue.threads_per_item;
    f.line(format!("let slot = lid / {tpi}u;"));
    f.line(format!("let thread = lid % {tpi}u;"));
    f.line(format!("sched_scratch_stride = {}u;", queue.scratch_words));
    for line in trace::runner_begin(plan, q) {
        f.line(line);
    }
    if !plan.guarded_resources().is_empty() {
        f.line(format!(
            "{} = {q}u; // checked mode: the guards count violations for this procedure",
            checked::RUNNING
        ));
    }
    let count_fan_out = crate::plan::fan_out::checked(plan) && !queue.targets.is_empty();
    if count_fan_out {
        f.line(fan_out::slot_line());
    }
    if plan.item_helpers {
        for line in helpers::runner_lines(tpi) {
            f.line(line);
        }
    }
    count_fan_out
}

/// The body's call on chunk `chunk` (a WGSL expression) of a batch: decode
/// the thread's item from its slot when it is one of the batch's, call the
/// body, then check whether the body spent the driver's loop budget.
/// In a graph with joins, the item's join is read with it, and with
/// `finish` the joins are released and fired after the call
/// (`codegen::joins`; `None`: the caller does it).
pub(crate) fn body_call_lines(
    plan: &Plan,
    q: usize,
    queue: &QueuePlan,
    chunk: &str,
    finish: Option<joins::Finish>,
) -> Vec<String> {
    let joins = joins::any(plan);
    let (join_reset, join_decode) = joins::decode_lines(q, queue);
    let mut lines = vec![
        format!("let at = {chunk} * {}u + slot;", queue.items_per_workgroup),
        "let valid = at < count;".to_owned(),
        format!("var item: {};", queue.item),
    ];
    if joins {
        lines.push(join_reset);
    }
    lines.push("if (valid) {".to_owned());
    lines.push(format!(
        "    item = {}(sched_slot_word({q}u, first + at));",
        decode_name(&queue.item)
    ));
    if joins {
        lines.push(join_decode);
    }
    lines.push("}".to_owned());
    lines.push(format!(
        "{}(item, valid, thread, slot);",
        body_name(&queue.name)
    ));
    lines.push("sched_check_body_loops();".to_owned());
    if let (true, Some(finish)) = (joins, finish) {
        lines.extend(joins::finish_lines(finish));
    }
    lines
}
