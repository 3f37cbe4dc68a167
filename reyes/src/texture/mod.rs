//! Textures: RenderMan's `texture(name, s, t)`, filtered identically on the
//! GPU and in the CPU reference.
//!
//! A [`TextureSet`] holds the textures of a frame. [`TextureSet::add`] reads
//! an image file (`load`: PNG of 8 or 16 bits, OpenEXR of half or single
//! floats, TIFF), converts it to linear RGBA ([`ColorSpace`]), builds its
//! mip chain ([`mipmap`]) and stores it as f16 texels, 8 bytes each, in one
//! flat buffer shared with the GPU ([`gpu`]). [`TextureSet::sample`]
//! filters on the CPU (`sample`); `texture_sample` in
//! `shaders/reyes/library_texture.wgsl` does the same on the GPU, over the
//! tables of [`TextureSet::gpu_tables`].
//!
//! [`TextureSet::environment`] reads a texture as a latitude-longitude
//! environment map ([`environment`], RenderMan's `environment(name, R)`).
//!
//! "Textures" in `docs/reyes.md` describes the formats, colour spaces, wrap
//! modes, filtering and the memory budget.

pub mod cube_faces;
pub mod environment;
mod error;
pub mod gpu;
mod load;
pub mod mipmap;
mod sample;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

pub use error::TextureError;
pub use gpu::{DUMMY_TEXELS, TEXTURE_WGSL, TextureInfo};
pub use sample::MAX_ANISOTROPY;

use load::LinearImage;

/// Largest side of an accepted texture, in texels (checked from the file's
/// header). Texel coordinates stay exact in `f32` far beyond it.
pub const MAX_TEXTURE_SIDE: u32 = 16384;

/// How a texture's values are encoded; texels are always stored linear.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ColorSpace {
    /// sRGB for 8-bit sources, linear for 16-bit and float ones.
    #[default]
    Auto,
    /// The values are linear already.
    Linear,
    /// R, G and B are sRGB-encoded (IEC 61966-2-1) and decoded on load;
    /// alpha is linear. Values are clamped to `[0, 1]` first.
    Srgb,
}

/// What a texture shows outside `[0, 1]` along one axis (RenderMan's wrap
/// modes, by their RenderMan names).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Wrap {
    /// The image repeats (and filters across its edges).
    #[default]
    Periodic,
    /// The edge texels extend forever.
    Clamp,
    /// Transparent black (all four channels 0) outside.
    Black,
}

impl Wrap {
    /// The mode's code in [`TextureInfo::wrap_s`] and `wrap_t`, and the
    /// `TEXTURE_WRAP_*` constants of the WGSL.
    pub const fn code(self) -> u32 {
        match self {
            Wrap::Periodic => 0,
            Wrap::Clamp => 1,
            Wrap::Black => 2,
        }
    }
}

/// A texture as a scene names it: a file and how to read and wrap it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    /// The image file (PNG, OpenEXR or TIFF, recognised by its content).
    pub path: PathBuf,
    /// How its values are encoded.
    #[serde(default)]
    pub color_space: ColorSpace,
    /// Wrap mode along s.
    #[serde(default)]
    pub wrap_s: Wrap,
    /// Wrap mode along t.
    #[serde(default)]
    pub wrap_t: Wrap,
}

impl TextureDesc {
    /// `path`, colour space [`ColorSpace::Auto`], periodic in s and t.
    pub fn new(path: impl Into<PathBuf>) -> TextureDesc {
        TextureDesc {
            path: path.into(),
            color_space: ColorSpace::Auto,
            wrap_s: Wrap::Periodic,
            wrap_t: Wrap::Periodic,
        }
    }

    /// The same texture with `wrap` along both axes.
    pub fn with_wrap(self, wrap: Wrap) -> TextureDesc {
        TextureDesc {
            wrap_s: wrap,
            wrap_t: wrap,
            ..self
        }
    }
}

/// A texture of a [`TextureSet`]: its index in [`TextureSet::gpu_tables`]'
/// info table, which the GPU receives as is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TextureId(pub u32);

/// The most GPU memory, in bytes, that a frame's packed mip chains may
/// take. [`TextureBudget::DEFAULT`] is 1 GiB (134 million texels, a little
/// over six 4096 x 4096 textures with their chains). The texel buffer must
/// also fit the device's storage-buffer binding limit, which the renderer
/// checks; whatever the budget, the texel offsets must fit a `u32`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextureBudget {
    /// Bytes of packed texels (8 per texel).
    pub bytes: u64,
}

impl TextureBudget {
    /// 1 GiB.
    pub const DEFAULT: TextureBudget = TextureBudget { bytes: 1 << 30 };
}

impl Default for TextureBudget {
    fn default() -> TextureBudget {
        TextureBudget::DEFAULT
    }
}

/// Bytes of one packed texel.
pub const TEXEL_BYTES: u64 = 8;

