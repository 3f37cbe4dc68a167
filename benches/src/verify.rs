//! Reading `out` back and comparing it with the CPU reference.

use std::time::Duration;

use scheduler::{bytemuck, wgpu};

use crate::BenchError;

/// Value written into `out` before a verified run, so that an id the GPU
/// never wrote cannot match the reference by accident (no id's hash is
/// checked against a stale value of another variant).
pub const SENTINEL: u32 = 0xdead_beef;

/// How long a read-back may take.
const READ_TIMEOUT: Duration = Duration::from_secs(60);

/// Fills `out` with [`SENTINEL`] (ordered before the next submission).
pub fn fill_sentinel(queue: &wgpu::Queue, out: &wgpu::Buffer) {
    let words = vec![SENTINEL; (out.size() / 4) as usize];
    queue.write_buffer(out, 0, bytemuck::cast_slice(&words));
}

/// Reads `out` back and fails with [`BenchError::Mismatch`] unless it equals
/// `expected` word for word.
pub fn check_out(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    out: &wgpu::Buffer,
    expected: &[u32],
    variant: &str,
) -> Result<(), BenchError> {
    compare(&read_out(device, queue, out)?, expected, variant)
}

/// Reads `out` back.
pub fn read_out(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    out: &wgpu::Buffer,
) -> Result<Vec<u32>, BenchError> {
    let bytes = scheduler::readback::read_buffer(device, queue, out, READ_TIMEOUT)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Compares two `out` arrays.
pub fn compare(actual: &[u32], expected: &[u32], variant: &str) -> Result<(), BenchError> {
    if actual.len() != expected.len() {
        return Err(BenchError::Counters {
            variant: variant.to_owned(),
            detail: format!(
                "out has {} entries, the reference {}",
                actual.len(),
                expected.len()
            ),
        });
    }
    let mut wrong = actual
        .iter()
        .zip(expected)
        .enumerate()
        .filter(|(_, (a, e))| a != e);
    match wrong.next() {
        None => Ok(()),
        Some((index, (&a, &e))) => Err(BenchError::Mismatch {
            variant: variant.to_owned(),
            wrong: 1 + wrong.count(),
            first: (index, e, a),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_reports_the_first_difference() {
        assert!(compare(&[1, 2, 3], &[1, 2, 3], "x").is_ok());
        match compare(&[1, 9, 8], &[1, 2, 3], "x") {
            Err(BenchError::Mismatch { wrong, first, .. }) => {
                assert_eq!((wrong, first), (2, (1, 2, 9)));
            }
            other => panic!("expected a mismatch, got {other:?}"),
        }
    }
}
