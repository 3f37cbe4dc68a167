//! Frames: each `FrameBegin n … FrameEnd` block of a RIB file is one image.
//!
//! A frame starts from the options, attributes, transform and named
//! coordinate systems in force at its `FrameBegin` (those given before the
//! first frame, and between frames); what it sets is its own and ends at
//! its `FrameEnd` (RenderMan's scoping). Declarations and the textures
//! `MakeTexture` and `MakeLatLongEnvironment` make are not scoped: a frame
//! uses those made before it, between frames included. At `FrameEnd` the
//! frame's scene is made ([`super::convert`]), so a frame whose scene is
//! invalid fails alone ([`RibFrame::scene`]); an error in the text (syntax,
//! block structure, a bad request) is the file's and stops the read.
//!
//! A file without `FrameBegin` is one frame, as RenderMan reads it. A file
//! with frames keeps every world block inside one: a `WorldBegin` outside
//! any frame after the first `FrameBegin`, a `FrameBegin` after a world
//! block outside any frame, a `FrameBegin` inside another frame or inside
//! any other block are errors with their line.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc::SyncSender;

use super::interp::{Interp, Options};
use super::parser::Value;
use super::state::{self, Attributes, Xform};
use super::{FrameRequest, RibError, RibScene, Warning, convert};
use crate::budget::PatchBudget;

/// The frame being read: its number, where its `FrameBegin` is, and the
/// state its `FrameEnd` restores.
#[derive(Debug)]
pub(super) struct OpenFrame {
    number: u32,
    line: usize,
    /// Whether a `Display` inside the frame named its image yet.
    pub(super) display_set: bool,
    saved: Saved,
}

/// What a frame may change and its end restores.
#[derive(Debug)]
struct Saved {
    opts: Options,
    attrs: Attributes,
    xf: Xform,
    coordsys: HashMap<String, Xform>,
}

/// Where the interpreter puts each frame it finishes: kept in order, or
/// handed to a reader one at a time ([`super::stream`]).
#[derive(Debug, Default)]
pub(super) enum FrameSink {
    /// Kept, for [`RibFrames::collect`].
    #[default]
    Keep,
    /// Kept frames.
    Kept(Vec<RibFrame>),
    /// Sent; the interpreter waits until the reader takes each.
    Send(SyncSender<RibFrame>),
}

impl FrameSink {
    /// Delivers `frame`; an error when the reader has stopped reading.
    fn deliver(&mut self, frame: RibFrame) -> Result<(), String> {
        match self {
            FrameSink::Keep => *self = FrameSink::Kept(vec![frame]),
            FrameSink::Kept(frames) => frames.push(frame),
            FrameSink::Send(sender) => sender
                .send(frame)
                .map_err(|_| "the reader of the frames stopped".to_owned())?,
        }
        Ok(())
    }

    /// The frames kept so far.
    fn take_kept(&mut self) -> Vec<RibFrame> {
        match std::mem::take(self) {
            FrameSink::Kept(frames) => frames,
            FrameSink::Keep => Vec::new(),
            FrameSink::Send(sender) => {
                *self = FrameSink::Send(sender);
                Vec::new()
            }
        }
    }
}

/// One frame of a RIB file.
#[derive(Debug)]
pub struct RibFrame {
    /// `FrameBegin`'s number; `None` for a file without `FrameBegin` (one
    /// frame).
    pub number: Option<u32>,
    /// The line of its `FrameBegin` in the RIB file (0 without one).
    pub line: usize,
    /// Its scene, or why the frame's requests make no valid scene. Its
    /// [`RibScene::display`] is the frame's `Display` (else the one before
    /// the frame), its warnings those of its requests and of the requests
    /// since the previous frame.
    pub scene: Result<RibScene, RibError>,
    /// The requests (`MakeShadow`) between the previous frame's `FrameEnd`
    /// (or the file's start) and this frame's `FrameEnd`, in order: to run
    /// before the frame is prepared ([`FrameRequest`]).
    pub requests_before: Vec<FrameRequest>,
}

impl RibFrame {
    /// `frame 3`, or `the scene` for a file without frames: how messages
    /// name it.
    pub fn label(&self) -> String {
        match self.number {
            Some(n) => format!("frame {n}"),
            None => "the scene".to_owned(),
        }
    }
}

/// Every frame of a RIB file, in order ([`RibFrames::load_with`]).
#[derive(Debug)]
pub struct RibFrames {
    /// The frames in the order of the file (at least one).
    pub frames: Vec<RibFrame>,
    /// Warnings of the requests after the last frame.
    pub warnings: Vec<Warning>,
    /// Every file read: the RIB file (unless the text was given), then its
    /// archives.
    pub sources: Vec<PathBuf>,
    /// The requests after the last frame (`MakeShadow`), in order: to run
    /// once it is written.
    pub requests_after: Vec<FrameRequest>,
}

impl RibFrames {
    /// Whether the file has `FrameBegin` blocks (else it is one frame).
    pub fn numbered(&self) -> bool {
        self.frames.first().is_some_and(|f| f.number.is_some())
    }

