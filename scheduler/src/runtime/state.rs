//! The device buffers of one executor configuration (queues, control words,
//! staging, configuration, indirect dispatch sizes), their bind groups, and
//! seeding them for a run. Rebuilt when a retry grows the queues.

use crate::codegen::bindings::{Kernels, SCHEDULER_BINDINGS, SchedulerBuffer};
use crate::codegen::uniform::{self, QueueConfig, RunConfig};
use crate::plan::{Plan, control};
use crate::{CompiledGraph, ExecutorConfig, RunError, Seeds};

/// Bind group layouts shared by every [`QueueState`] of an executor.
#[derive(Debug)]
pub(crate) struct Layouts {
    /// Group 0 of [`Kernels::Procedures`].
    pub scheduler: wgpu::BindGroupLayout,
    /// Group 0 of [`Kernels::Prepare`].
    pub prepare: wgpu::BindGroupLayout,
}

impl Layouts {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            scheduler: group_layout(device, Kernels::Procedures, "scheduler state"),
            prepare: group_layout(device, Kernels::Prepare, "scheduler round preparation"),
        }
    }
}

/// The group-0 layout of `kernels`, from the binding table.
fn group_layout(device: &wgpu::Device, kernels: Kernels, label: &str) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = SCHEDULER_BINDINGS
        .iter()
        .filter(|b| b.bound_to(kernels))
        .map(|b| b.kind.layout_entry(b.binding()))
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// Numbers written into the configuration uniform besides the capacities.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tuning {
    /// Persistent workgroups per megakernel dispatch.
    pub workgroups: u32,
    /// Most workgroups per round dispatch.
    pub round_workgroups: u32,
    pub iteration_budget: u32,
    pub spin_limit: u32,
    /// Records of the join pool.
    pub join_pool: u32,
}

/// The buffers for one set of queue capacities.
#[derive(Debug)]
pub(crate) struct QueueState {
    pub capacities: Vec<u32>,
    /// Records of the join pool.
    pub join_pool: u32,
    /// Where each queue's slots and markers start, as the uniform holds it.
    queue_configs: Vec<QueueConfig>,
    queue_words: wgpu::Buffer,
    pub control: wgpu::Buffer,
    pub control_readback: wgpu::Buffer,
    pub dispatch: wgpu::Buffer,
    pub scheduler_group: wgpu::BindGroup,
    pub prepare_group: wgpu::BindGroup,
}

