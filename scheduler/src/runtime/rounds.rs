//! The Rounds strategy on the host: its pipelines, created on first use, and
//! the passes of a batch of rounds.

use crate::codegen::bindings::{RESOURCE_GROUP, SCHEDULER_GROUP};
use crate::naming::{PREPARE_ENTRY_POINT, round_entry_point};
use crate::plan::Plan;
use crate::runtime::executor::{Executor, procedure_pipeline};
use crate::{Policy, RunError};

/// The Rounds strategy's pipelines, created on its first use.
#[derive(Debug)]
pub(super) struct RoundPipelines {
    prepare: wgpu::ComputePipeline,
    /// One per procedure, in declaration order.
    procedures: Vec<wgpu::ComputePipeline>,
}

impl Executor {
    /// A batch of rounds: per round, one indirect dispatch per procedure (in
    /// the policy's order), then the prepare kernel that retires the round and
    /// sizes the next. The first batch starts with a prepare of its own.
    /// Prepare kernels run in their own passes: their bind group writes the
    /// indirect arguments that the round dispatches read.
    pub(super) fn encode_rounds(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        resources: Option<&wgpu::BindGroup>,
        first_batch: bool,
        rounds: u32,
        first_round: u32,
    ) {
        let pipelines = self
            .rounds
            .as_ref()
            .expect("round pipelines are created before encoding rounds");
        let prepare = |encoder: &mut wgpu::CommandEncoder, first: bool, last: bool| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("prepare round"),
                timestamp_writes: self.timestamp_writes(first, last),
            });
            pass.set_pipeline(&pipelines.prepare);
            pass.set_bind_group(SCHEDULER_GROUP, &self.state.prepare_group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        };
        if first_batch {
            prepare(encoder, true, false);
        }
        let plan = &self.compiled.plan;
        for r in 0..rounds {
            {
                let first = !first_batch && r == 0;
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("round"),
                    timestamp_writes: self.timestamp_writes(first, false),
                });
                pass.set_bind_group(SCHEDULER_GROUP, &self.state.scheduler_group, &[]);
                if let Some(group) = resources {
                    pass.set_bind_group(RESOURCE_GROUP, group, &[]);
                }
                for q in round_order(plan, first_round + r) {
                    pass.set_pipeline(&pipelines.procedures[q]);
                    pass.dispatch_workgroups_indirect(&self.state.dispatch, 12 * q as u64);
                }
            }
            prepare(encoder, false, r + 1 == rounds);
        }
    }

    pub(super) fn create_round_pipelines(&mut self) -> Result<(), RunError> {
        if self.rounds.is_some() {
            return Ok(());
        }
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let cache = self.disk_cache.as_ref().map(|d| &d.cache);
        let prepare_layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(PREPARE_ENTRY_POINT),
                bind_group_layouts: &[Some(&self.layouts.prepare)],
                immediate_size: 0,
            });
        let prepare = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(PREPARE_ENTRY_POINT),
                layout: Some(&prepare_layout),
                module: &self.module,
                entry_point: Some(PREPARE_ENTRY_POINT),
                compilation_options: Default::default(),
                cache,
            });
        let procedures = self
            .compiled
            .plan
            .queues
            .iter()
            .map(|q| {
                procedure_pipeline(
                    &self.device,
                    &self.module,
                    &self.layouts,
                    self.resource_layout.as_ref(),
                    &round_entry_point(&q.name),
                    cache,
                )
            })
            .collect();
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(RunError::Gpu(error.to_string()));
        }
        // The file then holds the Rounds pipelines too.
        if let Some(disk) = &mut self.disk_cache {
            disk.save();
        }
        self.rounds = Some(RoundPipelines {
            prepare,
            procedures,
        });
        Ok(())
    }
}

/// The order of the per-procedure dispatches in round `round`: the scan order
/// (priority, highest first) or, under round-robin, that order rotated by one
/// each round. Every round runs only the items queued before it started, so
/// the order changes neither the counts nor the high-water marks, only the
/// order in which bodies' writes land.
fn round_order(plan: &Plan, round: u32) -> Vec<usize> {
    let n = plan.scan_order.len();
    let shift = match plan.policy {
        Policy::Priority => 0,
        Policy::RoundRobin => round as usize % n.max(1),
    };
    (0..n).map(|i| plan.scan_order[(i + shift) % n]).collect()
}
