//! Warnings for values a scene gives a shader that declares no parameter
//! of that name: each (shader, name) once per frame, with the line of the
//! TOML that gives it.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::scene::SourceLines;
use crate::surface_shader::ParameterWarning;

/// What has been warned about while a scene is prepared.
pub(super) struct UnknownParameters {
    /// Where the scene's text gives each parameter.
    lines: SourceLines,
    /// The (shader file, parameter name) pairs already warned about.
    warned: BTreeSet<(PathBuf, String)>,
}

impl UnknownParameters {
    /// Nothing warned yet, for a scene whose parameters are at `lines`.
    pub(super) fn new(lines: SourceLines) -> Self {
        Self {
            lines,
            warned: BTreeSet::new(),
        }
    }

    /// Warns about each of `warnings`, the names object `index`'s `kind`
    /// (`surface` or `displacement`) shader at `path` does not declare,
    /// unless that shader's name was warned about already.
    pub(super) fn warn(
        &mut self,
        index: usize,
        kind: &'static str,
        path: &Path,
        warnings: &[ParameterWarning],
    ) {
        for warning in warnings {
            if !self
                .warned
                .insert((path.to_path_buf(), warning.name.clone()))
            {
                continue;
            }
            let at = self
                .lines
                .parameter(index, kind, &warning.name)
                .map_or_else(String::new, |at| format!("{at}: "));
            log::warn!(
                "{at}object {index}: {kind} shader {} has no parameter `{}`; the value is ignored",
                path.display(),
                crate::input::excerpt(&warning.name)
            );
        }
    }
}
