//! Writing rendered images (and their statistics) to disk.
//!
//! The file extension chooses the format ([`ImageFormat`]): `.png` for
//! the 8-bit sRGB image (exposed and quantized, [`crate::quantize`]),
//! `.exr` for OpenEXR in float linear RGBA (the resolve's values as they
//! are). Every file is
//! written to a temporary file beside its target and renamed over it once
//! complete, so a failed write leaves no truncated file and destroys no old
//! one. [`OutputGuard`] checks every output of a command against every
//! file the run reads and against the other outputs, before any work;
//! [`OutputPlan`] writes a render's image and statistics all or nothing, and
//! [`StagedFiles`] does the same for any set of files (`reyes convert`'s
//! TOML and models).

pub mod console;
mod depth;
mod environment;
mod guard;
mod paths;
mod staged;
mod warnings;

use std::path::{Path, PathBuf};

use image::{ImageBuffer, Rgba, Rgba32FImage, RgbaImage};

pub use self::depth::{
    DEPTH_CHANNEL, DepthImage, MakeShadowError, ReadDepthError, make_shadow, read_depth,
    write_depth, write_shadow_map,
};
pub use self::environment::{MakeEnvironmentError, make_cube_face_environment};
pub use self::guard::{OutputGuard, OutputKind};
use self::staged::Staged;
pub use self::staged::{StagedFiles, ignore_file_size_signal};
pub use self::warnings::{DepthExtent, frame_warnings};
use crate::color::srgb_to_linear;
use crate::stats::RenderStats;

/// The extensions an image may be written with, for error messages.
pub const IMAGE_EXTENSIONS: &str = ".png (8-bit sRGB PNG) or .exr (float linear RGBA OpenEXR)";

/// Why an output could not be checked or written. Every variant names the
/// file concerned.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The path is empty or ends in `/`, `.` or `..`.
    #[error("{}: names no file (a file name must not be empty or end in `/`, `.` or `..`)", path.display())]
    NoFileName {
        /// The path as given.
        path: PathBuf,
    },
    /// The image path's extension names no format written here.
    #[error("{}: unknown image format; the extension chooses it: {IMAGE_EXTENSIONS}", path.display())]
    UnknownFormat {
        /// The path as given.
        path: PathBuf,
    },
    /// The path exists and is a directory, device, FIFO or socket, which a
    /// rename must not replace.
    #[error("{}: exists and is not a regular file", path.display())]
    NotAFile {
        /// The file the path leads to.
        path: PathBuf,
    },
    /// The path's extension names another format than the one written.
    #[error("{}: the extension does not match what is written here ({written}); name it *{expected}", path.display())]
    WrongExtension {
        /// The path as given.
        path: PathBuf,
        /// What would be written (e.g. `a TOML scene`).
        written: &'static str,
        /// The extension to use.
        expected: &'static str,
    },
    /// An output leads to a file the run reads (by name, through a link,
    /// or as a hard link of it).
    #[error(
        "the {output} {} is the input {input} {} (the same file): writing it would destroy the input; nothing was written",
        output_path.display(),
        input_path.display()
    )]
    ReplacesInput {
        /// What the output is for (e.g. `image`).
        output: String,
        /// The output path as given.
        output_path: PathBuf,
        /// What the input is (e.g. `height map`).
        input: String,
        /// The input path as given (or as the file that read it names it).
        input_path: PathBuf,
    },
    /// Two outputs lead to the same file.
    #[error("the {first} and the {second} both name {}; nothing was written", path.display())]
    SameFile {
        /// What the first path is for (e.g. `image`).
        first: String,
        /// What the second path is for (e.g. `statistics JSON`).
        second: String,
        /// The file both lead to.
        path: PathBuf,
    },
    /// The path's links could not be followed.
    #[error("cannot resolve {}: {source}", path.display())]
    Resolve {
        /// The path as given.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The parent directory could not be created.
    #[error("cannot create directory {}: {source}", path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// No file can be created in the directory (read-only, no permission,
    /// a pseudo file system such as `/proc`).
    #[error("cannot create files in {}: {source}", path.display())]
    NotWritable {
        /// The directory.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The depth output ([`crate::Aov::Z`]) was to be written as an 8-bit
    /// image.
    #[error("{}: the z (depth) output is 32-bit floats, which an 8-bit PNG cannot hold; name it *.exr", path.display())]
    DepthNeedsExr {
        /// The path as given.
        path: PathBuf,
    },
    /// Encoding the image failed (image errors wrap I/O errors).
    #[error("cannot write image {}: {source}", path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// The underlying image error.
        #[source]
        source: image::ImageError,
    },
    /// Serializing the statistics failed.
    #[error("cannot write statistics {}: {source}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: serde_json::Error,
    },
    /// Writing the temporary file failed (e.g. the disk is full).
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// Renaming the complete temporary file over the target failed.
    #[error("cannot replace {}: {source}", path.display())]
    Rename {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// An image file format, chosen by the file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// `.png`: the 8-bit sRGB image as rendered (exposed and quantized).
    Png,
    /// `.exr`: OpenEXR, 32-bit float linear RGBA: a render's resolved
    /// linear values (not clamped, exposed or quantized); for an image that
    /// has only 8 bits ([`write_image`]), those decoded with the exact sRGB
    /// transfer function (alpha scaled to [0, 1]).
    Exr,
}

