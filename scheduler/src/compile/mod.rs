//! Compiling a [`Graph`] into a [`CompiledGraph`]: graph checks, item layouts,
//! code generation, and naga validation of the result.

pub(crate) mod checks;
mod compiled;
pub(crate) mod diagnostics;
mod fan_out;
pub(crate) mod layout;
pub(crate) mod prune;
pub(crate) mod workgroup;

use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};

use crate::codegen::bindings::{self, Kernels};
use crate::codegen::generate::generate;
use crate::codegen::graph_constants;
use crate::codegen::module::{KernelModule, Rendered};
use crate::plan::joins::JoinPlan;
use crate::plan::layout::{ExtraStructs, ItemLayout};
use crate::plan::{Plan, build};
use crate::{CompileError, CompileOptions, Graph, MAX_CHUNKS_PER_BATCH, SourceOrigin};

pub use compiled::{CompiledGraph, Specialization};

fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.starts_with("__")
}

impl Graph {
    /// Checks the graph and generates its megakernel.
    ///
    /// An unreachable procedure is an **error**: it usually means a missing
    /// connection, and its queue would cost memory for nothing.
    pub fn compile(&self, options: &CompileOptions) -> Result<CompiledGraph, CompileError> {
        let workgroup_size = options.workgroup_size;
        let size_limit = options
            .limits
            .max_compute_workgroup_size_x
            .min(options.limits.max_compute_invocations_per_workgroup);
        if !workgroup_size.is_power_of_two() || workgroup_size > size_limit {
            return Err(CompileError::InvalidWorkgroupSize {
                size: workgroup_size,
                limit: size_limit,
            });
        }
        let chunks = options.chunks_per_batch;
        if !(1..=MAX_CHUNKS_PER_BATCH).contains(&chunks) {
            return Err(CompileError::InvalidChunksPerBatch {
                chunks,
                max: MAX_CHUNKS_PER_BATCH,
            });
        }

        let mut index = HashMap::new();
        for (i, p) in self.procedures.iter().enumerate() {
            if !is_identifier(&p.name) {
                return Err(CompileError::InvalidProcedureName(p.name.clone()));
            }
            if index.insert(p.name.as_str(), i).is_some() {
                return Err(CompileError::DuplicateProcedure(p.name.clone()));
            }
            if !p.threads_per_item.is_power_of_two() || p.threads_per_item > workgroup_size {
                return Err(CompileError::InvalidThreadCount {
                    procedure: p.name.clone(),
                    threads: p.threads_per_item,
                    workgroup_size,
                });
            }
        }

        // Declared fan-outs, merged per (from, to) keeping the largest; the
        // pairs connected without one get theirs derived from the module.
        let mut declared: Vec<BTreeMap<usize, u32>> = vec![BTreeMap::new(); self.procedures.len()];
        let mut derived = BTreeSet::new();
        for c in &self.connections {
            let lookup = |name: &str| {
                index
                    .get(name)
                    .copied()
                    .ok_or_else(|| CompileError::UnknownProcedure {
                        from: c.from.clone(),
                        to: c.to.clone(),
                        unknown: name.to_owned(),
                    })
            };
            let (from, to) = (lookup(&c.from)?, lookup(&c.to)?);
            match c.fan_out {
                Some(0) => {
                    return Err(CompileError::ZeroFanOut {
                        from: c.from.clone(),
                        to: c.to.clone(),
                    });
                }
                Some(fan_out) => {
                    let entry = declared[from].entry(to).or_insert(0);
                    *entry = (*entry).max(fan_out);
                }
                None => {
                    derived.insert((from, to));
                }
            }
        }
        // Until the module is parsed, a derived fan-out counts as 1.
        let mut targets = declared.clone();
        for &(from, to) in &derived {
            targets[from].entry(to).or_insert(1);
        }
        let joins = join_plans(self, &index)?;

        // Reachability from initial procedures.
        let mut reachable = vec![false; self.procedures.len()];
        let mut frontier: VecDeque<usize> = self
            .procedures
            .iter()
            .enumerate()
            .filter(|(_, p)| p.initial)
            .map(|(i, _)| i)
            .collect();
        if frontier.is_empty() {
            return Err(CompileError::NoInitialProcedure);
        }
        while let Some(p) = frontier.pop_front() {
            if std::mem::replace(&mut reachable[p], true) {
                continue;
            }
            frontier.extend(targets[p].keys().copied());
            frontier.extend(
                joins
                    .iter()
                    .filter(|j| j.openers.contains(&p))
                    .map(|j| j.continuation),
            );
        }
        if let Some(p) = reachable.iter().position(|r| !r) {
            return Err(CompileError::UnreachableProcedure(
                self.procedures[p].name.clone(),
            ));
        }

        check_resources(self, options)?;
        crate::constant::check(&self.constants)?;
        let (items, extra_structs) = item_layouts(self)?;

        let mut built = self.build(&targets, &joins, &items, &extra_structs, options)?;
        let fan_outs = fan_out::targets(&built.module, &built.plan, &declared, &derived)?;
        if fan_outs != targets {
            built = self.build(&fan_outs, &joins, &items, &extra_structs, options)?;
        }
        let Built {
            plan,
            rendered,
            module,
        } = built;
        let workgroup_bytes = workgroup::check(
            &module,
            &plan,
            options.limits.max_compute_workgroup_storage_size,
        )?;
        let (wgsl, module, specialization) = if options.specialize {
            specialize(&rendered.text, &module, options.features)?
        } else {
            (rendered.text, module, Specialization::default())
        };
        Ok(CompiledGraph {
            plan,
            wgsl,
            module,
            workgroup_bytes,
            specialization,
        })
    }
}

