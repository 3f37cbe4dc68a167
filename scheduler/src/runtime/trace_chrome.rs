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

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;
    use crate::{BatchRecord, SubmissionTrace};

    /// Two workgroups, two procedures, two submissions; the third batch
    /// leaves the fills as they were.
    fn trace() -> Trace {
        let record = |begin, end, workgroup, procedure, fills: [u32; 2], submission| BatchRecord {
            begin,
            end,
            workgroup,
            procedure,
            items: 8,
            first_ticket: 0,
            submission,
            round: 0,
            fills: fills.to_vec(),
        };
        Trace {
            graph: "g".into(),
            procedures: vec!["A".into(), "B".into()],
            capacity: 4,
            batches: 5,
            records: vec![
                record(0, 2, 0, 0, [3, 0], 0),
                record(1, 3, 1, 1, [2, 5], 0),
                record(2, 4, 0, 1, [2, 5], 1),
                record(3, 4, 1, 0, [0, 1], 1),
            ],
            submissions: vec![
                SubmissionTrace {
                    index: 0,
                    gpu_time: Some(Duration::from_micros(1500)),
                },
                SubmissionTrace {
                    index: 1,
                    gpu_time: None,
                },
            ],
        }
    }

    fn events<'a>(json: &'a Value, ph: &str) -> Vec<&'a Value> {
        json["traceEvents"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|e| e["ph"] == ph)
            .collect()
    }

    /// The fields the Trace Event Format asks of each kind of event.
    #[test]
    fn every_event_has_the_fields_of_its_kind() {
        let json: Value = serde_json::from_str(&trace().to_chrome_json()).unwrap();
        for event in json["traceEvents"].as_array().unwrap() {
            assert!(event["name"].is_string(), "{event}");
            assert!(event["pid"].is_u64(), "{event}");
            match event["ph"].as_str() {
                Some("X") => {
                    for field in ["tid", "ts", "dur"] {
                        assert!(event[field].is_u64(), "{field}: {event}");
                    }
                }
                Some("C") => {
                    assert!(event["ts"].is_u64(), "{event}");
                    let args = event["args"].as_object().unwrap();
                    assert!(args.values().all(Value::is_number), "{event}");
                }
                Some("M") => assert!(event["args"].is_object(), "{event}"),
                other => panic!("unexpected phase {other:?}: {event}"),
            }
        }
    }

    #[test]
    fn the_export_has_a_track_per_workgroup_a_counter_per_queue_and_the_submissions() {
        let json: Value = serde_json::from_str(&trace().to_chrome_json()).unwrap();
        let batches: Vec<_> = events(&json, "X")
            .into_iter()
            .filter(|e| e["cat"] == "batch")
            .collect();
        assert_eq!(batches.len(), 4);
        assert_eq!(batches[1]["name"], "B");
        assert_eq!(
            (&batches[1]["tid"], &batches[1]["ts"], &batches[1]["dur"]),
            (&json!(1), &json!(1), &json!(2))
        );
        assert_eq!(batches[1]["args"]["items"], 8);
        // Samples where a fill changed: A 3, 2, 0; B 0, 5, 1.
        let counters = events(&json, "C");
        let series = |name: &str| -> Vec<(u64, u64)> {
            counters
                .iter()
                .filter(|e| e["name"] == name)
                .map(|e| {
                    (
                        e["ts"].as_u64().unwrap(),
                        e["args"]["items"].as_u64().unwrap(),
                    )
                })
                .collect()
        };
        assert_eq!(series("fill A"), [(0, 3), (1, 2), (3, 0)]);
        assert_eq!(series("fill B"), [(0, 0), (1, 5), (3, 1)]);
        let names: Vec<_> = events(&json, "M")
            .iter()
            .filter(|e| e["name"] == "thread_name")
            .map(|e| e["args"]["name"].as_str().unwrap().to_owned())
            .collect();
        assert_eq!(names, ["workgroup 0", "workgroup 1"]);
        let submissions: Vec<_> = events(&json, "X")
            .into_iter()
            .filter(|e| e["cat"] == "submission")
            .collect();
        assert_eq!(submissions.len(), 2);
        assert_eq!(
            (&submissions[1]["ts"], &submissions[1]["dur"]),
            (&json!(2), &json!(2))
        );
        assert_eq!(submissions[0]["args"]["gpu_ms"], 1.5);
        assert_eq!(json["otherData"]["dropped"], 1);
    }
}
