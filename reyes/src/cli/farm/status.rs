//! `reyes farm status`: which frames of a sequence have their image, and
//! the commands that render only the missing ones.

use super::{Sequence, SequenceSpec, shell_command, text};
use crate::cli::BoxError;
use crate::cli::frames::FrameSelection;
use crate::output::console::outln;

/// `reyes farm status`'s arguments.
#[derive(Debug, clap::Args)]
pub(crate) struct StatusArgs {
    #[command(flatten)]
    spec: SequenceSpec,
}

/// What `reyes farm status` found.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct Status {
    /// The frames with an image.
    pub(crate) done: Vec<u32>,
    /// The frames without one.
    pub(crate) missing: Vec<u32>,
}

/// The frames of `sequence` with and without an image. Images are
/// written whole (a temporary file renamed into place), so an image that
/// exists is complete.
pub(crate) fn find(sequence: &Sequence) -> Result<Status, BoxError> {
    let mut status = Status {
        done: Vec::new(),
        missing: Vec::new(),
    };
    for &number in &sequence.numbers {
        if sequence.image(number)?.is_file() {
            status.done.push(number);
        } else {
            status.missing.push(number);
        }
    }
    Ok(status)
}

/// The report of `status`: the counts, the missing frames, and the
/// commands that render only those (here, and on Slurm).
pub(crate) fn report(sequence: &Sequence, status: &Status) -> Result<String, BoxError> {
    let total = sequence.numbers.len();
    if status.missing.is_empty() {
        return Ok(format!("{total} frames: all {total} done\n"));
    }
    let missing = FrameSelection::of_numbers(&status.missing).to_string();
    let mut lines = format!(
        "{total} frames: {} done, {} missing: {missing}\n",
        status.done.len(),
        status.missing.len()
    );
    let render = sequence.render_argv(&missing)?;
    lines.push_str(&format!(
        "render the missing frames here:\n  {}\n",
        shell_command(&render)?
    ));
    let mut slurm = vec![
        text(&sequence.reyes)?,
        "farm".to_owned(),
        "slurm".to_owned(),
        text(&sequence.scene)?,
        "--frames".to_owned(),
        missing,
        "--chunk".to_owned(),
        sequence.chunk.to_string(),
        "-o".to_owned(),
        text(&sequence.output)?,
        "--submit".to_owned(),
    ];
    if !sequence.render_options.is_empty() {
        slurm.push("--".to_owned());
        slurm.extend(sequence.render_options.iter().cloned());
    }
    lines.push_str(&format!(
        "or on Slurm (add your --partition, --gpus-per-task):\n  {}\n",
        shell_command(&slurm)?
    ));
    Ok(lines)
}

/// `reyes farm status`: prints the report; fails while frames are missing,
/// so that a script can wait on it.
pub(crate) fn status(args: &StatusArgs) -> Result<(), BoxError> {
    let sequence = args.spec.resolve()?;
    let status = find(&sequence)?;
    outln!("{}", report(&sequence, &status)?.trim_end())?;
    if status.missing.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} of {} frames are missing",
            status.missing.len(),
            sequence.numbers.len()
        )
        .into())
    }
}
