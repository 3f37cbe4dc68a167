//! The output guard: every file a command writes is checked against every
//! file the run reads, and against the command's other outputs, before
//! anything is written.
//!
//! A command records what it reads ([`OutputGuard::add_input`]: the scene,
//! RIB archives, models, height maps, user WGSL) and what it will write
//! ([`OutputGuard::add_output`]); the two may come in any order, and each
//! addition is checked against everything recorded before it. Files are
//! compared by identity, not by name: on Unix by device and inode after
//! following symbolic links, so a hard link, a symbolic link or a spelling
//! through `..` of an input is that input; elsewhere by the canonical path.
//! An output that does not exist yet is compared by the path it resolves to
//! (links followed, see [`super::paths::resolve`]).

use std::fs;
use std::path::{Path, PathBuf};

use super::{ImageFormat, OutputError, paths, prepare_dir};

/// Extensions of the formats the renderer reads or writes: a JSON output
/// with one of them is refused, because the name promises another format
/// (and a reader of that format would fail on it).
const FOREIGN_TO_JSON: [&str; 8] = ["png", "exr", "toml", "rib", "bpt", "bez", "obj", "wgsl"];

/// What an output holds, which its extension must agree with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum OutputKind {
    /// An image: `.png` or `.exr` (the extension chooses, [`ImageFormat`]).
    Image,
    /// The depth output ([`crate::Aov::Z`]), a single-channel float EXR:
    /// `.exr` or a name of RenderMan's depth files (`.z`, `.zfile`,
    /// `.shad`: any extension but `.png` and the other formats'
    /// the renderer reads or writes).
    Depth,
    /// An environment map (`MakeCubeFaceEnvironment`'s), a float RGBA
    /// EXR: `.exr` or a name of RenderMan's texture files (`.env`, `.tex`:
    /// any extension but `.png` and the other formats' the renderer reads
    /// or writes).
    Environment,
    /// A TOML scene: `.toml`.
    Toml,
    /// A `.bpt` patch model.
    Bpt,
    /// JSON (statistics, a trace, a log): any name but one whose extension
    /// names another format the renderer reads or writes (`.png`, `.toml`...).
    Json,
}

impl OutputKind {
    /// Checks `path`'s extension (case-insensitive) against the format.
    fn check_extension(self, path: &Path) -> Result<(), OutputError> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let wrong = |written: &'static str, expected: &'static str| {
            Err(OutputError::WrongExtension {
                path: path.to_path_buf(),
                written,
                expected,
            })
        };
        match self {
            OutputKind::Image => ImageFormat::from_path(path).map(|_| ()),
            OutputKind::Depth if extension.as_deref() == Some("png") => {
                Err(OutputError::DepthNeedsExr {
                    path: path.to_path_buf(),
                })
            }
            OutputKind::Depth
                if extension
                    .as_deref()
                    .is_some_and(|e| e != "exr" && FOREIGN_TO_JSON.contains(&e)) =>
            {
                wrong("a depth image (single-channel float EXR)", ".exr")
            }
            OutputKind::Environment
                if extension.as_deref().is_some_and(|e| {
                    e != "exr" && (e == "png" || FOREIGN_TO_JSON.contains(&e))
                }) =>
            {
                wrong("an environment map (float RGBA EXR)", ".exr")
            }
            OutputKind::Toml if extension.as_deref() != Some("toml") => {
                wrong("a TOML scene", ".toml")
            }
            OutputKind::Bpt if extension.as_deref() != Some("bpt") => wrong("a model", ".bpt"),
            OutputKind::Json
                if extension
                    .as_deref()
                    .is_some_and(|e| FOREIGN_TO_JSON.contains(&e)) =>
            {
                wrong("JSON", ".json")
            }
            _ => Ok(()),
        }
    }
}

/// The identity of a file on its file system: device and inode on Unix,
/// the canonical path elsewhere.
#[derive(Debug, Clone, PartialEq, Eq)]
enum FileId {
    /// `st_dev` and `st_ino`, after following symbolic links.
    #[cfg(unix)]
    Inode { dev: u64, ino: u64 },
    /// The canonical path (links followed, `..` removed).
    #[cfg(not(unix))]
    Canonical(PathBuf),
}

impl FileId {
    /// The identity of the file `path` leads to, if it exists.
    fn of(path: &Path) -> Option<FileId> {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            let meta = fs::metadata(path).ok()?;
            Some(FileId::Inode {
                dev: meta.dev(),
                ino: meta.ino(),
            })
        }
        #[cfg(not(unix))]
        {
            fs::canonicalize(path).ok().map(FileId::Canonical)
        }
    }
}

