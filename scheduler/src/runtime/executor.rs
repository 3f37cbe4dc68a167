//! Runs a compiled graph on a wgpu device: pipelines, dispatching under either
//! strategy until no work is left, opt-in retry on overflow, and the report.

use std::time::{Duration, Instant};

use crate::codegen::bindings::{RESOURCE_GROUP, SCHEDULER_GROUP, resource_bindings, resource_kind};
use crate::plan::control;
use crate::runtime::config::ExecutorConfig;
use crate::runtime::pipeline_cache::{self, CompileTimings, DiskCache, PipelineCacheState};
use crate::runtime::readback::{LONGEST_WAIT, map_read};
use crate::runtime::resources::OwnedBuffers;
use crate::runtime::rounds::RoundPipelines;
use crate::runtime::state::{Layouts, QueueState, Tuning};
use crate::runtime::{limits, outcome};
use crate::{CompiledGraph, Quirks, RunError, RunReport, Seeds, Strategy};

/// A user resource bound for a run, by its declared name.
#[derive(Clone, Debug)]
pub struct Binding<'a> {
    /// The name given in [`Resource`](crate::Resource).
    pub name: &'a str,
    /// The buffer (or buffer range) to bind.
    pub resource: wgpu::BindingResource<'a>,
}

impl<'a> Binding<'a> {
    /// Binds a whole buffer to the resource `name`.
    pub fn buffer(name: &'a str, buffer: &'a wgpu::Buffer) -> Self {
        Self {
            name,
            resource: buffer.as_entire_binding(),
        }
    }
}

/// Timestamp queries around each submission, when the device has them.
#[derive(Debug)]
struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
}

/// The GPU objects for one compiled graph and one configuration. Runs reuse
/// them; each run starts from empty queues.
#[derive(Debug)]
pub struct Executor {
    pub(super) device: wgpu::Device,
    pub(super) queue: wgpu::Queue,
    pub(super) compiled: CompiledGraph,
    pub(super) module: wgpu::ShaderModule,
    pub(super) layouts: Layouts,
    pub(super) resource_layout: Option<wgpu::BindGroupLayout>,
    /// Buffers created for typed resources.
    pub(super) owned: OwnedBuffers,
    pub(super) megakernel: wgpu::ComputePipeline,
    pub(super) rounds: Option<RoundPipelines>,
    pub(super) state: QueueState,
    timestamps: Option<Timestamps>,
    pub(super) tuning: Tuning,
    /// What the scheduler works around on this adapter.
    pub(super) quirks: Quirks,
    pub(super) timeout: Duration,
    /// The pipeline cache and its file, when one is configured and the
    /// device has the feature.
    pub(super) disk_cache: Option<DiskCache>,
    cache_state: PipelineCacheState,
    compile_timings: CompileTimings,
}

