//! Sequences of a TOML scene: `reyes render scene.toml --frames 1-240 -o
//! out/shot.####.png`. Every frame's still scene ([`Scene::frame`]) and
//! every output is made and checked, and the models are read once, before
//! the first frame renders; then each frame renders in turn through one
//! GPU renderer, whose pipelines every frame reuses ([`super::jobs`]).
//! `--skip-existing` skips the frames whose image is there, a line on
//! stderr says which frame of how many starts and when the run should end,
//! and a table on stdout sums the run up.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::BoxError;
use super::args::RenderArgs;
use super::frames::{FrameSelection, parse_frames};
use super::jobs::{Job, Plan, labelled, outputs};
use crate::aov::Aov;
use crate::model::Model;
use crate::output::console::{ConsoleError, outln};
use crate::scene::Scene;

/// The options of `reyes render` for sequences (not of `reyes view`, which
/// shows one frame).
#[derive(Debug, Default, clap::Args)]
pub(crate) struct SequenceArgs {
    /// The frames to render: of a TOML scene, any frame numbers (an
    /// animated scene shows time N / fps at frame N); of a RIB file, its
    /// `FrameBegin` numbers (as --frame). A number, a range `A-B`, every
    /// S-th frame of one `A-BxS`, or a list `1,5-9,20-40x2`; at most
    /// 100000 frames. Each frame's samples are drawn from its number, so
    /// it renders the same alone or in any range. Default: frame 1 of an
    /// animated scene, else the still scene.
    #[arg(long, value_name = "LIST", value_parser = parse_frames, conflicts_with = "frame")]
    pub(crate) frames: Option<FrameSelection>,
    /// Skip each frame (of a TOML sequence or a RIB file) whose image
    /// exists already (images are written whole, through a temporary file
    /// renamed into place, so an existing one is complete): resume an
    /// interrupted sequence.
    #[arg(long)]
    pub(crate) skip_existing: bool,
}

/// A TOML sequence's shared data: the models, read once for every frame.
pub(crate) struct SequenceSource {
    /// The scene file.
    pub(crate) path: PathBuf,
    /// The models of the scene's objects, in order.
    pub(crate) models: Vec<Model>,
    /// The model files read.
    pub(crate) model_files: Vec<PathBuf>,
    /// Whether the scene is animated: its frames' scenes were made with the
    /// command line's `--shutter` already.
    pub(crate) animated: bool,
}

/// The plan of the TOML scene at `path` rendered as the frames `selection`
/// names, or `None` for a still scene rendered once (no `--frames` and no
/// animation). Every frame's scene is made here, so a key that breaks a
/// frame fails the run before any frame renders.
pub(crate) fn plan_toml(
    args: &RenderArgs,
    path: &Path,
    selection: Option<&FrameSelection>,
) -> Result<Option<Plan>, BoxError> {
    let in_file = |error: BoxError| labelled(Some(&path.display().to_string()), error);
    let mut scene = match Scene::load(path) {
        Ok(scene) => scene,
        // Without --frames, the scene renders (and fails) as a still scene
        // always has, with the same messages.
        Err(_) if selection.is_none() => return Ok(None),
        Err(error) => return Err(in_file(error.into())),
    };
    if selection.is_none() && !scene.is_animated() {
        return Ok(None);
    }
    if scene.is_animated() {
        let moved = [
            ("--spin", args.spin.is_some()),
            ("--move", args.move_by.is_some()),
            ("--camera-move", args.camera_move.is_some()),
            ("--camera-pan", args.camera_pan.is_some()),
        ];
        if let Some((flag, _)) = moved.iter().find(|(_, given)| *given) {
            return Err(format!(
                "{flag}: {} is animated, and its keys make the motion of each frame's shutter; animate with keys instead",
                path.display()
            )
            .into());
        }
        // The frames' poses at shutter close follow from the shutter.
        if let Some(shutter) = args.shutter {
            scene.shutter = shutter;
            scene.validate().map_err(|e| in_file(e.into()))?;
        }
    }
    let numbers = selection.map_or_else(|| vec![1], FrameSelection::numbers);
    let several = numbers.len() > 1;
    let mut jobs = Vec::with_capacity(numbers.len());
    for &number in &numbers {
        let label = format!("frame {number}");
        let still = scene
            .frame(number)
            .map_err(|e| in_file(labelled(Some(&label), e.into())))?;
        let depth = args.aov.unwrap_or(still.aov) == Aov::Z;
        let outputs = outputs(args, None, Some(number), several, depth)?;
        jobs.push(Job::of_sequence(label, outputs, still));
    }
    // Read once, for every frame: a missing model fails the run now.
    let models = scene.load_models().map_err(|e| in_file(e.into()))?;
    Ok(Some(Plan::of_sequence(
        jobs,
        SequenceSource {
            path: path.to_path_buf(),
            models,
            model_files: scene.model_files(),
            animated: scene.is_animated(),
        },
    )))
}

/// What became of one frame of a sequence.
enum Outcome {
    Rendered { time: Duration, micropolygons: u64 },
    Skipped,
    Failed { time: Duration },
}

