//! The RIB interpreter: runs requests against the graphics state and
//! collects the scene's options, primitives (as Bezier patches in the
//! renderer's world space) and lights.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3, Vec2, Vec3};

use super::lights::RibLight;
use super::parser::Call;
use super::state::{self, Attributes, Decl, Xform};
use super::{RibError, Warning};
use crate::budget::{BudgetExceeded, PatchBudget};
use crate::input::{self, InputKind};

/// Why a request failed: a message, or the patch budget it would pass.
#[derive(Debug)]
pub(super) enum RequestError {
    /// What is wrong with the request.
    Message(String),
    /// The request would make more patches than the scene has left; the
    /// text says what it would make (`64 x 64 segments`), if anything.
    Budget(String, BudgetExceeded),
}

impl From<String> for RequestError {
    fn from(message: String) -> RequestError {
        RequestError::Message(message)
    }
}

impl std::fmt::Display for RequestError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RequestError::Message(m) => f.write_str(m),
            RequestError::Budget(what, e) if what.is_empty() => write!(f, "{e}"),
            RequestError::Budget(what, e) => write!(f, "{what}: {e}"),
        }
    }
}

/// Deepest `ReadArchive` nesting.
const MAX_INCLUDE_DEPTH: usize = 64;
/// Most warnings kept (the rest are counted).
pub const MAX_WARNINGS: usize = 100;
/// Longest warning or request error, in characters: messages quote names
/// from the input (a request, a shader, a basis, a light handle), which may
/// be arbitrarily long; the rest is cut (with `…`).
const MAX_MESSAGE_CHARS: usize = 512;
/// Longest `ReadArchive` name, in bytes: far beyond any real archive name,
/// and short enough for the messages that quote it.
const MAX_ARCHIVE_NAME_BYTES: usize = 1024;

pub use super::options::Options;

/// One primitive, in the renderer's (right-handed) world space.
#[derive(Debug, Clone)]
pub struct Prim {
    /// Its Bezier patches at shutter open.
    pub patches: Vec<[Vec3; 16]>,
    /// The texture coordinates of each patch's corners `(u, v) = (0,0),
    /// (1,0), (0,1), (1,1)` (`super::texcoords`).
    pub st: Vec<[Vec2; 4]>,
    /// The attributes it was made with.
    pub attrs: Attributes,
    /// The world-space motion from shutter open to close, if it moves.
    pub close: Option<DMat4>,
    /// Its request (`Sphere`, `PatchMesh`...).
    pub request: &'static str,
    /// The file of its request.
    pub file: PathBuf,
    /// The line of its request.
    pub line: usize,
    /// An instance's placement (`ObjectInstance`): its patches are in
    /// its definition's space, and this matrix places them in world space.
    /// `None`: the patches are in world space.
    pub placement: Option<glam::Mat4>,
}

#[derive(Debug)]
pub(super) struct Motion {
    pub(super) base: Xform,
    pub(super) index: usize,
    pub(super) line: usize,
}

