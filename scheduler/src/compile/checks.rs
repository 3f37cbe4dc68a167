//! Checks on the parsed module: reserved names, the scheduler's state out of
//! reach of user code, the enqueue call graph, and the layout of typed
//! resources.

use std::collections::{BTreeSet, HashMap};

use naga::{Block, Function, Handle, Module, Statement};

use crate::codegen::module::Rendered;
use crate::naming::{
    BODY_PREFIX, RESERVED_PREFIXES, SCHEDULER_PREFIX, body_name, enqueue_name, join_open_name,
    scratch_name,
};
use crate::plan::Plan;
use crate::plan::joins::FIRES_PER_ITEM;
use crate::{CompileError, Resource};

/// Rejects user declarations whose names start with a reserved prefix.
/// `generated` lists every name the generator itself declared.
pub(crate) fn reserved_names(
    module: &Module,
    generated: &BTreeSet<String>,
) -> Result<(), CompileError> {
    let names = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .chain(
            module
                .global_variables
                .iter()
                .filter_map(|(_, g)| g.name.clone()),
        )
        .chain(module.constants.iter().filter_map(|(_, c)| c.name.clone()))
        .chain(module.overrides.iter().filter_map(|(_, o)| o.name.clone()))
        .chain(module.types.iter().filter_map(|(_, t)| t.name.clone()));
    for name in names {
        if RESERVED_PREFIXES.iter().any(|p| name.starts_with(p)) && !generated.contains(&name) {
            return Err(CompileError::ReservedName { name });
        }
    }
    Ok(())
}

/// Walks each body's call graph (helpers included) and rejects any reachable
/// `enqueue_<T>` for which the procedure has no connection to `T`, and any
/// `join_open_<C>` for which it has no join to `C`.
pub(crate) fn enqueue_call_graph(module: &Module, plan: &Plan) -> Result<(), CompileError> {
    let by_name: HashMap<&str, Handle<Function>> = module
        .functions
        .iter()
        .filter_map(|(h, f)| f.name.as_deref().map(|n| (n, h)))
        .collect();
    let enqueue_targets: HashMap<String, usize> = plan
        .queues
        .iter()
        .enumerate()
        .map(|(q, queue)| (enqueue_name(&queue.name), q))
        .collect();
    let join_kinds: HashMap<String, usize> = plan
        .joins
        .iter()
        .enumerate()
        .map(|(k, join)| (join_open_name(&plan.queues[join.continuation].name), k))
        .collect();

    for queue in &plan.queues {
        let Some(&root) = by_name.get(body_name(&queue.name).as_str()) else {
            continue;
        };
        let mut seen = BTreeSet::new();
        let mut stack = vec![root];
        while let Some(handle) = stack.pop() {
            if !seen.insert(handle) {
                continue;
            }
            let caller = &module.functions[handle];
            let mut callees = Vec::new();
            collect_calls(&caller.body, &mut callees);
            for callee in callees {
                let callee_name = module.functions[callee].name.clone().unwrap_or_default();
                let via = || {
                    if handle == root {
                        "its body".to_owned()
                    } else {
                        format!("helper `{}`", caller.name.clone().unwrap_or_default())
                    }
                };
                if let Some(&kind) = join_kinds.get(&callee_name) {
                    let q = plan.queue_index(&queue.name).unwrap_or(usize::MAX);
                    if !plan.joins[kind].openers.contains(&q) {
                        return Err(CompileError::UndeclaredJoin {
                            procedure: queue.name.clone(),
                            continuation: plan.queues[plan.joins[kind].continuation].name.clone(),
                            via: via(),
                        });
                    }
                    continue;
                }
                if let Some(&target) = enqueue_targets.get(&callee_name) {
                    if !declared_target(plan, queue, target) {
                        return Err(CompileError::UndeclaredEnqueue {
                            procedure: queue.name.clone(),
                            target: plan.queues[target].name.clone(),
                            via: via(),
                        });
                    }
                    // Enqueue functions are generated; no need to descend.
                    continue;
                }
                stack.push(callee);
            }
        }
    }
    Ok(())
}