impl Executor {
    /// Creates the megakernel pipeline and allocates the queues for `config`.
    /// The Rounds strategy's pipelines are created on its first run. What
    /// `config` leaves to the adapter (workgroups per strategy, iteration
    /// budget, spin limit) comes from [`Quirks::of_device`].
    ///
    /// Fails with [`RunError::ExceedsDeviceLimit`] when the graph or the
    /// workgroup count exceeds one of the device's limits (the module may
    /// have been compiled for larger ones), [`RunError::TooLarge`] when a
    /// buffer would, and [`RunError::Gpu`] when the device rejects the module.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        compiled: &CompiledGraph,
        config: &ExecutorConfig,
    ) -> Result<Self, RunError> {
        let plan = &compiled.plan;
        let missing = plan.features - device.features();
        if !missing.is_empty() {
            return Err(RunError::Gpu(format!(
                "the device lacks features the graph was compiled for: {missing:?}"
            )));
        }
        let quirks = Quirks::of_device(device);
        let workgroups = config.megakernel_workgroups_on(&quirks);
        let round_workgroups = config.round_workgroups_or_default();
        limits::check_plan(plan, &device.limits(), workgroups.max(round_workgroups))?;
        let capacities: Vec<u32> = plan
            .queues
            .iter()
            .map(|q| config.capacities.of(&q.name))
            .collect();
        let iteration_budget = match config.iteration_budget {
            Some(budget) => budget.max(1),
            None => quirks
                .default_iteration_budget(plan.chunks_per_batch)
                .unwrap_or(u32::MAX),
        };
        let tuning = Tuning {
            workgroups,
            round_workgroups,
            iteration_budget,
            spin_limit: quirks.spin_limit(),
            join_pool: config.capacities.join_pool.max(1),
        };
        let layouts = Layouts::new(device);
        let state = QueueState::new(device, queue, compiled, &layouts, capacities, tuning)?;

        let (cache_state, mut disk_cache) =
            pipeline_cache::open(device, config.pipeline_cache_dir.as_deref(), &compiled.wgsl);
        let creation = Instant::now();
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        // SAFETY-free: `create_shader_module_trusted` is unsafe only because it
        // can switch checks off. We keep bounds checks on and switch off only
        // naga's loop bounding: the persistent loop is bounded by its iteration
        // budget and every spin-wait ends (docs/scheduler.md, "Progress").
        #[expect(
            unsafe_code,
            reason = "keeps bounds checks; only drops loop bounding, see comment above"
        )]
        let module = unsafe {
            device.create_shader_module_trusted(
                wgpu::ShaderModuleDescriptor {
                    label: Some("scheduler megakernel"),
                    source: wgpu::ShaderSource::Wgsl(compiled.wgsl.as_str().into()),
                },
                wgpu::ShaderRuntimeChecks {
                    bounds_checks: true,
                    force_loop_bounding: false,
                    ..wgpu::ShaderRuntimeChecks::checked()
                },
            )
        };
        let resource_layout = (!plan.resources.is_empty()).then(|| {
            let entries: Vec<_> = resource_bindings(&plan.resources)
                .map(|(binding, r)| resource_kind(r).layout_entry(binding))
                .collect();
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("graph resources"),
                entries: &entries,
            })
        });
        let megakernel = procedure_pipeline(
            device,
            &module,
            &layouts,
            resource_layout.as_ref(),
            compiled.entry_point(),
            disk_cache.as_ref().map(|d| &d.cache),
        );
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(RunError::Gpu(error.to_string()));
        }
        let pipeline_creation = creation.elapsed();
        if let Some(disk) = &mut disk_cache {
            disk.save();
        }

        let timestamps = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| Timestamps {
                queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("scheduler timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolve: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp resolve"),
                    size: 16,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                readback: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp read-back"),
                    size: 16,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                period_ns: f64::from(queue.get_timestamp_period()),
            });

        let mut executor = Self {
            device: device.clone(),
            queue: queue.clone(),
            compiled: compiled.clone(),
            module,
            layouts,
            resource_layout,
            owned: OwnedBuffers::default(),
            megakernel,
            rounds: None,
            state,
            timestamps,
            tuning,
            quirks,
            timeout: config.timeout,
            disk_cache,
            cache_state,
            compile_timings: CompileTimings {
                pipeline_creation,
                first_dispatch: None,
            },
        };
        executor.compile_timings.first_dispatch = executor.first_dispatch();
        // Drivers that compile at the first dispatch may add to the cache
        // then.
        if let Some(disk) = &mut executor.disk_cache
            && disk.save()
        {
            log::debug!("pipeline cache: its data changed at the first dispatch");
        }
        log::info!(
            "megakernel `{}`: pipeline {:.2?}, first dispatch {:?}, cache {:?}",
            compiled.plan.graph_name,
            executor.compile_timings.pipeline_creation,
            executor.compile_timings.first_dispatch,
            executor.cache_state
        );
        Ok(executor)
    }

    /// What became of the pipeline cache: off (no directory configured),
    /// unsupported by the device, a hit, a miss, or a rejected file.
    pub fn pipeline_cache(&self) -> &PipelineCacheState {
        &self.cache_state
    }

    /// How long creating the megakernel pipeline and its first dispatch
    /// took (see [`CompileTimings`]).
    pub fn compile_timings(&self) -> CompileTimings {
        self.compile_timings
    }

    /// Workgroups launched per megakernel dispatch.
    pub fn workgroups(&self) -> u32 {
        self.tuning.workgroups
    }

    /// The most workgroups launched per round dispatch (Rounds strategy).
    pub fn round_workgroups(&self) -> u32 {
        self.tuning.round_workgroups
    }

    /// What the scheduler works around on this executor's adapter.
    pub fn quirks(&self) -> &Quirks {
        &self.quirks
    }

    /// The strategy a run with `strategy` uses on this adapter
    /// ([`Strategy::Auto`] resolved, see [`Strategy::resolve`]).
    pub fn resolve(&self, strategy: Strategy) -> Strategy {
        strategy.resolve(&self.quirks)
    }

    /// Iterations after which a workgroup leaves (`u32::MAX`: no budget).
    pub fn iteration_budget(&self) -> u32 {
        self.tuning.iteration_budget
    }

    /// Allocated capacity of each queue, in declaration order.
    pub fn capacities(&self) -> &[u32] {
        &self.state.capacities
    }

    /// Runs the graph from `seeds` with [`Strategy::Auto`] (the megakernel
    /// where persistent workgroups are known to be safe, Rounds elsewhere)
    /// until no work is left.
    ///
    /// `bindings` must name every declared resource. Returns the report, or an
    /// error that carries it (overflow) or explains why there is none.
    pub fn run(&mut self, seeds: &Seeds, bindings: &[Binding<'_>]) -> Result<RunReport, RunError> {
        self.run_with(Strategy::Auto, seeds, bindings)
    }

    /// Runs the graph from `seeds` with the given strategy
    /// ([`Strategy::Auto`] resolved for the adapter).
    pub fn run_with(
        &mut self,
        strategy: Strategy,
        seeds: &Seeds,
        bindings: &[Binding<'_>],
    ) -> Result<RunReport, RunError> {
        let resources = self.resource_bind_group(bindings)?;
        self.attempt(strategy, seeds, resources.as_ref())
    }

    /// One run from the seeds to the end of the work.
    pub(super) fn attempt(
        &mut self,
        strategy: Strategy,
        seeds: &Seeds,
        resources: Option<&wgpu::BindGroup>,
    ) -> Result<RunReport, RunError> {
        let strategy = strategy.resolve(&self.quirks);
        if let Strategy::Rounds { .. } = strategy {
            self.create_round_pipelines()?;
        }
        let seeded = self
            .state
            .seed(&self.device, &self.queue, &self.compiled.plan, seeds)?;

        let start = Instant::now();
        // A timeout too long to add to `start` means no deadline at all.
        let deadline = start.checked_add(self.timeout);
        let mut gpu_time = self.timestamps.as_ref().map(|_| Duration::ZERO);
        let mut submissions = 0u32;
        let mut dispatches = 0u32;
        let mut progress = outcome::ProgressWatch::default();
        let workgroups = match strategy {
            Strategy::Rounds { .. } => self.tuning.round_workgroups,
            Strategy::Megakernel | Strategy::Auto => self.tuning.workgroups,
        };
        let mut gpu_times = Vec::new();
        // What the report is built from; the counts and the times are
        // filled in when it is.
        let facts = |(submissions, dispatches), gpu_time| outcome::RunFacts {
            plan: &self.compiled.plan,
            strategy,
            capacities: &self.state.capacities,
            seeded: &seeded,
            workgroups,
            submissions,
            dispatches,
            wall_time: start.elapsed(),
            gpu_time,
        };
        // The control words of the last submission read back, for the
        // partial report of a run that does not finish.
        let mut last: Option<Vec<u32>> = None;
        let partial = |last: &Option<Vec<u32>>, counts, gpu_time| {
            last.as_ref().map(|counters| {
                (
                    outcome::report(&facts(counts, gpu_time), counters),
                    outcome::Cuts::of(counters),
                )
            })
        };
        let counters = loop {
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("scheduler run"),
                });
            match strategy {
                Strategy::Rounds { rounds_per_batch } => self.encode_rounds(
                    &mut encoder,
                    resources,
                    submissions == 0,
                    rounds_per_batch.max(1),
                    submissions * rounds_per_batch.max(1),
                ),
                Strategy::Megakernel | Strategy::Auto => {
                    self.encode_megakernel(&mut encoder, resources);
                }
            }
            dispatches += outcome::dispatches(&self.compiled.plan, strategy, submissions == 0);
            let control = &self.state.control;
            encoder.copy_buffer_to_buffer(
                control,
                0,
                &self.state.control_readback,
                0,
                self.state.control_readback.size(),
            );
            if let Some(t) = &self.timestamps {
                encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
                encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, 16);
            }
            self.trace_submission(submissions);
            let submission = self.queue.submit([encoder.finish()]);
            let remaining = deadline.map_or(LONGEST_WAIT, |deadline| {
                deadline.saturating_duration_since(Instant::now())
            });
            // A run that does not finish reports the configured limit (not
            // the time that was left) and the counters of the submissions
            // that did.
            let bytes = map_read(
                &self.device,
                &self.state.control_readback,
                submission.clone(),
                remaining,
            )
            .map_err(|error| {
                outcome::interrupted(
                    error,
                    self.timeout,
                    partial(&last, (submissions, dispatches), gpu_time),
                )
            })?;
            submissions += 1;
            let counters: Vec<u32> = bytemuck::cast_slice(&bytes).to_vec();
            if let (Some(t), Some(total)) = (&self.timestamps, gpu_time.as_mut()) {
                // The counters of this submission are in: a failure now
                // still reports them.
                let stamps = map_read(&self.device, &t.readback, submission, remaining).map_err(
                    |error| {
                        outcome::interrupted(
                            error,
                            self.timeout,
                            partial(
                                &Some(counters.clone()),
                                (submissions, dispatches),
                                Some(*total),
                            ),
                        )
                    },
                )?;
                let stamps: &[u64] = bytemuck::cast_slice(&stamps);
                let ticks = stamps[1].saturating_sub(stamps[0]) as f64;
                let took = Duration::from_nanos((ticks * t.period_ns) as u64);
                *total += took;
                gpu_times.push(took);
            }
            // A cut loop ends the run: its counters are still read into the
            // report, and an overflow among them is named first.
            if outcome::Cuts::of(&counters).any() || counters[control::PENDING as usize] == 0 {
                break counters;
            }
            // Every wait is bounded, so a dispatch whose workgroups made no
            // progress ends; a run of them is a typed error, not a hang.
            if let Some(stalled) = progress.after(&self.compiled.plan, &counters) {
                return Err(RunError::NoProgress {
                    submissions: stalled,
                    pending: counters[control::PENDING as usize],
                    report: Box::new(outcome::report(
                        &facts((submissions, dispatches), gpu_time),
                        &counters,
                    )),
                });
            }
            // Work remains: the megakernel's workgroups spent their iteration
            // budget (or a driver ended the persistent loop early, between
            // batches, so nothing is lost), or the batch of rounds ended. The
            // queues persist, so submit again.
            last = Some(counters);
            if deadline.is_some_and(|deadline| Instant::now() >= deadline) {
                return Err(outcome::interrupted(
                    RunError::Timeout {
                        limit: self.timeout,
                        report: None,
                        also: Vec::new(),
                    },
                    self.timeout,
                    partial(&last, (submissions, dispatches), gpu_time),
                ));
            }
        };
        let mut report = outcome::report(&facts((submissions, dispatches), gpu_time), &counters);
        report.trace = self.read_trace(submissions, &gpu_times)?;
        outcome::judge(report, outcome::Cuts::of(&counters), |body_loops| {
            self.loop_limit_advice(strategy, body_loops)
        })
    }

    /// Timestamp writes for a pass that is the first and/or last of a submission.
    pub(super) fn timestamp_writes(
        &self,
        first: bool,
        last: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.timestamps.as_ref().filter(|_| first || last).map(|t| {
            wgpu::ComputePassTimestampWrites {
                query_set: &t.queries,
                beginning_of_pass_write_index: first.then_some(0),
                end_of_pass_write_index: last.then_some(1),
            }
        })
    }

    /// One megakernel dispatch of the persistent workgroups.
    fn encode_megakernel(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        resources: Option<&wgpu::BindGroup>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("megakernel"),
            timestamp_writes: self.timestamp_writes(true, true),
        });
        pass.set_pipeline(&self.megakernel);
        pass.set_bind_group(SCHEDULER_GROUP, &self.state.scheduler_group, &[]);
        if let Some(group) = resources {
            pass.set_bind_group(RESOURCE_GROUP, group, &[]);
        }
        pass.dispatch_workgroups(self.tuning.workgroups, 1, 1);
    }
}

/// A pipeline over the scheduler's group 0 and the graph's resources.
pub(super) fn procedure_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layouts: &Layouts,
    resources: Option<&wgpu::BindGroupLayout>,
    entry_point: &str,
    cache: Option<&wgpu::PipelineCache>,
) -> wgpu::ComputePipeline {
    // In group order: SCHEDULER_GROUP, then RESOURCE_GROUP.
    let groups = [Some(&layouts.scheduler), resources];
    let count = if resources.is_some() { 2 } else { 1 };
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry_point),
        bind_group_layouts: &groups[..count],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry_point),
        layout: Some(&layout),
        module,
        entry_point: Some(entry_point),
        compilation_options: Default::default(),
        cache,
    })
}
