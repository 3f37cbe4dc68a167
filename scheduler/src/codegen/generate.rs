//! Builds the [`KernelModule`] for a compiled plan: constants, bindings, item
//! codecs, enqueue functions, procedure bodies, runners and the entry point.

use std::collections::BTreeMap;

use crate::codegen::module::{Constant, Function, Global, KernelModule, Verbatim};
use crate::compile::layout::{ItemLayout, PACKET_WORDS, decode_name, encode_name};
use crate::compile::plan::{Plan, QueuePlan, control};
use crate::graph::Procedure;
use crate::{Access, Policy, Resource, SourceOrigin};

/// The queue protocol template shared by every module.
const RUNTIME_WGSL: &str = include_str!("../../../shaders/scheduler/runtime.wgsl");

/// Entry point name of the megakernel.
pub(crate) const ENTRY_POINT: &str = "sched_main";

/// Entry point of the Rounds strategy that prepares the next round.
pub(crate) const PREPARE_ENTRY_POINT: &str = "sched_prepare_round";

/// Entry point of the Rounds strategy that runs one round of a procedure.
pub(crate) fn round_entry_point(procedure: &str) -> String {
    format!("sched_round_{procedure}")
}

/// Name of the function holding a procedure's body.
pub(crate) fn body_name(procedure: &str) -> String {
    format!("sched_proc_{procedure}")
}

/// Name of the enqueue function for a target procedure.
pub(crate) fn enqueue_name(procedure: &str) -> String {
    format!("enqueue_{procedure}")
}

fn constant(name: &str, ty: &str, value: impl ToString, doc: &str) -> Constant {
    Constant {
        name: name.to_owned(),
        ty: ty.to_owned(),
        value: value.to_string(),
        doc: doc.to_owned(),
    }
}

fn u32_array(values: impl Iterator<Item = u32>) -> String {
    let items: Vec<String> = values.map(|v| format!("{v}u")).collect();
    format!("array<u32, {}>({})", items.len(), items.join(", "))
}

