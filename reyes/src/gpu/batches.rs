//! Batches of input patches: a scene with more patches than the Bound queue
//! holds next to the work queues in one device buffer is seeded in several
//! runs of the megakernel ([`plan_batch`], [`batch_ranges`]), which make up
//! the [`TileRuns`] of a tile.

use std::time::Duration;

use scheduler::RunReport;

/// The split and dice queues are never shrunk below this to fit a device.
pub(super) const MIN_WORK_CAPACITY: u32 = 1 << 12;
/// The work queues are shrunk (down to [`MIN_WORK_CAPACITY`]) to fit the
/// device only while batches of input patches would be smaller than this:
/// more runs cost less than overflowing work queues.
pub(super) const MIN_BATCH_PATCHES: u32 = 1 << 12;

/// Queue capacities of one run and the input patches it seeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct BatchPlan {
    /// Capacity of the Bound queue (a power of two).
    pub(super) bound: u32,
    /// Capacity of each work queue.
    pub(super) work: u32,
    /// Input patches per run (at most `bound`).
    pub(super) batch: u32,
}

/// Plans batches of at most `wanted` input patches with work queues of
/// `work` items, where `queue_bytes(bound, work)` is what the queues then
/// need and `limit` what one device buffer holds: the largest power-of-two
/// Bound queue up to `wanted` that fits next to `work`; `work` is halved
/// (not below [`MIN_WORK_CAPACITY`]) only while the batch would be smaller
/// than [`MIN_BATCH_PATCHES`] (and than `wanted`). `Err`: the bytes one
/// patch needs next to the smallest work queues, when that exceeds `limit`.
pub(super) fn plan_batch(
    wanted: u32,
    work: u32,
    limit: u64,
    queue_bytes: impl Fn(u32, u32) -> u64,
) -> Result<BatchPlan, u64> {
    let wanted = wanted.clamp(1, 1 << 31);
    // A smaller capacity asked for is kept (the scheduler grows an
    // overflowing queue); only shrinking to fit stops at the minimum.
    let mut work = work.max(1);
    loop {
        let mut bound = wanted.next_power_of_two();
        while bound > 1 && queue_bytes(bound, work) > limit {
            bound /= 2;
        }
        let fits = queue_bytes(bound, work) <= limit;
        if fits && (bound >= wanted || bound >= MIN_BATCH_PATCHES || work <= MIN_WORK_CAPACITY) {
            return Ok(BatchPlan {
                bound,
                work,
                batch: wanted.min(bound),
            });
        }
        if work <= MIN_WORK_CAPACITY {
            return Err(queue_bytes(1, work));
        }
        work /= 2;
    }
}

/// The runs of the megakernel for one tile, one per batch of input patches
/// (each retried by the scheduler as it needs).
#[derive(Debug, Default)]
pub(super) struct TileRuns {
    /// The report of the last run.
    pub(super) report: Option<RunReport>,
    /// GPU time of the runs' last attempts, when every run measured it.
    pub(super) gpu_time: Option<Duration>,
    /// Host wall time of the runs, retries included.
    pub(super) wall: Duration,
    /// Runs made (batches started).
    pub(super) batches: u32,
    /// Attempts repeated because a queue overflowed (or held too few seeds).
    pub(super) overflow_retries: u32,
    /// Attempts repeated because the driver cut loops short.
    pub(super) loop_retries: u32,
}

impl TileRuns {
    /// The batch the runs stopped in (1-based) and the batches of the tile,
    /// for `patches` patches in batches of `batch`.
    pub(super) fn batch_of(&self, patches: usize, batch: u32) -> (u32, u32) {
        let count = patches.div_ceil(batch.max(1) as usize) as u32;
        (self.batches.max(1), count.max(1))
    }

    /// These runs followed by `second`, a second pass over the same
    /// batches ([`crate::gpu::DepthTest::TwoPass32`]): times and retries
    /// add up, the report is the last run's, the batches are the same.
    pub(super) fn then(self, second: TileRuns) -> TileRuns {
        TileRuns {
            report: second.report.or(self.report),
            gpu_time: self.gpu_time.zip(second.gpu_time).map(|(a, b)| a + b),
            wall: self.wall + second.wall,
            batches: self.batches.max(second.batches),
            overflow_retries: self.overflow_retries + second.overflow_retries,
            loop_retries: self.loop_retries + second.loop_retries,
        }
    }

    /// Adds the retries `report` counts.
    pub(super) fn add_retries(&mut self, report: &RunReport) {
        self.overflow_retries += report.retries.overflow + report.retries.seeds;
        self.loop_retries += report.retries.loop_limit;
    }
}

