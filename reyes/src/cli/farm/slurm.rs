//! `reyes farm slurm`: a Slurm batch script whose job array renders one
//! chunk of frames per array task, and its `sbatch`.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::{Sequence, SequenceSpec, shell_command, text};
use crate::cli::BoxError;
use crate::output::console::outln;

/// `reyes farm slurm`'s arguments.
#[derive(Debug, clap::Args)]
pub(crate) struct SlurmArgs {
    #[command(flatten)]
    spec: SequenceSpec,
    /// GPUs for each array task (`#SBATCH --gpus-per-task`); default: none
    /// asked for (the cluster's default).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    gpus_per_task: Option<u32>,
    /// The partition to run in (`#SBATCH --partition`).
    #[arg(long, value_name = "P")]
    partition: Option<String>,
    /// The time limit of each array task (`#SBATCH --time`, e.g. `1:00:00`).
    #[arg(long, value_name = "LIMIT")]
    time: Option<String>,
    /// The job's name (default `reyes-<scene stem>`).
    #[arg(long, value_name = "NAME")]
    job_name: Option<String>,
    /// The directory of the tasks' logs, one per array task,
    /// `<job name>-<job id>_<array index>.log` (default: `logs` beside the
    /// images). Created if missing.
    #[arg(long, value_name = "DIR")]
    logs: Option<PathBuf>,
    /// Where to write the batch script (default: `<scene stem>.sbatch`
    /// beside the images).
    #[arg(long, value_name = "FILE")]
    script: Option<PathBuf>,
    /// Run `sbatch` on the script instead of printing the command.
    #[arg(long)]
    submit: bool,
}

/// The batch script's settings besides the sequence.
#[derive(Debug, Clone, Default)]
pub(crate) struct ScriptOptions {
    pub(crate) job_name: String,
    pub(crate) logs: PathBuf,
    pub(crate) gpus_per_task: Option<u32>,
    pub(crate) partition: Option<String>,
    pub(crate) time: Option<String>,
}

/// The batch script that renders `sequence`'s chunks as a job array: array
/// task `i` renders chunk `i` with `--skip-existing`, its log named by the
/// job and array index (`%A_%a`).
pub(crate) fn batch_script(
    sequence: &Sequence,
    options: &ScriptOptions,
) -> Result<String, BoxError> {
    let chunks = sequence.chunks()?;
    let logs = directive_path(&options.logs)?;
    let mut script = String::from("#!/bin/bash\n");
    let mut directive = |line: String| script.push_str(&format!("#SBATCH {line}\n"));
    directive(format!("--job-name={}", directive_word(&options.job_name)?));
    directive(format!("--array=0-{}", chunks.len() - 1));
    directive("--ntasks=1".to_owned());
    directive(format!("--output={logs}/{}-%A_%a.log", options.job_name));
    if let Some(gpus) = options.gpus_per_task {
        directive(format!("--gpus-per-task={gpus}"));
    }
    if let Some(partition) = &options.partition {
        directive(format!("--partition={}", directive_word(partition)?));
    }
    if let Some(time) = &options.time {
        directive(format!("--time={}", directive_word(time)?));
    }
    let largest = chunks.iter().map(|c| c.numbers.len()).max().unwrap_or(0);
    script.push_str(&format!(
        "# Written by `reyes farm slurm`: {} frames of {} in {} chunks of up to\n\
         # {largest} frames, one chunk per array task. Each task renders its chunk with\n\
         # --skip-existing: a task run again renders only the frames still missing.\n\
         set -euo pipefail\n\
         chunks=(\n",
        sequence.numbers.len(),
        text(&sequence.scene)?,
        chunks.len(),
    ));
    for chunk in &chunks {
        // Frame lists are digits, '-', 'x' and ',': no quoting needed.
        script.push_str(&format!("  {}\n", chunk.frames));
    }
    let argv = sequence.render_argv("")?;
    // argv: reyes render SCENE --frames FRAMES -o ...: the frames come
    // from the array index.
    script.push_str(&format!(
        ")\n\
         frames=${{chunks[$SLURM_ARRAY_TASK_ID]}}\n\
         echo \"reyes: job $SLURM_ARRAY_JOB_ID, array task $SLURM_ARRAY_TASK_ID on $(hostname): frames $frames\"\n\
         exec {} \"$frames\" {}\n",
        shell_command(&argv[..4])?,
        shell_command(&argv[5..])?,
    ));
    Ok(script)
}

