//! The trace of a run ([`CompileOptions::trace`](crate::CompileOptions::trace)):
//! one record per batch, with a logical timestamp and the queue fills, and the
//! GPU time of each submission. Read back by `trace_run`, exported by
//! `trace_chrome` (docs/scheduler.md, "Seeing a run").

use std::path::Path;
use std::time::Duration;

use crate::codegen::trace::{FIELDS, HEADER_WORDS, record_words};

/// One batch: a workgroup ran `items` items of one procedure.
///
/// Times are ticks of a logical clock that counts the batches begun in the
/// run, on all workgroups: each batch takes the next tick (unique), and its
/// end is the clock when it ended, so `end - begin` is the number of batches
/// begun while it ran (at least 1).
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct BatchRecord {
    /// The tick the batch began at; also its place in the run's order.
    pub begin: u32,
    /// The clock when the batch ended (greater than `begin`).
    pub end: u32,
    /// The workgroup that ran it (its index in its dispatch).
    pub workgroup: u32,
    /// The procedure, as its index in [`Trace::procedures`].
    pub procedure: u32,
    /// Items taken.
    pub items: u32,
    /// The queue ticket of the first item taken.
    pub first_ticket: u32,
    /// The submission it ran in (0 for the first).
    pub submission: u32,
    /// Under the Rounds strategy, the rounds that had found work before the
    /// one it ran in; 0 under the megakernel.
    pub round: u32,
    /// The fill of every queue (declaration order) when the batch began:
    /// items reserved and not yet claimed. Under the megakernel, right after
    /// this batch's claim; under Rounds, a queue's fill counts its running
    /// round's items and those queued for the next round.
    pub fills: Vec<u32>,
}

/// One submission of the run.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SubmissionTrace {
    /// Its index (the records' [`BatchRecord::submission`]).
    pub index: u32,
    /// Its GPU time from timestamp queries, when the device has them.
    pub gpu_time: Option<Duration>,
}

/// What a traced run recorded ([`RunReport::trace`](crate::RunReport::trace)).
///
/// The buffer keeps the first [`Trace::capacity`] batches of the run (not a
/// ring: the start of a run, where the queues fill, is kept whole); the later
/// ones are counted in [`Trace::batches`] and [`Trace::dropped`].
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Trace {
    /// The graph's name.
    pub graph: String,
    /// Procedure names, in declaration order.
    pub procedures: Vec<String>,
    /// Records the buffer holds.
    pub capacity: u32,
    /// Batches the run began, recorded or not.
    pub batches: u64,
    /// The recorded batches, by begin tick.
    pub records: Vec<BatchRecord>,
    /// Every submission of the run, in order.
    pub submissions: Vec<SubmissionTrace>,
}

impl Trace {
    /// Batches that did not fit into the buffer.
    pub fn dropped(&self) -> u64 {
        self.batches.saturating_sub(self.records.len() as u64)
    }

    /// The name of a record's procedure (`?` for an index out of range).
    pub fn procedure_name(&self, record: &BatchRecord) -> &str {
        self.procedures
            .get(record.procedure as usize)
            .map_or("?", String::as_str)
    }

    /// Items taken by the procedure called `name` in the recorded batches.
    pub fn items_of(&self, name: &str) -> u64 {
        let Some(index) = self.procedures.iter().position(|p| p == name) else {
            return 0;
        };
        self.records
            .iter()
            .filter(|r| r.procedure as usize == index)
            .map(|r| u64::from(r.items))
            .sum()
    }

    /// The fill of queue `queue` over logical time: (begin tick, fill) of
    /// every record.
    pub fn fill_samples(&self, queue: usize) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.records
            .iter()
            .filter_map(move |r| r.fills.get(queue).map(|&fill| (r.begin, fill)))
    }

    /// The trace in the Trace Event Format (Chrome's `chrome://tracing`,
    /// Perfetto): a track per workgroup with a complete event (`"X"`) per
    /// batch, a counter (`"C"`) per queue for its fill, and a track of the
    /// submissions with their GPU times. Timestamps are logical ticks, shown
    /// as microseconds.
    pub fn to_chrome_json(&self) -> String {
        crate::runtime::trace_chrome::chrome_json(self).to_string()
    }

    /// Writes [`Trace::to_chrome_json`] to `path`.
    pub fn write_chrome_trace(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        std::fs::write(path, self.to_chrome_json())
    }

    /// The trace from the words of the trace buffer: the header, then the
    /// records.
    pub(crate) fn from_words(
        graph: &str,
        procedures: Vec<String>,
        capacity: u32,
        words: &[u32],
        submissions: Vec<SubmissionTrace>,
    ) -> Self {
        let batches = words.first().copied().unwrap_or(0);
        let queues = procedures.len();
        let stride = record_words(queues) as usize;
        let kept = batches.min(capacity) as usize;
        let body = words.get(HEADER_WORDS as usize..).unwrap_or(&[]);
        let records = body
            .chunks_exact(stride)
            .take(kept)
            .map(|w| BatchRecord {
                begin: w[0],
                end: w[1],
                workgroup: w[2],
                procedure: w[3],
                items: w[4],
                first_ticket: w[5],
                submission: w[6],
                round: w[7],
                fills: w[FIELDS.len()..].to_vec(),
            })
            .collect();
        Self {
            graph: graph.to_owned(),
            procedures,
            capacity,
            batches: u64::from(batches),
            records,
            submissions,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_become_records_and_the_overflow_is_counted() {
        let stride = record_words(2) as usize;
        let mut words = vec![0u32; HEADER_WORDS as usize + 2 * stride];
        words[0] = 5; // five batches began, two fit
        for r in 0..2u32 {
            let at = HEADER_WORDS as usize + r as usize * stride;
            let record = [r, r + 2, 7, r, 32, 64 * r, 0, 0, 10 + r, 20 + r];
            words[at..at + stride].copy_from_slice(&record);
        }
        let trace = Trace::from_words("g", vec!["A".into(), "B".into()], 2, &words, Vec::new());
        assert_eq!(trace.records.len(), 2);
        assert_eq!(trace.dropped(), 3);
        assert_eq!(trace.records[1].fills, [11, 21]);
        assert_eq!(trace.procedure_name(&trace.records[1]), "B");
        assert_eq!(trace.items_of("A"), 32);
        assert_eq!(
            trace.fill_samples(1).collect::<Vec<_>>(),
            [(0, 20), (1, 21)]
        );
    }
}
