//! The layout of the configuration uniform `sched_config`: one `vec4<u32>`
//! row per queue, then one for the whole run. Each component is described
//! next to the function that computes it, so the comment in the generated
//! module and the words the host writes come from the same definition.
//! shaders/scheduler/runtime.wgsl reads the components as `.x` to `.w`.

/// What the host knows about one queue when it fills the uniform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct QueueConfig {
    /// Allocated capacity in items (a power of two).
    pub capacity: u32,
    /// First word of the queue's slots in `sched_queue_words`.
    pub first_slot_word: u32,
    /// First word of the queue's range markers in `sched_control`: the
    /// published markers, then (`capacity` words later) the released ones.
    pub first_marker_word: u32,
}

/// What the host writes into the last row, for every queue alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RunConfig {
    /// Batches after which a persistent workgroup leaves.
    pub iteration_budget: u32,
    /// Spin-wait iterations after which a workgroup leaves (CPU adapters).
    pub spin_limit: u32,
    /// Most workgroups of one round's dispatch (Rounds strategy).
    pub round_workgroups: u32,
}

/// Turns of the loop that checks, after each body call, whether the driver's
/// loop budget ran out in the body (`sched_check_body_loops`): two, from the
/// uniform so that the compiler cannot unroll the loop.
pub(crate) const CANARY_TURNS: u32 = 2;

/// One component of a row: what it holds, and how the host computes it.
pub(crate) struct Component<T> {
    pub meaning: &'static str,
    pub value: fn(&T) -> u32,
}

/// The row of each queue. `capacity - 1` is the slot mask: capacities are
/// powers of two.
pub(crate) const QUEUE_ROW: [Component<QueueConfig>; 4] = [
    Component {
        meaning: "capacity - 1",
        value: |q| q.capacity - 1,
    },
    Component {
        meaning: "first slot word",
        value: |q| q.first_slot_word,
    },
    Component {
        meaning: "first range marker word in sched_control",
        value: |q| q.first_marker_word,
    },
    Component {
        meaning: "0",
        value: |_| 0,
    },
];

/// The last row.
pub(crate) const RUN_ROW: [Component<RunConfig>; 4] = [
    Component {
        meaning: "iteration budget",
        value: |r| r.iteration_budget,
    },
    Component {
        meaning: "spin limit",
        value: |r| r.spin_limit,
    },
    Component {
        meaning: "workgroups per round dispatch",
        value: |r| r.round_workgroups,
    },
    Component {
        meaning: "turns of the body loop check (2)",
        value: |_| CANARY_TURNS,
    },
];

/// Rows of the uniform for `queues` queues.
pub(crate) fn rows(queues: usize) -> usize {
    queues + 1
}

/// Bytes of the uniform for `queues` queues.
pub(crate) fn bytes(queues: usize) -> u64 {
    16 * rows(queues) as u64
}

/// The words the host writes: one row per queue, then the run's row.
pub(crate) fn words(queues: &[QueueConfig], run: &RunConfig) -> Vec<u32> {
    let mut words = Vec::with_capacity(4 * rows(queues.len()));
    for queue in queues {
        words.extend(QUEUE_ROW.iter().map(|c| (c.value)(queue)));
    }
    words.extend(RUN_ROW.iter().map(|c| (c.value)(run)));
    words
}

/// The comment on `sched_config` in the generated module.
pub(crate) fn describe() -> String {
    fn row<T>(components: &[Component<T>]) -> String {
        let meanings: Vec<&str> = components.iter().map(|c| c.meaning).collect();
        format!("({})", meanings.join(", "))
    }
    format!("Per queue {}; last: {}.", row(&QUEUE_ROW), row(&RUN_ROW))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_follow_the_described_rows() {
        let queues = [
            QueueConfig {
                capacity: 8,
                first_slot_word: 0,
                first_marker_word: 28,
            },
            QueueConfig {
                capacity: 4,
                first_slot_word: 64,
                first_marker_word: 44,
            },
        ];
        let run = RunConfig {
            iteration_budget: 64,
            spin_limit: 8192,
            round_workgroups: 256,
        };
        assert_eq!(
            words(&queues, &run),
            [7, 0, 28, 0, 3, 64, 44, 0, 64, 8192, 256, 2]
        );
        assert_eq!(bytes(queues.len()), 4 * words(&queues, &run).len() as u64);
        assert_eq!(
            describe(),
            "Per queue (capacity - 1, first slot word, first range marker word in sched_control, 0); \
             last: (iteration budget, spin limit, workgroups per round dispatch, turns of the body loop check (2))."
        );
    }
}
