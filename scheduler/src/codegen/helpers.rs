//! The item-wide helpers (`item_sum_u32`, `item_broadcast_f32`, ...): added
//! to a module only when its bodies or library call one, so that graphs which
//! do not use them get the same module as before.

use crate::codegen::module::{Function, Global};
use crate::graph::Procedure;

/// The helper library (shaders/scheduler/item_helpers.wgsl).
pub(crate) const HELPERS_WGSL: &str = include_str!("../../../shaders/scheduler/item_helpers.wgsl");

/// The workgroup array of the helpers: one word per thread.
pub(crate) const ARRAY: &str = "sched_wg_item";

/// The public helper names: every `fn item_*` of the library.
pub(crate) fn public_names() -> impl Iterator<Item = &'static str> {
    HELPERS_WGSL.lines().filter_map(|line| {
        let name = line.strip_prefix("fn ")?.split('(').next()?;
        name.starts_with("item_").then_some(name)
    })
}

/// Whether a body or the library names a helper other than in its own
/// declaration (`fn item_sum_u32(`, which would then clash with ours).
pub(crate) fn used(procedures: &[Procedure], library: &str) -> bool {
    let names: Vec<&str> = public_names().collect();
    procedures
        .iter()
        .map(|p| p.body.as_str())
        .chain([library])
        .any(|text| {
            let mut previous = "";
            text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .filter(|token| !token.is_empty())
                .any(|token| {
                    let hit = previous != "fn" && names.contains(&token);
                    previous = token;
                    hit
                })
        })
}

/// The module-scope state of the helpers.
pub(crate) fn globals(workgroup_size: u32) -> [Global; 3] {
    let state = |space: &str, name: &str, ty: String, doc: &str| Global {
        attributes: String::new(),
        space: space.to_owned(),
        name: name.to_owned(),
        ty,
        doc: doc.to_owned(),
    };
    [
        state(
            "workgroup",
            ARRAY,
            format!("array<u32, {workgroup_size}>"),
            "One word per thread for the item-wide helpers (item_sum_u32, ...).",
        ),
        state(
            "private",
            "sched_item_lid",
            "u32".into(),
            "This thread's index in the workgroup, for the item-wide helpers.",
        ),
        state(
            "private",
            "sched_item_threads",
            "u32".into(),
            "Threads per item of the running procedure, for the item-wide helpers.",
        ),
    ]
}

/// The lines a runner adds before its body calls, so that the helpers know
/// the thread and the item's thread count.
pub(crate) fn runner_lines(threads_per_item: u32) -> [String; 2] {
    [
        "sched_item_lid = lid;".to_owned(),
        format!("sched_item_threads = {threads_per_item}u;"),
    ]
}

/// The tree reduction, unrolled for `workgroup_size` (no loops: llvmpipe's
/// loop budget, docs/scheduler.md "Loop limits"). A step whose stride is not
/// below the item's thread count is skipped by every thread alike, so its
/// barrier stays in uniform control flow.
pub(crate) fn reduce_function(workgroup_size: u32) -> Function {
    let mut f = Function::new("sched_item_reduce")
        .doc("Reduces `value` with `op` (SCHED_ITEM_*) over the threads of the calling")
        .doc("thread's item; every thread of the workgroup calls it, and each gets")
        .doc("its own item's result.")
        .param("value", "u32")
        .param("op", "u32")
        .returns("u32");
    f.line("let lid = sched_item_lid;");
    f.line("let threads = sched_item_threads;");
    f.line("let thread = lid % threads;");
    f.line("// Readers of an earlier helper are done before the array is overwritten.");
    f.line("workgroupBarrier();");
    f.line(format!("{ARRAY}[lid] = value;"));
    f.line("workgroupBarrier();");
    f.line("// Thread t adds thread t + stride's partial result, the stride halving.");
    let mut stride = workgroup_size / 2;
    while stride >= 1 {
        f.line(format!("if (threads > {stride}u) {{"));
        f.line(format!("    if (thread < {stride}u) {{"));
        f.line(format!(
            "        {ARRAY}[lid] = sched_item_combine(op, {ARRAY}[lid], {ARRAY}[lid + {stride}u]);"
        ));
        f.line("    }");
        f.line("    workgroupBarrier();");
        f.line("}");
        stride /= 2;
    }
    f.line(format!("return {ARRAY}[lid - thread];"));
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ItemType, item_type};

    #[repr(C)]
    #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
    struct Node {
        id: u32,
    }

    fn with_body(body: &str) -> Procedure {
        let item: ItemType = item_type!(Node, "struct Node { id: u32 }", [id]);
        Procedure::new("P", item).body(body)
    }

    #[test]
    fn public_names_are_the_item_functions() {
        let names: Vec<&str> = public_names().collect();
        assert!(names.contains(&"item_sum_f32"), "{names:?}");
        assert!(names.contains(&"item_broadcast_u32"), "{names:?}");
        assert!(names.iter().all(|n| n.starts_with("item_")));
    }

    #[test]
    fn only_calls_count_as_use() {
        assert!(used(&[with_body("let s = item_sum_u32(item.id);")], ""));
        assert!(used(&[], "fn f(x: f32) -> f32 { return item_max_f32(x); }"));
        assert!(!used(&[with_body("let item_sum = 1u;")], ""));
        assert!(!used(&[], "fn item_sum_u32(x: u32) -> u32 { return x; }"));
    }
}
