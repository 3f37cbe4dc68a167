//! The WGSL shader files that `Surface` and `Displacement` requests name,
//! checked when the request is read: a file that cannot be used is an
//! error at the request's line, and a parameter the shader does not
//! declare warns there (once per shader and name) and is dropped, rather
//! than being reported later without a line.

use std::collections::BTreeMap;
use std::path::Path;

use super::interp::Interp;
use crate::scene::ShaderValue;
use crate::surface_shader::{ShaderKind, SurfaceShader};

/// What a checked shader file offers, or why it cannot be used.
pub(super) type ShaderFile = Result<(ShaderKind, Vec<String>), String>;

/// A request that names a WGSL shader file.
pub(super) struct ShaderRequest<'a> {
    /// The request (`Surface`, `Displacement`).
    pub(super) request: &'a str,
    /// The shader's name in the request.
    pub(super) shader: &'a str,
    /// The file it names.
    pub(super) path: &'a Path,
    /// The kind of shader the request needs.
    pub(super) kind: ShaderKind,
}

impl Interp {
    /// `params` of the request for a shader, without the names the shader
    /// does not declare.
    pub(super) fn shader_parameters_checked(
        &mut self,
        named: ShaderRequest<'_>,
        params: BTreeMap<String, ShaderValue>,
        file: &Path,
        line: usize,
    ) -> Result<BTreeMap<String, ShaderValue>, String> {
        let ShaderRequest {
            request,
            shader,
            path,
            kind,
        } = named;
        let shown = crate::input::excerpt(shader);
        let checked = self
            .shader_files
            .entry(path.to_path_buf())
            .or_insert_with(|| {
                SurfaceShader::load(path)
                    .map(|s| (s.kind, s.parameters.into_iter().map(|p| p.name).collect()))
                    .map_err(|e| e.to_string())
            })
            .clone();
        let (found, names) =
            checked.map_err(|e| format!("{request} {shown:?}: {}: {e}", path.display()))?;
        if found != kind {
            return Err(format!(
                "{request} {shown:?}: {} is a {} shader (it defines `fn {}`), not a {} shader",
                path.display(),
                found.name(),
                found.entry(),
                kind.name()
            ));
        }
        let mut kept = BTreeMap::new();
        for (name, value) in params {
            if names.contains(&name) {
                kept.insert(name, value);
            } else {
                self.warn_once(
                    &format!("#shader-param {} {name}", path.display()),
                    file,
                    line,
                    format!(
                        "{request} {shown:?} has no parameter {:?} (its shader {} declares {}); ignored",
                        crate::input::excerpt(&name),
                        path.display(),
                        if names.is_empty() {
                            "none".to_owned()
                        } else {
                            names.join(", ")
                        }
                    ),
                );
            }
        }
        Ok(kept)
    }
}
