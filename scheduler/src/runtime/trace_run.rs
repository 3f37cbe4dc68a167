//! The trace of a traced module on the device: its room in the control
//! buffer (after the range markers, see `codegen::trace`), the submission
//! counter and the read-back into a [`Trace`]. Nothing is allocated for an
//! untraced module. The trace needs no reset of its own: seeding clears
//! every control word after the counters.

use std::time::Duration;

use crate::codegen::trace::{HEADER_WORDS, SUBMISSION, record_words};
use crate::plan::Plan;
use crate::runtime::executor::Executor;
use crate::runtime::readback;
use crate::{RunError, SubmissionTrace, Trace};

/// Bytes of the trace of `plan` (0 without tracing).
pub(crate) fn bytes(plan: &Plan) -> u64 {
    plan.trace.map_or(0, |trace| {
        let words = u64::from(HEADER_WORDS)
            + u64::from(trace.capacity) * u64::from(record_words(plan.queues.len()));
        4 * words
    })
}

/// The first control word of the trace: after the counters and every
/// queue's two markers per slot (as `sched_trace_base` computes it).
fn base_word(plan: &Plan, capacities: &[u32]) -> u64 {
    u64::from(plan.control_words()) + 2 * capacities.iter().map(|&c| u64::from(c)).sum::<u64>()
}

impl Executor {
    /// Before submission `index`: its records carry `index`.
    pub(super) fn trace_submission(&self, index: u32) {
        let plan = &self.compiled.plan;
        if plan.trace.is_some() {
            let word = base_word(plan, &self.state.capacities) + u64::from(SUBMISSION);
            self.queue
                .write_buffer(&self.state.control, 4 * word, bytemuck::bytes_of(&index));
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
        let plan = &self.compiled.plan;
        let Some(options) = plan.trace else {
            return Ok(None);
        };
        let size = bytes(plan);
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("trace read-back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("trace read-back"),
            });
        let offset = 4 * base_word(plan, &self.state.capacities);
        encoder.copy_buffer_to_buffer(&self.state.control, offset, &staging, 0, size);
        let submission = self.queue.submit([encoder.finish()]);
        let bytes = readback::map_read(&self.device, &staging, submission, self.timeout)?;
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
