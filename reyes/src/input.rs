//! Reading input files: every file the renderer reads from disk (models,
//! scenes, user WGSL, height-map PNGs, textures) goes through [`read_input`] or
//! [`read_text`].
//!
//! They guard against paths that would make a plain `std::fs::read` hang or
//! exhaust memory:
//!
//! * only regular files are read. A directory, a device (`/dev/zero`,
//!   `/dev/urandom`), a FIFO, a socket or `/dev/stdin` is refused with
//!   [`InputError::NotRegularFile`], also behind a symbolic link (the link's
//!   target is what is judged). On Unix the file is opened with `O_NONBLOCK`,
//!   so a FIFO swapped in after the check cannot block the open, and the
//!   opened file is checked again;
//! * at most a cap of bytes is read ([`InputError::TooLarge`]). The defaults
//!   ([`InputKind::default_limit`]) are 1 GiB for models, 16 MiB for scenes
//!   and WGSL, 64 MiB for height-map PNGs, 512 MiB for textures. [`set_limits`] changes them for the
//!   process (the CLI's `--max-input-bytes`). The read goes through
//!   `Read::take(limit + 1)`, so even a file that grows while it is read (or a
//!   device swapped in) cannot exceed the cap;
//! * text must be UTF-8 ([`InputError::NotUtf8`]); a leading UTF-8 byte-order
//!   mark is removed, for every text format alike.
//!
//! [`excerpt`] cuts text that an error message echoes (a malformed line, a
//! token) to [`EXCERPT_CHARS`] characters, so a 200 MB one-line file cannot
//! produce a 200 MB message.

use std::fmt;
use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, Read};
use std::path::{Path, PathBuf};
use std::sync::RwLock;

/// One mebibyte.
pub const MIB: u64 = 1 << 20;
/// One gibibyte.
pub const GIB: u64 = 1 << 30;

/// Longest text, in characters, that an error message quotes from an input
/// file (see [`excerpt`]).
pub const EXCERPT_CHARS: usize = 120;

/// Longest message, in characters, kept from a parser whose messages may
/// quote the input (serde's "invalid type: string \"...\""). Longer than
/// [`EXCERPT_CHARS`], because such messages also list the expected fields.
pub const MESSAGE_CHARS: usize = 1024;

/// The UTF-8 encoding of U+FEFF, the byte-order mark some editors write at
/// the start of a text file.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// What a file is read as: decides the default size cap and names the file
/// in error messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InputKind {
    /// A `.bpt` or `.bez` patch model, or an `.obj` mesh.
    Model,
    /// A `.toml` scene.
    Scene,
    /// A `.wgsl` user displacement function.
    Wgsl,
    /// A `.wgsl` surface shader (the same cap as [`InputKind::Wgsl`]).
    Shader,
    /// A PNG height map.
    HeightMap,
    /// A texture image (PNG, OpenEXR or TIFF; `crate::texture`).
    Texture,
}

impl InputKind {
    /// The cap used unless `set_limits` changes it.
    ///
    /// * models: 1 GiB. The parser needs the whole text, and a 1 GiB `.bpt`
    ///   holds about 10 million patches, far more than one frame renders;
    /// * scenes and WGSL: 16 MiB, thousands of times a hand-written file;
    /// * height maps: 64 MiB. The largest accepted map
    ///   (`crate::params::MAX_HEIGHT_MAP_SIDE`² texels of 16 bits) is 32 MiB
    ///   of pixel data even stored uncompressed;
    /// * textures: 512 MiB, an uncompressed 4096 x 4096 RGBA float EXR
    ///   twice over. The image size has its own limits
    ///   (`crate::texture::MAX_TEXTURE_SIDE` and the texture budget), checked
    ///   from the header before decoding.
    pub const fn default_limit(self) -> u64 {
        match self {
            InputKind::Model => GIB,
            InputKind::Scene | InputKind::Wgsl | InputKind::Shader => 16 * MIB,
            InputKind::HeightMap => 64 * MIB,
            InputKind::Texture => 512 * MIB,
        }
    }

    /// The cap in force now: `limits` for this kind.
    pub fn limit(self) -> u64 {
        limits().get(self)
    }
}

impl fmt::Display for InputKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            InputKind::Model => "model file",
            InputKind::Scene => "scene file",
            InputKind::Wgsl => "displacement function",
            InputKind::Shader => "surface shader",
            InputKind::HeightMap => "height map",
            InputKind::Texture => "texture",
        })
    }
}

/// The size cap, in bytes, of every kind of input file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// `.bpt`, `.bez` and `.obj` models.
    pub model: u64,
    /// `.toml` scenes.
    pub scene: u64,
    /// `.wgsl` user functions.
    pub wgsl: u64,
    /// PNG height maps (the file; the image size has its own limit,
    /// [`crate::params::MAX_HEIGHT_MAP_SIDE`]).
    pub height_map: u64,
    /// Texture images (the file; the image size is checked separately).
    pub texture: u64,
}