/// The kinds of join of `graph`, one per continuation in the order of
/// their first declaration, with the procedures that open them.
fn join_plans(graph: &Graph, index: &HashMap<&str, usize>) -> Result<Vec<JoinPlan>, CompileError> {
    let mut plans: Vec<JoinPlan> = Vec::new();
    for join in &graph.joins {
        let lookup = |name: &str| {
            index
                .get(name)
                .copied()
                .ok_or_else(|| CompileError::UnknownJoinProcedure {
                    parent: join.parent.clone(),
                    continuation: join.continuation.clone(),
                    unknown: name.to_owned(),
                })
        };
        let (parent, continuation) = (lookup(&join.parent)?, lookup(&join.continuation)?);
        match plans.iter_mut().find(|p| p.continuation == continuation) {
            Some(plan) if !plan.openers.contains(&parent) => plan.openers.push(parent),
            Some(_) => {}
            None => plans.push(JoinPlan {
                continuation,
                openers: vec![parent],
            }),
        }
    }
    Ok(plans)
}

/// A generated module, parsed, validated and checked, with its plan.
struct Built {
    plan: Plan,
    rendered: Rendered,
    module: naga::Module,
}

impl Graph {
    /// Plans the queues for `targets` (per procedure: target and fan-out),
    /// generates the module, and parses, validates and checks it.
    fn build(
        &self,
        targets: &[BTreeMap<usize, u32>],
        joins: &[JoinPlan],
        items: &BTreeMap<String, (String, ItemLayout)>,
        extra_structs: &[ExtraStructs],
        options: &CompileOptions,
    ) -> Result<Built, CompileError> {
        // Any item may be the last to finish under a join of any kind, and
        // fire it (and the join it opened): every procedure stages
        // continuations.
        let mut targets = targets.to_vec();
        for join in joins {
            for procedure_targets in &mut targets {
                *procedure_targets.entry(join.continuation).or_insert(0) +=
                    crate::plan::joins::FIRES_PER_ITEM;
            }
        }
        let (queues, stage_words) = build::queue_plans(
            &self.procedures,
            &targets,
            items,
            options.workgroup_size,
            options.chunks_per_batch,
            !joins.is_empty(),
        );
        let scratch_words = build::shared_scratch_words(&queues);
        let scan_order = Plan::compute_scan_order(&queues, options.policy);
        let plan = Plan {
            graph_name: self.name.clone(),
            workgroup_size: options.workgroup_size,
            chunks_per_batch: options.chunks_per_batch,
            policy: options.policy,
            queues,
            scan_order,
            stage_words,
            scratch_words,
            resources: self.resources.clone(),
            item_helpers: crate::codegen::helpers::used(&self.procedures, &self.library),
            features: options.features,
            checked: options.checked,
            trace: options.trace,
            joins: joins.to_vec(),
        };
        let mut kernel = generate(&plan, &self.procedures, &self.library, items, extra_structs);
        kernel
            .constants
            .extend(graph_constants::declarations(&self.constants));
        let rendered = kernel.render();
        let (module, _info) = diagnostics::parse_and_validate(&rendered, options.features)?;
        let generated = generated_names(&kernel);
        checks::reserved_names(&module, &generated)?;
        checks::scheduler_state_private(&module, &rendered, &generated)?;
        checks::enqueue_call_graph(&module, &plan)?;
        checks::resource_layouts(&module, &plan.resources)?;
        Ok(Built {
            plan,
            rendered,
            module,
        })
    }
}

