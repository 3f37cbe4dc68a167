//! RenderMan RIB input (ASCII RIB; see `docs/rib.md` for what each request
//! does here).
//!
//! [`RibScene::load`] reads a `.rib` file (through `crate::input`: regular
//! files only, at most the scene cap over the file and all its archives),
//! interprets it and gives a [`Scene`] with its [`Model`]s in memory, plus
//! the warnings for what was ignored. All geometry is baked into the
//! renderer's world space, which is RenderMan's camera space with x
//! mirrored (camera space is left-handed; the renderer's world is
//! right-handed): the camera sits at the origin looking down +z with +y up.
//!
//! * `lexer`: tokens with line and column; `parser`: requests and their
//!   values; `state`: graphics state and parameter lists;
//!   `basis`: spline bases and the change of basis to Bezier;
//!   `interp`: the interpreter (`options`: its option requests;
//!   `geometry`: its transform, motion, basis and geometry requests;
//!   `quadrics`: the quadrics as Bezier patches; `polygons`:
//!   `PointsPolygons` and `GeneralPolygon`; `subdivision`: `SubdivisionMesh`
//!   as a [`crate::subdiv::Mesh`]; `spaces`: coordinate systems
//!   and `Skew`; `blocks`: the begin/end structure; `texcoords`: `s`, `t`
//!   of the patches' corners; `environments`: the environment maps'
//!   names; `frames`: `FrameBegin`/`FrameEnd`, each frame's scene;
//!   `requests`: `MakeShadow`, run between frames; `shadow_lights`: the
//!   shadowed lights' maps and filters);
//!   `convert`: the [`Scene`] it makes.
//!
//! [`RibFrames::load`] reads every frame of a file; [`RibScene::load`] the
//! one scene of a file without frames (or the first frame, with a warning).

mod attributes;
mod blocks;
internal_modules! {
    basis;
    interp;
    lexer;
    lights;
    parser;
    quadrics;
    state;
    subdivision;
}
mod convert;
mod displacements;
mod environments;
mod frames;
mod geometry;
mod instances;
mod options;
mod polygons;
mod requests;
mod shader_files;
mod shadow_lights;
mod spaces;
mod stream;
mod surfaces;
mod texcoords;

use std::path::{Path, PathBuf};

use crate::input::InputError;
use crate::model::Model;
use crate::output::{OutputError, OutputGuard, OutputKind, StagedFiles};
use crate::scene::{Scene, SceneError};

pub use self::frames::{RibFrame, RibFrames};
pub use self::requests::FrameRequest;
pub use self::stream::{FrameStream, StreamEnd};

/// Why a RIB file could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RibError {
    /// A tokenizer, parser or request error at a position of a file.
    #[error("{}:{line}:{col}: {message}", file.display())]
    Syntax {
        /// The file (the archive, for an error inside one).
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column (in characters).
        col: usize,
        /// What is wrong.
        message: String,
    },
    /// A request would make more patches than the scene's budget has left
    /// ([`crate::budget`]); nothing of it was made.
    #[error("{}:{line}:{col}: {request}: {}{source}", file.display(), if what.is_empty() { String::new() } else { format!("{what}: ") })]
    PatchBudget {
        /// The file (the archive, for a request inside one).
        file: PathBuf,
        /// 1-based line of the request.
        line: usize,
        /// 1-based column of the request.
        col: usize,
        /// The request (`Sphere`, `PointsPolygons`...).
        request: String,
        /// What it would make (`64 x 64 segments`), or empty.
        what: String,
        /// The estimate and the budget.
        #[source]
        source: crate::budget::BudgetExceeded,
    },
    /// The file was refused or could not be read (see `crate::input`).
    #[error(transparent)]
    Input(InputError),
    /// The scene made from the RIB is not valid for the renderer.
    #[error("{}: the converted scene is invalid: {source}", file.display())]
    Scene {
        /// The RIB file.
        file: PathBuf,
        /// Why.
        #[source]
        source: Box<SceneError>,
    },
}

impl RibError {
    /// The `(line, column)` of a syntax or request error.
    pub fn position(&self) -> Option<(usize, usize)> {
        match self {
            RibError::Syntax { line, col, .. } | RibError::PatchBudget { line, col, .. } => {
                Some((*line, *col))
            }
            _ => None,
        }
    }
}

/// How a RIB file is read.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RibOptions {
    /// Unbalanced or truncated block structure (a missing `WorldEnd`, an
    /// unclosed `AttributeBegin`, an `AttributeEnd` without its begin) is a
    /// warning instead of an error, and what was read is used: an end
    /// without its begin is ignored, blocks left open are closed where the
    /// enclosing block ends or at the end of the scene.
    pub lenient: bool,
}