impl Limits {
    /// The documented defaults ([`InputKind::default_limit`]).
    pub const DEFAULT: Limits = Limits {
        model: InputKind::Model.default_limit(),
        scene: InputKind::Scene.default_limit(),
        wgsl: InputKind::Wgsl.default_limit(),
        height_map: InputKind::HeightMap.default_limit(),
        texture: InputKind::Texture.default_limit(),
    };

    /// The same cap for every kind (what `--max-input-bytes` sets).
    pub const fn all(bytes: u64) -> Limits {
        Limits {
            model: bytes,
            scene: bytes,
            wgsl: bytes,
            height_map: bytes,
            texture: bytes,
        }
    }

    /// The cap for `kind`.
    pub const fn get(&self, kind: InputKind) -> u64 {
        match kind {
            InputKind::Model => self.model,
            InputKind::Scene => self.scene,
            InputKind::Wgsl | InputKind::Shader => self.wgsl,
            InputKind::HeightMap => self.height_map,
            InputKind::Texture => self.texture,
        }
    }
}

impl Default for Limits {
    fn default() -> Limits {
        Limits::DEFAULT
    }
}

/// The process-wide caps. A global, because files are read deep inside
/// [`crate::scene::Scene::load_models`] and
/// [`crate::prepare::PreparedScene::load`], which a command line sets up once.
static LIMITS: RwLock<Limits> = RwLock::new(Limits::DEFAULT);

/// Sets the caps used by every later load ([`crate::model::Model::load`],
/// [`crate::scene::Scene::load`], height maps, ...), for the whole process.
pub fn set_limits(limits: Limits) {
    // The lock only guards a Copy value, so a poisoned lock still holds a valid one.
    *LIMITS.write().unwrap_or_else(|e| e.into_inner()) = limits;
}

/// The caps in force ([`Limits::DEFAULT`] unless [`set_limits`] was called).
pub fn limits() -> Limits {
    *LIMITS.read().unwrap_or_else(|e| e.into_inner())
}

/// What a refused path is, when it is not a regular file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A directory.
    Directory,
    /// A character device such as `/dev/zero`, `/dev/urandom` or a terminal.
    CharDevice,
    /// A block device such as a disk.
    BlockDevice,
    /// A FIFO (named pipe), or a pipe such as `/dev/stdin` under a shell pipe.
    Fifo,
    /// A Unix domain socket.
    Socket,
    /// Anything else that is not a regular file.
    Other,
}

impl FileKind {
    fn of(metadata: &Metadata) -> Option<FileKind> {
        let file_type = metadata.file_type();
        if file_type.is_file() {
            return None;
        }
        if file_type.is_dir() {
            return Some(FileKind::Directory);
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            if file_type.is_char_device() {
                return Some(FileKind::CharDevice);
            }
            if file_type.is_block_device() {
                return Some(FileKind::BlockDevice);
            }
            if file_type.is_fifo() {
                return Some(FileKind::Fifo);
            }
            if file_type.is_socket() {
                return Some(FileKind::Socket);
            }
        }
        Some(FileKind::Other)
    }
}

impl fmt::Display for FileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileKind::Directory => "a directory",
            FileKind::CharDevice => "a character device",
            FileKind::BlockDevice => "a block device",
            FileKind::Fifo => "a FIFO (named pipe)",
            FileKind::Socket => "a socket",
            FileKind::Other => "a special file",
        })
    }
}

/// `bytes` for a message: exact, with a binary unit where it is round.
fn show_bytes(bytes: u64) -> String {
    if bytes >= GIB && bytes.is_multiple_of(GIB) {
        format!("{} GiB", bytes / GIB)
    } else if bytes >= MIB && bytes.is_multiple_of(MIB) {
        format!("{} MiB", bytes / MIB)
    } else {
        format!("{bytes} bytes")
    }
}

/// Why an input file could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// The operating system could not stat, open or read the file.
    #[error("cannot read {kind} {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What it was read as.
        kind: InputKind,
        /// The underlying I/O error.
        #[source]
        source: io::Error,
    },
    /// The path (or the target of a symbolic link) is not a regular file.
    #[error("{kind} {} is {file}, not a regular file; only regular files are read", path.display())]
    NotRegularFile {
        /// The path as given.
        path: PathBuf,
        /// What it was read as.
        kind: InputKind,
        /// What it is instead.
        file: FileKind,
    },
    /// The file is larger than the cap for its kind.
    #[error(
        "{kind} {} is larger than the limit of {} ({}); raise the limit with `--max-input-bytes`",
        path.display(),
        show_bytes(*limit),
        size.map_or_else(|| "it grew while being read".to_string(), |s| format!("{s} bytes")),
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// What it was read as.
        kind: InputKind,
        /// Its size, when known before reading (`None`: it grew past the cap while being read).
        size: Option<u64>,
        /// The cap, in bytes.
        limit: u64,
    },
    /// A text file is not valid UTF-8.
    #[error("{kind} {} is not UTF-8 text (invalid bytes at byte offset {offset})", path.display())]
    NotUtf8 {
        /// The file.
        path: PathBuf,
        /// What it was read as.
        kind: InputKind,
        /// Offset of the first invalid byte (after a removed byte-order mark).
        offset: usize,
    },
}

