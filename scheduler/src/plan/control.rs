//! Layout of the control buffer (atomic u32 words). Mirrored as WGSL constants.

/// Outstanding work: items reserved and not yet finished.
pub(crate) const PENDING: u32 = 0;
/// Spin-waits that a driver's loop limiter ended early (llvmpipe).
pub(crate) const LOOPS_CUT: u32 = 1;
/// Rounds strategy: rounds that found work.
pub(crate) const ROUNDS: u32 = 2;
/// Body calls after which the driver's loop budget was found spent: the
/// bodies' own loops were cut (llvmpipe).
pub(crate) const BODY_LOOPS_CUT: u32 = 3;
/// First per-queue block.
pub(crate) const QUEUE_BASE: u32 = 4;
/// Words per queue block.
pub(crate) const QUEUE_STRIDE: u32 = 12;
/// Consumer ticket counter.
pub(crate) const HEAD: u32 = 0;
/// Producer ticket counter.
pub(crate) const TAIL: u32 = 1;
/// Reserved and unclaimed items (tested against the capacity).
pub(crate) const FILL: u32 = 2;
/// Highest fill seen.
pub(crate) const HIGH_WATER: u32 = 3;
/// Items executed.
pub(crate) const EXECUTED: u32 = 4;
/// Items accepted into the queue by enqueues.
pub(crate) const ENQUEUED: u32 = 5;
/// Items that did not fit.
pub(crate) const DROPPED: u32 = 6;
/// Largest fill an overflowing flush asked for.
pub(crate) const NEEDED: u32 = 7;
/// Enqueues beyond the staging room (declared fan-out).
pub(crate) const FANOUT_OVERFLOW: u32 = 8;
/// Every ticket below it holds a complete item.
pub(crate) const PUBLISHED: u32 = 9;
/// Every ticket below it has been copied out (its slot is free).
pub(crate) const RELEASED: u32 = 10;
/// Rounds strategy: end of the running round's tickets (it starts at `HEAD`).
pub(crate) const ROUND_END: u32 = 11;

/// Number of control words for `queues` queues.
pub(crate) fn words(queues: usize) -> u32 {
    QUEUE_BASE + QUEUE_STRIDE * queues as u32
}

/// Index of `field` of queue `q`.
pub(crate) fn index(q: usize, field: u32) -> usize {
    (QUEUE_BASE + QUEUE_STRIDE * q as u32 + field) as usize
}
