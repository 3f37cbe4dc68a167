//! How far a retry grows the queues: to the need an overflowing run measured,
//! plus room for the children its refused items would have had, within what
//! the device's buffer limits allow.

use crate::plan::Plan;
use crate::{RunError, RunReport};

/// The largest queue capacity: slots are addressed with a `u32` mask.
pub(crate) const MAX_CAPACITY: u32 = 1 << 31;

/// Generations of children estimated for the refused items (see
/// [`grown_capacities`]): deeper descendants are left to a further retry
/// rather than guessed. Two left one random graph of 64 runs needing three
/// retries; three kept every measured run within two (docs/scheduler.md,
/// "Overflow and retry").
const ESTIMATED_GENERATIONS: usize = 3;

/// What a retry grows the queues to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Growth {
    /// The capacities to retry with, one per queue.
    pub capacities: Vec<u32>,
    /// Whether a queue that feeds itself was held at twice its measured need
    /// below what the estimate of its refused items' children asked for: the
    /// memory bound, which leaves that queue to be measured again.
    pub held: bool,
}

/// The capacities to retry with after the overflowing run `report`, or
/// [`RunError::QueueExceedsDevice`] when a queue's measured need does not fit
/// the device.
///
/// Each overflowing queue gets at least its measured need (`needed`: the
/// high-water mark plus every refused item), which holds all the items that
/// run produced. The refused items never ran, so their children were never
/// counted; each queue also gets room for an estimate of them, for
/// [`ESTIMATED_GENERATIONS`] generations: a refused item of a producer is
/// taken to enqueue as many items into each queue it feeds as that producer's
/// executed items did on average in this run. The estimate only adds room
/// (capped by the device), never replaces the measurement, so a queue whose
/// estimate is too low overflows once more and is measured again, and
/// never grows a queue that feeds itself past twice its measured need (the
/// high-water mark for a queue that did not overflow): a compounding
/// estimate of a self-feeding queue overshoots by far more than one more
/// attempt costs. Any other queue gets the whole estimate: its own
/// measurement is short by the refused items upstream.
/// Capacities are powers of two (the ring's slots are addressed with a mask):
/// the largest one within twice the need, which is never below the smallest
/// one that holds the need.
pub(crate) fn grown_capacities(
    plan: &Plan,
    limits: &wgpu::Limits,
    report: &RunReport,
) -> Result<Growth, RunError> {
    let stats = &report.procedures;
    let n = plan.queues.len();
    // Items each queue received from enqueues (accepted or refused), per item
    // executed by the procedures that feed it.
    let producers: Vec<Vec<usize>> = (0..n)
        .map(|r| {
            (0..n)
                .filter(|&q| plan.queues[q].targets.iter().any(|&(t, _)| t == r))
                .collect()
        })
        .collect();
    let rate: Vec<f64> = (0..n)
        .map(|r| {
            let executed: u64 = producers[r].iter().map(|&q| stats[q].executed).sum();
            let received = stats[r].enqueued + stats[r].dropped;
            if executed == 0 {
                0.0
            } else {
                received as f64 / executed as f64
            }
        })
        .collect();
    let mut headroom = vec![0f64; n];
    let mut generation: Vec<f64> = stats.iter().map(|s| s.dropped as f64).collect();
    for _ in 0..ESTIMATED_GENERATIONS {
        let next: Vec<f64> = (0..n)
            .map(|r| producers[r].iter().map(|&q| generation[q]).sum::<f64>() * rate[r])
            .collect();
        for (h, g) in headroom.iter_mut().zip(&next) {
            *h += g;
        }
        generation = next;
    }

    let mut capacities: Vec<u32> = stats.iter().map(|s| s.capacity).collect();
    // First the measured needs, which must fit.
    for (q, s) in stats.iter().enumerate() {
        if s.dropped > 0 {
            capacities[q] = power_of_two_at_least(s.needed.max(u64::from(s.capacity) + 1));
        }
    }
    // The queues share the device's buffers: when the grown ones do not
    // fit, every queue's check fails, so the grown queues are checked
    // first, the largest first, and the error names one of them with its
    // need, not a queue that needs nothing more (`Bound needs 0 items but
    // at most 0 fit`).
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&q| {
        let slot = u64::from(plan.queues[q].slot_words);
        (
            stats[q].dropped == 0,
            std::cmp::Reverse(u64::from(capacities[q]) * slot),
        )
    });
    for q in order {
        let max = max_capacity(plan, limits, &capacities, q);
        if capacities[q] > max {
            return Err(RunError::QueueExceedsDevice {
                procedure: plan.queues[q].name.clone(),
                needed: stats[q].needed,
                max,
                report: Some(Box::new(report.clone())),
            });
        }
    }
    // Then the estimated room for the refused items' children, as far as
    // the device allows.
    let mut held = false;
    for q in 0..n {
        if headroom[q] < 1.0 {
            continue;
        }
        let base = measured_need(&stats[q]);
        let room = headroom[q].ceil() as u64;
        let mut wanted = power_of_two_at_least(base.saturating_add(room));
        // A queue that feeds itself compounds its own estimate: at most
        // twice its need. Any other queue with room to estimate was
        // measured short (the refused items upstream never reached it), so
        // the cap would hold it to a fraction of its need, one more
        // attempt at a time.
        if producers[q].contains(&q) {
            let bound = power_of_two_at_most(base.max(1).saturating_mul(2));
            held |= wanted > bound;
            wanted = wanted.min(bound);
        }
        let max = max_capacity(plan, limits, &capacities, q);
        capacities[q] = capacities[q].max(wanted.min(max));
    }
    Ok(Growth { capacities, held })
}

