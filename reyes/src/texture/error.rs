//! Why a texture could not be added to a [`super::TextureSet`].

use std::path::{Path, PathBuf};

use crate::input::{InputError, excerpt};

/// A path for an error message, cut to a bounded length (a scene may name
/// any string as a texture).
fn shown(path: &Path) -> String {
    excerpt(&path.display().to_string())
}

/// `bytes` for a message, in MiB with two decimals next to the exact count.
fn mib(bytes: u64) -> String {
    format!(
        "{:.2} MiB ({bytes} bytes)",
        bytes as f64 / (1u64 << 20) as f64
    )
}

/// Errors of [`super::TextureSet::add`] and [`super::TextureSet::add_linear`];
/// every one names the texture's path (or, for an image made in memory, the
/// name it was given).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TextureError {
    /// No file at the path (or a directory on the way is missing).
    #[error("texture {} does not exist", shown(path))]
    Missing {
        /// The path as given.
        path: PathBuf,
    },
    /// The file was refused or could not be read: not a regular file, over
    /// the texture file cap (`crate::input::InputKind::Texture`), no
    /// permission, an I/O error.
    #[error(transparent)]
    Input(InputError),
    /// The file is not an image the decoders read (PNG, OpenEXR or TIFF), or
    /// it is malformed, or an image made in memory is inconsistent.
    #[error("texture {} cannot be decoded: {message}", shown(path))]
    Decode {
        /// The file.
        path: PathBuf,
        /// What the decoder (or the check) said.
        message: String,
    },
    /// The image is larger than [`super::MAX_TEXTURE_SIDE`] on a side (found
    /// from the header, before any pixel is decoded).
    #[error(
        "texture {} is {width}x{height}; at most {max}x{max} texels are supported",
        shown(path)
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Largest accepted side.
        max: u32,
    },
    /// Adding the texture's mip chain would take the frame's textures past
    /// the [`super::TextureBudget`] (found from the header, before decoding).
    #[error(
        "texture {} needs {} of GPU memory (its mip chain, 8 bytes per texel); the frame's textures already use {} of a budget of {}",
        shown(path),
        mib(*needed),
        mib(*used),
        mib(*budget)
    )]
    OverBudget {
        /// The file.
        path: PathBuf,
        /// Bytes of this texture's packed mip chain.
        needed: u64,
        /// Bytes of the textures added before it.
        used: u64,
        /// The budget in bytes.
        budget: u64,
    },
    /// A texel is NaN or infinite (float images only): filtering would
    /// spread it over its neighbourhood.
    #[error("texture {} has a non-finite value at texel ({x}, {y})", shown(path))]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Column of the first such texel.
        x: u32,
        /// Row of the first such texel (0 at the top).
        y: u32,
    },
}

impl TextureError {
    /// The texture the error is about.
    pub fn path(&self) -> &Path {
        match self {
            TextureError::Input(error) => error.path(),
            TextureError::Missing { path }
            | TextureError::Decode { path, .. }
            | TextureError::TooLarge { path, .. }
            | TextureError::OverBudget { path, .. }
            | TextureError::NonFinite { path, .. } => path,
        }
    }

    /// A missing file is [`TextureError::Missing`]; any other read failure
    /// keeps the input layer's error.
    pub(super) fn from_input(error: InputError) -> TextureError {
        match error {
            InputError::Io { path, source, .. }
                if source.kind() == std::io::ErrorKind::NotFound =>
            {
                TextureError::Missing { path }
            }
            other => TextureError::Input(other),
        }
    }
}
