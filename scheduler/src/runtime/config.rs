//! Run-time configuration of an executor and the memory it will allocate.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

use crate::codegen::uniform;
use crate::{CompiledGraph, Quirks};

/// Default queue capacity in items.
pub const DEFAULT_CAPACITY: u32 = 1 << 16;

/// Default number of persistent workgroups, and of workgroups per round
/// dispatch. WebGPU cannot tell how many workgroups are resident at once, so
/// this is a fixed guess that fills a large GPU (4 x 256-thread workgroups on
/// each of ~64 compute units). Launching more than are resident is safe (see
/// docs/scheduler.md) but wastes a little; fewer leave the GPU partly idle.
/// Drivers that run workgroups on CPU threads get fewer persistent ones
/// ([`ExecutorConfig::megakernel_workgroups_on`]).
/// Tune it with [`ExecutorConfig::workgroups`] and
/// [`ExecutorConfig::round_workgroups`].
pub const DEFAULT_WORKGROUPS: u32 = 256;

/// Default capacity of the join pool in records (graphs with joins only):
/// each record is a few words of the control buffer, and a run needs one
/// per join it opens.
pub const DEFAULT_JOIN_POOL: u32 = 1 << 16;

/// Default host-side timeout of one run.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(60);

/// Queue capacities in items, per procedure.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Capacities {
    /// Capacity of every queue not named in `per_procedure`.
    pub default: u32,
    /// Overrides by procedure name.
    pub per_procedure: BTreeMap<String, u32>,
    /// Records of the join pool ([`Graph::join`](crate::Graph::join)): the
    /// joins one run may open (records are not reused within a run; at
    /// least 1). Only graphs with joins allocate it.
    /// [`Executor::run_with_retry`](crate::Executor::run_with_retry) grows
    /// it to a run's measured need.
    pub join_pool: u32,
}

impl Default for Capacities {
    fn default() -> Self {
        Self::uniform(DEFAULT_CAPACITY)
    }
}

impl Capacities {
    /// Every queue gets `capacity` items.
    pub fn uniform(capacity: u32) -> Self {
        Self {
            default: capacity,
            per_procedure: BTreeMap::new(),
            join_pool: DEFAULT_JOIN_POOL,
        }
    }

    /// Sets the join pool's capacity in records.
    pub fn with_join_pool(mut self, records: u32) -> Self {
        self.join_pool = records;
        self
    }

    /// Sets the capacity of one procedure's queue.
    pub fn with(mut self, procedure: &str, capacity: u32) -> Self {
        self.per_procedure.insert(procedure.to_owned(), capacity);
        self
    }

    /// The capacity of `procedure`'s queue.
    ///
    /// The allocated capacity: the requested value rounded up to a power of
    /// two (slots are addressed with a mask), at least 1 and at most 2^31.
    pub fn of(&self, procedure: &str) -> u32 {
        let requested = self
            .per_procedure
            .get(procedure)
            .copied()
            .unwrap_or(self.default);
        requested.clamp(1, 1 << 31).next_power_of_two()
    }
}

/// How an [`Executor`](crate::Executor) runs a compiled graph.
#[derive(Clone, Debug)]
pub struct ExecutorConfig {
    /// Queue capacities.
    pub capacities: Capacities,
    /// Persistent workgroups per megakernel dispatch. `None`: the adapter's
    /// default ([`ExecutorConfig::megakernel_workgroups_on`]:
    /// one per CPU thread on llvmpipe, [`DEFAULT_WORKGROUPS`] elsewhere). A
    /// value set here is also the most workgroups per round dispatch unless
    /// [`ExecutorConfig::round_workgroups`] names its own.
    pub workgroups: Option<u32>,
    /// Most workgroups per round dispatch (Rounds strategy). `None`:
    /// [`ExecutorConfig::workgroups`] if set, else the adapter's default
    /// ([`ExecutorConfig::round_workgroups_or_default`],
    /// [`DEFAULT_WORKGROUPS`] everywhere).
    pub round_workgroups: Option<u32>,
    /// Batches after which each workgroup leaves; the host then dispatches
    /// again until the work is done. `None`: no budget (one dispatch), except
    /// on drivers that cap loops, which get their default budget
    /// ([`Quirks::default_iteration_budget`](crate::Quirks::default_iteration_budget)).
    pub iteration_budget: Option<u32>,
    /// Host-side limit on one run.
    pub timeout: Duration,
    /// A directory for compiled pipelines kept across runs of the program
    /// (`None`, the default: nothing is read or written). One file per
    /// adapter, driver and module; at most
    /// [`pipeline_cache::MAX_FILES`](crate::pipeline_cache::MAX_FILES) files and
    /// [`pipeline_cache::MAX_BYTES`](crate::pipeline_cache::MAX_BYTES) bytes, the
    /// least recently used evicted. See
    /// [`Executor::pipeline_cache`](crate::Executor::pipeline_cache).
    pub pipeline_cache_dir: Option<PathBuf>,
}