/// A path for an `#SBATCH` line, which takes no quoting: refused with
/// white space, or with `%`, which Slurm would expand.
fn directive_path(path: &Path) -> Result<String, BoxError> {
    let path = text(path)?;
    if path.chars().any(|c| c.is_whitespace() || c == '%') {
        return Err(format!(
            "{path}: a Slurm #SBATCH path cannot hold white space or '%'; choose another --logs directory"
        )
        .into());
    }
    Ok(path)
}

/// A word for an `#SBATCH` line: no white space.
fn directive_word(word: &str) -> Result<String, BoxError> {
    if word.is_empty() || word.chars().any(char::is_whitespace) {
        return Err(format!("{word:?}: a Slurm setting must be one word").into());
    }
    Ok(word.to_owned())
}

/// `reyes farm slurm`: writes the batch script (and makes its log
/// directory), then prints its `sbatch` command or, with `--submit`, runs
/// it and prints the job's id.
pub(crate) fn slurm(args: &SlurmArgs) -> Result<(), BoxError> {
    let sequence = args.spec.resolve()?;
    let images = sequence
        .output
        .parent()
        .map_or_else(|| PathBuf::from("/"), Path::to_path_buf);
    let stem = sequence.stem();
    let options = ScriptOptions {
        job_name: args
            .job_name
            .clone()
            .unwrap_or_else(|| format!("reyes-{stem}")),
        logs: std::path::absolute(args.logs.clone().unwrap_or_else(|| images.join("logs")))?,
        gpus_per_task: args.gpus_per_task,
        partition: args.partition.clone(),
        time: args.time.clone(),
    };
    let script_path = std::path::absolute(
        args.script
            .clone()
            .unwrap_or_else(|| images.join(format!("{stem}.sbatch"))),
    )?;
    let script = batch_script(&sequence, &options)?;
    // Slurm does not make the log directory: a task whose log cannot be
    // opened fails without a word.
    for dir in [Some(options.logs.as_path()), script_path.parent()]
        .into_iter()
        .flatten()
    {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create directory {}: {e}", dir.display()))?;
    }
    std::fs::write(&script_path, script)
        .map_err(|e| format!("cannot write {}: {e}", script_path.display()))?;
    let tasks = sequence.numbers.len().div_ceil(sequence.chunk as usize);
    outln!(
        "wrote {}: {} frames in {tasks} array task(s) of up to {} frames; logs in {}",
        script_path.display(),
        sequence.numbers.len(),
        sequence.chunk,
        options.logs.display()
    )?;
    let sbatch = vec!["sbatch".to_owned(), text(&script_path)?];
    if !args.submit {
        outln!("submit it with:\n  {}", shell_command(&sbatch)?)?;
        return Ok(());
    }
    let output = Command::new("sbatch")
        .arg("--parsable")
        .arg(&script_path)
        .output()
        .map_err(|e| format!("cannot run sbatch (is Slurm installed, and sbatch on PATH?): {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "sbatch {} failed ({}): {}",
            script_path.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        )
        .into());
    }
    // `--parsable` prints `id` or `id;cluster`.
    let stdout = String::from_utf8_lossy(&output.stdout);
    let job = stdout.trim().split(';').next().unwrap_or_default();
    let plural = if tasks == 1 { "" } else { "s" };
    outln!(
        "submitted batch job {job}: {tasks} array task{plural}; logs {}/{}-{job}_<task>.log",
        options.logs.display(),
        options.job_name
    )?;
    Ok(())
}
