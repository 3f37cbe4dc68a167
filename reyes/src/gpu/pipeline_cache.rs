//! Where the command line keeps compiled megakernel pipelines across runs,
//! and what the renderer tells about the pipeline it runs
//! ([`PipelineInfo`]).
//!
//! The library writes nothing unless
//! [`GpuOptions::pipeline_cache_dir`](super::GpuOptions::pipeline_cache_dir)
//! names a directory; `reyes render` and `reyes view` use
//! [`pipeline_cache_dir`]: `$REYES_CACHE_DIR` if set, else the platform's
//! cache directory. The files and their limits are the scheduler's
//! ([`scheduler::pipeline_cache`]).

use std::path::PathBuf;

use scheduler::{CompileTimings, PipelineCacheState};

/// The environment variable that overrides the cache directory.
pub const CACHE_DIR_ENV: &str = "REYES_CACHE_DIR";

/// The platform's cache directory for `reyes`'s pipelines: e.g.
/// `~/.cache/reyes/pipelines` on Linux, `~/Library/Caches/reyes/pipelines`
/// on macOS. `None` when the platform has no home directory.
pub fn default_pipeline_cache_dir() -> Option<PathBuf> {
    directories::ProjectDirs::from("", "", "reyes").map(|dirs| dirs.cache_dir().join("pipelines"))
}

/// The directory the command line uses: `$REYES_CACHE_DIR` when it is set
/// and not empty, else [`default_pipeline_cache_dir`].
pub fn pipeline_cache_dir() -> Option<PathBuf> {
    match std::env::var_os(CACHE_DIR_ENV) {
        Some(dir) if !dir.is_empty() => Some(PathBuf::from(dir)),
        _ => default_pipeline_cache_dir(),
    }
}

/// The pipeline the renderer runs: whether it came from the pipeline cache,
/// and how long the driver took to compile it.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct PipelineInfo {
    /// What became of the pipeline cache when the pipeline was created.
    pub cache: PipelineCacheState,
    /// The driver's compile: pipeline creation and the first dispatch.
    pub timings: CompileTimings,
}

impl PipelineInfo {
    /// The state and timings of `executor`'s pipeline.
    pub(crate) fn of(executor: &scheduler::Executor) -> Self {
        Self {
            cache: executor.pipeline_cache().clone(),
            timings: executor.compile_timings(),
        }
    }
}