/// Generates the module. `items` maps WGSL item names to their checked layouts
/// and sources, in a deterministic (sorted) order.
pub(crate) fn generate(
    plan: &Plan,
    procedures: &[Procedure],
    library: &str,
    items: &BTreeMap<String, (String, ItemLayout)>,
) -> KernelModule {
    let n = plan.queues.len();
    let mut module = KernelModule {
        header: header(plan),
        ..KernelModule::default()
    };

    let c = &mut module.constants;
    c.push(constant(
        "SCHED_WORKGROUP_SIZE",
        "u32",
        format!("{}u", plan.workgroup_size),
        "Threads per workgroup.",
    ));
    c.push(constant(
        "SCHED_NUM_QUEUES",
        "u32",
        format!("{n}u"),
        "One queue per procedure.",
    ));
    c.push(constant(
        "SCHED_WORKGROUP_WORDS",
        "u32",
        format!("{}u", plan.stage_words),
        "Words of the staging buffer per workgroup.",
    ));
    c.push(constant(
        "SCHED_IDLE",
        "u32",
        "0xfffffffeu",
        "Pick result: no work found, but work is outstanding.",
    ));
    c.push(constant(
        "SCHED_EXIT",
        "u32",
        "0xffffffffu",
        "Pick result: no work is left anywhere.",
    ));
    c.push(constant(
        "SCHED_CTRL_PENDING",
        "u32",
        format!("{}u", control::PENDING),
        "Control word: outstanding items.",
    ));
    c.push(constant(
        "SCHED_CTRL_LOOPS_CUT",
        "u32",
        format!("{}u", control::LOOPS_CUT),
        "Control word: spin-waits the driver cut short (llvmpipe loop limit).",
    ));
    c.push(constant(
        "SCHED_CTRL_ROUNDS",
        "u32",
        format!("{}u", control::ROUNDS),
        "Control word: rounds that found work (Rounds strategy).",
    ));
    c.push(constant(
        "SCHED_CTRL_QUEUE_BASE",
        "u32",
        format!("{}u", control::QUEUE_BASE),
        "Control word of queue 0's block.",
    ));
    c.push(constant(
        "SCHED_CTRL_QUEUE_STRIDE",
        "u32",
        format!("{}u", control::QUEUE_STRIDE),
        "Control words per queue.",
    ));
    for (name, value) in [
        ("HEAD", control::HEAD),
        ("TAIL", control::TAIL),
        ("FILL", control::FILL),
        ("HIGH_WATER", control::HIGH_WATER),
        ("EXECUTED", control::EXECUTED),
        ("ENQUEUED", control::ENQUEUED),
        ("DROPPED", control::DROPPED),
        ("NEEDED", control::NEEDED),
        ("FANOUT_OVERFLOW", control::FANOUT_OVERFLOW),
        ("PUBLISHED", control::PUBLISHED),
        ("RELEASED", control::RELEASED),
        ("ROUND_END", control::ROUND_END),
    ] {
        c.push(constant(
            &format!("SCHED_Q_{name}"),
            "u32",
            format!("{value}u"),
            "",
        ));
    }
    for (q, queue) in plan.queues.iter().enumerate() {
        c.push(constant(
            &format!("SCHED_QUEUE_{}", queue.name.to_uppercase()),
            "u32",
            format!("{q}u"),
            &format!("Queue of `{}`.", queue.name),
        ));
    }
    c.push(constant(
        "sched_slot_words",
        &format!("array<u32, {n}>"),
        u32_array(plan.queues.iter().map(|q| q.slot_words)),
        "Slot size in words (the item rounded up to whole vec4<u32> packets), per queue.",
    ));
    c.push(constant(
        "sched_items_per_batch",
        &format!("array<u32, {n}>"),
        u32_array(plan.queues.iter().map(|q| q.items_per_batch)),
        "Items claimed per batch (all its chunks), per queue.",
    ));
    c.push(constant(
        "sched_queue_order",
        &format!("array<u32, {n}>"),
        u32_array(plan.scan_order.iter().map(|&q| q as u32)),
        "Queue scan order.",
    ));

    for (name, (source, _)) in items {
        module.items.push(Verbatim {
            title: format!("item type {name}"),
            text: source.clone(),
            origin: SourceOrigin::Item(name.clone()),
        });
    }

    let g = &mut module.globals;
    let global = |attributes: &str, declaration: String, doc: &str| Global {
        attributes: attributes.to_owned(),
        declaration,
        doc: doc.to_owned(),
    };
    let coherent = plan
        .features
        .contains(wgpu::Features::MEMORY_DECORATION_COHERENT);
    if coherent {
        g.push(global(
            "@coherent @group(0) @binding(0)",
            "var<storage, read_write> sched_queue_words: array<vec4<u32>>".into(),
            "Item slots of every queue (coherent: plain accesses are seen across workgroups after the fences).",
        ));
    } else {
        g.push(global(
            "@group(0) @binding(0)",
            "var<storage, read_write> sched_queue_words: array<atomic<u32>>".into(),
            "Item slots of every queue (atomic words: no coherent memory decoration compiled for).",
        ));
    }
    g.push(global(
        "@group(0) @binding(1)",
        "var<storage, read_write> sched_control: array<atomic<u32>>".into(),
        "Counters: outstanding work and per-queue statistics.",
    ));
    g.push(global(
        "@group(0) @binding(2)",
        "var<storage, read_write> sched_staging: array<vec4<u32>>".into(),
        "Per-workgroup staging of enqueued items, copied into queue slots at the flush.",
    ));
    g.push(global(
        "@group(0) @binding(3)",
        format!("var<uniform> sched_config: array<vec4<u32>, {}>", n + 1),
        "Per queue (capacity - 1, first slot word, 0, 0); last: (iteration budget, spin limit, workgroups per round dispatch, 0).",
    ));
    g.push(global(
        "@group(0) @binding(4)",
        "var<storage, read_write> sched_dispatch: array<u32>".into(),
        "Rounds strategy: indirect dispatch sizes (x, y, z) per queue, written by sched_prepare_round. Bound only to that entry point.",
    ));
    for (binding, resource) in plan.resources.iter().enumerate() {
        let declaration = match resource {
            Resource::Storage {
                name,
                wgsl_type,
                access: Access::ReadWrite,
            } => format!("var<storage, read_write> {name}: {wgsl_type}"),
            Resource::Storage {
                name,
                wgsl_type,
                access: Access::Read,
            } => format!("var<storage, read> {name}: {wgsl_type}"),
            Resource::Uniform { name, wgsl_type } => format!("var<uniform> {name}: {wgsl_type}"),
        };
        g.push(global(
            &format!("@group(1) @binding({binding})"),
            declaration,
            "User resource.",
        ));
    }
    g.push(global(
        "",
        "var<workgroup> sched_wg_pick: vec4<u32>".into(),
        "The batch thread 0 picked, broadcast with workgroupUniformLoad.",
    ));
    g.push(global(
        "",
        "var<workgroup> sched_wg_flush: vec2<u32>".into(),
        "First ticket and count of the flush in progress.",
    ));
    g.push(global(
        "",
        format!("var<workgroup> sched_wg_staged: array<atomic<u32>, {n}>"),
        "Items staged per queue in this batch.",
    ));
    g.push(global(
        "",
        format!(
            "var<workgroup> sched_wg_scratch: array<u32, {}>",
            plan.scratch_words.max(1)
        ),
        "Scratch shared by all procedures, sized by the largest.",
    ));
    g.push(global(
        "",
        "var<private> sched_spins: u32".into(),
        "Spin-wait iterations of this invocation (thread 0), for the spin limit.",
    ));
    g.push(global(
        "",
        "var<private> sched_rounds: bool".into(),
        "Whether a Rounds entry point runs (no waiting on other workgroups).",
    ));
    g.push(global(
        "",
        "var<private> sched_wg_base: u32".into(),
        "First word of this workgroup's region of the staging buffer.",
    ));
    g.push(global(
        "",
        "var<private> sched_scratch_stride: u32".into(),
        "Scratch words per item of the running procedure.",
    ));

    if !library.trim().is_empty() {
        module.library = Some(Verbatim {
            title: "graph library".into(),
            text: library.to_owned(),
            origin: SourceOrigin::Library,
        });
    }
    module.runtime = Some(Verbatim {
        title: "runtime".into(),
        text: RUNTIME_WGSL.to_owned(),
        origin: SourceOrigin::Generated,
    });

    module.functions.push(policy_function(plan.policy));
    module.functions.extend(payload_functions(coherent));
    for (_, layout) in items.values() {
        module.functions.push(layout.decode.clone());
        module.functions.push(layout.encode.clone());
    }
    for queue in &plan.queues {
        module.functions.push(copy_out_function(queue));
    }
    for (q, queue) in plan.queues.iter().enumerate() {
        let mut f = Function::new(enqueue_name(&queue.name))
            .doc(format!(
                "Stages one `{}` item for `{}`; it is published when the batch ends.",
                queue.item, queue.name
            ))
            .param("item", &queue.item);
        f.line(format!(
            "let base = sched_stage({q}u, {}u, {}u);",
            queue.stage_offset, queue.stage_capacity
        ));
        f.line("if (base != 0xffffffffu) {");
        f.line(format!("    {}(base, item);", encode_name(&queue.item)));
        f.line("}");
        module.functions.push(f);
    }
    for procedure in procedures {
        let mut f = Function::new(body_name(&procedure.name))
            .doc(format!("Body of `{}` (user code).", procedure.name))
            .param("item", procedure.item.wgsl_name())
            .param("valid", "bool")
            .param("thread", "u32")
            .param("slot", "u32");
        f.body = procedure
            .body
            .trim_end()
            .lines()
            .map(str::to_owned)
            .collect();
        f.origin = SourceOrigin::Body(procedure.name.clone());
        module.functions.push(f);
    }
    for (q, queue) in plan.queues.iter().enumerate() {
        module.functions.push(runner(plan, q, queue));
    }
    module.functions.push(entry_point(plan));
    module.functions.push(prepare_entry_point());
    for (q, queue) in plan.queues.iter().enumerate() {
        module.functions.push(round_entry(plan, q, queue));
    }
    module
}

