//! Megakernel vs. Rounds (kernel-by-kernel) over the same compiled graph,
//! under each queue policy: the comparison Whippletree is about.
//!
//! A [`StrategyRow`] holds both strategies measured side by side in one
//! process on one workload and policy; [`format_strategy_table`] prints them
//! with the ratio. Each workload builds its rows with
//! [`Measured::from_samples`], so the spawn tree here and the Reyes frames
//! (`crate::reyes_strategies`) share the table.

use std::fmt::Write;
use std::time::Duration;

use scheduler::{Capacities, ExecutorConfig, Gpu, Policy, RunReport, Strategy};

use crate::BenchError;
use crate::megakernel::{SpawnTree, check_counters, compile_with_policy};
use crate::timing::TimeSource;
use crate::workload::Workload;

/// One strategy's figures on one workload: the median run's time and what it
/// reported.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Measured {
    /// Median time over the timed runs.
    pub median: Duration,
    /// Where the times come from.
    pub source: TimeSource,
    /// Largest queue high-water mark of the median run, over all procedures.
    pub high_water: u64,
    /// Sum of the procedures' high-water marks (the queue memory in use at
    /// their peaks, in items).
    pub high_water_sum: u64,
    /// Submissions of the median run (megakernel dispatches or batches of
    /// rounds).
    pub submissions: u32,
    /// Rounds that found work (Rounds only).
    pub rounds: u32,
}

impl Measured {
    /// The median of `samples` (time, report), with that run's counters.
    pub fn from_samples(samples: &[(Duration, RunReport)], source: TimeSource) -> Self {
        let mut times: Vec<Duration> = samples.iter().map(|(t, _)| *t).collect();
        times.sort();
        let median = times[times.len() / 2];
        let report = &samples
            .iter()
            .find(|(t, _)| *t == median)
            .expect("the median is one of the samples")
            .1;
        Self {
            median,
            source,
            high_water: report
                .procedures
                .iter()
                .map(|p| p.high_water)
                .max()
                .unwrap_or(0),
            high_water_sum: report.procedures.iter().map(|p| p.high_water).sum(),
            submissions: report.submissions,
            rounds: report.rounds,
        }
    }
}

/// Both strategies on one workload under one policy.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StrategyRow {
    /// What ran.
    pub workload: String,
    /// The queue policy compiled for.
    pub policy: Policy,
    /// The persistent megakernel.
    pub megakernel: Measured,
    /// Kernel-by-kernel rounds.
    pub rounds: Measured,
}

impl StrategyRow {
    /// Rounds time over megakernel time: above 1, the megakernel is faster.
    pub fn speedup(&self) -> f64 {
        self.rounds.median.as_secs_f64() / self.megakernel.median.as_secs_f64().max(1e-12)
    }
}

/// Times the spawn tree of `workload` under `policy` with both strategies:
/// one verified warm-up each, then `runs` timed runs, alternating strategies
/// so that both see the same machine state.
pub fn measure_spawn_tree(
    gpu: &Gpu,
    workload: Workload,
    policy: Policy,
    workgroups: Option<u32>,
    runs: u32,
) -> Result<StrategyRow, BenchError> {
    let expected = workload.reference();
    let compiled = compile_with_policy(&workload, &gpu.device, policy)?;
    let config = ExecutorConfig {
        workgroups,
        capacities: Capacities::uniform(workload.items()),
        ..ExecutorConfig::default()
    };
    let strategies = [Strategy::Megakernel, Strategy::rounds()];
    let mut trees = Vec::new();
    for strategy in strategies {
        let mut tree = SpawnTree::new(&gpu.device, &gpu.queue, &compiled, workload, &config)?;
        tree.set_strategy(strategy);
        tree.run_verified(&expected, &format!("spawn tree, {strategy}, {policy:?}"))?;
        trees.push(tree);
    }
    let mut samples: [Vec<(Duration, RunReport)>; 2] = [Vec::new(), Vec::new()];
    let mut sources = [TimeSource::GpuTimestamps; 2];
    for _ in 0..runs {
        for (i, tree) in trees.iter_mut().enumerate() {
            let (sample, source) = tree.run()?;
            check_counters(&sample.report, workload.items(), strategies[i].name())?;
            if source == TimeSource::WallClock {
                sources[i] = source;
            }
            samples[i].push((sample.time, sample.report));
        }
    }
    Ok(StrategyRow {
        workload: format!(
            "spawn tree 2^{}, work {}",
            workload.items_log2, workload.work
        ),
        policy,
        megakernel: Measured::from_samples(&samples[0], sources[0]),
        rounds: Measured::from_samples(&samples[1], sources[1]),
    })
}

/// The rows as one table.
pub fn format_strategy_table(rows: &[StrategyRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<30}{:<12}{:>13}{:>11}{:>9}{:>14}{:>14}{:>8}  timer",
        "workload",
        "policy",
        "megakernel ms",
        "rounds ms",
        "speedup",
        "high-water MK",
        "high-water R",
        "rounds",
    );
    for row in rows {
        let _ = writeln!(s, "{}", format_strategy_row(row));
    }
    s
}

/// One table line.
pub fn format_strategy_row(row: &StrategyRow) -> String {
    let ms = |d: Duration| format!("{:.2}", d.as_secs_f64() * 1e3);
    let policy = match row.policy {
        Policy::Priority => "priority",
        Policy::RoundRobin => "round-robin",
    };
    format!(
        "{:<30}{:<12}{:>13}{:>11}{:>9.2}{:>14}{:>14}{:>8}  {}",
        row.workload,
        policy,
        ms(row.megakernel.median),
        ms(row.rounds.median),
        row.speedup(),
        row.megakernel.high_water_sum,
        row.rounds.high_water_sum,
        row.rounds.rounds,
        row.megakernel.source.label(),
    )
}
