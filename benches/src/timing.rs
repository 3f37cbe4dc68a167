//! Where a time comes from, and the median of several runs.

use std::time::Duration;

/// How a run was timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimeSource {
    /// GPU timestamp queries at the beginning and end of the compute pass.
    GpuTimestamps,
    /// Host wall time around submit and wait (no `TIMESTAMP_QUERY`).
    WallClock,
}

impl TimeSource {
    /// A short label for tables.
    pub fn label(self) -> &'static str {
        match self {
            Self::GpuTimestamps => "gpu-ts",
            Self::WallClock => "wall",
        }
    }
}

/// Converts a pair of raw timestamps to a duration.
pub fn timestamp_delta(begin: u64, end: u64, period_ns: f64) -> Duration {
    let ticks = end.saturating_sub(begin) as f64;
    Duration::from_nanos((ticks * period_ns) as u64)
}

/// Summary of the timed runs of one variant.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Timings {
    /// Every timed run, in order.
    #[serde(serialize_with = "ms_list")]
    pub runs: Vec<Duration>,
    /// Their median (mean of the middle two for an even count).
    #[serde(serialize_with = "ms")]
    pub median: Duration,
    /// The fastest run.
    #[serde(serialize_with = "ms")]
    pub min: Duration,
    /// The slowest run.
    #[serde(serialize_with = "ms")]
    pub max: Duration,
    /// How the runs were timed.
    pub source: TimeSource,
    /// Median host wall time from submission to completion (includes the
    /// host round trips between megakernel dispatches, unlike `median`).
    #[serde(serialize_with = "ms")]
    pub wall_median: Duration,
}

impl Timings {
    /// Summarises `runs` and the matching host wall times `walls`.
    pub fn new(runs: Vec<Duration>, walls: &[Duration], source: TimeSource) -> Self {
        let mut sorted = runs.clone();
        sorted.sort();
        let mut walls = walls.to_vec();
        walls.sort();
        Self {
            wall_median: median(&walls),
            median: median(&sorted),
            min: sorted.first().copied().unwrap_or_default(),
            max: sorted.last().copied().unwrap_or_default(),
            runs,
            source,
        }
    }
}

/// The median of sorted durations (zero for none).
pub fn median(sorted: &[Duration]) -> Duration {
    match sorted.len() {
        0 => Duration::ZERO,
        n if n % 2 == 1 => sorted[n / 2],
        n => (sorted[n / 2 - 1] + sorted[n / 2]) / 2,
    }
}

fn ms<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64() * 1e3)
}

fn ms_list<S: serde::Serializer>(d: &[Duration], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(d.iter().map(|d| d.as_secs_f64() * 1e3))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        let ms = Duration::from_millis;
        assert_eq!(median(&[ms(1), ms(2), ms(9)]), ms(2));
        assert_eq!(median(&[ms(1), ms(3), ms(5), ms(9)]), ms(4));
        let t = Timings::new(vec![ms(5), ms(1), ms(3)], &[ms(2)], TimeSource::WallClock);
        assert_eq!((t.min, t.median, t.max), (ms(1), ms(3), ms(5)));
    }
}