/// The interpreter's state.
#[derive(Debug)]
pub struct Interp {
    /// Warnings so far.
    pub warnings: Vec<Warning>,
    pub(super) warned: HashSet<String>,
    pub(super) declared: HashMap<String, Decl>,
    /// The options.
    pub opts: Options,
    pub(super) attrs: Attributes,
    pub(super) xf: Xform,
    pub(super) stack: Vec<(Option<Attributes>, Xform)>,
    pub(super) coordsys: HashMap<String, Xform>,
    /// The world-to-camera transform, from `WorldBegin` on.
    pub camera: Option<DMat4>,
    /// The request from which on the camera transform leaves f32, if it
    /// does ([`state::Xform::overflow`] at `WorldBegin`).
    pub(super) camera_overflow: Option<state::Origin>,
    /// The files [`state::Origin`]s name.
    pub(super) origin_files: Vec<PathBuf>,
    /// The world-to-camera transform at shutter close, if the camera
    /// moves, and the line of its `WorldBegin`.
    pub camera_close: Option<(DMat4, usize)>,
    pub(super) world_done: bool,
    pub(super) motion: Option<Motion>,
    /// The primitives.
    pub prims: Vec<Prim>,
    /// The patches the primitives may still make ([`crate::budget`]).
    pub(super) patches: PatchBudget,
    /// The distant and point lights, in declaration order.
    pub lights: Vec<RibLight>,
    pub(super) includes: Vec<PathBuf>,
    /// Every file read, in order: the scene, then its archives.
    pub sources: Vec<PathBuf>,
    pub(super) budget: u64,
    /// The object definitions by name ([`super::instances`]).
    pub(super) definitions: HashMap<String, super::instances::Definition>,
    /// The definition being recorded, if any.
    pub(super) defining: Option<super::instances::OpenDefinition>,
    /// Warnings beyond [`MAX_WARNINGS`], counted only.
    pub more_warnings: usize,
    /// Stop reading at `WorldBegin` (only the options are wanted).
    pub options_only: bool,
    /// The open blocks, innermost last ([`super::blocks`]).
    pub(super) blocks: Vec<super::blocks::Block>,
    /// Structure problems are warnings, not errors
    /// ([`super::RibOptions::lenient`]).
    pub lenient: bool,
    /// `MakeTexture`'s texture names and the pictures they stand for
    /// (resolved beside the RIB file that made them): shader parameters
    /// naming a texture read the picture, which the renderer mipmaps itself.
    /// Their wrap modes come along (an environment map's are periodic).
    pub(super) made_textures: HashMap<String, crate::texture::TextureDesc>,
    /// The WGSL shaders requests have named, checked once per file: their
    /// kind and parameter names, or why the file cannot be used
    /// ([`super::shader_files`]).
    pub(super) shader_files: HashMap<PathBuf, super::shader_files::ShaderFile>,
    /// The frame being read, from its `FrameBegin` ([`super::frames`]).
    pub(super) frame: Option<super::frames::OpenFrame>,
    /// Where finished frames go ([`super::frames::FrameSink`]).
    pub(super) frames: super::frames::FrameSink,
    /// The line of the file's first `FrameBegin`, once there is one.
    pub(super) first_frame_line: Option<usize>,
    /// The line of a `WorldBegin` outside any frame, once there is one.
    pub(super) bare_world_line: Option<usize>,
    /// The RIB file (or the name its text was given under): the scene's
    /// warnings and errors name it.
    pub(super) main_file: PathBuf,
    /// Requests to run before the next frame ([`super::requests`]).
    pub(super) requests: Vec<super::requests::FrameRequest>,
}

/// RenderMan's camera space is left-handed (x right, y up, z forward); the
/// renderer's world is right-handed and its camera looks down -z with x to
/// the left when looking from the origin along +z: mirror x.
pub fn camera_to_world() -> DMat4 {
    DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0))
}

impl Interp {
    /// A fresh state; `budget` bounds the bytes read over all files.
    pub fn new(budget: u64) -> Interp {
        Interp {
            warnings: Vec::new(),
            warned: HashSet::new(),
            declared: HashMap::new(),
            opts: Options::default(),
            attrs: Attributes::default(),
            xf: Xform::default(),
            stack: Vec::new(),
            coordsys: HashMap::new(),
            camera: None,
            camera_close: None,
            camera_overflow: None,
            origin_files: Vec::new(),
            world_done: false,
            motion: None,
            prims: Vec::new(),
            patches: PatchBudget::from_setting(),
            lights: Vec::new(),
            includes: Vec::new(),
            sources: Vec::new(),
            budget,
            definitions: HashMap::new(),
            defining: None,
            more_warnings: 0,
            made_textures: HashMap::new(),
            shader_files: HashMap::new(),
            options_only: false,
            blocks: Vec::new(),
            lenient: false,
            frame: None,
            frames: super::frames::FrameSink::default(),
            first_frame_line: None,
            bare_world_line: None,
            main_file: PathBuf::new(),
            requests: Vec::new(),
        }
    }

    pub(super) fn warn(&mut self, file: &Path, line: usize, message: String) {
        if self.warnings.len() >= MAX_WARNINGS {
            self.more_warnings += 1;
            return;
        }
        self.warnings.push(Warning {
            file: file.to_path_buf(),
            line,
            message: bounded(message),
        });
    }

    pub(super) fn warn_once(&mut self, key: &str, file: &Path, line: usize, message: String) {
        if self.warned.insert(key.to_owned()) {
            self.warn(file, line, message);
        }
    }

    /// Reads and runs the RIB file at `path`.
    pub fn run_file(&mut self, path: &Path) -> Result<(), RibError> {
        let bytes =
            input::read_input(path, InputKind::Scene, self.budget).map_err(RibError::Input)?;
        self.budget = self.budget.saturating_sub(bytes.len() as u64);
        self.sources.push(path.to_path_buf());
        let text = super::decode(bytes, path)?;
        self.run_text(&text, path)
    }

