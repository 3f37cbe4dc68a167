//! `reyes farm`: a sequence's frames handed to a render farm or a cluster
//! scheduler. A frame's image is a deterministic function of its scene and
//! number, so the renderer needs no distribution system of its own: each
//! of these commands only splits the frames into chunks and says how to
//! render each with `reyes render --frames ... --skip-existing
//! --keep-going`.
//!
//! * `reyes farm frames` prints the chunks and their exact commands, as
//!   text or JSON, for any farm manager;
//! * `reyes farm slurm` writes a Slurm batch script with a job array, one
//!   chunk per array task, and prints (or runs, `--submit`) its `sbatch`;
//! * `reyes farm status` lists the frames whose image is missing and
//!   prints the commands that render only those.
//!
//! Paths in the commands are absolute, so they run from any directory of
//! a machine that sees the same files (a cluster's shared file system).

mod slurm;
mod status;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use clap::{Subcommand, ValueEnum};
use serde::Serialize;

use super::BoxError;
use super::frames::{FrameSelection, frame_path, parse_frames};
use crate::output::console::outln;
use crate::scene::Scene;

/// The most frames one chunk may hold (a chunk is one `reyes render`).
const MAX_CHUNK: u32 = 100_000;

/// `reyes farm`'s commands.
#[derive(Debug, clap::Args)]
pub(crate) struct FarmArgs {
    #[command(subcommand)]
    command: FarmCommand,
}

#[derive(Debug, Subcommand)]
enum FarmCommand {
    /// Print the chunks of frames and the exact `reyes render` command of
    /// each (text, or JSON for a farm manager).
    Frames(FramesArgs),
    /// Write a Slurm batch script that renders the chunks as a job array,
    /// one chunk per array task, and print its `sbatch` command (run it
    /// with --submit).
    Slurm(slurm::SlurmArgs),
    /// List the frames whose image is missing and print the commands that
    /// render only those; exits non-zero while any is missing.
    Status(status::StatusArgs),
}

/// What every farm command needs: the scene, the frames, their output
/// pattern and the chunk size.
#[derive(Debug, clap::Args)]
pub(crate) struct SequenceSpec {
    /// The scene (.toml or .rib).
    scene: PathBuf,
    /// The frames: a number, a range `A-B`, every S-th frame of one
    /// `A-BxS`, or a list `1,5-9,20-40x2` (as `reyes render --frames`).
    #[arg(long, value_name = "LIST", value_parser = parse_frames)]
    frames: FrameSelection,
    /// The images, a run of `#`s taking the frame number
    /// (`out/shot.####.png`).
    #[arg(short, long, value_name = "PATTERN")]
    output: PathBuf,
    /// Frames per chunk: each chunk is one `reyes render`, which compiles
    /// its GPU programs once for all its frames.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_CHUNK)))]
    chunk: u32,
    /// The `reyes` binary the commands run (default: this one).
    #[arg(long, value_name = "PATH")]
    reyes: Option<PathBuf>,
    /// Further options of `reyes render` for every chunk, after `--`
    /// (e.g. `-- --spp 16 --quiet`).
    #[arg(last = true, value_name = "RENDER OPTIONS")]
    render_options: Vec<String>,
}

/// A sequence resolved for a farm: absolute paths, the frame numbers, and
/// the checks done.
#[derive(Debug, Clone)]
pub(crate) struct Sequence {
    /// The `reyes` binary.
    pub(crate) reyes: PathBuf,
    /// The scene, absolute.
    pub(crate) scene: PathBuf,
    /// The output pattern, absolute.
    pub(crate) output: PathBuf,
    /// The frames, in order.
    pub(crate) numbers: Vec<u32>,
    /// Frames per chunk.
    pub(crate) chunk: u32,
    /// Options added to every `reyes render`.
    pub(crate) render_options: Vec<String>,
}

/// One chunk: its index (the Slurm array index), frames and command.
#[derive(Debug, Serialize)]
pub(crate) struct Chunk {
    /// Its place among the chunks, from 0.
    pub(crate) index: usize,
    /// Its frames as `--frames` takes them (`1-10`).
    pub(crate) frames: String,
    /// Its frame numbers.
    pub(crate) numbers: Vec<u32>,
    /// The command's words.
    pub(crate) argv: Vec<String>,
    /// The command for a POSIX shell.
    pub(crate) command: String,
}

impl SequenceSpec {
    /// The sequence, checked: the frames' output names (a pattern with
    /// `#`s for several frames), and of a TOML scene every frame's scene.
    fn resolve(&self) -> Result<Sequence, BoxError> {
        let numbers = self.frames.numbers();
        let several = numbers.len() > 1;
        for &number in numbers.iter().take(1) {
            frame_path(&self.output, "-o", Some(number), several)?;
        }
        let is_toml = self
            .scene
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        if is_toml {
            // Bad keys fail here, not on the farm.
            let scene =
                Scene::load(&self.scene).map_err(|e| format!("{}: {e}", self.scene.display()))?;
            for &number in &numbers {
                scene
                    .frame(number)
                    .map_err(|e| format!("{}: frame {number}: {e}", self.scene.display()))?;
            }
        } else if !self.scene.is_file() {
            return Err(format!("{}: no such scene file", self.scene.display()).into());
        }
        let reyes = match &self.reyes {
            Some(path) => path.clone(),
            None => std::env::current_exe()?,
        };
        Ok(Sequence {
            reyes: std::path::absolute(reyes)?,
            scene: std::path::absolute(&self.scene)?,
            output: std::path::absolute(&self.output)?,
            numbers,
            chunk: self.chunk,
            render_options: self.render_options.clone(),
        })
    }
}