impl ImageFormat {
    /// The format `path`'s extension names (case-insensitive), or
    /// [`OutputError::UnknownFormat`].
    pub fn from_path(path: &Path) -> Result<ImageFormat, OutputError> {
        let extension = path.extension().and_then(|e| e.to_str());
        match extension.map(str::to_ascii_lowercase).as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("exr") => Ok(ImageFormat::Exr),
            _ => Err(OutputError::UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// The checked outputs of one render: the image and, optionally, the
/// statistics as JSON. Recorded in the run's [`OutputGuard`] before
/// rendering by [`OutputPlan::new`], written after it by [`OutputPlan::write`].
#[derive(Debug, Clone)]
pub struct OutputPlan {
    /// The image's resolved path (links followed) and format.
    image: (PathBuf, ImageFormat),
    /// Where the statistics go, resolved.
    stats_json: Option<PathBuf>,
}

impl OutputPlan {
    /// Records the outputs of a render in `guard` (see
    /// [`OutputGuard::add_output`]): the image, whose extension names its
    /// format, and the statistics JSON. The directories are created by the
    /// guard's [`OutputGuard::prepare_dirs`], once every input is recorded.
    pub fn new(
        guard: &mut OutputGuard,
        image: &Path,
        stats_json: Option<&Path>,
    ) -> Result<OutputPlan, OutputError> {
        OutputPlan::of_frame(guard, None, image, stats_json)
    }

    /// [`OutputPlan::new`] for one of several frames: messages call the
    /// outputs `image of frame 2`, `statistics JSON of frame 2`.
    pub fn of_frame(
        guard: &mut OutputGuard,
        frame: Option<&str>,
        image: &Path,
        stats_json: Option<&Path>,
    ) -> Result<OutputPlan, OutputError> {
        OutputPlan::planned(guard, frame, OutputKind::Image, image, stats_json)
    }

    /// [`OutputPlan::of_frame`] for a depth frame ([`crate::Aov::Z`]): the
    /// image is a single-channel float EXR whatever its extension (a `.z`
    /// or `.shad` name, as RenderMan's depth passes have), but `.png` is
    /// [`OutputError::DepthNeedsExr`] (see [`OutputKind::Depth`]).
    pub fn of_depth_frame(
        guard: &mut OutputGuard,
        frame: Option<&str>,
        image: &Path,
        stats_json: Option<&Path>,
    ) -> Result<OutputPlan, OutputError> {
        OutputPlan::planned(guard, frame, OutputKind::Depth, image, stats_json)
    }

    fn planned(
        guard: &mut OutputGuard,
        frame: Option<&str>,
        kind: OutputKind,
        image: &Path,
        stats_json: Option<&Path>,
    ) -> Result<OutputPlan, OutputError> {
        let label = |what: &str| match frame {
            Some(frame) => format!("{what} of {frame}"),
            None => what.to_owned(),
        };
        let image_file = guard.add_output(kind, label("image"), image)?;
        let format = match kind {
            OutputKind::Depth => ImageFormat::Exr,
            _ => ImageFormat::from_path(image)?,
        };
        let stats_file = stats_json
            .map(|path| guard.add_output(OutputKind::Json, label("statistics JSON"), path))
            .transpose()?;
        Ok(OutputPlan {
            image: (image_file, format),
            stats_json: stats_file,
        })
    }

    /// Checks the outputs of a render before it starts, in a guard of its
    /// own: [`OutputPlan::new`] after `inputs` (labelled files the render
    /// reads, which an output must not replace), then the directories
    /// ([`OutputGuard::prepare_dirs`]). Nothing is created unless every
    /// other check passed.
    pub fn check(
        image: &Path,
        stats_json: Option<&Path>,
        inputs: &[(&str, &Path)],
    ) -> Result<OutputPlan, OutputError> {
        let mut guard = OutputGuard::new();
        guard.add_inputs(inputs.iter().copied())?;
        let plan = OutputPlan::new(&mut guard, image, stats_json)?;
        guard.prepare_dirs()?;
        Ok(plan)
    }

    /// The file the image goes to (links followed).
    pub fn image_path(&self) -> &Path {
        &self.image.0
    }

    /// Writes the image and, if planned, `stats` as pretty JSON: both go to
    /// temporary files first and are renamed over their targets only when
    /// both were written, so a failure leaves neither new file behind. A
    /// PNG holds `image` (8-bit), an EXR `linear` (the resolve's floats).
    pub fn write(
        &self,
        image: &RgbaImage,
        linear: &Rgba32FImage,
        stats: &RenderStats,
    ) -> Result<(), OutputError> {
        let (path, format) = &self.image;
        let staged_image = stage_image(image, Some(linear), path, *format)?;
        let staged_stats = self.stage_stats(stats)?;
        staged_image.commit()?;
        staged_stats.map(Staged::commit).transpose()?;
        Ok(())
    }

    /// The statistics as pretty JSON in a temporary file, if planned.
    fn stage_stats(&self, stats: &RenderStats) -> Result<Option<Staged>, OutputError> {
        match &self.stats_json {
            Some(path) => {
                let json =
                    serde_json::to_string_pretty(stats).map_err(|source| OutputError::Json {
                        path: path.clone(),
                        source,
                    })?;
                Ok(Some(staged::write_bytes(path, (json + "\n").as_bytes())?))
            }
            None => Ok(None),
        }
    }
}

/// Creates `file`'s directory if missing and checks that it takes files.
fn prepare_dir(file: &Path) -> Result<(), OutputError> {
    let dir = file.parent().unwrap_or(Path::new("/"));
    std::fs::create_dir_all(dir).map_err(|source| OutputError::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    paths::probe_writable(dir, &name).map_err(|source| OutputError::NotWritable {
        path: dir.to_path_buf(),
        source,
    })
}

/// Encodes `image` (as PNG) or `linear` (as EXR; without it, `image`
/// decoded to linear) in `format` to a temporary file beside `path`. A
/// failure of the file itself (a full disk, a size limit) is reported as
/// the write error it is, with its path: the EXR encoder reports one as
/// "Format error decoding OpenExr".
fn stage_image(
    image: &RgbaImage,
    linear: Option<&Rgba32FImage>,
    path: &Path,
    format: ImageFormat,
) -> Result<Staged, OutputError> {
    Staged::write(path, |writer| {
        let mut file = FirstIoError::new(writer);
        let encoded = match (format, linear) {
            (ImageFormat::Png, _) => image.write_to(&mut file, image::ImageFormat::Png),
            (ImageFormat::Exr, Some(linear)) => {
                linear.write_to(&mut file, image::ImageFormat::OpenExr)
            }
            (ImageFormat::Exr, None) => {
                to_linear(image).write_to(&mut file, image::ImageFormat::OpenExr)
            }
        };
        encoded.map_err(|source| match file.error.take() {
            Some(io) => OutputError::Write {
                path: path.to_path_buf(),
                source: io,
            },
            None => OutputError::Encode {
                path: path.to_path_buf(),
                source,
            },
        })
    })
}

/// A writer that keeps (a copy of) the first error of the writer it wraps:
/// what the file said, whatever an encoder makes of it.
struct FirstIoError<'a, W> {
    inner: &'a mut W,
    error: Option<std::io::Error>,
}

impl<'a, W> FirstIoError<'a, W> {
    fn new(inner: &'a mut W) -> Self {
        FirstIoError { inner, error: None }
    }

    fn keep<T>(&mut self, result: std::io::Result<T>) -> std::io::Result<T> {
        // An interrupted write is retried by its caller: no failure yet.
        if let Err(e) = &result
            && self.error.is_none()
            && e.kind() != std::io::ErrorKind::Interrupted
        {
            self.error = Some(match e.raw_os_error() {
                Some(code) => std::io::Error::from_raw_os_error(code),
                None => std::io::Error::new(e.kind(), e.to_string()),
            });
        }
        result
    }
}

impl<W: std::io::Write> std::io::Write for FirstIoError<'_, W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let result = self.inner.write(buf);
        self.keep(result)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let result = self.inner.flush();
        self.keep(result)
    }
}

impl<W: std::io::Seek> std::io::Seek for FirstIoError<'_, W> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        let result = self.inner.seek(pos);
        self.keep(result)
    }
}