impl Default for ExecutorConfig {
    fn default() -> Self {
        Self {
            capacities: Capacities::default(),
            workgroups: None,
            round_workgroups: None,
            iteration_budget: None,
            timeout: DEFAULT_TIMEOUT,
            pipeline_cache_dir: None,
        }
    }
}

impl ExecutorConfig {
    /// Persistent workgroups per megakernel dispatch on an adapter with
    /// `quirks`: [`ExecutorConfig::workgroups`] if set, else
    /// [`Quirks::megakernel_workgroups`] (one per CPU thread on drivers that
    /// run workgroups on CPU threads), else [`DEFAULT_WORKGROUPS`]. At least 1.
    pub fn megakernel_workgroups_on(&self, quirks: &Quirks) -> u32 {
        self.workgroups
            .or_else(|| quirks.megakernel_workgroups())
            .unwrap_or(DEFAULT_WORKGROUPS)
            .max(1)
    }

    /// Most workgroups per round dispatch, on every adapter:
    /// [`ExecutorConfig::round_workgroups`] if set, else
    /// [`ExecutorConfig::workgroups`], else [`DEFAULT_WORKGROUPS`] on every
    /// adapter. Each round workgroup strides over its share of a round's
    /// batches within one loop, so on llvmpipe few workgroups would spend the
    /// loop budget (2 ran into it even at 1 chunk per batch); many share the
    /// batches out, and none waits on another. At least 1.
    pub fn round_workgroups_or_default(&self) -> u32 {
        self.round_workgroups
            .or(self.workgroups)
            .unwrap_or(DEFAULT_WORKGROUPS)
            .max(1)
    }
}

/// Bytes a configuration allocates on the device.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct MemoryPlan {
    /// Queue slots.
    pub queue_bytes: u64,
    /// Per-workgroup staging of enqueued items.
    pub staging_bytes: u64,
    /// Counters (plus their read-back copy), per-slot range markers and the
    /// join pool.
    pub control_bytes: u64,
    /// Uniform configuration.
    pub config_bytes: u64,
    /// Everything together.
    pub total_bytes: u64,
}

impl CompiledGraph {
    /// The device memory `config` will allocate for this graph. Staging
    /// serves the larger of the two strategies' workgroup counts; a count
    /// left to the adapter is taken as [`DEFAULT_WORKGROUPS`], the most any
    /// adapter's default is.
    pub fn memory_plan(&self, config: &ExecutorConfig) -> MemoryPlan {
        let megakernel = config.workgroups.unwrap_or(DEFAULT_WORKGROUPS);
        let rounds = config
            .round_workgroups
            .or(config.workgroups)
            .unwrap_or(DEFAULT_WORKGROUPS);
        let workgroups = u64::from(megakernel.max(rounds));
        let queue_words: u64 = self
            .plan
            .queues
            .iter()
            .map(|q| u64::from(config.capacities.of(&q.name)) * u64::from(q.slot_words))
            .sum();
        // Both are arrays of vec4<u32>: at least one packet each.
        let queue_bytes = 4 * queue_words.max(4);
        let staging_bytes = 4 * (workgroups * u64::from(self.plan.stage_words)).max(4);
        // Counters (and their read-back copy), then two range markers per
        // queue slot (published and released ranges).
        let slots: u64 = self
            .plan
            .queues
            .iter()
            .map(|q| u64::from(config.capacities.of(&q.name)))
            .sum();
        let control_bytes = 2 * 4 * u64::from(self.plan.control_words())
            + 4 * 2 * slots
            + join_pool_bytes(&self.plan, config.capacities.join_pool.max(1));
        let config_bytes = uniform::bytes(self.plan.queues.len());
        MemoryPlan {
            queue_bytes,
            staging_bytes,
            control_bytes,
            config_bytes,
            total_bytes: queue_bytes + staging_bytes + control_bytes + config_bytes,
        }
    }
}

/// Bytes of a join pool of `records` records for `plan` (0 without joins).
pub(crate) fn join_pool_bytes(plan: &crate::plan::Plan, records: u32) -> u64 {
    if plan.joins.is_empty() {
        return 0;
    }
    4 * u64::from(records) * u64::from(crate::plan::joins::record_words(plan))
}