/// Whether `queue` has a connection to `target` of the user's: in a graph
/// with joins every procedure gets [`FIRES_PER_ITEM`] into every
/// continuation for the joins it fires, which a connection of its own
/// (fan-out at least 1) comes on top of.
fn declared_target(plan: &Plan, queue: &crate::plan::QueuePlan, target: usize) -> bool {
    let for_joins = if plan.joins.iter().any(|j| j.continuation == target) {
        FIRES_PER_ITEM
    } else {
        0
    };
    queue
        .targets
        .iter()
        .any(|&(t, fan_out)| t == target && fan_out > for_joins)
}

/// Every function `block` calls, pushed onto `out`.
pub(crate) fn collect_calls(block: &Block, out: &mut Vec<Handle<Function>>) {
    for statement in block.iter() {
        match statement {
            Statement::Call { function, .. } => out.push(*function),
            Statement::Block(inner) => collect_calls(inner, out),
            Statement::If { accept, reject, .. } => {
                collect_calls(accept, out);
                collect_calls(reject, out);
            }
            Statement::Switch { cases, .. } => {
                cases.iter().for_each(|c| collect_calls(&c.body, out))
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                collect_calls(body, out);
                collect_calls(continuing, out);
            }
            _ => {}
        }
    }
}

/// Checks every typed resource against the module naga laid out: the array
/// stride of an `array<T>`, or the size of a single `T`, must be the element
/// size the host writes and reads. The derive makes them agree; this catches
/// a hand-written [`WgslType`](crate::WgslType) that does not.
pub(crate) fn resource_layouts(
    module: &Module,
    resources: &[Resource],
) -> Result<(), CompileError> {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| CompileError::Resource(format!("naga cannot lay out the module: {e}")))?;
    for resource in resources {
        let Some(shape) = resource.shape() else {
            continue;
        };
        let Some((_, global)) = module
            .global_variables
            .iter()
            .find(|(_, g)| g.name.as_deref() == Some(resource.name()))
        else {
            continue;
        };
        let wgsl_bytes = match module.types[global.ty].inner {
            naga::TypeInner::Array { stride, .. } if shape.runtime_array => u64::from(stride),
            _ => u64::from(layouter[global.ty].size),
        };
        if wgsl_bytes != shape.element_bytes {
            return Err(CompileError::Resource(format!(
                "resource `{}`: WGSL lays out `{}` with {wgsl_bytes} bytes per element, the Rust type has {}",
                resource.name(),
                resource.wgsl_type(),
                shape.element_bytes
            )));
        }
    }
    Ok(())
}

/// Rejects user code (bodies and the library's functions) that names a
/// global of the scheduler (`sched_*`: queues, control words, staging): a
/// body that writes `sched_control` corrupts the run, and on a GPU could
/// hang it. User code reaches scheduler state only through the generated
/// functions (`enqueue_*`, the item-wide and scratch helpers). The one
/// exception is a procedure's own typed scratch, which its body's
/// generated prologue points `scratch` at. The error names the global and
/// the line in the user's source.
pub(crate) fn scheduler_state_private(
    module: &Module,
    rendered: &Rendered,
    generated: &BTreeSet<String>,
) -> Result<(), CompileError> {
    for (_, function) in module.functions.iter() {
        let name = function.name.as_deref().unwrap_or_default();
        let body_of = name.strip_prefix(BODY_PREFIX);
        if generated.contains(name) && body_of.is_none() {
            continue;
        }
        let own_scratch = body_of.map(scratch_name);
        for (handle, expression) in function.expressions.iter() {
            let naga::Expression::GlobalVariable(global) = expression else {
                continue;
            };
            let Some(global_name) = module.global_variables[*global].name.as_deref() else {
                continue;
            };
            if !global_name.starts_with(SCHEDULER_PREFIX)
                || Some(global_name) == own_scratch.as_deref()
            {
                continue;
            }
            let location = function
                .expressions
                .get_span(handle)
                .location(&rendered.text);
            let (origin, line, column) =
                rendered.locate(location.line_number, location.line_position);
            return Err(CompileError::Wgsl {
                origin,
                line,
                column,
                message: format!(
                    "`{global_name}` is the scheduler's own state: bodies and library code may not name it (use `enqueue_*` and the helpers)"
                ),
            });
        }
    }
    Ok(())
}