    /// The frames' numbers, in order, for messages: `1, 2, 5`.
    pub fn list(&self) -> String {
        self.frames
            .iter()
            .filter_map(|f| f.number.map(|n| n.to_string()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Frame `index` (in the file's order) and every file the whole file
    /// read; `None` past the last frame.
    pub fn into_frame(self, index: usize) -> Option<(RibFrame, Vec<PathBuf>)> {
        let sources = self.sources;
        self.frames.into_iter().nth(index).map(|f| (f, sources))
    }

    /// A warning for each request between frames (`MakeShadow`): they act
    /// on files a render writes, and a scene read on its own (`reyes
    /// convert`, `reyes view`) runs none of them.
    pub fn requests_not_run(&self) -> Vec<Warning> {
        self.frames
            .iter()
            .flat_map(|f| &f.requests_before)
            .chain(&self.requests_after)
            .map(|request| {
                let (file, line) = request.origin();
                Warning {
                    file: file.to_path_buf(),
                    line,
                    message: format!(
                        "{} is not run (not converted) when the file is read as one scene; `reyes render` runs it between the frames",
                        request.name()
                    ),
                }
            })
            .collect()
    }

    /// The interpreted file's frames: the one frame of a file without
    /// `FrameBegin`, else those its `FrameEnd`s made.
    pub(super) fn collect(mut interp: Interp, file: &Path) -> RibFrames {
        // A collecting interpreter's sink never refuses a frame.
        let _ = interp.deliver_frameless(file);
        let mut warnings = std::mem::take(&mut interp.warnings);
        if interp.more_warnings > 0 {
            warnings.push(Warning {
                file: file.to_path_buf(),
                line: 0,
                message: format!("{} more warnings not shown", interp.more_warnings),
            });
        }
        RibFrames {
            frames: interp.frames.take_kept(),
            warnings,
            sources: std::mem::take(&mut interp.sources),
            requests_after: std::mem::take(&mut interp.requests),
        }
    }

    /// The scene of a file read as one scene ([`RibScene::load`]): its
    /// only frame, or the first of several with a warning that says so.
    pub(super) fn into_first(self, file: &Path) -> Result<RibScene, RibError> {
        let count = self.frames.len();
        let list = self.list();
        let not_run = self.requests_not_run();
        let mut frames = self.frames.into_iter();
        let first = frames.next().expect("a file has at least one frame");
        let label = first.label();
        let mut scene = first.scene?;
        scene.warnings.extend(not_run);
        if count > 1 {
            scene.warnings.push(Warning {
                file: file.to_path_buf(),
                line: first.line,
                message: format!(
                    "the file has {count} frames ({list}): this scene is its first, {label}; `reyes render` renders them all, `--frame N` selects"
                ),
            });
        }
        scene.warnings.extend(self.warnings);
        Ok(scene)
    }
}

impl Interp {
    /// `FrameBegin n`: saves the state the frame may change.
    pub(super) fn frame_begin(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        if let Some(open) = &self.frame {
            return Err(format!(
                "inside the FrameBegin of line {}: frames do not nest (FrameEnd missing?)",
                open.line
            ));
        }
        // The structure check has pushed this frame's block.
        if let Some(outer) = self.blocks.iter().rev().nth(1) {
            return Err(format!(
                "inside {}: a frame is the outermost block",
                outer.describe(file)
            ));
        }
        if let Some(world) = self.bare_world_line {
            return Err(format!(
                "after the world block of line {world}, which is outside any frame: a file's world blocks are either all inside FrameBegin/FrameEnd or the file has no FrameBegin (one frame)"
            ));
        }
        let number = state::all_nums(v, 1)?[0];
        if !(number >= 0.0 && number.fract() == 0.0 && number <= f64::from(u32::MAX)) {
            return Err(format!(
                "the frame number {number} is not a whole number in [0, {}]",
                u32::MAX
            ));
        }
        self.first_frame_line.get_or_insert(line);
        self.frame = Some(OpenFrame {
            number: number as u32,
            line,
            display_set: false,
            saved: Saved {
                opts: self.opts.clone(),
                attrs: self.attrs.clone(),
                xf: self.xf,
                coordsys: self.coordsys.clone(),
            },
        });
        Ok(())
    }

    /// `FrameEnd`: makes the frame's scene and restores the state of its
    /// `FrameBegin`.
    pub(super) fn frame_end(&mut self, _file: &Path) -> Result<(), String> {
        // The structure check matched it to a FrameBegin, which opened it.
        let Some(open) = self.frame.take() else {
            return Ok(());
        };
        let main = self.main_file.clone();
        let scene = convert::build(self, &main);
        // Each frame has the whole patch budget: a frame is rendered, and
        // its patches dropped, before the next is read.
        self.patches = PatchBudget::from_setting();
        let requests_before = std::mem::take(&mut self.requests);
        self.frames.deliver(RibFrame {
            number: Some(open.number),
            line: open.line,
            scene,
            requests_before,
        })?;
        let Saved {
            opts,
            attrs,
            xf,
            coordsys,
        } = open.saved;
        self.opts = opts;
        self.attrs = attrs;
        self.xf = xf;
        self.coordsys = coordsys;
        self.stack.clear();
        self.camera = None;
        self.camera_close = None;
        self.camera_overflow = None;
        self.world_done = false;
        self.motion = None;
        // A definition left open in the frame is closed with it.
        self.defining = None;
        Ok(())
    }

    /// The one frame of a file without `FrameBegin`, once the file is read,
    /// to the sink; nothing for a file with frames.
    pub(super) fn deliver_frameless(&mut self, file: &Path) -> Result<(), String> {
        if self.first_frame_line.is_some() {
            return Ok(());
        }
        let scene = convert::build(self, file);
        let requests_before = std::mem::take(&mut self.requests);
        self.frames.deliver(RibFrame {
            number: None,
            line: 0,
            scene,
            requests_before,
        })
    }

    /// Refuses a `WorldBegin` outside any frame once frames began; records
    /// where the first one outside a frame is.
    pub(super) fn world_begin_outside_frames(&mut self, line: usize) -> Result<(), String> {
        if self.frame.is_some() {
            return Ok(());
        }
        if let Some(first) = self.first_frame_line {
            return Err(format!(
                "outside FrameBegin/FrameEnd, after the frames that begin at line {first}: put the world block in a frame"
            ));
        }
        self.bare_world_line.get_or_insert(line);
        Ok(())
    }
}
