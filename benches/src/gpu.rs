//! Small device helpers shared by both variants.

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};

use scheduler::wgpu;

/// Drives a wgpu future to completion on this thread. On native backends the
/// futures wgpu returns (error scopes) are ready at once; the loop only yields.
pub fn block_on<F: Future>(future: F) -> F::Output {
    let mut future = pin!(future);
    let mut context = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(output) = future.as_mut().poll(&mut context) {
            return output;
        }
        std::thread::yield_now();
    }
}

/// A storage buffer of `items` words that can be filled and read back.
pub fn out_buffer(device: &wgpu::Device, items: u32, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: 4 * u64::from(items),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
