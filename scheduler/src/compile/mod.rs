//! Compiling a [`Graph`] into a [`CompiledGraph`]: graph checks, item layouts,
//! code generation, and naga validation of the result.

pub(crate) mod checks;
pub(crate) mod diagnostics;
pub(crate) mod layout;
pub(crate) mod plan;

use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};

use crate::codegen::generate::{ENTRY_POINT, generate};
use crate::codegen::module::{KernelModule, Rendered};
use crate::{CompileError, CompileOptions, Graph, MAX_CHUNKS_PER_BATCH, SourceOrigin};
use layout::ItemLayout;
use plan::{Plan, QueuePlan};

/// A compiled graph: the WGSL megakernel plus everything the runtime needs.
/// It holds no GPU objects; create an [`Executor`](crate::Executor) to run it.
#[derive(Clone, Debug)]
pub struct CompiledGraph {
    pub(crate) plan: Plan,
    pub(crate) wgsl: String,
    pub(crate) module: naga::Module,
}

impl CompiledGraph {
    /// The generated WGSL (deterministic for a given graph and options).
    pub fn wgsl(&self) -> &str {
        &self.wgsl
    }

    /// The validated naga module.
    pub fn naga_module(&self) -> &naga::Module {
        &self.module
    }

    /// The name of the compute entry point.
    pub fn entry_point(&self) -> &'static str {
        ENTRY_POINT
    }

    /// Per-procedure queue plans, in declaration order.
    pub fn queues(&self) -> &[QueuePlan] {
        &self.plan.queues
    }

    /// The workgroup size compiled for.
    pub fn workgroup_size(&self) -> u32 {
        self.plan.workgroup_size
    }

    /// Features the module was compiled for (the device must have them).
    pub fn features(&self) -> wgpu::Features {
        self.plan.features
    }
}

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

        // Connections, merged per (from, to) keeping the largest fan-out.
        let mut targets: Vec<BTreeMap<usize, u32>> = vec![BTreeMap::new(); self.procedures.len()];
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
            if c.fan_out == 0 {
                return Err(CompileError::ZeroFanOut {
                    from: c.from.clone(),
                    to: c.to.clone(),
                });
            }
            let entry = targets[from].entry(to).or_insert(0);
            *entry = (*entry).max(c.fan_out);
        }

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
        }
        if let Some(p) = reachable.iter().position(|r| !r) {
            return Err(CompileError::UnreachableProcedure(
                self.procedures[p].name.clone(),
            ));
        }

        check_resources(self, options)?;
        let items = item_layouts(self)?;

        // Queue plans: staging capacity of a queue is the most items any single
        // source batch (all its chunks) may stage into it.
        let mut queues: Vec<QueuePlan> = self
            .procedures
            .iter()
            .enumerate()
            .map(|(i, p)| QueuePlan {
                name: p.name.clone(),
                item: p.item.wgsl_name.clone(),
                item_words: items[&p.item.wgsl_name].1.words,
                slot_words: items[&p.item.wgsl_name].1.slot_words,
                threads_per_item: p.threads_per_item,
                items_per_workgroup: workgroup_size / p.threads_per_item,
                items_per_batch: workgroup_size / p.threads_per_item * chunks,
                priority: p.priority,
                initial: p.initial,
                scratch_words: p.scratch_bytes.div_ceil(4),
                stage_offset: 0,
                stage_capacity: 0,
                targets: targets[i].iter().map(|(&t, &f)| (t, f)).collect(),
            })
            .collect();
        for source in 0..queues.len() {
            let batch = queues[source].items_per_batch;
            for (t, fan_out) in queues[source].targets.clone() {
                queues[t].stage_capacity =
                    queues[t].stage_capacity.max(batch.saturating_mul(fan_out));
            }
        }
        let mut stage_words = 0u32;
        for queue in &mut queues {
            queue.stage_offset = stage_words;
            stage_words += queue.stage_capacity * queue.slot_words;
        }

        // One scratch region, sized by the largest procedure.
        let internal = plan::internal_workgroup_bytes(queues.len());
        let (scratch_words, largest) = queues
            .iter()
            .map(|q| (q.scratch_words * q.items_per_workgroup, q))
            .max_by_key(|(words, _)| *words)
            .map(|(words, q)| (words, Some(q)))
            .unwrap_or((0, None));
        let limit = options.limits.max_compute_workgroup_storage_size;
        if let Some(q) = largest {
            let needed = scratch_words.max(1) * 4 + internal;
            if needed > limit {
                return Err(CompileError::ScratchTooLarge {
                    procedure: q.name.clone(),
                    per_item: q.scratch_words * 4,
                    items: q.items_per_workgroup,
                    internal,
                    needed,
                    limit,
                });
            }
        }

        let scan_order = Plan::compute_scan_order(&queues, options.policy);
        let plan = Plan {
            graph_name: self.name.clone(),
            workgroup_size,
            chunks_per_batch: chunks,
            policy: options.policy,
            queues,
            scan_order,
            stage_words,
            scratch_words,
            resources: self.resources.clone(),
            features: options.features,
        };

        let kernel = generate(&plan, &self.procedures, &self.library, &items);
        let rendered = kernel.render();
        let (module, _info) = diagnostics::parse_and_validate(&rendered, options.features)?;
        checks::reserved_names(&module, &generated_names(&kernel))?;
        checks::enqueue_call_graph(&module, &plan)?;
        Ok(CompiledGraph {
            plan,
            wgsl: rendered.text,
            module,
        })
    }
}

/// Names the generator declared: functions, constants, globals and those of the
/// runtime template.
fn generated_names(kernel: &KernelModule) -> BTreeSet<String> {
    let mut names: BTreeSet<String> = kernel.functions.iter().map(|f| f.name.clone()).collect();
    names.extend(kernel.constants.iter().map(|c| c.name.clone()));
    for global in &kernel.globals {
        if let Some(name) = global
            .declaration
            .split_once("> ")
            .and_then(|(_, rest)| rest.split(':').next())
        {
            names.insert(name.trim().to_owned());
        }
    }
    if let Some(runtime) = &kernel.runtime {
        for line in runtime.text.lines() {
            if let Some(rest) = line.strip_prefix("fn ") {
                names.insert(rest.split('(').next().unwrap_or_default().to_owned());
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
    // The scheduler itself uses 3 storage buffers and 1 uniform buffer.
    let storage = 3 + graph
        .resources
        .iter()
        .filter(|r| matches!(r, crate::Resource::Storage { .. }))
        .count() as u32;
    let uniform = 1 + graph
        .resources
        .iter()
        .filter(|r| matches!(r, crate::Resource::Uniform { .. }))
        .count() as u32;
    let limits = &options.limits;
    if storage > limits.max_storage_buffers_per_shader_stage {
        return Err(CompileError::Resource(format!(
            "{storage} storage buffers (3 for the scheduler) exceed the limit of {}",
            limits.max_storage_buffers_per_shader_stage
        )));
    }
    if uniform > limits.max_uniform_buffers_per_shader_stage {
        return Err(CompileError::Resource(format!(
            "{uniform} uniform buffers (1 for the scheduler) exceed the limit of {}",
            limits.max_uniform_buffers_per_shader_stage
        )));
    }
    Ok(())
}

/// Parses every distinct item declaration and checks its layout. Returns a
/// sorted map so the generated module does not depend on declaration order of
/// equal item types.
fn item_layouts(graph: &Graph) -> Result<BTreeMap<String, (String, ItemLayout)>, CompileError> {
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
        layouts.insert(name, (item.wgsl_source.clone(), layout));
    }
    Ok(layouts)
}