fn header(plan: &Plan) -> Vec<String> {
    let mut lines = vec![
        format!("Megakernel for graph `{}`, generated by the `scheduler` crate {}.", plan.graph_name, env!("CARGO_PKG_VERSION")),
        "Do not edit: regenerate it from the procedure graph. docs/scheduler.md explains the protocol.".to_owned(),
        format!("Entry points: {ENTRY_POINT} (persistent megakernel); {PREPARE_ENTRY_POINT} and sched_round_<procedure> (Rounds strategy)."),
        format!("Workgroup size {}, {} chunk(s) per batch, policy {:?}, {} procedures:", plan.workgroup_size, plan.chunks_per_batch, plan.policy, plan.queues.len()),
        String::new(),
        format!("{:<6}{:<20}{:<16}{:>8}{:>10}{:>10}  {}", "queue", "procedure", "item", "threads", "per batch", "priority", "enqueues into (fan-out)"),
    ];
    for (q, queue) in plan.queues.iter().enumerate() {
        let targets: Vec<String> = queue
            .targets
            .iter()
            .map(|&(t, f)| format!("{} ({f})", plan.queues[t].name))
            .collect();
        let targets = if targets.is_empty() {
            "-".to_owned()
        } else {
            targets.join(", ")
        };
        lines.push(format!(
            "{:<6}{:<20}{:<16}{:>8}{:>10}{:>10}  {}",
            q,
            queue.name,
            queue.item,
            queue.threads_per_item,
            queue.items_per_batch,
            queue.priority,
            targets
        ));
    }
    lines
}