/// A recorded file: what it is for, its path as given, the path it
/// resolves to, and its identity when it exists.
#[derive(Debug, Clone)]
struct Entry {
    label: String,
    path: PathBuf,
    file: PathBuf,
    id: Option<FileId>,
}

impl Entry {
    /// Whether `self` and `other` are one file: by identity when both
    /// exist, else by resolved path (a file that does not exist yet has no
    /// other name).
    fn same_file(&self, other: &Entry) -> bool {
        match (&self.id, &other.id) {
            (Some(a), Some(b)) => a == b,
            _ => self.file == other.file,
        }
    }
}

/// The files one run reads and writes; see the module documentation.
#[derive(Debug, Clone, Default)]
pub struct OutputGuard {
    inputs: Vec<Entry>,
    outputs: Vec<Entry>,
}

impl OutputGuard {
    /// A guard that knows no file yet.
    pub fn new() -> OutputGuard {
        OutputGuard::default()
    }

    /// Records a file the run reads, described by `label` in messages
    /// (`scene`, `RIB archive`, `model`...). Refused with
    /// [`OutputError::ReplacesInput`] if an output recorded earlier is that
    /// file. A path that does not resolve is recorded as spelled: reading it
    /// fails on its own.
    pub fn add_input(
        &mut self,
        label: impl Into<String>,
        path: impl AsRef<Path>,
    ) -> Result<(), OutputError> {
        let path = path.as_ref();
        let file = paths::resolve(path)
            .ok()
            .flatten()
            .unwrap_or_else(|| path.to_path_buf());
        let entry = Entry {
            label: label.into(),
            path: path.to_path_buf(),
            id: FileId::of(&file),
            file,
        };
        if let Some(output) = self.outputs.iter().find(|o| o.same_file(&entry)) {
            return Err(replaces(output, &entry));
        }
        // One model may serve many objects: record each file once.
        if !self.inputs.iter().any(|i| i.same_file(&entry)) {
            self.inputs.push(entry);
        }
        Ok(())
    }

    /// [`OutputGuard::add_input`] for each `(label, path)`.
    pub fn add_inputs<L: Into<String>, P: AsRef<Path>>(
        &mut self,
        inputs: impl IntoIterator<Item = (L, P)>,
    ) -> Result<(), OutputError> {
        inputs
            .into_iter()
            .try_for_each(|(label, path)| self.add_input(label, path))
    }

    /// Records a file the run will write, holding `kind`, described by
    /// `label` in messages, and returns the file it leads to (links
    /// followed), which is where it is to be written. Refused, in this
    /// order, when the path names no file (empty, or ending in `/`, `.` or
    /// `..`), when it is an output recorded earlier
    /// ([`OutputError::SameFile`]) or an input ([`OutputError::ReplacesInput`]),
    /// when it exists and is not a regular file, and when its extension
    /// does not match `kind`. Nothing is created.
    pub fn add_output(
        &mut self,
        kind: OutputKind,
        label: impl Into<String>,
        path: impl AsRef<Path>,
    ) -> Result<PathBuf, OutputError> {
        let path = path.as_ref();
        let label = label.into();
        let no_file_name = || OutputError::NoFileName {
            path: path.to_path_buf(),
        };
        if !names_a_file(path) {
            return Err(no_file_name());
        }
        let file = paths::resolve(path)
            .map_err(|source| OutputError::Resolve {
                path: path.to_path_buf(),
                source,
            })?
            .ok_or_else(no_file_name)?;
        let entry = Entry {
            label,
            path: path.to_path_buf(),
            id: FileId::of(&file),
            file: file.clone(),
        };
        if let Some(other) = self.outputs.iter().find(|o| o.same_file(&entry)) {
            return Err(OutputError::SameFile {
                first: other.label.clone(),
                second: entry.label,
                path: file,
            });
        }
        if let Some(input) = self.inputs.iter().find(|i| i.same_file(&entry)) {
            return Err(replaces(&entry, input));
        }
        // A rename would replace a directory entry of any other kind.
        if fs::metadata(&file).is_ok_and(|meta| !meta.is_file()) {
            return Err(OutputError::NotAFile { path: file });
        }
        kind.check_extension(path)?;
        self.outputs.push(entry);
        Ok(file)
    }

    /// Creates the directories of every recorded output that are missing
    /// and checks that each accepts new files. Call it once every input and
    /// output is recorded: nothing is created before all checks passed.
    pub fn prepare_dirs(&self) -> Result<(), OutputError> {
        self.outputs
            .iter()
            .try_for_each(|output| prepare_dir(&output.file))
    }
}

/// The error for `output` leading to `input`.
fn replaces(output: &Entry, input: &Entry) -> OutputError {
    OutputError::ReplacesInput {
        output: output.label.clone(),
        output_path: output.path.clone(),
        input: input.label.clone(),
        input_path: input.path.clone(),
    }
}

