//! `reyes cache`: what the pipeline cache directory holds (`info`), and
//! emptying it (`clear`). Only the scheduler's cache files are listed or
//! removed; any other file there, and the driver's own shader cache, are
//! left alone.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::BoxError;
use super::args::RenderArgs;
use crate::gpu::pipeline_cache_dir;
use crate::output::console::outln;

/// The arguments of `reyes cache`.
#[derive(Debug, clap::Args)]
pub(crate) struct CacheArgs {
    #[command(subcommand)]
    action: CacheAction,
}

#[derive(Debug, clap::Subcommand)]
enum CacheAction {
    /// Print the directory, its cache files and their total size.
    Info,
    /// Remove the cache files (and print each one removed).
    Clear,
}

impl RenderArgs {
    /// The pipeline cache directory of `render` and `view`: `None` with
    /// `--no-pipeline-cache`.
    pub(crate) fn pipeline_cache_dir(&self) -> Option<PathBuf> {
        if self.no_pipeline_cache {
            None
        } else {
            pipeline_cache_dir()
        }
    }
}

/// Runs `reyes cache`.
pub(crate) fn cache(args: &CacheArgs) -> Result<(), BoxError> {
    let dir = pipeline_cache_dir().ok_or("no cache directory: set REYES_CACHE_DIR")?;
    let files = cache_files(&dir)?;
    let total: u64 = files.iter().map(|(_, bytes)| bytes).sum();
    match args.action {
        CacheAction::Info => {
            let exists = if dir.is_dir() {
                ""
            } else {
                " (does not exist)"
            };
            outln!("directory: {}{exists}", dir.display())?;
            for (path, bytes) in &files {
                outln!("  {} ({})", file_name(path), size(*bytes))?;
            }
            outln!(
                "{} file(s), {} (kept at most: {} files, {})",
                files.len(),
                size(total),
                scheduler::pipeline_cache::MAX_FILES,
                size(scheduler::pipeline_cache::MAX_BYTES)
            )?;
        }
        CacheAction::Clear => {
            for (path, bytes) in &files {
                fs::remove_file(path)
                    .map_err(|e| format!("cannot remove {}: {e}", path.display()))?;
                outln!("removed {} ({})", path.display(), size(*bytes))?;
            }
            outln!(
                "removed {} file(s), {} from {}",
                files.len(),
                size(total),
                dir.display()
            )?;
        }
    }
    Ok(())
}

/// The scheduler's cache files in `dir` with their sizes, by name; none
/// when `dir` does not exist.
fn cache_files(dir: &Path) -> Result<Vec<(PathBuf, u64)>, BoxError> {
    let entries = match fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(format!("cannot read {}: {e}", dir.display()).into()),
    };
    let mut files = Vec::new();
    for entry in entries {
        let entry = entry?;
        let ours = entry
            .file_name()
            .to_str()
            .is_some_and(scheduler::pipeline_cache::is_cache_file_name);
        let meta = entry.metadata()?;
        if ours && meta.is_file() {
            files.push((entry.path(), meta.len()));
        }
    }
    files.sort();
    Ok(files)
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

/// `bytes` in the largest binary unit that keeps it at least 1.
fn size(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["bytes", "KiB", "MiB", "GiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} bytes")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}
