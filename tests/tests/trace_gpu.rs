//! Tracing: a traced run records exactly the batches its report counts, under
//! both strategies; the buffer keeps the first batches and counts the rest;
//! the Chrome export of a real run parses; an untraced module holds no trace
//! code.

use std::collections::{BTreeMap, BTreeSet};

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    CompileOptions, Executor, ExecutorConfig, Retry, RunReport, Seeds, Strategy, Trace,
    TraceOptions,
};
use tests::config;
use tests::graphs::{Node, PingPongIds, WithIds, ping_pong, ping_pong_counts};

/// The ping-pong graph with random seeds (the seed is printed).
fn workload(test: &str) -> (WithIds<PingPongIds>, Vec<Node>, (u64, u64)) {
    let mut rng = StdRng::seed_from_u64(tests::seed(test));
    let depth = rng.random_range(4..=7);
    // More seeds than the 16-item queues of the retried run hold.
    let seeds: Vec<Node> = (0..rng.random_range(17..200))
        .map(|_| Node {
            depth: 0,
            id: rng.random(),
        })
        .collect();
    let counts = ping_pong_counts(depth, &seeds);
    (ping_pong(depth), seeds, counts)
}

fn run(
    graph: &WithIds<PingPongIds>,
    seeds: &[Node],
    capacity: u32,
    workgroups: u32,
    strategy: Strategy,
) -> RunReport {
    let gpu = tests::gpu();
    let options = CompileOptions::default().traced(TraceOptions { capacity });
    let compiled = graph.compile(&options).unwrap();
    let mut executor = Executor::new(
        &gpu.device,
        &gpu.queue,
        &compiled,
        &config(workgroups, 1 << 15),
    )
    .unwrap();
    executor
        .run_with(strategy, &Seeds::new().add(&graph.ids.ping, seeds), &[])
        .unwrap()
}

/// What every complete trace of a run satisfies.
fn check_complete(trace: &Trace, report: &RunReport, items_per_batch: u32) {
    let context = format!("{report}");
    assert_eq!(trace.dropped(), 0, "{context}");
    assert_eq!(trace.records.len() as u64, trace.batches, "{context}");
    for p in &report.procedures {
        assert_eq!(trace.items_of(&p.name), p.executed, "{}: {context}", p.name);
    }
    // One tick per batch: the begin ticks are 0..batches, each once.
    let ticks: Vec<u32> = trace.records.iter().map(|r| r.begin).collect();
    let expected: Vec<u32> = (0..trace.records.len() as u32).collect();
    assert_eq!(ticks, expected, "{context}");
    // Per workgroup, batches follow each other: each begins after the
    // previous one ended.
    let mut last_end: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for r in &trace.records {
        assert!(r.end > r.begin, "{r:?}");
        assert!((1..=items_per_batch).contains(&r.items), "{r:?}");
        assert_eq!(r.fills.len(), report.procedures.len(), "{r:?}");
        assert!(r.workgroup < report.workgroups, "{r:?}");
        // Workgroup indices restart at every dispatch (a round, a submission).
        let key = (r.workgroup, r.submission * 1000 + r.round);
        if let Some(&end) = last_end.get(&key) {
            assert!(r.begin >= end, "{r:?} after an end at {end}");
        }
        last_end.insert(key, r.end);
    }
    let submissions: BTreeSet<u32> = trace.records.iter().map(|r| r.submission).collect();
    assert!(
        submissions.iter().all(|&s| s < report.submissions),
        "{submissions:?}: {context}"
    );
    assert_eq!(trace.submissions.len() as u32, report.submissions);
}