    /// Runs RIB `text`, named `file` (relative archives resolve against its directory).
    pub fn run_text(&mut self, text: &str, file: &Path) -> Result<(), RibError> {
        let key = std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf());
        if self.includes.contains(&key) {
            return Err(RibError::Syntax {
                file: file.to_path_buf(),
                line: 1,
                col: 1,
                message: "ReadArchive cycle: this file includes itself".into(),
            });
        }
        // One request at a time: memory holds one request's values, not
        // the file's tokens.
        let mut parser = super::parser::Parser::new(input::strip_bom(text), file);
        self.includes.push(key);
        let result = (|| {
            while let Some(call) = parser.next_call()? {
                self.call(&call, file)?;
                if self.options_only && self.camera.is_some() {
                    break;
                }
            }
            Ok(())
        })();
        self.includes.pop();
        result
    }

    fn call(&mut self, call: &Call, file: &Path) -> Result<(), RibError> {
        let at = |message: String| RibError::Syntax {
            file: file.to_path_buf(),
            line: call.line,
            col: call.col,
            message: bounded(format!("{}: {message}", input::excerpt(&call.name))),
        };
        if call.name == "ReadArchive" && !self.world_done {
            let (args, _, _) = state::split_params(&call.values, 1, &self.declared).map_err(at)?;
            let name = state::arg_str(&args, 0, "the archive name").map_err(at)?;
            // The messages below quote the path: keep them short (no file
            // system takes a longer path anyway).
            if name.len() > MAX_ARCHIVE_NAME_BYTES {
                return Err(at(format!(
                    "the archive name {:?} is {} bytes long (at most {MAX_ARCHIVE_NAME_BYTES})",
                    input::excerpt(name),
                    name.len()
                )));
            }
            let dir = file.parent().unwrap_or(Path::new(""));
            let path = dir.join(name);
            if self.includes.len() >= MAX_INCLUDE_DEPTH {
                return Err(at(format!(
                    "archives nested deeper than {MAX_INCLUDE_DEPTH}"
                )));
            }
            let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
            if self.includes.contains(&key) {
                return Err(at(format!(
                    "include cycle: {} is already being read",
                    path.display()
                )));
            }
            return self.run_file(&path).map_err(|e| match e {
                RibError::Input(_) => at(e.to_string()),
                other => other,
            });
        }
        self.request(call, file).map_err(|e| match e {
            RequestError::Message(message) => at(message),
            RequestError::Budget(what, source) => RibError::PatchBudget {
                file: file.to_path_buf(),
                line: call.line,
                col: call.col,
                request: input::excerpt(&call.name),
                what,
                source,
            },
        })
    }

    pub(super) fn request(&mut self, call: &Call, file: &Path) -> Result<(), RequestError> {
        // Before anything skips the request: the structure is checked
        // everywhere.
        if !self.structure(call, file)? {
            return Ok(());
        }
        let v = &call.values;
        let line = call.line;
        let name = call.name.as_str();
        // For messages: a request name from the input may be of any length.
        let shown = input::excerpt(name);
        if self.world_done && !matches!(name, "FrameEnd" | "FrameBegin") {
            let message = if self.frame.is_some() {
                "only the first world block of a frame is rendered; the requests after its WorldEnd up to FrameEnd are ignored"
            } else {
                "only the first world block is rendered; the requests after its WorldEnd are ignored (a file of several images puts each in a FrameBegin/FrameEnd block)"
            };
            self.warn_once("#frames", file, line, message.into());
            return Ok(());
        }
        if let Some(m) = &mut self.motion
            && !is_transform(name)
            && name != "MotionEnd"
        {
            m.index += 1;
            if m.index > 1 {
                return Ok(());
            }
            self.warn(
                file,
                line,
                format!(
                    "{shown} inside MotionBegin: only transforms can move; the first sample is used"
                ),
            );
        }
        let world = self.camera.is_some();
        match name {
            "version" => {}
            "FrameBegin" => self.frame_begin(v, file, line)?,
            "FrameEnd" => self.frame_end(file)?,
            "Declare" => {
                let name = state::arg_str(v, 0, "the name")?.to_owned();
                let decl = state::parse_decl(state::arg_str(v, 1, "the declaration")?)?;
                self.declared.insert(name, decl);
            }
            "Format"
            | "PixelSamples"
            | "ShadingRate"
            | "Projection"
            | "ScreenWindow"
            | "FrameAspectRatio"
            | "Clipping"
            | "Shutter"
            | "DepthOfField"
            | "Display"
            | "Hider"
            | "PixelFilter"
            | "Exposure"
            | "Quantize"
            | "ShadingInterpolation" => self.option(name, v, file, line)?,
            "WorldBegin" => {
                if world {
                    return Err("WorldBegin inside a world block".to_owned().into());
                }
                self.world_begin_outside_frames(line)?;
                if self.xf.open != self.xf.close {
                    self.camera_close = Some((self.xf.close, line));
                }
                self.camera = Some(self.xf.open);
                self.camera_overflow = self.xf.overflow;
                self.xf = Xform::default();
                self.stack.clear();
            }
            "WorldEnd" => {
                if !world {
                    return Err("WorldEnd without WorldBegin".to_owned().into());
                }
                self.world_done = true;
            }
            "AttributeBegin" => self.stack.push((Some(self.attrs.clone()), self.xf)),
            "TransformBegin" => self.stack.push((None, self.xf)),
            "AttributeEnd" | "TransformEnd" => {
                let Some((attrs, xf)) = self.stack.pop() else {
                    return Err("without a matching begin".to_owned().into());
                };
                if attrs.is_some() != (name == "AttributeEnd") {
                    return Err("does not match the innermost begin".to_owned().into());
                }
                if let Some(a) = attrs {
                    self.attrs = a;
                }
                self.xf = xf;
            }
            "MotionBegin" | "MotionEnd" => self.motion_request(name, v, file, line)?,
            "Color" => {
                let n = state::all_nums(v, 3)?;
                if !n.iter().all(|c| c.is_finite() && *c >= 0.0) {
                    return Err(format!(
                        "[{} {} {}] is out of range: every channel must be a finite number >= 0",
                        n[0], n[1], n[2]
                    )
                    .into());
                }
                self.attrs.color = DVec3::new(n[0], n[1], n[2]);
            }
            "Surface" => {
                let (args, params, _) = state::split_params(v, 1, &self.declared)?;
                let shader = state::arg_str(&args, 0, "the shader")?;
                self.attrs.surface = self.surface(shader, &params, file, line)?;
            }
            "MakeTexture" => self.make_texture(v, file)?,
            "MakeLatLongEnvironment" => self.make_latlong_environment(v, file)?,
            "MakeCubeFaceEnvironment" => self.make_cube_face_environment(v, file, line)?,
            "MakeShadow" => self.make_shadow(v, file, line)?,
            "LightSource" => self.light_source(v, file, line)?,
            "Illuminate" => self.illuminate(v, file, line)?,
            "Sides" => {
                let n = state::all_nums(v, 1)?[0];
                self.attrs.sides = if n == 1.0 {
                    1
                } else if n == 2.0 {
                    2
                } else {
                    return Err(format!("{n} is out of range: must be 1 or 2").into());
                };
            }
            "Orientation" => {
                let lh_now = self.handedness_lh();
                self.attrs.orientation_lh = match state::arg_str(v, 0, "the orientation")? {
                    "lh" => true,
                    "rh" => false,
                    "outside" => lh_now,
                    "inside" => !lh_now,
                    other => return Err(format!("unknown orientation {other:?}").into()),
                };
            }
            "ReverseOrientation" => self.attrs.orientation_lh = !self.attrs.orientation_lh,
            "Attribute" => self.attribute(v, file, line)?,
            "Displacement" => self.displacement(v, file, line)?,
            "Opacity" => self.opacity(v, file, line)?,
            "Basis" => self.basis(v)?,
            "TextureCoordinates" => self.texture_coordinates(v)?,
            "Identity" | "Transform" | "ConcatTransform" | "Translate" | "Rotate" | "Scale"
            | "Skew" => {
                self.transform(name, v)?;
                self.track_overflow(name, file, line);
            }
            "CoordinateSystem" | "CoordSysTransform" => {
                self.coordinate_system(name, v)?;
                self.track_overflow(name, file, line);
            }
            name if super::geometry::is_geometry(name) => {
                self.geometry_request(name, v, file, line)?
            }
            // The structure pass has matched it; CSG is not supported.
            "SolidEnd" => {}
            "SolidBegin" => self.warn_once(
                name,
                file,
                line,
                "SolidBegin is not supported (no CSG): the primitives inside are drawn as they are"
                    .into(),
            ),
            "ObjectBegin" => self.object_begin(v)?,
            "ObjectEnd" => self.object_end()?,
            "ObjectInstance" => self.object_instance(v, file, line)?,
            _ => {
                self.warn_once(
                    name,
                    file,
                    line,
                    format!("{shown} is not supported; ignored"),
                );
            }
        }
        Ok(())
    }

    /// Whether the current object space is left-handed (camera space is).
    fn handedness_lh(&self) -> bool {
        let m = self.camera.unwrap_or(DMat4::IDENTITY) * self.xf.open;
        m.determinant() >= 0.0
    }
}

/// `message` cut to [`MAX_MESSAGE_CHARS`].
fn bounded(message: String) -> String {
    if message.len() > MAX_MESSAGE_CHARS {
        input::excerpt_to(&message, MAX_MESSAGE_CHARS)
    } else {
        message
    }
}

/// Whether `name` is a transform request (allowed as a motion sample).
pub(super) fn is_transform(name: &str) -> bool {
    matches!(
        name,
        "Identity" | "Transform" | "ConcatTransform" | "Translate" | "Rotate" | "Scale" | "Skew"
    )
}
