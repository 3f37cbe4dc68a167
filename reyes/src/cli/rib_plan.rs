//! A RIB file's frames for `reyes render`: read once to plan them, then
//! again one at a time to render them, so that memory holds one frame's
//! geometry, not the whole file's ([`super::jobs`]).

use std::path::{Path, PathBuf};

use super::BoxError;
use crate::output::console::errln;
use crate::rib::{FrameStream, RibError, RibFrames, RibOptions, RibScene};

/// The frames of the RIB file at `path`, read one at a time and each but
/// a single frame's models dropped (they are read again to render); the
/// file's warnings are printed.
pub(crate) fn plan_rib(path: &Path, lenient: bool) -> Result<RibFrames, BoxError> {
    let mut stream = RibFrames::stream(path, RibOptions { lenient });
    let mut frames = Vec::new();
    for frame in stream.by_ref() {
        // The frame before this one is not the only one: drop its models.
        if let Some(Ok(previous)) = frames
            .last_mut()
            .map(|f: &mut crate::rib::RibFrame| &mut f.scene)
        {
            previous.models = Vec::new();
        }
        frames.push(frame);
    }
    let end = stream.finish()?;
    if frames.len() > 1
        && let Some(Ok(last)) = frames.last_mut().map(|f| &mut f.scene)
    {
        last.models = Vec::new();
    }
    for warning in &end.warnings {
        errln!("warning: {warning}")?;
    }
    Ok(RibFrames {
        frames,
        warnings: end.warnings,
        sources: end.sources,
        requests_after: end.requests_after,
    })
}

/// A RIB file's frames read again in order, each when its turn to render
/// comes.
pub(crate) struct Reread {
    path: PathBuf,
    stream: FrameStream,
    /// The place in the file of the frame the stream gives next.
    next: usize,
}

impl Reread {
    /// The frames of `path` from its start.
    pub(crate) fn new(path: &Path, lenient: bool) -> Reread {
        Reread {
            stream: RibFrames::stream(path, RibOptions { lenient }),
            path: path.to_path_buf(),
            next: 0,
        }
    }

    /// Frame `index` of the file, which the plan found numbered `number`
    /// (the frames before it, not selected, are read and dropped).
    pub(crate) fn frame(
        &mut self,
        index: usize,
        number: Option<u32>,
    ) -> Result<Result<RibScene, RibError>, BoxError> {
        while let Some(frame) = self.stream.next_frame() {
            let at = self.next;
            self.next += 1;
            if at == index && frame.number == number {
                return Ok(frame.scene);
            }
            if at >= index {
                break;
            }
        }
        let which = number.map_or("its scene".to_owned(), |n| format!("its frame {n}"));
        Err(format!(
            "{} changed while its frames were rendered: {which} is not where it was",
            self.path.display(),
        )
        .into())
    }
}
