//! A RIB file's frames handed over one at a time, so that a long file
//! holds one frame's geometry in memory, not every frame's.
//!
//! The file is interpreted on a thread of its own. At each `FrameEnd` (or,
//! for a file without frames, at its end) the thread hands the frame over
//! and waits until the reader has taken it; the reader renders a frame
//! while the thread builds the next. Dropping the stream stops the thread
//! at its next frame.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, sync_channel};
use std::thread::JoinHandle;

use super::frames::FrameSink;
use super::{RibError, RibFrame, RibOptions, Warning, interp};

/// What the whole file gave once every frame is read: the warnings of the
/// requests after the last frame, and every file read.
#[derive(Debug)]
pub struct StreamEnd {
    /// Warnings of the requests outside every frame's scene.
    pub warnings: Vec<Warning>,
    /// The RIB file, then its archives, as they were read.
    pub sources: Vec<PathBuf>,
    /// The requests after the last frame ([`super::RibFrames::requests_after`]).
    pub requests_after: Vec<super::FrameRequest>,
}

/// The frames of a RIB file in order ([`super::RibFrames::stream`]).
#[derive(Debug)]
pub struct FrameStream {
    frames: Option<Receiver<RibFrame>>,
    reader: Option<JoinHandle<Result<StreamEnd, RibError>>>,
}

impl FrameStream {
    /// Starts reading `path` with `options` on a thread.
    pub(super) fn start(path: &Path, options: RibOptions) -> FrameStream {
        // No frame waits in the channel: the thread builds the next frame
        // while the reader works on this one, and no further.
        let (sender, frames) = sync_channel(0);
        let path = path.to_path_buf();
        let reader = std::thread::spawn(move || {
            let mut interp = interp::Interp::new(crate::input::InputKind::Scene.limit());
            interp.lenient = options.lenient;
            interp.main_file = path.clone();
            interp.frames = FrameSink::Send(sender);
            interp.run_file(&path)?;
            interp.finish()?;
            // Hands over the one frame of a file without FrameBegin.
            let collected = super::RibFrames::collect(interp, &path);
            Ok(StreamEnd {
                warnings: collected.warnings,
                sources: collected.sources,
                requests_after: collected.requests_after,
            })
        });
        FrameStream {
            frames: Some(frames),
            reader: Some(reader),
        }
    }

    /// The next frame, or `None` once the file has no more (or its reading
    /// failed: [`FrameStream::finish`] says why).
    pub fn next_frame(&mut self) -> Option<RibFrame> {
        self.frames.as_ref()?.recv().ok()
    }

    /// Waits for the reading to end (taking no further frame) and returns
    /// how it ended: the file's warnings and sources, or the error in its
    /// text. Frames not taken are dropped.
    pub fn finish(mut self) -> Result<StreamEnd, RibError> {
        self.stop()
    }

    /// Stops the thread (it fails at its next frame, if any) and joins it.
    fn stop(&mut self) -> Result<StreamEnd, RibError> {
        // Without a reader, the thread's next hand-over fails and it ends.
        let frames = self.frames.take();
        let reader = self.reader.take();
        // Frames already built are taken and dropped so that a frame being
        // handed over now does not wait.
        if let Some(frames) = &frames {
            while frames.try_recv().is_ok() {}
        }
        drop(frames);
        match reader.map(JoinHandle::join) {
            Some(Ok(end)) => end,
            Some(Err(panic)) => std::panic::resume_unwind(panic),
            None => Ok(StreamEnd {
                warnings: Vec::new(),
                sources: Vec::new(),
                requests_after: Vec::new(),
            }),
        }
    }
}

impl Iterator for FrameStream {
    type Item = RibFrame;

    fn next(&mut self) -> Option<RibFrame> {
        self.next_frame()
    }
}

impl Drop for FrameStream {
    fn drop(&mut self) {
        if self.reader.is_some() {
            let _ = self.stop();
        }
    }
}