/// The module `text` (parsed as `module`, already validated and checked)
/// specialized by [`prune::prune`], parsed and validated again. Errors there
/// are the scheduler's own: the user's sources were checked before.
fn specialize(
    text: &str,
    module: &naga::Module,
    features: wgpu::Features,
) -> Result<(String, naga::Module, Specialization), CompileError> {
    let internal = |message: String| CompileError::Wgsl {
        origin: SourceOrigin::Generated,
        line: 0,
        column: 0,
        message: format!("specializing the module: {message}"),
    };
    let pruned = prune::prune(text, module).map_err(|e| internal(e.emit_to_string(text)))?;
    let rendered = Rendered {
        text: pruned.text,
        regions: Vec::new(),
    };
    let (module, _info) = diagnostics::parse_and_validate(&rendered, features)
        .map_err(|e| internal(e.to_string()))?;
    let specialization = Specialization {
        folded_branches: pruned.folded_branches,
        dropped_functions: pruned.dropped_functions,
    };
    Ok((rendered.text, module, specialization))
}

/// Names the generator declared: functions, constants, globals and those of the
/// runtime template.
fn generated_names(kernel: &KernelModule) -> BTreeSet<String> {
    let mut names: BTreeSet<String> = kernel.functions.iter().map(|f| f.name.clone()).collect();
    names.extend(kernel.constants.iter().map(|c| c.name.clone()));
    names.extend(kernel.globals.iter().map(|g| g.name.clone()));
    for verbatim in kernel.runtime.iter().chain(&kernel.helpers) {
        for line in verbatim.text.lines() {
            if let Some(rest) = line.strip_prefix("fn ") {
                names.insert(rest.split('(').next().unwrap_or_default().to_owned());
            } else if let Some(rest) = line.strip_prefix("const ") {
                names.insert(rest.split(':').next().unwrap_or_default().to_owned());
            }
        }
    }
    names
}

fn check_resources(graph: &Graph, options: &CompileOptions) -> Result<(), CompileError> {
    let mut seen = BTreeSet::new();
    for r in &graph.resources {
        if !is_identifier(r.name()) {
            return Err(CompileError::Resource(format!(
                "`{}` is not a WGSL identifier",
                r.name()
            )));
        }
        if !seen.insert(r.name()) {
            return Err(CompileError::Resource(format!(
                "duplicate resource `{}`",
                r.name()
            )));
        }
    }
    // Per pipeline: every kernel's stage binds its group-0 buffers, and the
    // procedure kernels the graph's resources too.
    let limits = &options.limits;
    for kernels in Kernels::ALL {
        let own = bindings::scheduler_buffers(kernels);
        let count = bindings::buffers(kernels, &graph.resources);
        if count.storage > limits.max_storage_buffers_per_shader_stage {
            return Err(CompileError::Resource(format!(
                "{} storage buffers ({} for the scheduler) exceed the limit of {}",
                count.storage, own.storage, limits.max_storage_buffers_per_shader_stage
            )));
        }
        if count.uniform > limits.max_uniform_buffers_per_shader_stage {
            return Err(CompileError::Resource(format!(
                "{} uniform buffers ({} for the scheduler) exceed the limit of {}",
                count.uniform, own.uniform, limits.max_uniform_buffers_per_shader_stage
            )));
        }
    }
    Ok(())
}

