//! Builds the [`KernelModule`] for a compiled plan: constants, bindings, item
//! codecs, enqueue functions, procedure bodies, runners and the entry point.

use std::collections::BTreeMap;

use crate::SourceOrigin;
use crate::codegen::kernels::{
    copy_out_function, entry_point, payload_functions, policy_function, runner,
};
use crate::codegen::module::{Constant, Function, Global, KernelModule, Verbatim};
use crate::codegen::{checked, codec, fan_out, globals, helpers, joins, rounds, trace};
use crate::graph::Procedure;
use crate::naming::{
    ENTRY_POINT, PREPARE_ENTRY_POINT, body_name, encode_name, enqueue_name, queue_constant_name,
    queue_field_constant_name, scratch_name,
};
use crate::plan::layout::{ExtraStructs, ItemLayout};
use crate::plan::{Plan, control};

/// The queue protocol template shared by every module.
const RUNTIME_WGSL: &str = include_str!("../../../shaders/scheduler/runtime.wgsl");

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
    extra_structs: &[ExtraStructs],
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
    let max_targets = plan
        .queues
        .iter()
        .map(|q| q.targets.len())
        .max()
        .unwrap_or(0);
    c.push(constant(
        "SCHED_MAX_TARGETS",
        "u32",
        format!("{}u", max_targets.max(1)),
        "The most queues one procedure enqueues into (at least 1).",
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
        "SCHED_CTRL_BODY_LOOPS_CUT",
        "u32",
        format!("{}u", control::BODY_LOOPS_CUT),
        "Control word: body calls that spent the driver's loop budget (llvmpipe loop limit).",
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
            &queue_field_constant_name(name),
            "u32",
            format!("{value}u"),
            "",
        ));
    }
    for (q, queue) in plan.queues.iter().enumerate() {
        c.push(constant(
            &queue_constant_name(&queue.name),
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

    for extra in extra_structs {
        module.items.push(Verbatim {
            title: extra.title.clone(),
            text: extra.text.clone(),
            origin: SourceOrigin::Item(extra.origin.clone()),
        });
    }

    module.globals = globals::globals(plan);
    for (procedure, queue) in procedures.iter().zip(&plan.queues) {
        if let Some(ty) = &procedure.scratch_type {
            module.globals.push(Global {
                attributes: String::new(),
                space: "workgroup".into(),
                name: scratch_name(&procedure.name),
                ty: format!("array<{}, {}>", ty.wgsl_type, queue.items_per_workgroup),
                doc: format!(
                    "Typed scratch of `{}`: one `{}` per item slot.",
                    procedure.name, ty.wgsl_type
                ),
            });
        }
    }
    let coherent = globals::shape(plan).coherent;

    let guarded = plan.guarded_resources();
    // Checked mode guards the user's indices; otherwise their text is kept.
    let user_text = |text: &str| {
        if guarded.is_empty() {
            text.to_owned()
        } else {
            checked::rewrite(text, &guarded)
        }
    };
    if !guarded.is_empty() {
        module.constants.extend(checked::constants(plan));
        module.globals.extend(checked::globals());
    }
    module.constants.extend(trace::constants(plan));
    module.globals.extend(trace::globals(plan));
    module.constants.extend(joins::constants(plan));
    module.globals.extend(joins::globals(plan));
    if !library.trim().is_empty() {
        module.library = Some(Verbatim {
            title: "graph library".into(),
            text: user_text(library),
            origin: SourceOrigin::Library,
        });
    }
    module.runtime = Some(Verbatim {
        title: "runtime".into(),
        text: RUNTIME_WGSL.to_owned(),
        origin: SourceOrigin::Generated,
    });

    if plan.item_helpers {
        module.globals.extend(helpers::globals(plan.workgroup_size));
        module.helpers = Some(Verbatim {
            title: "item-wide helpers".into(),
            text: helpers::HELPERS_WGSL.to_owned(),
            origin: SourceOrigin::Generated,
        });
        module
            .functions
            .push(helpers::reduce_function(plan.workgroup_size));
    }
    if !guarded.is_empty() {
        module.functions.extend(checked::functions(plan));
    }
    module.functions.extend(trace::functions(plan));
    let count_fan_out = crate::plan::fan_out::checked(plan);
    if count_fan_out {
        module.constants.extend(fan_out::constants(plan));
        module.globals.extend(fan_out::globals(plan));
        module.functions.extend(fan_out::functions());
    }
    module.functions.push(policy_function(plan.policy));
    module.functions.extend(payload_functions(coherent));
    for (name, (_, layout)) in items {
        module.functions.push(codec::decode_function(name, layout));
        module.functions.push(codec::encode_function(name, layout));
    }
    for queue in &plan.queues {
        module.functions.push(copy_out_function(queue));
    }
    module.functions.extend(joins::functions(plan, items));
    for (q, queue) in plan.queues.iter().enumerate() {
        let mut f = Function::new(enqueue_name(&queue.name))
            .doc(format!(
                "Stages one `{}` item for `{}`; it is published when the batch ends.",
                queue.item, queue.name
            ))
            .param("item", &queue.item);
        if count_fan_out {
            f.line(format!("sched_fan_out_count({q}u);"));
        }
        if joins::any(plan) {
            f.line("sched_join_add_child();");
        }
        f.line(format!(
            "let base = sched_stage({q}u, {}u, {}u);",
            queue.stage_offset, queue.stage_capacity
        ));
        f.line("if (base != 0xffffffffu) {");
        f.line(format!("    {}(base, item);", encode_name(&queue.item)));
        if joins::any(plan) {
            f.line(joins::enqueue_tag_line(queue));
        }
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
        f.body = user_text(procedure.body.trim_end())
            .lines()
            .map(str::to_owned)
            .collect();
        if procedure.scratch_type.is_some() {
            f.prelude.push(format!(
                "let scratch = &{}[slot];",
                scratch_name(&procedure.name)
            ));
        }
        f.origin = SourceOrigin::Body(procedure.name.clone());
        module.functions.push(f);
    }
    for (q, queue) in plan.queues.iter().enumerate() {
        module.functions.push(runner(plan, q, queue));
    }
    module.functions.push(entry_point(plan));
    module
        .functions
        .extend(rounds::functions(plan, procedures, library));
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