impl Sequence {
    /// The chunks: `chunk` frames each, in order, the last one shorter.
    pub(crate) fn chunks(&self) -> Result<Vec<Chunk>, BoxError> {
        self.numbers
            .chunks(self.chunk as usize)
            .enumerate()
            .map(|(index, numbers)| {
                let frames = FrameSelection::of_numbers(numbers).to_string();
                let argv = self.render_argv(&frames)?;
                Ok(Chunk {
                    index,
                    command: shell_command(&argv)?,
                    frames,
                    numbers: numbers.to_vec(),
                    argv,
                })
            })
            .collect()
    }

    /// The words of `reyes render` for the frames `frames`, which skips
    /// the frames rendered already (a chunk run again resumes) and
    /// renders the rest of its frames past one that fails (the command
    /// still fails, naming it).
    pub(crate) fn render_argv(&self, frames: &str) -> Result<Vec<String>, BoxError> {
        let mut argv = vec![
            text(&self.reyes)?,
            "render".to_owned(),
            text(&self.scene)?,
            "--frames".to_owned(),
            frames.to_owned(),
            "-o".to_owned(),
            text(&self.output)?,
            "--skip-existing".to_owned(),
            "--keep-going".to_owned(),
        ];
        argv.extend(self.render_options.iter().cloned());
        Ok(argv)
    }

    /// The image of frame `number`.
    pub(crate) fn image(&self, number: u32) -> Result<PathBuf, BoxError> {
        Ok(frame_path(
            &self.output,
            "-o",
            Some(number),
            self.numbers.len() > 1,
        )?)
    }

    /// The scene file's stem, for names (`shot` of `shot.toml`).
    pub(crate) fn stem(&self) -> String {
        self.scene
            .file_stem()
            .map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned())
    }
}

/// `path` as text: the commands are text, so a path that is not UTF-8 is
/// refused rather than mangled.
pub(crate) fn text(path: &Path) -> Result<String, BoxError> {
    path.to_str().map(str::to_owned).ok_or_else(|| {
        format!(
            "{}: the path is not UTF-8, and the farm's commands are text; rename it",
            path.display()
        )
        .into()
    })
}

/// `argv` as one POSIX shell command, each word quoted where it needs it.
pub(crate) fn shell_command(argv: &[String]) -> Result<String, BoxError> {
    Ok(shlex::try_join(argv.iter().map(String::as_str))?)
}

/// How `reyes farm frames` prints.
#[derive(Debug, Clone, Copy, Default, ValueEnum)]
enum Format {
    /// One line per chunk: index, frames, command (tab-separated).
    #[default]
    Text,
    /// One JSON document: the scene, output, frames and chunks with their
    /// commands (as words and as a shell line).
    Json,
}

/// `reyes farm frames`'s arguments.
#[derive(Debug, clap::Args)]
struct FramesArgs {
    #[command(flatten)]
    spec: SequenceSpec,
    /// `text` or `json`.
    #[arg(long, value_enum, default_value_t)]
    format: Format,
}

/// The document `reyes farm frames --format json` prints.
#[derive(Debug, Serialize)]
struct FramesDocument<'a> {
    scene: String,
    output: String,
    frames: &'a [u32],
    chunk: u32,
    chunks: Vec<Chunk>,
}

/// `reyes farm frames`'s text for `sequence` in `format`.
fn frames_text(sequence: &Sequence, format: Format) -> Result<String, BoxError> {
    let chunks = sequence.chunks()?;
    Ok(match format {
        Format::Text => chunks
            .iter()
            .map(|c| format!("{}\t{}\t{}\n", c.index, c.frames, c.command))
            .collect(),
        Format::Json => {
            let document = FramesDocument {
                scene: text(&sequence.scene)?,
                output: text(&sequence.output)?,
                frames: &sequence.numbers,
                chunk: sequence.chunk,
                chunks,
            };
            serde_json::to_string_pretty(&document)? + "\n"
        }
    })
}

/// Runs `reyes farm`'s command.
pub(crate) fn farm(args: &FarmArgs) -> Result<(), BoxError> {
    match &args.command {
        FarmCommand::Frames(args) => {
            let sequence = args.spec.resolve()?;
            let text = frames_text(&sequence, args.format)?;
            outln!("{}", text.trim_end())?;
            Ok(())
        }
        FarmCommand::Slurm(args) => slurm::slurm(args),
        FarmCommand::Status(args) => status::status(args),
    }
}