/// The progress and the summary of a sequence's frames.
pub(crate) struct SequenceReport {
    started: Instant,
    total: usize,
    rows: Vec<(String, Outcome)>,
}

impl SequenceReport {
    /// The report of a run of `total` frames, starting now.
    pub(crate) fn new(total: usize) -> SequenceReport {
        SequenceReport {
            started: Instant::now(),
            total,
            rows: Vec::new(),
        }
    }

    /// The line that says frame `label` starts: which of how many, the
    /// time so far, and the time left at the mean time of the frames
    /// rendered so far.
    pub(crate) fn start_line(&self, label: &str) -> String {
        let k = self.rows.len() + 1;
        let elapsed = self.started.elapsed();
        let rendered: Vec<Duration> = self
            .rows
            .iter()
            .filter_map(|(_, o)| match o {
                Outcome::Rendered { time, .. } | Outcome::Failed { time } => Some(*time),
                Outcome::Skipped => None,
            })
            .collect();
        let eta = if rendered.is_empty() {
            String::new()
        } else {
            let mean = rendered.iter().sum::<Duration>() / rendered.len() as u32;
            let left = mean * (self.total - self.rows.len()) as u32;
            format!(", ETA {}", clock(left))
        };
        format!(
            "{label}: {k} of {} (elapsed {}{eta})",
            self.total,
            clock(elapsed)
        )
    }

    /// Records a rendered frame.
    pub(crate) fn rendered(&mut self, label: &str, time: Duration, micropolygons: u64) {
        let outcome = Outcome::Rendered {
            time,
            micropolygons,
        };
        self.rows.push((label.to_owned(), outcome));
    }

    /// Records a frame skipped because its image exists.
    pub(crate) fn skipped(&mut self, label: &str) {
        self.rows.push((label.to_owned(), Outcome::Skipped));
    }

    /// Records a frame that failed after `time`.
    pub(crate) fn failed(&mut self, label: &str, time: Duration) {
        self.rows.push((label.to_owned(), Outcome::Failed { time }));
    }

    /// Prints the summary table on standard output: a row per frame (its
    /// time and micropolygons, or that it was skipped or failed) and the
    /// totals.
    pub(crate) fn print(&self) -> Result<(), ConsoleError> {
        outln!(
            "{:<14} {:>10} {:>14}  status",
            "frame",
            "time",
            "micropolygons"
        )?;
        let (mut rendered, mut skipped, mut failed) = (0, 0, 0);
        let mut micropolygons_total = 0u64;
        for (label, outcome) in &self.rows {
            let (time, micropolygons, status) = match outcome {
                Outcome::Rendered {
                    time,
                    micropolygons,
                } => {
                    rendered += 1;
                    micropolygons_total += micropolygons;
                    (seconds(*time), micropolygons.to_string(), "rendered")
                }
                Outcome::Skipped => {
                    skipped += 1;
                    ("-".into(), "-".into(), "skipped (exists)")
                }
                Outcome::Failed { time } => {
                    failed += 1;
                    (seconds(*time), "-".into(), "FAILED")
                }
            };
            outln!("{label:<14} {time:>10} {micropolygons:>14}  {status}")?;
        }
        let not_reached = self.total - self.rows.len();
        let mut total = format!(
            "{} frames: {rendered} rendered, {skipped} skipped, {failed} failed",
            self.total
        );
        if not_reached > 0 {
            total.push_str(&format!(", {not_reached} not rendered"));
        }
        outln!(
            "{total} in {} ({micropolygons_total} micropolygons)",
            clock(self.started.elapsed())
        )
    }
}

/// `d` in seconds with milliseconds: `1.234 s`.
fn seconds(d: Duration) -> String {
    format!("{:.3} s", d.as_secs_f64())
}

/// `d` as `h:mm:ss` (or `m:ss` under an hour).
fn clock(d: Duration) -> String {
    let s = d.as_secs();
    if s >= 3600 {
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    } else {
        format!("{}:{:02}", s / 60, s % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_eta_is_the_mean_frame_time_times_the_frames_left() {
        let mut report = SequenceReport::new(5);
        assert_eq!(&report.start_line("frame 1")[..17], "frame 1: 1 of 5 (");
        assert!(!report.start_line("frame 1").contains("ETA"));
        report.rendered("frame 1", Duration::from_secs(10), 7);
        report.skipped("frame 2");
        report.failed("frame 3", Duration::from_secs(30));
        // Two frames timed, 20 s on average; two frames left.
        let line = report.start_line("frame 4");
        assert!(line.starts_with("frame 4: 4 of 5"), "{line}");
        assert!(line.ends_with("ETA 0:40)"), "{line}");
    }

    #[test]
    fn clocks_read_as_minutes_or_hours() {
        assert_eq!(clock(Duration::from_secs(59)), "0:59");
        assert_eq!(clock(Duration::from_secs(61)), "1:01");
        assert_eq!(clock(Duration::from_secs(3723)), "1:02:03");
    }
}
