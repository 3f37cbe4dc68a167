//! What failed in a `reyes render` of several frames or with requests
//! between frames, and what a failure left undone ([`super::jobs`]).

use super::BoxError;
use super::args::RenderArgs;
use super::input::ReadFile;
use crate::rib::FrameRequest;

/// What failed in a run of several frames or with requests, and what was
/// left undone because of it.
#[derive(Default)]
pub(crate) struct Failures {
    /// The frames that failed.
    pub(crate) frames: Vec<String>,
    /// The requests that failed (`scene.rib:12: MakeShadow ...`).
    requests: Vec<String>,
    /// The frames not rendered after a failure.
    pub(crate) not_rendered: Vec<String>,
    /// The requests not run after a failure.
    not_run: Vec<String>,
}

impl Failures {
    /// Whether what follows is skipped: something failed and `--keep-going`
    /// is not given.
    pub(crate) fn stop(&self, args: &RenderArgs) -> bool {
        let failed = !(self.frames.is_empty() && self.requests.is_empty());
        failed && !args.keep_going
    }

    /// Runs `request` unless a failure stops it; reports its error.
    pub(crate) fn run_request(
        &mut self,
        args: &RenderArgs,
        request: &FrameRequest,
        reads: &[ReadFile],
    ) {
        if self.stop(args) {
            self.not_run.push(request.describe());
            return;
        }
        if let Err(error) = super::requests::run_request(request, reads) {
            super::print_error(error.as_ref());
            self.requests.push(request.describe());
        }
    }

    /// `Ok` when nothing failed, else the list of what failed and what was
    /// not done, of `frame_count` frames.
    pub(crate) fn into_result(self, frame_count: usize) -> Result<(), BoxError> {
        if self.frames.is_empty() && self.requests.is_empty() {
            return Ok(());
        }
        let mut parts = Vec::new();
        if !self.frames.is_empty() {
            parts.push(format!(
                "{} of {frame_count} frames failed: {}",
                self.frames.len(),
                self.frames.join(", ")
            ));
        }
        if !self.requests.is_empty() {
            parts.push(format!(
                "{} request{} failed: {}",
                self.requests.len(),
                if self.requests.len() == 1 { "" } else { "s" },
                self.requests.join("; ")
            ));
        }
        let mut message = parts.join("; ");
        if !self.not_rendered.is_empty() {
            message.push_str(&format!("; not rendered: {}", self.not_rendered.join(", ")));
        }
        if !self.not_run.is_empty() {
            message.push_str(&format!("; not run: {}", self.not_run.join("; ")));
        }
        if !(self.not_rendered.is_empty() && self.not_run.is_empty()) {
            message.push_str(
                " (a failure stops the later frames and requests; --keep-going renders them)",
            );
        }
        Err(message.into())
    }
}
