//! The compiled shape of a graph: one queue per procedure with its constants.
//! Shared by the code generator and the runtime so both agree on every number.
//!
//! This layer is pure data and arithmetic about *what* to build: it knows no
//! WGSL text (that is `codegen`) and no naga checks (that is `compile`).

pub(crate) mod build;
pub(crate) mod checked;
pub(crate) mod control;
pub(crate) mod fan_out;
pub(crate) mod joins;
pub(crate) mod layout;

use crate::{Policy, Resource};

/// One procedure's queue as compiled.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct QueuePlan {
    /// Procedure name.
    pub name: String,
    /// WGSL item type name.
    pub item: String,
    /// Item size in 32-bit words (naga's array stride / 4).
    pub item_words: u32,
    /// Words of one slot, in the queue and in staging: `item_words` rounded
    /// up to whole `vec4<u32>` packets, the unit items move in.
    pub slot_words: u32,
    /// Threads that run one item.
    pub threads_per_item: u32,
    /// Items in one chunk, the body's call: workgroup size / threads per item.
    pub items_per_workgroup: u32,
    /// Items one workgroup claims at once: `items_per_workgroup` times the
    /// chunks per batch.
    pub items_per_batch: u32,
    /// Scheduling priority.
    pub priority: i32,
    /// Whether the host may seed it.
    pub initial: bool,
    /// Scratch words per item.
    pub scratch_words: u32,
    /// First staging word of this queue inside a workgroup's staging area.
    pub stage_offset: u32,
    /// Items one workgroup can stage for this queue per batch.
    pub stage_capacity: u32,
    /// Queues this procedure may enqueue into, with fan-outs.
    pub targets: Vec<(usize, u32)>,
}

/// The whole compiled shape.
#[derive(Clone, Debug)]
pub(crate) struct Plan {
    pub graph_name: String,
    pub workgroup_size: u32,
    /// Chunks (workgroup-fulls of items) per batch.
    pub chunks_per_batch: u32,
    pub policy: Policy,
    pub queues: Vec<QueuePlan>,
    /// Queue indices in the order a workgroup scans them.
    pub scan_order: Vec<usize>,
    /// Staging words per workgroup.
    pub stage_words: u32,
    /// Words of the shared scratch region.
    pub scratch_words: u32,
    pub resources: Vec<Resource>,
    /// Whether bodies or the library call the item-wide helpers.
    pub item_helpers: bool,
    pub features: wgpu::Features,
    /// Checked mode: indices into runtime-sized array resources are guarded.
    pub checked: bool,
    /// Tracing: the trace buffer's capacity in records (`None`: off).
    pub trace: Option<crate::TraceOptions>,
    /// The kinds of join, one per continuation (empty without joins).
    pub joins: Vec<joins::JoinPlan>,
}

impl Plan {
    /// The resources checked mode guards (none without it), in declaration
    /// order; a guard's number is its position here.
    pub(crate) fn guarded_resources(&self) -> Vec<&str> {
        if !self.checked {
            return Vec::new();
        }
        self.resources
            .iter()
            .filter(|r| checked::guarded(r))
            .map(|r| r.name())
            .collect()
    }

    /// Control words the host reads back: the counters, then checked mode's
    /// words per procedure and guarded resource, its per-item fan-out words
    /// per procedure, and the joins' words.
    pub(crate) fn control_words(&self) -> u32 {
        joins::first_word(self) + joins::words(self)
    }

    pub(crate) fn queue_index(&self, name: &str) -> Option<usize> {
        self.queues.iter().position(|q| q.name == name)
    }

    /// Fixed order in which workgroups scan queues. Priority: highest first,
    /// ties by declaration. Round-robin: declaration order (rotated at run time).
    pub(crate) fn compute_scan_order(queues: &[QueuePlan], policy: Policy) -> Vec<usize> {
        let mut order: Vec<usize> = (0..queues.len()).collect();
        if policy == Policy::Priority {
            order.sort_by_key(|&q| (std::cmp::Reverse(queues[q].priority), q));
        }
        order
    }
}