/// A request that was ignored or only approximated.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    /// The file.
    pub file: PathBuf,
    /// 1-based line (0: the scene as a whole).
    pub line: usize,
    /// What happened.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file.display(), self.message)
        } else {
            write!(f, "{}:{}: {}", self.file.display(), self.line, self.message)
        }
    }
}

/// A scene read from RIB: the scene, its models in memory (`models[i]` is
/// object `i`'s), the `Display` file name and the warnings.
#[derive(Debug, Clone)]
pub struct RibScene {
    /// The scene; object `i`'s `model` is a placeholder name until
    /// [`RibScene::write`] writes the models.
    pub scene: Scene,
    /// One model per object.
    pub models: Vec<Model>,
    /// The first `Display` file name (before `WorldBegin`, not `+name`; in
    /// a frame, the frame's first, else the one before the frame):
    /// `reyes render` writes the image there unless `-o` is given.
    pub display: Option<String>,
    /// What was ignored or approximated.
    pub warnings: Vec<Warning>,
    /// Where each of the scene's lights was declared (`scene.lights[i]`'s
    /// `LightSource` file and line), for messages.
    pub light_origins: Vec<(PathBuf, usize)>,
    /// Every file read, in order: the RIB file (unless the text was given,
    /// [`RibScene::from_text`]), then each `ReadArchive` file as it was
    /// named. [`RibScene::write`] refuses to replace any of them.
    pub sources: Vec<PathBuf>,
}

/// The UTF-8 text of a RIB file's bytes; anything else is taken for binary
/// RIB, which is not supported.
pub(crate) fn decode(bytes: Vec<u8>, file: &Path) -> Result<String, RibError> {
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let before = &bytes[..valid];
        let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        let col = String::from_utf8_lossy(&before[line_start..])
            .chars()
            .count()
            + 1;
        RibError::Syntax {
            file: file.to_path_buf(),
            line,
            col,
            message: format!(
                "byte {:#04x} is not ASCII text: binary RIB is not supported (only ASCII RIB)",
                bytes[valid]
            ),
        }
    })
}

impl RibScene {
    /// Reads and interprets the RIB file at `path`. `ReadArchive` paths are
    /// relative to the including file's directory.
    /// Unbalanced or truncated block structure is an error (see
    /// [`RibScene::load_with`]).
    pub fn load(path: impl AsRef<Path>) -> Result<RibScene, RibError> {
        RibScene::load_with(path, RibOptions::default())
    }

    /// [`RibScene::load`] with `options` (see [`RibOptions`]). A file of
    /// several frames gives its first, with a warning ([`RibFrames`] reads
    /// them all).
    pub fn load_with(path: impl AsRef<Path>, options: RibOptions) -> Result<RibScene, RibError> {
        let path = path.as_ref();
        RibFrames::load_with(path, options)?.into_first(path)
    }

    /// The first `Display` file name of the RIB file at `path` (not a
    /// `+name`), reading only up to `WorldBegin` (and the archives read
    /// before it): what [`RibScene::load`] gives as [`RibScene::display`].
    pub fn display_of(path: impl AsRef<Path>) -> Result<Option<String>, RibError> {
        let mut interp = interp::Interp::new(crate::input::InputKind::Scene.limit());
        interp.options_only = true;
        interp.run_file(path.as_ref())?;
        Ok(interp.opts.display)
    }

    /// Interprets RIB `text` as if read from the file `name` (which names
    /// it in errors; archives resolve against its directory).
    pub fn from_text(text: &str, name: impl AsRef<Path>) -> Result<RibScene, RibError> {
        RibScene::from_text_with(text, name, RibOptions::default())
    }

    /// [`RibScene::from_text`] with `options` (see [`RibOptions`]).
    pub fn from_text_with(
        text: &str,
        name: impl AsRef<Path>,
        options: RibOptions,
    ) -> Result<RibScene, RibError> {
        let name = name.as_ref();
        RibFrames::from_text_with(text, name, options)?.into_first(name)
    }

    /// Interprets the bytes of a RIB file as if read from `name` (non-UTF-8
    /// bytes are reported as unsupported binary RIB).
    pub fn from_bytes(bytes: &[u8], name: impl AsRef<Path>) -> Result<RibScene, RibError> {
        let name = name.as_ref();
        let text = decode(bytes.to_vec(), name)?;
        RibScene::from_text(&text, name)
    }

