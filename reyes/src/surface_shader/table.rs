//! The user shaders of a frame and their objects' parameter blocks.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use super::{
    ParameterWarning, ShaderKind, ShaderValue, SurfaceShader, SurfaceShaderError, pack_parameters,
};
use crate::texture::{TextureDesc, TextureSet};

/// The distinct user shaders of a frame, surface and displacement (shader
/// `k` is what an object with
/// [`crate::shading::PreparedSurface::User`]`{ shader: k, .. }` runs, or
/// with a displacement shader `k`) and the objects' parameter blocks, one `[f32; 4]` slot per
/// parameter, concatenated: the GPU's `shader_parameters` buffer.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShaderTable {
    /// The shaders, each file once.
    pub shaders: Vec<Arc<SurfaceShader>>,
    /// The parameter blocks.
    pub parameters: Vec<[f32; 4]>,
}

/// Where an object's shader and parameters are in a [`ShaderTable`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShaderRef {
    /// The shader's index.
    pub shader: u32,
    /// The first slot of the object's parameter block.
    pub parameters: u32,
}

impl ShaderTable {
    /// Adds an object running the shader file `path`, which must be a
    /// shader of `kind`, with `values`, loading the file unless an earlier
    /// object uses it. Names the shader does not declare come back as
    /// warnings.
    /// Texture parameters' files (relative to `base_dir`, if given) are
    /// added to `textures`.
    pub fn add(
        &mut self,
        path: &Path,
        kind: ShaderKind,
        values: &BTreeMap<String, ShaderValue>,
        textures: &mut TextureSet,
        base_dir: Option<&Path>,
    ) -> Result<(ShaderRef, Vec<ParameterWarning>), SurfaceShaderError> {
        let index = match self.shaders.iter().position(|s| s.path == path) {
            Some(index) => index,
            None => {
                let shader = match super::builtin::shader(path) {
                    Some(builtin) => builtin?,
                    None => SurfaceShader::load(path)?,
                };
                self.shaders.push(Arc::new(shader));
                self.shaders.len() - 1
            }
        };
        let found = self.shaders[index].kind;
        if found != kind {
            return Err(SurfaceShaderError::WrongKind {
                expected: kind,
                found,
            });
        }
        let (slots, warnings) = pack_parameters(&self.shaders[index], values, |name, desc| {
            let path = match base_dir {
                Some(dir) if desc.path.is_relative() => dir.join(&desc.path),
                _ => desc.path.clone(),
            };
            textures
                .add(&TextureDesc {
                    path,
                    ..desc.clone()
                })
                .map(|id| id.0)
                .map_err(|source| SurfaceShaderError::Texture {
                    name: name.to_owned(),
                    source,
                })
        })?;
        let reference = ShaderRef {
            shader: index as u32,
            parameters: self.parameters.len() as u32,
        };
        self.parameters.extend(slots);
        Ok((reference, warnings))
    }

    /// The parameter slots of `shader` in the block that starts at slot
    /// `first` (cut short where the table ends).
    pub fn slots(&self, first: u32, shader: &SurfaceShader) -> &[[f32; 4]] {
        let start = (first as usize).min(self.parameters.len());
        let end = (start + shader.parameters.len()).min(self.parameters.len());
        &self.parameters[start..end]
    }
}