/// Item layouts by WGSL name, and the struct declarations that typed scratch
/// and typed resources add.
type Layouts = (BTreeMap<String, (String, ItemLayout)>, Vec<ExtraStructs>);

/// Parses every distinct item declaration and checks its layout. Returns a
/// sorted map so the generated module does not depend on declaration order of
/// equal item types. Then adds the structs of typed scratch that no item type
/// declares, in procedure order, and those of typed resources, in
/// declaration order.
fn item_layouts(graph: &Graph) -> Result<Layouts, CompileError> {
    let mut sources: BTreeMap<String, &crate::ItemType> = BTreeMap::new();
    for p in &graph.procedures {
        let item = &p.item;
        if let Some(existing) = sources.get(&item.wgsl_name) {
            if existing.wgsl_source != item.wgsl_source || existing.rust_size != item.rust_size {
                return Err(CompileError::ItemLayoutMismatch {
                    item: item.wgsl_name.clone(),
                    rust: item.rust_name.to_owned(),
                    detail: "two procedures declare different item types with this WGSL name"
                        .into(),
                });
            }
            continue;
        }
        sources.insert(item.wgsl_name.clone(), item);
    }
    let mut layouts = BTreeMap::new();
    let mut declared = crate::item::Declared::default();
    for (name, item) in sources {
        let rendered = Rendered {
            text: item.wgsl_source.clone(),
            regions: vec![crate::codegen::module::Region {
                first_line: 1,
                last_line: u32::MAX,
                indent: 0,
                origin: SourceOrigin::Item(name.clone()),
            }],
        };
        let (module, _) = diagnostics::parse_and_validate(&rendered, wgpu::Features::all())?;
        let mut layouter = naga::proc::Layouter::default();
        layouter
            .update(module.to_ctx())
            .map_err(|e| CompileError::ItemLayoutMismatch {
                item: name.clone(),
                rust: item.rust_name.to_owned(),
                detail: e.to_string(),
            })?;
        let layout = layout::analyze(item, &module, &layouter)?;
        layouts.insert(name, (declared.fresh(item)?, layout));
    }
    let mut extra = Vec::new();
    for p in &graph.procedures {
        let Some(ty) = &p.scratch_type else { continue };
        let text =
            declared
                .fresh_structs(&ty.structs)
                .map_err(|name| CompileError::ItemLayoutMismatch {
                    item: name.clone(),
                    rust: ty.wgsl_type.clone(),
                    detail: format!(
                        "the scratch type of `{}` declares a WGSL struct `{name}` that an item type declares differently",
                        p.name
                    ),
                })?;
        if !text.is_empty() {
            extra.push(ExtraStructs {
                title: format!("scratch type of {}", p.name),
                origin: p.name.clone(),
                text,
            });
        }
    }
    for r in &graph.resources {
        let text = declared
            .fresh_structs(&r.structs)
            .map_err(|name| CompileError::ItemLayoutMismatch {
                item: name.clone(),
                rust: r.wgsl_type.clone(),
                detail: format!(
                    "the type of resource `{}` declares a WGSL struct `{name}` that an item or scratch type declares differently",
                    r.name
                ),
            })?;
        if !text.is_empty() {
            extra.push(ExtraStructs {
                title: format!("types of resource {}", r.name),
                origin: r.name.clone(),
                text,
            });
        }
    }
    Ok((layouts, extra))
}