/// The input patches `0..patches` in consecutive batches of at most `batch`
/// (at least one patch each); none for no patches.
pub(super) fn batch_ranges(patches: usize, batch: u32) -> Vec<std::ops::Range<usize>> {
    let batch = batch.max(1) as usize;
    (0..patches)
        .step_by(batch)
        .map(|start| start..(start + batch).min(patches))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::options::DEFAULT_WORK_CAPACITY;
    use crate::gpu::render_error::RenderError;

    /// A model of six queues of 240-byte slots (Bound, SplitU, SplitV and
    /// three dice queues; the Reyes graph's Bound slots are smaller, which
    /// the planner takes from the compiled graph).
    fn six_queues(bound: u32, work: u32) -> u64 {
        240 * (u64::from(bound.next_power_of_two()) + 5 * u64::from(work.next_power_of_two()))
    }

    #[test]
    fn patches_beyond_the_queue_are_planned_in_batches() {
        // About 540k patches in 128 MiB: 2^17 per run next to
        // the full work queues (2^18 would need 141 MB), so five runs (D17).
        let plan = plan_batch(540_000, DEFAULT_WORK_CAPACITY, 1 << 27, six_queues).unwrap();
        assert_eq!(
            plan,
            BatchPlan {
                bound: 1 << 17,
                work: DEFAULT_WORK_CAPACITY,
                batch: 1 << 17
            }
        );
        assert_eq!(batch_ranges(540_000, plan.batch).len(), 5);
        // What fits is one run, with the batch limit if there is one.
        let plan = plan_batch(32, DEFAULT_WORK_CAPACITY, 1 << 27, six_queues).unwrap();
        assert_eq!((plan.bound, plan.batch), (32, 32));
        let plan = plan_batch(7, DEFAULT_WORK_CAPACITY, 1 << 27, six_queues).unwrap();
        assert_eq!((plan.bound, plan.batch), (8, 7));
    }

    #[test]
    fn work_queues_shrink_only_for_batches_below_the_minimum() {
        // Room for the work queues at 2^14 and a Bound queue of 2^12.
        let limit = six_queues(1 << 12, 1 << 14);
        let plan = plan_batch(100_000, 1 << 16, limit, six_queues).unwrap();
        assert_eq!(
            (plan.work, plan.bound, plan.batch),
            (1 << 14, 1 << 12, 1 << 12)
        );
        // A small scene keeps its one run with smaller work queues.
        let plan = plan_batch(100, 1 << 16, limit, six_queues).unwrap();
        assert_eq!((plan.bound, plan.batch), (128, 100));
        assert!(six_queues(128, plan.work) <= limit && plan.work >= 1 << 14);
        // At the smallest work queues any batch that fits is taken.
        let limit = six_queues(16, MIN_WORK_CAPACITY);
        let plan = plan_batch(1000, 1 << 16, limit, six_queues).unwrap();
        assert_eq!((plan.work, plan.batch), (MIN_WORK_CAPACITY, 16));
    }

    #[test]
    fn a_device_too_small_for_one_patch_says_what_it_needs() {
        let needed = six_queues(1, MIN_WORK_CAPACITY);
        assert_eq!(plan_batch(10, 1 << 16, needed - 1, six_queues), Err(needed));
        assert!(plan_batch(10, 1 << 16, needed, six_queues).is_ok());
        let message = RenderError::NoBatchFits {
            patches: 10,
            work_capacity: MIN_WORK_CAPACITY,
            needed,
            limit: needed - 1,
        }
        .to_string();
        assert!(message.contains("0 of the 10 patches fit"), "{message}");
        let message = RenderError::TooManyPatches {
            patches: 800_000,
            fit: 699_050,
            needed: 153_600_000,
            limit: 1 << 27,
        }
        .to_string();
        assert!(message.contains("699050 patches fit"), "{message}");
    }

    #[test]
    fn batches_cover_the_patches_in_order() {
        assert!(batch_ranges(0, 5).is_empty());
        assert_eq!(batch_ranges(3, 5), Vec::from_iter(std::iter::once(0..3)));
        assert_eq!(batch_ranges(10, 5), [0..5, 5..10]);
        assert_eq!(batch_ranges(11, 4), [0..4, 4..8, 8..11]);
        assert_eq!(batch_ranges(2, 0), [0..1, 1..2]);
        let runs = TileRuns {
            batches: 2,
            ..TileRuns::default()
        };
        assert_eq!(runs.batch_of(11, 4), (2, 3));
        assert_eq!(TileRuns::default().batch_of(3, 8), (1, 1));
    }
}
