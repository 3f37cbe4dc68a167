//! The trace buffer of a traced module on the device: its allocation, its
//! reset before a run, the submission counter and the read-back into a
//! [`Trace`]. Nothing is allocated for an untraced module.

use std::time::Duration;

use crate::codegen::trace::{HEADER_WORDS, SUBMISSION, record_words};
use crate::plan::Plan;
use crate::runtime::executor::Executor;
use crate::runtime::readback;
use crate::{RunError, SubmissionTrace, Trace};

/// Bytes of the trace buffer of `plan`.
fn bytes(plan: &Plan, capacity: u32) -> u64 {
    let words =
        u64::from(HEADER_WORDS) + u64::from(capacity) * u64::from(record_words(plan.queues.len()));
    4 * words
}

/// The trace buffer of a traced `plan` (`None` without tracing), failing with
/// [`RunError::TooLarge`] beyond `binding_limit`.
pub(crate) fn buffer(
    device: &wgpu::Device,
    plan: &Plan,
    binding_limit: u64,
) -> Result<Option<wgpu::Buffer>, RunError> {
    let Some(trace) = plan.trace else {
        return Ok(None);
    };
    let size = bytes(plan, trace.capacity);
    if size > binding_limit {
        return Err(RunError::TooLarge {
            what: "trace buffer",
            needed: size,
            limit: binding_limit,
        });
    }
    Ok(Some(device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("scheduler trace"),
        size,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })))
}

impl Executor {
    /// Before a run: the clock and the submission counter start at 0.
    pub(super) fn reset_trace(&self) {
        if let Some(buffer) = &self.state.trace {
            let header = [0u32; HEADER_WORDS as usize];
            self.queue
                .write_buffer(buffer, 0, bytemuck::cast_slice(&header));
        }
    }

    /// Before submission `index`: its records carry `index`.
    pub(super) fn trace_submission(&self, index: u32) {
        if let Some(buffer) = &self.state.trace {
            self.queue.write_buffer(
                buffer,
                4 * u64::from(SUBMISSION),
                bytemuck::bytes_of(&index),
            );
        }
    }

    /// After a run of `submissions` submissions: the trace, with the GPU
    /// time of each (`gpu_times`, empty without timestamp queries). `None`
    /// without tracing.
    pub(super) fn read_trace(
        &self,
        submissions: u32,
        gpu_times: &[Duration],
    ) -> Result<Option<Trace>, RunError> {
        let (Some(buffer), Some(options)) = (&self.state.trace, self.compiled.plan.trace) else {
            return Ok(None);
        };
        let plan = &self.compiled.plan;
        let bytes = readback::read_buffer(&self.device, &self.queue, buffer, self.timeout)?;
        let submissions = (0..submissions)
            .zip(0usize..)
            .map(|(index, i)| SubmissionTrace {
                index,
                gpu_time: gpu_times.get(i).copied(),
            })
            .collect();
        Ok(Some(Trace::from_words(
            &plan.graph_name,
            plan.queues.iter().map(|q| q.name.clone()).collect(),
            options.capacity,
            bytemuck::cast_slice(&bytes),
            submissions,
        )))
    }
}