/// The 8-bit sRGB image as float linear RGBA: colour channels decoded with
/// the sRGB transfer function, alpha scaled to [0, 1] (it is not encoded).
pub fn to_linear(image: &RgbaImage) -> ImageBuffer<Rgba<f32>, Vec<f32>> {
    let table: Vec<f32> = (0..=255u8)
        .map(|v| srgb_to_linear(f32::from(v) / 255.0))
        .collect();
    ImageBuffer::from_fn(image.width(), image.height(), |x, y| {
        let Rgba([r, g, b, a]) = *image.get_pixel(x, y);
        Rgba([
            table[usize::from(r)],
            table[usize::from(g)],
            table[usize::from(b)],
            f32::from(a) / 255.0,
        ])
    })
}

/// The file a single output at `path` holding `kind` goes to, checked on
/// its own ([`OutputGuard::add_output`]: a file name of the right
/// extension, not a directory or a device) with its directory created.
fn single_output(kind: OutputKind, label: &str, path: &Path) -> Result<PathBuf, OutputError> {
    let mut guard = OutputGuard::new();
    let file = guard.add_output(kind, label, path)?;
    guard.prepare_dirs()?;
    Ok(file)
}

/// `linear` staged as a float RGBA EXR at `path`.
fn stage_linear_exr(linear: &Rgba32FImage, path: &Path) -> Result<Staged, OutputError> {
    // The 8-bit image is not read for an EXR with its floats.
    stage_image(&RgbaImage::new(0, 0), Some(linear), path, ImageFormat::Exr)
}