impl QueueState {
    /// Allocates the buffers for `capacities` (allocated sizes, powers of
    /// two), failing with [`RunError::TooLarge`] beyond the device's limits.
    pub(crate) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        compiled: &CompiledGraph,
        layouts: &Layouts,
        capacities: Vec<u32>,
        tuning: Tuning,
    ) -> Result<Self, RunError> {
        let plan = &compiled.plan;
        let config = ExecutorConfig {
            capacities: crate::Capacities {
                default: 1,
                join_pool: tuning.join_pool,
                per_procedure: plan
                    .queues
                    .iter()
                    .zip(&capacities)
                    .map(|(q, &c)| (q.name.clone(), c))
                    .collect(),
            },
            workgroups: Some(tuning.workgroups),
            round_workgroups: Some(tuning.round_workgroups),
            ..ExecutorConfig::default()
        };
        let memory = compiled.memory_plan(&config);
        let limits = device.limits();
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
        let header_bytes = 4 * u64::from(plan.control_words());
        // A traced module's records follow the markers, then the join pool
        // (counted in the memory plan).
        let control_bytes =
            memory.control_bytes - header_bytes + crate::runtime::trace_run::bytes(plan);
        if control_bytes > binding_limit {
            return Err(RunError::TooLarge {
                what: "control buffer",
                needed: control_bytes,
                limit: binding_limit,
            });
        }
        let control = buffer(
            "scheduler control",
            control_bytes,
            U::STORAGE | U::COPY_DST | U::COPY_SRC,
        );
        // Only the counters come back to the host, not the markers.
        let control_readback = buffer(
            "scheduler control read-back",
            header_bytes,
            U::MAP_READ | U::COPY_DST,
        );
        let config_buffer = buffer(
            "scheduler config",
            memory.config_bytes,
            U::UNIFORM | U::COPY_DST,
        );
        let dispatch = buffer(
            "scheduler round dispatch sizes",
            12 * plan.queues.len() as u64,
            U::STORAGE | U::INDIRECT,
        );

        // Slots and then markers (two per slot) are laid out queue after queue.
        let mut first_slot_word = 0u32;
        let mut first_marker_word = plan.control_words();
        let queue_configs: Vec<QueueConfig> = plan
            .queues
            .iter()
            .zip(&capacities)
            .map(|(queue_plan, &capacity)| {
                let config = QueueConfig {
                    capacity,
                    first_slot_word,
                    first_marker_word,
                };
                first_slot_word += capacity * queue_plan.slot_words;
                first_marker_word += 2 * capacity;
                config
            })
            .collect();
        // The round clamp is the staging room, which `Executor::new` keeps
        // within the device's workgroups-per-dimension limit.
        let run = RunConfig {
            iteration_budget: tuning.iteration_budget,
            spin_limit: tuning.spin_limit,
            round_workgroups: tuning.round_workgroups,
        };
        let words = uniform::words(&queue_configs, &run);
        queue.write_buffer(&config_buffer, 0, bytemuck::cast_slice(&words));

        let buffer_of = |which: SchedulerBuffer| match which {
            SchedulerBuffer::QueueWords => &queue_words,
            SchedulerBuffer::Control => &control,
            SchedulerBuffer::Staging => &staging,
            SchedulerBuffer::Config => &config_buffer,
            SchedulerBuffer::Dispatch => &dispatch,
        };
        let group = |kernels: Kernels, layout: &wgpu::BindGroupLayout, label: &str| {
            let entries: Vec<_> = SCHEDULER_BINDINGS
                .iter()
                .filter(|b| b.bound_to(kernels))
                .map(|b| wgpu::BindGroupEntry {
                    binding: b.binding(),
                    resource: buffer_of(b.buffer).as_entire_binding(),
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries: &entries,
            })
        };
        let scheduler_group = group(Kernels::Procedures, &layouts.scheduler, "scheduler state");
        let prepare_group = group(
            Kernels::Prepare,
            &layouts.prepare,
            "scheduler round preparation",
        );
        Ok(Self {
            capacities,
            join_pool: tuning.join_pool,
            queue_configs,
            queue_words,
            control,
            control_readback,
            dispatch,
            scheduler_group,
            prepare_group,
        })
    }

    /// Empties every queue, then writes the seeds and the matching counters.
    /// Returns the number of items seeded per queue.
    pub(crate) fn seed(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        plan: &Plan,
        seeds: &Seeds,
    ) -> Result<Vec<u64>, RunError> {
        let n = plan.queues.len();
        let mut per_queue: Vec<Vec<u8>> = vec![Vec::new(); n];
        let mut counts = vec![0u64; n];
        for entry in &seeds.entries {
            let fail = |reason: String| RunError::Seed {
                procedure: entry.procedure.clone(),
                reason,
            };
            let q = plan
                .queue_index(&entry.procedure)
                .ok_or_else(|| fail("no such procedure".into()))?;
            let queue_plan = &plan.queues[q];
            if !queue_plan.initial {
                return Err(fail(
                    "it does not accept initial items (declare it with `.initial(true)`)".into(),
                ));
            }
            if entry.item_size != 4 * queue_plan.item_words as usize {
                return Err(fail(format!(
                    "items are {} bytes but `{}` is {} bytes",
                    entry.item_size,
                    queue_plan.item,
                    4 * queue_plan.item_words
                )));
            }
            // Each item goes into a whole slot; the padding words stay zero.
            let slot_bytes = 4 * queue_plan.slot_words as usize;
            let slots = &mut per_queue[q];
            for item in entry.bytes.chunks_exact(entry.item_size) {
                slots.extend_from_slice(item);
                slots.resize(slots.len() + slot_bytes - item.len(), 0);
            }
            counts[q] += entry.count as u64;
        }
        for (q, &count) in counts.iter().enumerate() {
            if count > u64::from(self.capacities[q]) {
                return Err(RunError::TooManySeeds {
                    procedure: plan.queues[q].name.clone(),
                    seeds: count,
                    capacity: self.capacities[q],
                });
            }
        }

        // Stale payload in the queues is harmless: only tickets below
        // `published` are ever read, so the queues need no clearing.
        let mut control_words = vec![0u32; plan.control_words() as usize];
        for (q, config) in self.queue_configs.iter().enumerate() {
            if counts[q] > 0 {
                let offset = 4 * u64::from(config.first_slot_word);
                queue.write_buffer(&self.queue_words, offset, &per_queue[q]);
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
        }
        control_words[control::PENDING as usize] = counts.iter().sum::<u64>() as u32;
        if !plan.joins.is_empty() {
            let word = crate::plan::joins::first_word(plan) + crate::plan::joins::CAPACITY;
            control_words[word as usize] = self.join_pool;
        }
        queue.write_buffer(&self.control, 0, bytemuck::cast_slice(&control_words));
        // Markers of an earlier run could look like complete ranges: clear them.
        let header = 4 * control_words.len() as u64;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("clear range markers"),
        });
        encoder.clear_buffer(&self.control, header, None);
        queue.submit([encoder.finish()]);
        Ok(counts)
    }
}
