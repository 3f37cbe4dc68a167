//! Reading scenes: TOML text or a scene file, parsed and validated, and the
//! scene written back as TOML.

use std::path::{Path, PathBuf};

use crate::input::{self, InputError, InputKind};

use super::lines::{SourceLines, line_of};
use super::{Scene, SceneError};

fn parse_toml(text: &str, path: Option<&Path>) -> Result<Scene, SceneError> {
    let mut scene = toml::from_str::<Scene>(text).map_err(|e| SceneError::Parse {
        path: path.map(Path::to_path_buf),
        line: e.span().map(|span| line_of(text, span.start)),
        // serde quotes offending string values whole: bound the message.
        message: input::excerpt_to(e.message(), input::MESSAGE_CHARS),
    })?;
    scene.lines = SourceLines::of_toml(text, path);
    Ok(scene)
}

impl Scene {
    /// Parses and validates a TOML scene. Relative model paths will be
    /// resolved against the current directory (set [`Scene::base_dir`] to change that).
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let scene = parse_toml(text, None)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads, parses and validates a TOML scene file; relative model paths are
    /// resolved against the file's directory. The file is read through
    /// `crate::input`: a regular file of at most the scene cap (16 MiB by
    /// default), else [`SceneError::Input`].
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        // A regular file of at most the scene cap, byte-order mark removed.
        let text = input::read_text(path, InputKind::Scene, InputKind::Scene.limit()).map_err(
            |error| match error {
                InputError::Io { path, source, .. } => SceneError::Io { path, source },
                other => SceneError::Input(other),
            },
        )?;
        let mut scene = parse_toml(&text, Some(path))?;
        scene.base_dir = Some(
            path.parent()
                .map(Path::to_path_buf)
                .unwrap_or_else(|| PathBuf::from(".")),
        );
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as TOML text (without [`Scene::base_dir`]).
    pub fn to_toml_string(&self) -> String {
        // Every field is representable in TOML (no maps with non-string keys,
        // no None inside arrays), so serialization cannot fail.
        toml::to_string(self).expect("a scene always serializes to TOML")
    }
}
