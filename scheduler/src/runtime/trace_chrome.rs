//! A [`Trace`] in the Trace Event Format that `chrome://tracing` and Perfetto
//! open: process 1 holds a thread per workgroup with a complete event per
//! batch and a counter per queue for its fill; process 2 the submissions.
//! Timestamps are the logical clock's ticks, written as microseconds.

use std::collections::BTreeSet;

use serde_json::{Value, json};

use crate::Trace;

/// The process of the batches and the queue fills.
const BATCHES: u32 = 1;
/// The process of the submissions.
const SUBMISSIONS: u32 = 2;

/// The trace as a Trace Event Format object.
pub(crate) fn chrome_json(trace: &Trace) -> Value {
    let mut events = vec![
        metadata(
            "process_name",
            BATCHES,
            0,
            json!({ "name": format!("{}: batches (logical clock)", trace.graph) }),
        ),
        metadata("process_sort_index", BATCHES, 0, json!({ "sort_index": 0 })),
    ];
    let workgroups: BTreeSet<u32> = trace.records.iter().map(|r| r.workgroup).collect();
    for &w in &workgroups {
        events.push(metadata(
            "thread_name",
            BATCHES,
            w,
            json!({ "name": format!("workgroup {w}") }),
        ));
        events.push(metadata(
            "thread_sort_index",
            BATCHES,
            w,
            json!({ "sort_index": w }),
        ));
    }
    for record in &trace.records {
        events.push(json!({
            "name": trace.procedure_name(record),
            "cat": "batch",
            "ph": "X",
            "pid": BATCHES,
            "tid": record.workgroup,
            "ts": record.begin,
            "dur": record.end.saturating_sub(record.begin).max(1),
            "args": {
                "items": record.items,
                "first_ticket": record.first_ticket,
                "submission": record.submission,
                "round": record.round,
            },
        }));
    }
    // A counter per queue; a sample only where its fill changed.
    for (q, name) in trace.procedures.iter().enumerate() {
        let mut last = None;
        for (tick, fill) in trace.fill_samples(q) {
            if last != Some(fill) {
                events.push(json!({
                    "name": format!("fill {name}"),
                    "cat": "queue",
                    "ph": "C",
                    "pid": BATCHES,
                    "ts": tick,
                    "args": { "items": fill },
                }));
                last = Some(fill);
            }
        }
    }
    events.push(metadata(
        "process_name",
        SUBMISSIONS,
        0,
        json!({ "name": "submissions" }),
    ));
    events.push(metadata(
        "process_sort_index",
        SUBMISSIONS,
        0,
        json!({ "sort_index": 1 }),
    ));
    for submission in &trace.submissions {
        let ticks = trace
            .records
            .iter()
            .filter(|r| r.submission == submission.index);
        let (Some(begin), Some(end)) = (
            ticks.clone().map(|r| r.begin).min(),
            ticks.map(|r| r.end).max(),
        ) else {
            continue;
        };
        let gpu_ms = submission.gpu_time.map(|t| t.as_secs_f64() * 1e3);
        events.push(json!({
            "name": format!("submission {}", submission.index),
            "cat": "submission",
            "ph": "X",
            "pid": SUBMISSIONS,
            "tid": 0,
            "ts": begin,
            "dur": end.saturating_sub(begin).max(1),
            "args": { "gpu_ms": gpu_ms },
        }));
    }
    json!({
        "traceEvents": events,
        "displayTimeUnit": "ms",
        "otherData": {
            "graph": trace.graph,
            "clock": "logical: one tick per batch begun, shown as 1 us",
            "capacity": trace.capacity,
            "batches": trace.batches,
            "dropped": trace.dropped(),
        },
    })
}

fn metadata(name: &str, pid: u32, tid: u32, args: Value) -> Value {
    json!({ "name": name, "ph": "M", "pid": pid, "tid": tid, "args": args })
}