/// One decoded image's chain in the texel buffer (shared by the textures
/// that differ only in their wrap modes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Chain {
    offset: u32,
    width: u32,
    height: u32,
}

/// The textures of a frame, their mip chains in one texel buffer.
///
/// Textures are deduplicated: adding a file again (by its canonical path)
/// with the same colour space and wrap modes returns the first id, and one
/// with other wrap modes gets an id of its own over the same texels.
#[derive(Debug, Clone, Default)]
pub struct TextureSet {
    /// Changes with every texture added, and only then: a clone keeps it,
    /// so the GPU path uploads a set's texels once for as long as it sees
    /// the same revision ([`TextureSet::revision`]). 0 for an empty set.
    revision: u64,
    budget: TextureBudget,
    infos: Vec<TextureInfo>,
    /// The path each texture was first added by, for messages.
    paths: Vec<PathBuf>,
    texels: Vec<[u32; 2]>,
    chains: HashMap<(PathBuf, ColorSpace), Chain>,
    ids: HashMap<(PathBuf, ColorSpace, Wrap, Wrap), TextureId>,
}

/// Two sets are equal when they hold the same textures, whatever their
/// revisions.
impl PartialEq for TextureSet {
    fn eq(&self, other: &Self) -> bool {
        self.budget == other.budget
            && self.infos == other.infos
            && self.paths == other.paths
            && self.texels == other.texels
            && self.chains == other.chains
            && self.ids == other.ids
    }
}

impl TextureSet {
    /// An empty set whose packed texels may take at most `budget`.
    pub fn new(budget: TextureBudget) -> TextureSet {
        TextureSet {
            budget,
            ..TextureSet::default()
        }
    }

    /// Loads `desc` (unless the set has it already) and returns its id.
    ///
    /// The file's header is read first: a side over [`MAX_TEXTURE_SIDE`] is
    /// [`TextureError::TooLarge`], and a chain that would take the set past
    /// its budget [`TextureError::OverBudget`], both before any pixel is
    /// decoded. A failed add leaves the set as it was.
    pub fn add(&mut self, desc: &TextureDesc) -> Result<TextureId, TextureError> {
        let path = &desc.path;
        let canonical = std::fs::canonicalize(path).map_err(|source| {
            TextureError::from_input(crate::input::InputError::Io {
                path: path.clone(),
                kind: crate::input::InputKind::Texture,
                source,
            })
        })?;
        let key = (
            canonical.clone(),
            desc.color_space,
            desc.wrap_s,
            desc.wrap_t,
        );
        if let Some(&id) = self.ids.get(&key) {
            return Ok(id);
        }
        let chain_key = (canonical, desc.color_space);
        let chain = match self.chains.get(&chain_key) {
            Some(&chain) => chain,
            None => {
                let bytes = load::read(path)?;
                let (image, _) = load::decode(&bytes, path, desc.color_space, |w, h| {
                    self.admit(path, w, h)
                })?;
                let chain = self.push_chain(image);
                self.chains.insert(chain_key, chain);
                chain
            }
        };
        let id = self.push_info(path, chain, desc.wrap_s, desc.wrap_t);
        self.ids.insert(key, id);
        Ok(id)
    }