    /// Writes the scene as TOML to `toml` plus its models as `.bpt` files
    /// beside it (`{toml stem}-{i}.bpt`, one per distinct model: the
    /// instances of one RIB object share theirs), creating missing
    /// directories; returns every file written, the TOML last.
    ///
    /// Every output goes through one [`OutputGuard`] before anything is
    /// written: `toml` must end in `.toml`, and no output may be one of
    /// [`RibScene::sources`] (compared by identity, so also not through a
    /// link) or a directory or device. The files are then written to
    /// temporaries beside their targets and renamed into place (the models,
    /// then the TOML) only once all are complete: a failure (a full disk, a
    /// file-size limit) leaves the previous files as they were. Every error
    /// names its path.
    pub fn write(&self, toml: &Path) -> Result<Vec<PathBuf>, OutputError> {
        let mut guard = OutputGuard::new();
        for (i, source) in self.sources.iter().enumerate() {
            let label = if i == 0 { "RIB scene" } else { "RIB archive" };
            guard.add_input(label, source)?;
        }
        let toml_file = guard.add_output(OutputKind::Toml, "TOML scene", toml)?;
        let dir = match toml.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let stem = toml
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene")
            .to_owned();
        let mut scene = self.scene.clone();
        let mut models: Vec<(usize, PathBuf, PathBuf)> = Vec::with_capacity(self.models.len());
        // Objects with equal models (the instances of one RIB object) name
        // one file, written once: `models` holds each distinct model's first
        // object, its path and its file.
        let firsts = crate::model::first_of_equal(&self.models);
        for (i, object) in scene.objects.iter_mut().enumerate() {
            let name = format!("{stem}-{}.bpt", firsts[i]);
            if firsts[i] == i {
                let path = dir.join(&name);
                let file = guard.add_output(OutputKind::Bpt, "model", &path)?;
                models.push((i, path, file));
            }
            object.model = name;
        }
        // The maps' space matters only to a scene that reads or writes maps.
        if !scene.may_use_shadow_map_files() {
            scene.shadow_map_space = None;
        }
        guard.prepare_dirs()?;
        let mut staged = StagedFiles::new();
        // Streamed: the set holds files, not their bytes (a model's text
        // is several times its patches).
        for (index, _, file) in &models {
            let model = &self.models[*index];
            staged.write_with(file, |out| crate::load::bpt::write_to(model, out))?;
        }
        let header = "# Converted from RenderMan RIB by `reyes convert`.\n";
        let text = format!("{header}{}", scene.to_toml_string());
        staged.write(&toml_file, text.as_bytes())?;
        staged.commit()?;
        let mut written: Vec<PathBuf> = models.into_iter().map(|(_, path, _)| path).collect();
        written.push(toml.to_path_buf());
        Ok(written)
    }

    /// The scene prepared with its in-memory models.
    pub fn prepare(&self) -> Result<crate::prepare::PreparedScene, SceneError> {
        crate::prepare::PreparedScene::new(&self.scene, &self.models)
    }
}

impl RibFrames {
    /// Reads and interprets every frame of the RIB file at `path` (see
    /// [`RibScene::load`] for the file and its archives). An error in the
    /// text (syntax, block structure, a bad request, the patch budget,
    /// which each frame has to itself) is the file's; a frame whose
    /// scene is invalid has the error as its [`RibFrame::scene`].
    pub fn load(path: impl AsRef<Path>) -> Result<RibFrames, RibError> {
        RibFrames::load_with(path, RibOptions::default())
    }

    /// The frames of the RIB file at `path`, read on a thread and handed
    /// over one at a time (see [`FrameStream`]): memory holds the frame
    /// being read and the one being used, not every frame. An error in the
    /// text ends the stream; [`FrameStream::finish`] returns it.
    pub fn stream(path: impl AsRef<Path>, options: RibOptions) -> FrameStream {
        FrameStream::start(path.as_ref(), options)
    }

    /// [`RibFrames::load`] with `options` (see [`RibOptions`]).
    pub fn load_with(path: impl AsRef<Path>, options: RibOptions) -> Result<RibFrames, RibError> {
        let path = path.as_ref();
        let mut interp = interp::Interp::new(crate::input::InputKind::Scene.limit());
        interp.lenient = options.lenient;
        interp.main_file = path.to_path_buf();
        interp.run_file(path)?;
        interp.finish()?;
        Ok(RibFrames::collect(interp, path))
    }

    /// The frames of RIB `text` as if read from the file `name` (see
    /// [`RibScene::from_text`]).
    pub fn from_text_with(
        text: &str,
        name: impl AsRef<Path>,
        options: RibOptions,
    ) -> Result<RibFrames, RibError> {
        let name = name.as_ref();
        let mut interp = interp::Interp::new(crate::input::InputKind::Scene.limit());
        interp.lenient = options.lenient;
        interp.main_file = name.to_path_buf();
        interp.run_text(text, name)?;
        interp.finish()?;
        Ok(RibFrames::collect(interp, name))
    }
}

impl Scene {
    /// Reads a RenderMan RIB file ([`RibScene::load`]).
    pub fn load_rib(path: impl AsRef<Path>) -> Result<RibScene, RibError> {
        RibScene::load(path)
    }
}