#[gpu_test]
fn a_trace_holds_exactly_the_batches_of_the_run_under_both_strategies() {
    let (graph, seeds, (pings, pongs)) = workload("trace_exact");
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        for workgroups in [1, 4] {
            let report = run(&graph, &seeds, 1 << 16, workgroups, strategy);
            let ping = report.procedure(&graph.ids.ping).unwrap();
            let pong = report.procedure(&graph.ids.pong).unwrap();
            assert_eq!((ping.executed, pong.executed), (pings, pongs));
            let trace = report.trace().expect("a traced run has a trace");
            check_complete(trace, &report, 256);
            if let Strategy::Rounds { .. } = strategy {
                // Every round that found work ran batches, and only those.
                let rounds: BTreeSet<u32> = trace.records.iter().map(|r| r.round).collect();
                let expected: BTreeSet<u32> = (1..=report.rounds).collect();
                assert_eq!(rounds, expected, "{report}");
            } else {
                assert!(trace.records.iter().all(|r| r.round == 0));
            }
            // The Chrome export of the run: a complete event per batch.
            let json: serde_json::Value = serde_json::from_str(&trace.to_chrome_json()).unwrap();
            let events = json["traceEvents"].as_array().unwrap();
            let batches = events
                .iter()
                .filter(|e| e["ph"] == "X" && e["cat"] == "batch")
                .count();
            assert_eq!(batches, trace.records.len());
        }
    }
}

#[gpu_test]
fn a_small_trace_buffer_keeps_the_first_batches_and_counts_the_rest() {
    let (graph, seeds, _) = workload("trace_dropped");
    // Rounds run the same batches every time: compare a full trace with a
    // short one.
    let full = run(&graph, &seeds, 1 << 16, 2, Strategy::rounds());
    let full = full.trace().unwrap();
    let batches = full.batches;
    assert!(batches >= 2, "{batches} batches");
    let capacity =
        StdRng::seed_from_u64(tests::seed("trace_capacity")).random_range(1..batches) as u32;
    let short = run(&graph, &seeds, capacity, 2, Strategy::rounds());
    let short = short.trace().unwrap();
    assert_eq!(short.batches, batches);
    assert_eq!(short.records.len() as u32, capacity);
    assert_eq!(short.dropped(), batches - u64::from(capacity));
    let first: Vec<u32> = short.records.iter().map(|r| r.begin).collect();
    assert_eq!(first, (0..capacity).collect::<Vec<_>>());
}

#[gpu_test]
fn an_untraced_run_has_no_trace_and_its_module_no_trace_code() {
    let (graph, seeds, _) = workload("trace_off");
    let gpu = tests::gpu();
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    assert!(
        !compiled.wgsl().contains("sched_trace"),
        "{}",
        compiled.wgsl()
    );
    let traced = graph
        .compile(&CompileOptions::default().traced(TraceOptions::default()))
        .unwrap();
    assert!(traced.wgsl().contains("sched_trace_begin"));
    let mut executor =
        Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 1 << 15)).unwrap();
    let report = executor
        .run(&Seeds::new().add(&graph.ids.ping, &seeds), &[])
        .unwrap();
    assert!(report.trace().is_none());
}

/// A megakernel run of several submissions (an iteration budget of one batch
/// per workgroup), and a run retried after an overflow (the queues, and with
/// them the trace's place in the control buffer, grow): the trace is that of
/// the whole last attempt, with every submission's batches.
#[gpu_test]
fn a_trace_spans_every_submission_and_the_last_attempt_of_a_retried_run() {
    let (graph, seeds, (pings, pongs)) = workload("trace_submissions");
    let gpu = tests::gpu();
    let options = CompileOptions::default().traced(TraceOptions::default());
    let compiled = graph.compile(&options).unwrap();
    let seeds = Seeds::new().add(&graph.ids.ping, &seeds);

    let budget = ExecutorConfig {
        iteration_budget: Some(1),
        ..config(2, 1 << 15)
    };
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &budget).unwrap();
    let report = executor
        .run_with(Strategy::Megakernel, &seeds, &[])
        .unwrap();
    assert!(report.submissions > 1, "{report}");
    let trace = report.trace().unwrap();
    check_complete(trace, &report, 256);
    let submissions: BTreeSet<u32> = trace.records.iter().map(|r| r.submission).collect();
    assert_eq!(submissions.len() as u32, report.submissions, "{report}");

    let mut small = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 16)).unwrap();
    let report = small
        .run_with_retry(Strategy::Megakernel, &seeds, &[], Retry::without_reset(12))
        .unwrap();
    assert!(report.attempts > 1, "{report}");
    let ping = report.procedure(&graph.ids.ping).unwrap();
    let pong = report.procedure(&graph.ids.pong).unwrap();
    assert_eq!((ping.executed, pong.executed), (pings, pongs));
    check_complete(report.trace().unwrap(), &report, 256);
}
