//! The megakernel's first dispatch, in `Executor::new`: drivers that compile
//! a pipeline at its first dispatch (llvmpipe runs LLVM there) compile it
//! at this known point, where it is timed
//! ([`CompileTimings::first_dispatch`](crate::CompileTimings::first_dispatch)),
//! instead of in the first run.

use std::time::{Duration, Instant};

use crate::codegen::bindings::{
    BufferKind, RESOURCE_GROUP, SCHEDULER_GROUP, resource_bindings, resource_kind,
};
use crate::runtime::executor::Executor;

/// Bytes of a placeholder for a resource declared by its WGSL type alone,
/// whose size the host does not know: within the smallest uniform binding
/// limit WebGPU allows.
const PLACEHOLDER_BYTES: u64 = 16 << 10;

impl Executor {
    /// Submits a dispatch of no workgroups of the megakernel and waits for
    /// it: drivers that compile at the first dispatch (llvmpipe) compile
    /// here, where it can be timed, instead of in the first run. The
    /// graph's resources are bound to small placeholder buffers, which no
    /// workgroup reads. `None` when the device refused the dispatch.
    pub(super) fn first_dispatch(&self) -> Option<Duration> {
        let start = Instant::now();
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let placeholders: Vec<(u32, wgpu::Buffer)> =
            resource_bindings(&self.compiled.plan.resources)
                .map(|(binding, resource)| {
                    let bytes = resource.shape().map_or(PLACEHOLDER_BYTES, |s| {
                        s.min_bytes().max(256).next_multiple_of(256)
                    });
                    let usage = match resource_kind(resource) {
                        BufferKind::Uniform => wgpu::BufferUsages::UNIFORM,
                        BufferKind::Storage { .. } => wgpu::BufferUsages::STORAGE,
                    };
                    let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("first dispatch placeholder"),
                        size: bytes,
                        usage,
                        mapped_at_creation: false,
                    });
                    (binding, buffer)
                })
                .collect();
        let resources = self.resource_layout.as_ref().map(|layout| {
            let entries: Vec<_> = placeholders
                .iter()
                .map(|(binding, buffer)| wgpu::BindGroupEntry {
                    binding: *binding,
                    resource: buffer.as_entire_binding(),
                })
                .collect();
            self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("first dispatch placeholders"),
                layout,
                entries: &entries,
            })
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("first dispatch"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("first dispatch"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.megakernel);
            pass.set_bind_group(SCHEDULER_GROUP, &self.state.scheduler_group, &[]);
            if let Some(group) = &resources {
                pass.set_bind_group(RESOURCE_GROUP, group, &[]);
            }
            pass.dispatch_workgroups(0, 1, 1);
        }
        let submission = self.queue.submit([encoder.finish()]);
        if let Some(error) = pollster::block_on(scope.pop()) {
            log::warn!("the first dispatch of the megakernel failed: {error}");
            return None;
        }
        match self.device.poll(wgpu::PollType::Wait {
            submission_index: Some(submission),
            timeout: Some(self.timeout),
        }) {
            Ok(_) => Some(start.elapsed()),
            Err(error) => {
                log::warn!("the first dispatch of the megakernel did not finish: {error}");
                None
            }
        }
    }
}