impl InputError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            InputError::Io { path, .. }
            | InputError::NotRegularFile { path, .. }
            | InputError::TooLarge { path, .. }
            | InputError::NotUtf8 { path, .. } => path,
        }
    }
}

/// Refuses what is not a regular file, or is larger than `limit`.
fn check(metadata: &Metadata, path: &Path, kind: InputKind, limit: u64) -> Result<(), InputError> {
    if let Some(file) = FileKind::of(metadata) {
        return Err(InputError::NotRegularFile {
            path: path.to_path_buf(),
            kind,
            file,
        });
    }
    if metadata.len() > limit {
        return Err(InputError::TooLarge {
            path: path.to_path_buf(),
            kind,
            size: Some(metadata.len()),
            limit,
        });
    }
    Ok(())
}

/// Opens for reading without blocking: opening a FIFO that has no writer
/// blocks forever, and the path may have become one after it was checked.
fn open_nonblocking(path: &Path) -> io::Result<File> {
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Reads from a regular file ignore O_NONBLOCK, so it changes nothing
        // for the files that are accepted.
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

/// Reads the bytes of the regular file at `path`, at most `limit` of them.
///
/// Symbolic links are followed; what they point to must be a regular file.
/// Errors name `path` and say what `kind` of file it was read as.
pub fn read_input(path: &Path, kind: InputKind, limit: u64) -> Result<Vec<u8>, InputError> {
    let io_error = |source| InputError::Io {
        path: path.to_path_buf(),
        kind,
        source,
    };
    // `fs::metadata` follows symbolic links, so a link to /dev/zero is refused too.
    check(
        &std::fs::metadata(path).map_err(io_error)?,
        path,
        kind,
        limit,
    )?;
    let file = open_nonblocking(path).map_err(io_error)?;
    // The path may have been replaced between the check and the open: judge
    // the file that was actually opened.
    let opened = file.metadata().map_err(io_error)?;
    check(&opened, path, kind, limit)?;
    // Reserve what the file says it holds (at most the cap), so reading a
    // large model does not copy it over and over while the buffer grows.
    let expected = usize::try_from(opened.len()).unwrap_or(0);
    let mut bytes = Vec::with_capacity(expected);
    // One byte more than the cap tells a file that grew past it from one
    // that is exactly at it.
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io_error)?;
    if bytes.len() as u64 > limit {
        return Err(InputError::TooLarge {
            path: path.to_path_buf(),
            kind,
            size: None,
            limit,
        });
    }
    Ok(bytes)
}

/// Reads a UTF-8 text file through [`read_input`], without a leading
/// byte-order mark.
pub fn read_text(path: &Path, kind: InputKind, limit: u64) -> Result<String, InputError> {
    let mut bytes = read_input(path, kind, limit)?;
    if bytes.starts_with(UTF8_BOM) {
        bytes.drain(..UTF8_BOM.len());
    }
    String::from_utf8(bytes).map_err(|e| InputError::NotUtf8 {
        path: path.to_path_buf(),
        kind,
        offset: e.utf8_error().valid_up_to(),
    })
}

/// `text` without a leading byte-order mark (for parsers given text that
/// did not come through [`read_text`]).
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// `text` for an error message: at most [`EXCERPT_CHARS`] characters, with
/// `…` when it was cut.
pub fn excerpt(text: &str) -> String {
    excerpt_to(text, EXCERPT_CHARS)
}

/// `text` cut to at most `max_chars` characters, with `…` when it was cut.
pub fn excerpt_to(text: &str, max_chars: usize) -> String {
    match text.char_indices().nth(max_chars) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excerpts_are_bounded() {
        assert_eq!(excerpt("short"), "short");
        let long = "é".repeat(1000);
        let cut = excerpt(&long);
        assert_eq!(cut.chars().count(), EXCERPT_CHARS + 1);
        assert!(cut.ends_with('…'));
        assert_eq!(excerpt_to("abcdef", 3), "abc…");
        assert_eq!(excerpt_to("abc", 3), "abc");
    }

    #[test]
    fn limits_cover_every_kind() {
        let all = Limits::all(7);
        for kind in [
            InputKind::Model,
            InputKind::Scene,
            InputKind::Wgsl,
            InputKind::Shader,
            InputKind::HeightMap,
        ] {
            assert_eq!(all.get(kind), 7);
            assert_eq!(Limits::DEFAULT.get(kind), kind.default_limit());
        }
        assert_eq!(show_bytes(GIB), "1 GiB");
        assert_eq!(show_bytes(16 * MIB), "16 MiB");
        assert_eq!(show_bytes(10), "10 bytes");
    }

    #[test]
    fn bom_is_stripped() {
        assert_eq!(strip_bom("\u{feff}12"), "12");
        assert_eq!(strip_bom("12"), "12");
    }
}