/// Whether `path` as spelled names a file: not empty, and not ending in a
/// separator, `.` or `..`. `Path::components` forgets a trailing `/` or
/// `/.`, which would make `out.png/` write `out.png`; the spelling says a
/// directory was meant.
fn names_a_file(path: &Path) -> bool {
    let bytes = path.as_os_str().as_encoded_bytes();
    let Some(&last) = bytes.last() else {
        return false;
    };
    if std::path::is_separator(char::from(last)) {
        return false;
    }
    let last_component = bytes
        .rsplit(|&b| std::path::is_separator(char::from(b)))
        .next()
        .unwrap_or_default();
    !matches!(last_component, b"." | b"..")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory under the system temp directory.
    fn scratch(name: &str) -> PathBuf {
        crate::output::scratch_dir("guard", name)
    }

    #[test]
    fn spellings_that_name_a_directory_are_no_file() {
        for refused in ["", "/", "out.png/", "out.png/.", "a/..", ".", "..", "a//"] {
            assert!(!names_a_file(Path::new(refused)), "{refused:?}");
        }
        for accepted in ["out.png", "./out.png", "a/../out.png", "/tmp/x.json", ".x"] {
            assert!(names_a_file(Path::new(accepted)), "{accepted:?}");
        }
    }

    #[test]
    fn extensions_must_match_what_is_written() {
        let ok = |kind: OutputKind, name: &str| kind.check_extension(Path::new(name)).is_ok();
        assert!(ok(OutputKind::Image, "a.PNG") && ok(OutputKind::Image, "a.exr"));
        assert!(!ok(OutputKind::Image, "a.jpg") && !ok(OutputKind::Image, "a"));
        assert!(ok(OutputKind::Toml, "s.Toml") && !ok(OutputKind::Toml, "s.png"));
        assert!(!ok(OutputKind::Toml, "s") && !ok(OutputKind::Toml, "s.rib"));
        assert!(ok(OutputKind::Bpt, "m.bpt") && !ok(OutputKind::Bpt, "m.bez"));
        for json in ["s.json", "s", "s.txt", "s.JSON"] {
            assert!(ok(OutputKind::Json, json), "{json}");
        }
        for foreign in [
            "s.png", "s.EXR", "s.toml", "s.rib", "s.bpt", "s.bez", "s.wgsl",
        ] {
            assert!(!ok(OutputKind::Json, foreign), "{foreign}");
        }
    }

    #[test]
    fn an_input_is_no_output_in_either_order() {
        let dir = scratch("order");
        let scene = dir.join("scene.toml");
        fs::write(&scene, "x").unwrap();
        // Input first.
        let mut guard = OutputGuard::new();
        guard.add_input("scene", &scene).unwrap();
        let error = guard
            .add_output(OutputKind::Json, "statistics JSON", &scene)
            .unwrap_err();
        assert!(
            matches!(error, OutputError::ReplacesInput { .. }),
            "{error}"
        );
        let text = error.to_string();
        assert!(
            text.contains("input scene") && text.contains("scene.toml"),
            "{text}"
        );
        // Output first.
        let mut guard = OutputGuard::new();
        guard
            .add_output(OutputKind::Toml, "TOML scene", dir.join("x/../scene.toml"))
            .unwrap();
        let error = guard.add_input("scene", &scene).unwrap_err();
        assert!(
            matches!(error, OutputError::ReplacesInput { .. }),
            "{error}"
        );
        // A different file is fine, and nothing was created.
        guard
            .add_output(OutputKind::Image, "image", dir.join("sub/r.png"))
            .unwrap();
        assert!(!dir.join("sub").exists());
        guard.prepare_dirs().unwrap();
        assert!(dir.join("sub").is_dir());
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn links_of_every_kind_are_the_input() {
        let dir = scratch("links");
        let model = dir.join("model.bpt");
        fs::write(&model, "1\n").unwrap();
        fs::hard_link(&model, dir.join("hard.png")).unwrap();
        std::os::unix::fs::symlink(&model, dir.join("soft.png")).unwrap();
        std::os::unix::fs::symlink(&dir, dir.join("here")).unwrap();
        let mut guard = OutputGuard::new();
        // Through a link to the model, from the other side.
        guard.add_input("model", dir.join("here/soft.png")).unwrap();
        for output in ["hard.png", "soft.png", "here/hard.png", "sub/../model.bpt"] {
            let error = guard
                .clone()
                .add_output(OutputKind::Image, "image", dir.join(output))
                .unwrap_err();
            assert!(
                matches!(&error, OutputError::ReplacesInput { input_path, .. }
                    if input_path.ends_with("here/soft.png")),
                "{output}: {error}"
            );
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}