/// Writes an 8-bit image in the format its extension names (see
/// [`ImageFormat`]; an EXR holds it decoded to linear, so a render's
/// floats go through [`write_rendered_image`] instead), creating the parent
/// directory if needed, through a temporary file renamed over `path` once
/// complete. The path is checked on its own: a command that also reads
/// files records it in its [`OutputGuard`] first.
pub fn write_image(image: &RgbaImage, path: impl AsRef<Path>) -> Result<(), OutputError> {
    let path = path.as_ref();
    let file = single_output(OutputKind::Image, "image", path)?;
    stage_image(image, None, &file, ImageFormat::from_path(path)?)?.commit()
}

/// Writes a render's image as [`write_image`] does, an EXR from `linear`
/// (the resolve's floats, e.g. [`crate::GpuRendered::linear`]) and a PNG
/// from `image` (its 8-bit encoding).
pub fn write_rendered_image(
    image: &RgbaImage,
    linear: &Rgba32FImage,
    path: impl AsRef<Path>,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    let file = single_output(OutputKind::Image, "image", path)?;
    stage_image(image, Some(linear), &file, ImageFormat::from_path(path)?)?.commit()
}

/// Writes an image as PNG to a `.png` path (any other extension is
/// [`OutputError::WrongExtension`]: PNG bytes under another name would
/// mislead every reader), as [`write_image`] does.
pub fn write_png(image: &RgbaImage, path: impl AsRef<Path>) -> Result<(), OutputError> {
    let path = path.as_ref();
    match ImageFormat::from_path(path) {
        Ok(ImageFormat::Png) => write_image(image, path),
        _ => Err(OutputError::WrongExtension {
            path: path.to_path_buf(),
            written: "a PNG image",
            expected: ".png",
        }),
    }
}

/// Writes JSON text (a trace, a log) to `path` through a temporary file
/// renamed over it once complete, creating the parent directory if
/// needed. The path is checked as an [`OutputKind::Json`] output on its own.
pub fn write_json(path: impl AsRef<Path>, json: &str) -> Result<(), OutputError> {
    let file = single_output(OutputKind::Json, "JSON", path.as_ref())?;
    staged::write_bytes(&file, json.as_bytes())?.commit()
}

#[cfg(test)]
mod tests;

/// A fresh, empty directory under the system temp directory for the tests
/// of this module's files, named after the file (`tag`) and the test.
#[cfg(test)]
pub(crate) fn scratch_dir(tag: &str, name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("reyes-{tag}-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
