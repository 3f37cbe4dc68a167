//! Where a TOML scene's text gives each object's shader parameters, so that
//! a message about a parameter (one the shader does not declare) can name
//! its line, as the RIB reader's messages name theirs.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};

/// The lines (1-based) of the `parameters` entries of every object's
/// `surface` and `displacement` tables in a TOML scene's text, and the
/// scene file's path. Empty for a scene not read from TOML text.
///
/// Where a scene was written is not part of what it is: two scenes that
/// differ only in their lines are equal (a scene written back as TOML and
/// read again is the same scene).
#[derive(Debug, Clone, Default)]
pub struct SourceLines {
    /// The scene file, when the text was read from one.
    file: Option<PathBuf>,
    /// `(object index, shader kind, parameter name)` to the line of the
    /// parameter's key. The kind is the object's key: `surface` or
    /// `displacement`.
    parameters: BTreeMap<(usize, &'static str, String), usize>,
}

impl PartialEq for SourceLines {
    fn eq(&self, _: &SourceLines) -> bool {
        true
    }
}

/// The shader tables of an object whose parameters have lines.
const SHADER_KEYS: [&str; 2] = ["surface", "displacement"];

/// 1-based line of a byte offset in `text`.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The entry `key` of `table`.
fn entry<'t, 'i>(table: &'t DeTable<'i>, key: &str) -> Option<&'t DeValue<'i>> {
    table
        .iter()
        .find(|(k, _)| k.get_ref().as_ref() == key)
        .map(|(_, v)| v.get_ref())
}

impl SourceLines {
    /// The lines of `text`, a TOML scene that has already parsed (text that
    /// does not parse has no lines), read from `file` if given.
    pub fn of_toml(text: &str, file: Option<&Path>) -> SourceLines {
        let mut lines = SourceLines {
            file: file.map(Path::to_path_buf),
            parameters: BTreeMap::new(),
        };
        let Ok(document) = DeTable::parse(text) else {
            return lines;
        };
        let Some(DeValue::Array(objects)) = entry(document.get_ref(), "objects") else {
            return lines;
        };
        for (index, object) in objects.iter().enumerate() {
            let Some(object) = object.get_ref().as_table() else {
                continue;
            };
            for kind in SHADER_KEYS {
                let Some(DeValue::Table(shader)) = entry(object, kind) else {
                    continue;
                };
                let Some(DeValue::Table(parameters)) = entry(shader, "parameters") else {
                    continue;
                };
                for (name, _) in parameters {
                    lines.parameters.insert(
                        (index, kind, name.get_ref().to_string()),
                        line_of(text, name.span().start),
                    );
                }
            }
        }
        lines
    }

    /// Where object `index`'s `kind` (`surface` or `displacement`)
    /// parameter `name` is given: `scene.toml:12`, or `line 12` for text
    /// not read from a file; `None` when the scene has no line for it.
    pub fn parameter(&self, index: usize, kind: &str, name: &str) -> Option<String> {
        let line = self
            .parameters
            .iter()
            .find(|((i, k, n), _)| *i == index && *k == kind && n == name)
            .map(|(_, line)| *line)?;
        Some(match &self.file {
            Some(file) => format!("{}:{line}", file.display()),
            None => format!("line {line}"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_are_found_inline_and_in_tables() {
        let text = "\
[[objects]]
model = \"teapot\"
surface = { shader = \"wgsl\", file = \"a.wgsl\", parameters = { Kd = 0.5 } }

[[objects]]
model = \"teapot\"
[objects.surface]
shader = \"wgsl\"
file = \"b.wgsl\"
[objects.surface.parameters]
Ks = 0.1
roughness = 0.2
[objects.displacement]
source = \"shader\"
file = \"c.wgsl\"
parameters = { Km = 1.0 }
";
        let lines = SourceLines::of_toml(text, Some(Path::new("s.toml")));
        assert_eq!(
            lines.parameter(0, "surface", "Kd").as_deref(),
            Some("s.toml:3")
        );
        assert_eq!(
            lines.parameter(1, "surface", "Ks").as_deref(),
            Some("s.toml:11")
        );
        assert_eq!(
            lines.parameter(1, "surface", "roughness").as_deref(),
            Some("s.toml:12")
        );
        assert_eq!(
            lines.parameter(1, "displacement", "Km").as_deref(),
            Some("s.toml:16")
        );
        assert_eq!(lines.parameter(0, "surface", "Ks"), None);
        assert_eq!(lines.parameter(2, "surface", "Kd"), None);
        let unnamed = SourceLines::of_toml(text, None);
        assert_eq!(
            unnamed.parameter(0, "surface", "Kd").as_deref(),
            Some("line 3")
        );
    }
}