    /// Adds an image made in memory: `width x height` linear RGBA texels,
    /// row-major, top row first. `name` only names it in errors; such
    /// images are never deduplicated.
    pub fn add_linear(
        &mut self,
        name: &Path,
        width: u32,
        height: u32,
        texels: Vec<Vec4>,
        wrap_s: Wrap,
        wrap_t: Wrap,
    ) -> Result<TextureId, TextureError> {
        if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(TextureError::TooLarge {
                path: name.to_path_buf(),
                width,
                height,
                max: MAX_TEXTURE_SIDE,
            });
        }
        if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
            return Err(TextureError::Decode {
                path: name.to_path_buf(),
                message: format!("{} texels given for a {width}x{height} image", texels.len()),
            });
        }
        if let Some(at) = texels.iter().position(|t| !t.is_finite()) {
            return Err(TextureError::NonFinite {
                path: name.to_path_buf(),
                x: (at % width as usize) as u32,
                y: (at / width as usize) as u32,
            });
        }
        self.admit(name, width, height)?;
        let chain = self.push_chain(LinearImage {
            width,
            height,
            texels,
        });
        Ok(self.push_info(name, chain, wrap_s, wrap_t))
    }

    /// Refuses a `width x height` chain that would not fit the budget (nor
    /// `u32` texel offsets).
    fn admit(&self, path: &Path, width: u32, height: u32) -> Result<(), TextureError> {
        let needed = mipmap::chain_texels(width, height) * TEXEL_BYTES;
        let used = self.packed_bytes();
        let budget = self.budget.bytes.min(u64::from(u32::MAX) * TEXEL_BYTES);
        if used + needed > budget {
            return Err(TextureError::OverBudget {
                path: path.to_path_buf(),
                needed,
                used,
                budget: self.budget.bytes,
            });
        }
        Ok(())
    }

    fn push_chain(&mut self, image: LinearImage) -> Chain {
        // `admit` kept the total within u32 texels.
        let chain = Chain {
            offset: self.texels.len() as u32,
            width: image.width,
            height: image.height,
        };
        self.texels.extend(mipmap::build(image));
        chain
    }

    fn push_info(&mut self, path: &Path, chain: Chain, wrap_s: Wrap, wrap_t: Wrap) -> TextureId {
        // Unique over the process: sets made apart never share one.
        static REVISIONS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        self.revision = REVISIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let id = TextureId(self.infos.len() as u32);
        self.infos.push(TextureInfo {
            offset: chain.offset,
            width: chain.width,
            height: chain.height,
            levels: mipmap::level_count(chain.width, chain.height),
            wrap_s: wrap_s.code(),
            wrap_t: wrap_t.code(),
            pad0: 0,
            pad1: 0,
        });
        self.paths.push(path.to_path_buf());
        id
    }

    /// Identifies the set's contents: equal revisions mean the same
    /// textures (a set and its clones), a texture added gives a new one.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Number of textures (ids).
    pub fn len(&self) -> usize {
        self.infos.len()
    }

    /// No texture was added.
    pub fn is_empty(&self) -> bool {
        self.infos.is_empty()
    }

    /// The budget the set was made with.
    pub fn budget(&self) -> TextureBudget {
        self.budget
    }

    /// Bytes of packed texels so far (8 per texel of every chain).
    pub fn packed_bytes(&self) -> u64 {
        self.texels.len() as u64 * TEXEL_BYTES
    }

    /// The GPU entry of texture `id`.
    pub fn info(&self, id: TextureId) -> Option<&TextureInfo> {
        self.infos.get(id.0 as usize)
    }

    /// The path texture `id` was added by.
    pub fn path(&self, id: TextureId) -> Option<&Path> {
        self.paths.get(id.0 as usize).map(PathBuf::as_path)
    }

    /// The filtered colour (linear RGBA) of texture `id` at `st`, for a
    /// shading point whose footprint spans `axis_a` and `axis_b` in (s, t):
    /// the micropolygon's extent along u, `(ds/du du, dt/du du)`, and along
    /// v, `(ds/dv dv, dt/dv dv)`. Trilinear: `lod = log2` of the longer
    /// axis in level-0 texels, bilinear within the two levels around it
    /// (wrap modes per tap), blended linearly ("Textures" in `docs/reyes.md`).
    /// An id from another set, or a non-finite `st`, gives transparent
    /// black, as on the GPU.
    pub fn sample(&self, id: TextureId, st: Vec2, axis_a: Vec2, axis_b: Vec2) -> Vec4 {
        sample::sample(&self.infos, &self.texels, id.0, st, axis_a, axis_b)
    }

    /// The largest `|value|` of `channel` (0 = red) over texture `id`'s
    /// level 0, `None` for an id from another set. No filtered lookup
    /// exceeds it: the other levels average level 0, and filtering blends
    /// texels with weights that sum to 1 (or 0 outside a black wrap).
    pub fn largest_magnitude(&self, id: TextureId, channel: usize) -> Option<f32> {
        let info = self.infos.get(id.0 as usize)?;
        let start = info.offset as usize;
        let end = start + info.width as usize * info.height as usize;
        let level0 = self.texels.get(start..end)?;
        Some(
            level0
                .iter()
                .map(|&texel| mipmap::unpack(texel)[channel.min(3)].abs())
                .fold(0.0, f32::max),
        )
    }

    /// Texture `id` as a latitude-longitude environment map, seen along the
    /// world-space direction `r` (RenderMan's `environment(name, R)`), over
    /// the footprint of the direction's changes `dr_du` and `dr_dv` across
    /// the shading point (zero: level 0, bilinear). Periodic in longitude
    /// and clamped in latitude, whatever the texture's wrap modes; the
    /// convention is [`environment`]'s. A zero or non-finite `r`, or an id
    /// from another set, gives transparent black, as on the GPU.
    pub fn environment(&self, id: TextureId, r: Vec3, dr_du: Vec3, dr_dv: Vec3) -> Vec4 {
        environment::environment(&self.infos, &self.texels, id.0, r, dr_du, dr_dv)
    }

    /// The GPU tables: the `texture_infos` entries (indexed by
    /// [`TextureId`]) and the `texels` buffer. A set without textures gives
    /// [`TextureInfo::DUMMY`] and [`DUMMY_TEXELS`], so that neither buffer
    /// is ever empty.
    pub fn gpu_tables(&self) -> (Vec<TextureInfo>, &[[u32; 2]]) {
        if self.infos.is_empty() {
            return (vec![TextureInfo::DUMMY], DUMMY_TEXELS);
        }
        (self.infos.clone(), &self.texels)
    }
}