/// What a queue was measured to need in one run: `needed` if it overflowed,
/// else its high-water mark.
pub(crate) fn measured_need(stats: &crate::ProcedureStats) -> u64 {
    if stats.dropped > 0 {
        stats.needed
    } else {
        stats.high_water
    }
}

/// Capacities that hold `seeds[q]` seeds in each queue `q`, or
/// [`RunError::QueueExceedsDevice`] when they cannot fit the device.
pub(crate) fn capacities_for_seeds(
    plan: &Plan,
    limits: &wgpu::Limits,
    current: &[u32],
    procedure: &str,
    seeds: u64,
) -> Result<Vec<u32>, RunError> {
    let mut capacities = current.to_vec();
    if let Some(q) = plan.queue_index(procedure) {
        capacities[q] = capacities[q].max(power_of_two_at_least(seeds));
        let max = max_capacity(plan, limits, &capacities, q);
        if capacities[q] > max {
            return Err(RunError::QueueExceedsDevice {
                procedure: procedure.to_owned(),
                needed: seeds,
                max,
                report: None,
            });
        }
    }
    Ok(capacities)
}

/// The smallest power of two of at least `items`, at most [`MAX_CAPACITY`]
/// (a larger need is refused by [`max_capacity`]'s check, as it exceeds it).
fn power_of_two_at_least(items: u64) -> u32 {
    if items > u64::from(MAX_CAPACITY) {
        // Not representable: one above the largest capacity, so that the
        // device check fails with the real need.
        return u32::MAX;
    }
    (items.max(1) as u32).next_power_of_two()
}

/// The largest power of two of at most `items` (at least 1), at most
/// [`MAX_CAPACITY`].
fn power_of_two_at_most(items: u64) -> u32 {
    let items = items.clamp(1, u64::from(MAX_CAPACITY));
    1 << items.ilog2()
}

