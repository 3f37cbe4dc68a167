//! What a retry's reset receives: the device, the queue and the executor's
//! own resources, so that it can restore them while the executor is busy
//! retrying.

use crate::{Executor, RunError};

/// Handed to [`Retry`](crate::Retry)'s reset before each retry: the device
/// and queue, and the executor's own buffers by resource name (those made by
/// [`Executor::create_buffer`] or [`Executor::write`]), which the reset can
/// clear or read from although the executor itself is borrowed by the run.
#[derive(Debug)]
pub struct ResetContext<'a> {
    executor: &'a Executor,
}

impl<'a> ResetContext<'a> {
    pub(crate) fn new(executor: &'a Executor) -> Self {
        Self { executor }
    }

    /// The executor's device.
    pub fn device(&self) -> &'a wgpu::Device {
        &self.executor.device
    }

    /// The executor's queue.
    pub fn queue(&self) -> &'a wgpu::Queue {
        &self.executor.queue
    }

    /// The executor's own buffer for `name`, if it created one (as
    /// [`Executor::buffer`]).
    pub fn buffer(&self, name: &str) -> Option<&'a wgpu::Buffer> {
        self.executor.buffer(name)
    }

    /// Zeroes the executor's buffer for `name`, as [`Executor::clear`] does;
    /// [`RunError::Binding`] when the executor has no buffer by that name.
    pub fn clear(&self, name: &str) -> Result<(), RunError> {
        let buffer = self.buffer(name).ok_or_else(|| {
            RunError::Binding(format!(
                "the executor has no buffer for `{name}`: create it with `create_buffer` or `write`"
            ))
        })?;
        let mut encoder = self
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("clear resource"),
            });
        encoder.clear_buffer(buffer, 0, None);
        self.queue().submit([encoder.finish()]);
        Ok(())
    }

    /// Writes `data` at the start of the executor's buffer for `name`;
    /// [`RunError::Binding`] when there is no such buffer or `data` does not
    /// fit it.
    pub fn write<T: bytemuck::Pod>(&self, name: &str, data: &[T]) -> Result<(), RunError> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let buffer = self
            .buffer(name)
            .filter(|buffer| buffer.size() >= bytes.len() as u64)
            .ok_or_else(|| {
                RunError::Binding(format!(
                    "the executor has no buffer for `{name}` that holds {} bytes",
                    bytes.len()
                ))
            })?;
        self.queue().write_buffer(buffer, 0, bytes);
        Ok(())
    }
}
