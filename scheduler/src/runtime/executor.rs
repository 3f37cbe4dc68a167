//! Runs a compiled graph on a wgpu device: buffers, pipeline, seeding,
//! dispatching until no work is left, and reading the counters back.

use std::time::{Duration, Instant};

use crate::compile::plan::{Plan, control};
use crate::readback::map_read;
use crate::runtime::config::{
    CPU_ITERATION_BUDGET, CPU_SPIN_LIMIT, DEFAULT_WORKGROUPS, ExecutorConfig,
};
use crate::{Access, CompiledGraph, ProcedureStats, Resource, RunError, RunReport, Seeds};

/// A user resource bound for a run, by its declared name.
#[derive(Clone, Debug)]
pub struct Binding<'a> {
    /// The name given in [`Resource`].
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

/// Timestamp queries around each dispatch, when the device has them.
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
    device: wgpu::Device,
    queue: wgpu::Queue,
    plan: Plan,
    pipeline: wgpu::ComputePipeline,
    resource_layout: Option<wgpu::BindGroupLayout>,
    scheduler_bind_group: wgpu::BindGroup,
    queue_words: wgpu::Buffer,
    control: wgpu::Buffer,
    control_readback: wgpu::Buffer,
    timestamps: Option<Timestamps>,
    capacities: Vec<u32>,
    workgroups: u32,
    iteration_budget: u32,
    timeout: Duration,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl Executor {
    /// Creates the pipeline and allocates the queues for `config`.
    ///
    /// Fails with [`RunError::TooLarge`] when a buffer would exceed the
    /// device's limits and [`RunError::Gpu`] when the device rejects the module.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        compiled: &CompiledGraph,
        config: &ExecutorConfig,
    ) -> Result<Self, RunError> {
        let plan = compiled.plan.clone();
        let missing = plan.features - device.features();
        if !missing.is_empty() {
            return Err(RunError::Gpu(format!(
                "the device lacks features the graph was compiled for: {missing:?}"
            )));
        }
        let workgroups = config.workgroups.unwrap_or(DEFAULT_WORKGROUPS).max(1);
        let limits = device.limits();
        if workgroups > limits.max_compute_workgroups_per_dimension {
            return Err(RunError::TooLarge {
                what: "workgroup count",
                needed: u64::from(workgroups),
                limit: u64::from(limits.max_compute_workgroups_per_dimension),
            });
        }
        let capacities: Vec<u32> = plan
            .queues
            .iter()
            .map(|q| config.capacities.of(&q.name))
            .collect();
        let cpu = device.adapter_info().device_type == wgpu::DeviceType::Cpu;
        let iteration_budget = match config.iteration_budget {
            Some(budget) => budget.max(1),
            None if cpu => CPU_ITERATION_BUDGET,
            None => u32::MAX,
        };
        let spin_limit = if cpu { CPU_SPIN_LIMIT } else { u32::MAX };
        let memory = compiled.memory_plan(config);
        let binding_limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        for (what, bytes) in [
            ("queue buffer", memory.queue_bytes),
            ("staging buffer", memory.staging_bytes),
        ] {
            if bytes > binding_limit {
                return Err(RunError::TooLarge {
                    what,
                    needed: bytes,
                    limit: binding_limit,
                });
            }
        }

        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        // SAFETY-free: `create_shader_module_trusted` is unsafe only because it
        // can switch checks off. We keep bounds checks on and switch off only
        // naga's loop bounding: the persistent loop is bounded by its iteration
        // budget and every spin-wait ends (docs/scheduler.md, "Progress").
        #[allow(
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
        let scheduler_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scheduler state"),
            entries: &[
                storage_entry(0, false),
                storage_entry(1, false),
                storage_entry(2, false),
                uniform_entry(3),
            ],
        });
        let resource_layout = (!plan.resources.is_empty()).then(|| {
            let entries: Vec<_> = plan
                .resources
                .iter()
                .enumerate()
                .map(|(i, r)| match r {
                    Resource::Storage { access, .. } => {
                        storage_entry(i as u32, *access == Access::Read)
                    }
                    Resource::Uniform { .. } => uniform_entry(i as u32),
                })
                .collect();
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("graph resources"),
                entries: &entries,
            })
        });
        let layouts = [Some(&scheduler_layout), resource_layout.as_ref()];
        let layout_count = if resource_layout.is_some() { 2 } else { 1 };
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("megakernel"),
            bind_group_layouts: &layouts[..layout_count],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("megakernel"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(compiled.entry_point()),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(RunError::Gpu(error.to_string()));
        }

        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        let queue_words = buffer(
            "scheduler queues",
            memory.queue_bytes,
            U::STORAGE | U::COPY_DST,
        );
        let staging = buffer("scheduler staging", memory.staging_bytes, U::STORAGE);
        let control_bytes = memory.control_bytes / 2;
        let control = buffer(
            "scheduler control",
            control_bytes,
            U::STORAGE | U::COPY_DST | U::COPY_SRC,
        );
        let control_readback = buffer(
            "scheduler control read-back",
            control_bytes,
            U::MAP_READ | U::COPY_DST,
        );
        let config_buffer = buffer(
            "scheduler config",
            memory.config_bytes,
            U::UNIFORM | U::COPY_DST,
        );

        // Config: per queue (capacity - 1, first slot word, 0, 0), then
        // (iteration budget, spin limit, 0, 0).
        let mut words = Vec::with_capacity(4 * (plan.queues.len() + 1));
        let mut next = 0u32;
        for (q, queue_plan) in plan.queues.iter().enumerate() {
            let slots = next;
            next = slots + capacities[q] * queue_plan.item_words;
            words.extend_from_slice(&[capacities[q] - 1, slots, 0, 0]);
        }
        words.extend_from_slice(&[iteration_budget, spin_limit, 0, 0]);
        queue.write_buffer(&config_buffer, 0, bytemuck::cast_slice(&words));

        let scheduler_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scheduler state"),
            layout: &scheduler_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: queue_words.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: control.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: staging.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: config_buffer.as_entire_binding(),
                },
            ],
        });

        let timestamps = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| Timestamps {
                queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("megakernel timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolve: buffer("timestamp resolve", 16, U::QUERY_RESOLVE | U::COPY_SRC),
                readback: buffer("timestamp read-back", 16, U::MAP_READ | U::COPY_DST),
                period_ns: f64::from(queue.get_timestamp_period()),
            });

        Ok(Self {
            device: device.clone(),
            queue: queue.clone(),
            plan,
            pipeline,
            resource_layout,
            scheduler_bind_group,
            queue_words,
            control,
            control_readback,
            timestamps,
            capacities,
            workgroups,
            iteration_budget,
            timeout: config.timeout,
        })
    }

    /// Workgroups launched per dispatch.
    pub fn workgroups(&self) -> u32 {
        self.workgroups
    }

    /// Iterations after which a workgroup leaves (`u32::MAX`: no budget).
    pub fn iteration_budget(&self) -> u32 {
        self.iteration_budget
    }

    /// Allocated capacity of each queue, in declaration order.
    pub fn capacities(&self) -> &[u32] {
        &self.capacities
    }

    /// Runs the graph from `seeds` until no work is left.
    ///
    /// `bindings` must name every declared resource. Returns the report, or an
    /// error that carries it (overflow) or explains why there is none.
    pub fn run(&mut self, seeds: &Seeds, bindings: &[Binding<'_>]) -> Result<RunReport, RunError> {
        let resource_group = self.resource_bind_group(bindings)?;
        let seeded = self.seed(seeds)?;

        let start = Instant::now();
        let deadline = start + self.timeout;
        let mut gpu_time = self.timestamps.as_ref().map(|_| Duration::ZERO);
        let mut dispatches = 0;
        let counters = loop {
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("megakernel"),
                });
            {
                let timestamp_writes =
                    self.timestamps
                        .as_ref()
                        .map(|t| wgpu::ComputePassTimestampWrites {
                            query_set: &t.queries,
                            beginning_of_pass_write_index: Some(0),
                            end_of_pass_write_index: Some(1),
                        });
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("megakernel"),
                    timestamp_writes,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.scheduler_bind_group, &[]);
                if let Some(group) = &resource_group {
                    pass.set_bind_group(1, group, &[]);
                }
                pass.dispatch_workgroups(self.workgroups, 1, 1);
            }
            encoder.copy_buffer_to_buffer(
                &self.control,
                0,
                &self.control_readback,
                0,
                self.control.size(),
            );
            if let Some(t) = &self.timestamps {
                encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
                encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, 16);
            }
            let submission = self.queue.submit([encoder.finish()]);
            dispatches += 1;
            let remaining = deadline.saturating_duration_since(Instant::now());
            let bytes = map_read(
                &self.device,
                &self.control_readback,
                submission.clone(),
                remaining,
            )?;
            let counters: Vec<u32> = bytemuck::cast_slice(&bytes).to_vec();
            if let (Some(t), Some(total)) = (&self.timestamps, gpu_time.as_mut()) {
                let stamps = map_read(&self.device, &t.readback, submission, remaining)?;
                let stamps: &[u64] = bytemuck::cast_slice(&stamps);
                let ticks = stamps[1].saturating_sub(stamps[0]) as f64;
                *total += Duration::from_nanos((ticks * t.period_ns) as u64);
            }
            if counters[control::LOOPS_CUT as usize] > 0 {
                return Err(RunError::LoopLimit {
                    waits: counters[control::LOOPS_CUT as usize],
                });
            }
            if counters[control::PENDING as usize] == 0 {
                break counters;
            }
            // Work remains: the workgroups spent their iteration budget, or a
            // driver ended the persistent loop early (llvmpipe stops any loop
            // after 65535 iterations; that happens between batches, so nothing
            // is lost). The queues persist, so dispatch again.
            if Instant::now() >= deadline {
                return Err(RunError::Timeout(self.timeout));
            }
        };
        let report = RunReport {
            procedures: self
                .plan
                .queues
                .iter()
                .enumerate()
                .map(|(q, queue)| {
                    let word = |field| u64::from(counters[control::index(q, field)]);
                    ProcedureStats {
                        name: queue.name.clone(),
                        capacity: self.capacities[q],
                        seeded: seeded[q],
                        executed: word(control::EXECUTED),
                        enqueued: word(control::ENQUEUED),
                        high_water: word(control::HIGH_WATER),
                        dropped: word(control::DROPPED),
                        needed_at_least: word(control::NEEDED),
                        fan_out_overflow: word(control::FANOUT_OVERFLOW),
                    }
                })
                .collect(),
            workgroups: self.workgroups,
            dispatches,
            wall_time: start.elapsed(),
            gpu_time,
        };
        if let Some(p) = report.procedures.iter().find(|p| p.dropped > 0) {
            return Err(RunError::QueueOverflow {
                procedure: p.name.clone(),
                capacity: p.capacity,
                dropped: p.dropped,
                needed_at_least: p.needed_at_least.max(u64::from(p.capacity) + 1),
                report: Box::new(report),
            });
        }
        if let Some(p) = report.procedures.iter().find(|p| p.fan_out_overflow > 0) {
            return Err(RunError::FanOutExceeded {
                procedure: p.name.clone(),
                excess: p.fan_out_overflow,
                report: Box::new(report),
            });
        }
        Ok(report)
    }

    fn resource_bind_group(
        &self,
        bindings: &[Binding<'_>],
    ) -> Result<Option<wgpu::BindGroup>, RunError> {
        for b in bindings {
            if !self.plan.resources.iter().any(|r| r.name() == b.name) {
                return Err(RunError::Binding(format!(
                    "`{}` is not a declared resource",
                    b.name
                )));
            }
        }
        let Some(layout) = &self.resource_layout else {
            return Ok(None);
        };
        let mut entries = Vec::with_capacity(self.plan.resources.len());
        for (i, resource) in self.plan.resources.iter().enumerate() {
            let binding = bindings
                .iter()
                .find(|b| b.name == resource.name())
                .ok_or_else(|| {
                    RunError::Binding(format!("resource `{}` is not bound", resource.name()))
                })?;
            entries.push(wgpu::BindGroupEntry {
                binding: i as u32,
                resource: binding.resource.clone(),
            });
        }
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("graph resources"),
            layout,
            entries: &entries,
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(RunError::Binding(error.to_string()));
        }
        Ok(Some(group))
    }

    /// Empties every queue, then writes the seeds and the matching counters.
    /// Returns the number of items seeded per queue.
    fn seed(&self, seeds: &Seeds) -> Result<Vec<u64>, RunError> {
        let n = self.plan.queues.len();
        let mut per_queue: Vec<Vec<u8>> = vec![Vec::new(); n];
        let mut counts = vec![0u64; n];
        for entry in &seeds.entries {
            let fail = |reason: String| RunError::Seed {
                procedure: entry.procedure.clone(),
                reason,
            };
            let q = self
                .plan
                .queue_index(&entry.procedure)
                .ok_or_else(|| fail("no such procedure".into()))?;
            let queue = &self.plan.queues[q];
            if !queue.initial {
                return Err(fail(
                    "it does not accept initial items (declare it with `.initial(true)`)".into(),
                ));
            }
            if entry.item_size != 4 * queue.item_words as usize {
                return Err(fail(format!(
                    "items are {} bytes but `{}` is {} bytes",
                    entry.item_size,
                    queue.item,
                    4 * queue.item_words
                )));
            }
            per_queue[q].extend_from_slice(&entry.bytes);
            counts[q] += entry.count as u64;
        }
        for (q, &count) in counts.iter().enumerate() {
            if count > u64::from(self.capacities[q]) {
                return Err(RunError::Seed {
                    procedure: self.plan.queues[q].name.clone(),
                    reason: format!(
                        "{count} seeds exceed the queue capacity {}",
                        self.capacities[q]
                    ),
                });
            }
        }

        // Stale payload in the queues is harmless: only tickets below
        // `published` are ever read, so the queues need no clearing.
        let mut control_words = vec![0u32; control::words(n) as usize];
        let mut slot_base = 0u64;
        for (q, queue) in self.plan.queues.iter().enumerate() {
            if counts[q] > 0 {
                self.queue
                    .write_buffer(&self.queue_words, 4 * slot_base, &per_queue[q]);
            }
            // Seeds hold tickets 0..count, published and unclaimed.
            let count = counts[q] as u32;
            for field in [
                control::TAIL,
                control::PUBLISHED,
                control::FILL,
                control::HIGH_WATER,
            ] {
                control_words[control::index(q, field)] = count;
            }
            slot_base += u64::from(self.capacities[q]) * u64::from(queue.item_words);
        }
        control_words[control::PENDING as usize] = counts.iter().sum::<u64>() as u32;
        self.queue
            .write_buffer(&self.control, 0, bytemuck::cast_slice(&control_words));
        Ok(counts)
    }
}