/// The largest power-of-two capacity queue `q` can have next to the other
/// queues' `capacities`: its slots must fit the queue buffer and its range
/// markers the control buffer, each within one storage binding.
pub(crate) fn max_capacity(
    plan: &Plan,
    limits: &wgpu::Limits,
    capacities: &[u32],
    q: usize,
) -> u32 {
    let limit = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let others = |bytes_per_slot: &dyn Fn(usize) -> u64| -> u64 {
        (0..plan.queues.len())
            .filter(|&r| r != q)
            .map(|r| u64::from(capacities[r]) * bytes_per_slot(r))
            .sum()
    };
    let slot_bytes = |r: usize| 4 * u64::from(plan.queues[r].slot_words);
    // The control buffer holds the counters, then two markers per slot.
    let counters = 4 * u64::from(plan.control_words());
    let by_queue = limit.saturating_sub(others(&slot_bytes)) / slot_bytes(q).max(1);
    let by_control = limit.saturating_sub(counters + others(&|_| 8)) / 8;
    let items = by_queue.min(by_control).min(u64::from(MAX_CAPACITY));
    if items == 0 { 0 } else { 1 << items.ilog2() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CompileOptions, Graph, Procedure, ProcedureStats};

    #[crate::item]
    struct Node {
        depth: u32,
        id: u32,
    }

    /// `Split` feeds itself (fan-out 2) and `Leaf`.
    fn plan() -> Plan {
        let mut graph = Graph::new("growth");
        let split = graph.procedure(
            Procedure::of::<Node>("Split")
                .initial(true)
                .body("if (valid) { enqueue_Split(item); enqueue_Leaf(item); }"),
        );
        let leaf = graph.procedure(Procedure::of::<Node>("Leaf").body(""));
        graph.connect_with_fan_out(&split, &split, 2);
        graph.connect(&split, &leaf);
        graph.compile(&CompileOptions::default()).unwrap().plan
    }

    fn stats(
        name: &str,
        capacity: u32,
        executed: u64,
        enqueued: u64,
        dropped: u64,
    ) -> ProcedureStats {
        ProcedureStats {
            name: name.to_owned(),
            capacity,
            executed,
            enqueued,
            high_water: u64::from(capacity),
            dropped,
            needed: if dropped > 0 {
                u64::from(capacity) + dropped
            } else {
                0
            },
            ..ProcedureStats::default()
        }
    }

    #[test]
    fn an_overflowing_queue_grows_to_its_need_plus_its_children() {
        let plan = plan();
        // 16 `Split`s ran, enqueued 16 and had 48 refused: each received 4
        // per `Split` executed, so the 48 refused would have had 192
        // children, and `Leaf` 48 more.
        let report = RunReport {
            procedures: vec![stats("Split", 16, 16, 16, 48), stats("Leaf", 64, 16, 16, 0)],
            ..RunReport::default()
        };
        let grown = grown_capacities(&plan, &wgpu::Limits::default(), &report).unwrap();
        assert!(grown.held, "Split's estimate is held at twice its need");
        let grown = grown.capacities;
        // Split: need 64 (16 + 48), plus 192 + 768 + 3072 estimated over
        // three generations, capped at twice the need as it feeds itself:
        // 128; Leaf, fed by Split only: high-water 64 (short by Split's
        // refused items) plus 48 + 192 + 768, uncapped: 1072, so 2048.
        assert_eq!(grown, [128, 2048]);
    }

    #[test]
    fn a_grown_queue_stays_within_twice_its_measured_need() {
        let plan = plan();
        // Needs just above a power of two, where rounding need plus margin
        // up to the next power of two would give almost four times the need.
        for (capacity, dropped) in [(16, 1), (512, 1), (1000, 30), (16, 48)] {
            let report = RunReport {
                procedures: vec![
                    stats("Split", capacity, capacity.into(), capacity.into(), dropped),
                    stats("Leaf", 64, 16, 16, 0),
                ],
                ..RunReport::default()
            };
            let need = u64::from(capacity) + dropped;
            let grown = grown_capacities(&plan, &wgpu::Limits::default(), &report)
                .unwrap()
                .capacities;
            assert!(
                u64::from(grown[0]) >= need,
                "{grown:?} for a need of {need}"
            );
            assert!(
                u64::from(grown[0]) <= 2 * need,
                "{grown:?} for a need of {need}"
            );
            assert!(grown[0].is_power_of_two());
        }
    }

    #[test]
    fn a_need_beyond_the_device_is_a_typed_error() {
        let plan = plan();
        let report = RunReport {
            procedures: vec![
                stats("Split", 16, 16, 16, 1 << 20),
                stats("Leaf", 64, 0, 0, 0),
            ],
            ..RunReport::default()
        };
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 1 << 20,
            ..wgpu::Limits::default()
        };
        let error = grown_capacities(&plan, &limits, &report).unwrap_err();
        let RunError::QueueExceedsDevice {
            procedure,
            needed,
            max,
            report,
        } = &error
        else {
            panic!("expected QueueExceedsDevice, got {error:?}");
        };
        assert_eq!((procedure.as_str(), *needed), ("Split", 16 + (1 << 20)));
        assert!(*max < 1 << 20 && max.is_power_of_two(), "{max}");
        assert!(report.is_some());
        // Without that need, the children estimate is only capped.
        let report = RunReport {
            procedures: vec![stats("Split", 16, 16, 16, 48), stats("Leaf", 64, 16, 16, 0)],
            ..RunReport::default()
        };
        let tight = wgpu::Limits {
            max_storage_buffer_binding_size: 4096,
            ..wgpu::Limits::default()
        };
        let grown = grown_capacities(&plan, &tight, &report).unwrap().capacities;
        assert!(grown.iter().all(|c| c.is_power_of_two()));
        assert!(grown[0] >= 64 && grown[0] < 1024, "{grown:?}");
    }

    /// The queue named is the one whose need does not fit, even when an
    /// earlier queue that needs nothing more fails the same check (they
    /// share the buffer): it was `Split needs 0 items but at most 0 fit`.
    #[test]
    fn the_queue_beyond_the_device_is_the_one_that_grew() {
        let plan = plan();
        let report = RunReport {
            procedures: vec![
                stats("Split", 1 << 12, 16, 16, 0),
                stats("Leaf", 64, 64, 1 << 20, 1 << 20),
            ],
            ..RunReport::default()
        };
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 1 << 20,
            ..wgpu::Limits::default()
        };
        let error = grown_capacities(&plan, &limits, &report).unwrap_err();
        let RunError::QueueExceedsDevice {
            procedure, needed, ..
        } = &error
        else {
            panic!("expected QueueExceedsDevice, got {error:?}");
        };
        assert_eq!((procedure.as_str(), *needed), ("Leaf", 64 + (1 << 20)));
    }

    #[test]
    fn seeds_grow_their_queue_to_a_power_of_two() {
        let plan = plan();
        let limits = wgpu::Limits::default();
        assert_eq!(
            capacities_for_seeds(&plan, &limits, &[16, 16], "Split", 40).unwrap(),
            [64, 16]
        );
        let tiny = wgpu::Limits {
            max_storage_buffer_binding_size: 256,
            ..wgpu::Limits::default()
        };
        assert!(matches!(
            capacities_for_seeds(&plan, &tiny, &[16, 16], "Split", 40),
            Err(RunError::QueueExceedsDevice { report: None, .. })
        ));
    }
}
