//! Copying GPU buffers back to the host with a timeout.

use std::time::Duration;

use crate::RunError;

/// The longest single wait handed to the driver. Vulkan takes its fence
/// timeout in nanoseconds as a `u64` (about 584 years), and a longer
/// `Duration` would wrap in the conversion; a century is "forever" for a run.
pub const LONGEST_WAIT: Duration = Duration::from_secs(100 * 365 * 24 * 60 * 60);

/// Waits for all work submitted so far, failing with [`RunError::Timeout`]
/// (without a report: the caller adds what it could read)
/// after `timeout`.
pub fn wait(
    device: &wgpu::Device,
    submission: wgpu::SubmissionIndex,
    timeout: Duration,
) -> Result<(), RunError> {
    match device.poll(wgpu::PollType::Wait {
        submission_index: Some(submission),
        timeout: Some(timeout.min(LONGEST_WAIT)),
    }) {
        Ok(_) => Ok(()),
        Err(wgpu::PollError::Timeout) => Err(RunError::timeout(timeout)),
        Err(e) => Err(RunError::Gpu(e.to_string())),
    }
}

/// Maps `buffer` (which must have `MAP_READ`) after `submission` completes and
/// returns its bytes.
pub fn map_read(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    submission: wgpu::SubmissionIndex,
    timeout: Duration,
) -> Result<Vec<u8>, RunError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        let _ = sender.send(result);
    });
    let mapped = wait(device, submission, timeout).and_then(|()| {
        receiver
            .recv_timeout(timeout)
            .map_err(|_| RunError::timeout(timeout))?
            .map_err(|e| RunError::Gpu(e.to_string()))
    });
    if let Err(error) = mapped {
        // Cancel the pending map, so that the buffer can be used (and mapped)
        // again by a later run instead of failing as "still mapped".
        buffer.unmap();
        return Err(error);
    }
    let bytes = buffer
        .get_mapped_range(..)
        .map_err(|e| RunError::Gpu(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Copies `source` (which needs `COPY_SRC`) into a fresh mappable buffer and
/// returns its contents.
pub fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    source: &wgpu::Buffer,
    timeout: Duration,
) -> Result<Vec<u8>, RunError> {
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: source.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("read-back"),
    });
    encoder.copy_buffer_to_buffer(source, 0, &staging, 0, source.size());
    let submission = queue.submit([encoder.finish()]);
    map_read(device, &staging, submission, timeout)
}
