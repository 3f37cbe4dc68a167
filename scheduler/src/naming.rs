//! Every identifier scheme of the generated module, stated once. The code
//! generator declares these names, the compile checks look them up in the
//! parsed module and the runtime names the entry points by them, so all three
//! agree by construction. It depends on nothing else in the crate.

/// Prefixes reserved for generated identifiers; user declarations may not
/// start with them.
pub(crate) const RESERVED_PREFIXES: [&str; 4] = [
    SCHEDULER_PREFIX,
    CONSTANT_PREFIX,
    ENQUEUE_PREFIX,
    JOIN_OPEN_PREFIX,
];

/// Prefix of the scheduler's functions and module-scope variables.
pub(crate) const SCHEDULER_PREFIX: &str = "sched_";

/// Prefix of the scheduler's constants.
pub(crate) const CONSTANT_PREFIX: &str = "SCHED_";

/// Prefix of the enqueue functions.
pub(crate) const ENQUEUE_PREFIX: &str = "enqueue_";

/// Prefix of the functions holding procedure bodies.
pub(crate) const BODY_PREFIX: &str = "sched_proc_";

/// Prefix of the procedure runners.
pub(crate) const RUNNER_PREFIX: &str = "sched_run_";

/// Prefix of the item decoders.
pub(crate) const DECODE_PREFIX: &str = "sched_decode_";

/// Prefix of the item encoders.
pub(crate) const ENCODE_PREFIX: &str = "sched_encode_";

/// Entry point name of the megakernel.
pub(crate) const ENTRY_POINT: &str = "sched_main";

/// Entry point of the Rounds strategy that prepares the next round.
pub(crate) const PREPARE_ENTRY_POINT: &str = "sched_prepare_round";

/// Entry point of the Rounds strategy that runs one round of a procedure.
pub(crate) fn round_entry_point(procedure: &str) -> String {
    format!("sched_round_{procedure}")
}

/// Name of the function that runs one batch of a procedure inside a round
/// (the Rounds strategy's counterpart of [`runner_name`]).
pub(crate) fn round_runner_name(procedure: &str) -> String {
    format!("sched_batch_{procedure}")
}

/// Name of the function holding a procedure's body.
pub(crate) fn body_name(procedure: &str) -> String {
    format!("{BODY_PREFIX}{procedure}")
}

/// Name of the function that runs one batch of a procedure.
pub(crate) fn runner_name(procedure: &str) -> String {
    format!("{RUNNER_PREFIX}{procedure}")
}

/// Name of the workgroup array holding a procedure's typed scratch.
pub(crate) fn scratch_name(procedure: &str) -> String {
    format!("sched_scratch_{procedure}")
}

/// Name of the enqueue function for a target procedure.
pub(crate) fn enqueue_name(procedure: &str) -> String {
    format!("{ENQUEUE_PREFIX}{procedure}")
}

/// Name of the function that reads an item of `item` from its queue slot.
pub(crate) fn decode_name(item: &str) -> String {
    format!("{DECODE_PREFIX}{item}")
}

/// Name of the function that writes an item of `item` into staging.
pub(crate) fn encode_name(item: &str) -> String {
    format!("{ENCODE_PREFIX}{item}")
}

/// Name of the function that copies one staged item of `queue` into its slot.
pub(crate) fn copy_out_name(queue: &str) -> String {
    format!("sched_copy_out_{queue}")
}

/// Name of the checked-mode guard of resource `resource`.
pub(crate) fn guard_name(resource: &str) -> String {
    format!("sched_checked_{resource}")
}

/// Name of the constant holding a queue's index.
pub(crate) fn queue_constant_name(procedure: &str) -> String {
    format!("SCHED_QUEUE_{}", procedure.to_uppercase())
}

/// Name of the constant holding the offset of `field` in a queue's control
/// block.
pub(crate) fn queue_field_constant_name(field: &str) -> String {
    format!("SCHED_Q_{field}")
}

/// Prefix of the functions that open a join ([`join_open_name`]).
pub(crate) const JOIN_OPEN_PREFIX: &str = "join_open_";

/// Name of the function a body calls to open a join whose continuation is
/// `continuation`.
pub(crate) fn join_open_name(continuation: &str) -> String {
    format!("{JOIN_OPEN_PREFIX}{continuation}")
}

/// Name of the function that enqueues a fired join's record into
/// `continuation`.
pub(crate) fn join_continue_name(continuation: &str) -> String {
    format!("sched_join_continue_{continuation}")
}

/// Name of the function that writes an `item` into a join record.
pub(crate) fn join_store_name(item: &str) -> String {
    format!("sched_join_store_{item}")
}
