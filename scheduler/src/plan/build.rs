//! The arithmetic that sizes a graph's queues: items per chunk and batch,
//! the staging room each queue needs, where it lies, and the shared scratch.

use std::collections::BTreeMap;

use crate::graph::Procedure;
use crate::plan::QueuePlan;
use crate::plan::layout::ItemLayout;

/// One queue plan per procedure, in declaration order, with its staging
/// region placed; and the staging words per workgroup. `targets` holds each
/// procedure's connections (target index and fan-out, merged), `layouts` the
/// checked item layouts by WGSL name. With `joins`, every slot also holds
/// the join its item runs under (`plan::joins`).
pub(crate) fn queue_plans(
    procedures: &[Procedure],
    targets: &[BTreeMap<usize, u32>],
    layouts: &BTreeMap<String, (String, ItemLayout)>,
    workgroup_size: u32,
    chunks_per_batch: u32,
    joins: bool,
) -> (Vec<QueuePlan>, u32) {
    let mut queues: Vec<QueuePlan> = procedures
        .iter()
        .enumerate()
        .map(|(i, p)| QueuePlan {
            name: p.name.clone(),
            item: p.item.wgsl_name.clone(),
            item_words: layouts[&p.item.wgsl_name].1.words,
            slot_words: if joins {
                crate::plan::joins::tagged_slot_words(layouts[&p.item.wgsl_name].1.words)
            } else {
                layouts[&p.item.wgsl_name].1.slot_words
            },
            threads_per_item: p.threads_per_item,
            items_per_workgroup: workgroup_size / p.threads_per_item,
            items_per_batch: workgroup_size / p.threads_per_item * chunks_per_batch,
            priority: p.priority,
            initial: p.initial,
            scratch_words: p.scratch_bytes.div_ceil(4),
            stage_offset: 0,
            stage_capacity: 0,
            targets: targets[i].iter().map(|(&t, &f)| (t, f)).collect(),
        })
        .collect();
    let stage_words = place_staging(&mut queues);
    (queues, stage_words)
}

/// Sizes and places every queue's staging region; returns the staging words
/// per workgroup. A queue's capacity is the most items any single source
/// batch (all its chunks) may stage into it.
fn place_staging(queues: &mut [QueuePlan]) -> u32 {
    for source in 0..queues.len() {
        let batch = queues[source].items_per_batch;
        for (t, fan_out) in queues[source].targets.clone() {
            queues[t].stage_capacity = queues[t].stage_capacity.max(batch.saturating_mul(fan_out));
        }
    }
    let mut stage_words = 0u32;
    for queue in queues {
        queue.stage_offset = stage_words;
        stage_words += queue.stage_capacity * queue.slot_words;
    }
    stage_words
}

/// Words of the one scratch region, sized by the largest procedure. Whether
/// it fits is measured on the module, with every other workgroup variable.
pub(crate) fn shared_scratch_words(queues: &[QueuePlan]) -> u32 {
    queues
        .iter()
        .map(|q| q.scratch_words.saturating_mul(q.items_per_workgroup))
        .max()
        .unwrap_or(0)
}