/// Name of the function that copies one staged item of `queue` into its slot.
fn copy_out_name(queue: &str) -> String {
    format!("sched_copy_out_{queue}")
}

/// Straight-line packet copy from the workgroup's region of the staging buffer
/// into a queue slot. It is written out word by word on purpose: a loop here
/// could be cut short by llvmpipe's loop limiter (docs/scheduler.md, "Loop
/// limits"), publishing half-copied items.
fn copy_out_function(queue: &QueuePlan) -> Function {
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
fn payload_functions(coherent: bool) -> [Function; 2] {
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

fn policy_function(policy: Policy) -> Function {
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

fn runner(plan: &Plan, q: usize, queue: &QueuePlan) -> Function {
    let tpi = queue.threads_per_item;
    let mut f = Function::new(format!("sched_run_{}", queue.name))
        .doc(format!("Runs one batch of `{}`: receive the items, run the body on every thread, publish the children.", queue.name))
        .param("lid", "u32")
        .param("first", "u32")
        .param("count", "u32");
    let per_chunk = queue.items_per_workgroup;
    f.line(format!("let slot = lid / {tpi}u;"));
    f.line(format!("let thread = lid % {tpi}u;"));
    f.line(format!("sched_scratch_stride = {}u;", queue.scratch_words));
    f.line("// Acquire: the reads below come after the claim saw `published`.");
    f.line("storageBarrier();");
    // The body's call on one chunk; `chunk` is its index within the batch.
    let call = |chunk: &str| {
        [
            format!("let at = {chunk} * {per_chunk}u + slot;"),
            "let valid = at < count;".to_owned(),
            "// Every thread decodes its item straight from the slot, without loops".to_owned(),
            "// (docs/scheduler.md, \"Loop limits\").".to_owned(),
            format!("var item: {};", queue.item),
            "if (valid) {".to_owned(),
            format!(
                "    item = {}(sched_slot_word({q}u, first + at));",
                decode_name(&queue.item)
            ),
            "}".to_owned(),
            format!("{}(item, valid, thread, slot);", body_name(&queue.name)),
        ]
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
    for &(t, _) in &queue.targets {
        let target = &plan.queues[t];
        let flush = format!("flush_{}", target.name);
        f.line(format!(
            "// Publish the items staged for `{}`.",
            target.name
        ));
        f.line(format!(
            "let {flush} = sched_flush_reserve(lid, {t}u, {}u);",
            target.stage_capacity
        ));
        f.line(format!("if ({flush}.y > 0u) {{"));
        let per_thread = target.stage_capacity.div_ceil(plan.workgroup_size);
        for j in 0..per_thread {
            let k = if j == 0 {
                "lid".to_owned()
            } else {
                format!("lid + {}u", j * plan.workgroup_size)
            };
            f.line(format!("    if ({k} < {flush}.y) {{"));
            f.line(format!(
                "        {}(sched_stage_word({}u, {}u, {k}), sched_slot_word({t}u, {flush}.x + {k}));",
                copy_out_name(&target.name),
                target.stage_offset,
                target.slot_words
            ));
            f.line("    }");
        }
        f.line(format!("    sched_flush_publish(lid, {t}u, {flush});"));
        f.line("}");
    }
    f.line("if (lid == 0u) {");
    f.line(format!(
        "    atomicAdd(&sched_control[sched_ctrl({q}u, SCHED_Q_EXECUTED)], count);"
    ));
    f.line("    // Children were counted by the flushes above, so outstanding work");
    f.line("    // never reaches zero while any of them exists.");
    f.line("    atomicSub(&sched_control[SCHED_CTRL_PENDING], count);");
    f.line("}");
    f
}

fn entry_point(plan: &Plan) -> Function {
    let mut f = Function::new(ENTRY_POINT)
        .doc("Persistent workgroups: pick a batch, run it, until no work is left or the iteration budget is spent.")
        .param("@builtin(local_invocation_index) lid", "u32")
        .param("@builtin(workgroup_id) workgroup", "vec3<u32>");
    f.attributes
        .push(format!("@compute @workgroup_size({})", plan.workgroup_size));
    f.line("sched_wg_base = workgroup.x * SCHED_WORKGROUP_WORDS;");
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
            "        case {q}u: {{ sched_run_{}(lid, pick.y, pick.z); }}",
            queue.name
        ));
    }
    f.line("        default: {}");
    f.line("    }");
    f.line("}");
    f.line("sched_check_left_in_step(finished || iteration >= budget);");
    f
}

/// The Rounds strategy's prepare kernel: one thread retires the round that ran
/// and sizes the next one for every queue.
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

/// One procedure's kernel for the Rounds strategy: workgroups stride over the
/// batches of the round's items; nobody waits on another workgroup.
fn round_entry(plan: &Plan, q: usize, queue: &QueuePlan) -> Function {
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
    f.line("if (lid == 0u) {");
    f.line(format!(
        "    sched_wg_pick = vec4<u32>(sched_round_range({q}u), 0u, 0u);"
    ));
    f.line("}");
    f.line("let range = workgroupUniformLoad(&sched_wg_pick).xy;");
    f.line(format!("let per = {}u;", queue.items_per_batch));
    f.line("// Grid-stride over batches: the dispatch size may be clamped.");
    f.line("var batch = workgroup.x;");
    f.line("for (; batch * per < range.y; batch += groups.x) {");
    f.line(format!(
        "    sched_run_{}(lid, range.x + batch * per, min(per, range.y - batch * per));",
        queue.name
    ));
    f.line("}");
    f.line("// A driver that cut a loop short (llvmpipe's loop limit) may have");
    f.line("// skipped items or part of a body: flag it so the run fails loudly.");
    f.line("sched_check_left_in_step(batch * per >= range.y);");
    f
}
