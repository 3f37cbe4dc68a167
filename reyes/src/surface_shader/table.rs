//! The user shaders of a frame and their objects' parameter blocks.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{
    ParameterKind, ParameterWarning, ShaderKind, ShaderValue, ShadowSlot, SurfaceShader,
    SurfaceShaderError, pack_parameters,
};
use crate::shadow::{ShadowMap, read_shadow_map};
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
    /// The slots (in [`ShaderTable::parameters`]) of the `ShadowId`
    /// parameters ([`ShadowSlot`]), whose map the GPU finds where the
    /// renderer places the frame's maps.
    pub shadow_slots: Vec<u32>,
    /// The shadow map files the parameters name, each read once, with the
    /// map's index in the frame's shadow maps.
    pub shadow_files: Vec<(PathBuf, u32)>,
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
    /// added to `textures`; shadow map parameters' files are read (once
    /// each) into `shadow_maps`, the frame's maps.
    pub fn add(
        &mut self,
        path: &Path,
        kind: ShaderKind,
        values: &BTreeMap<String, ShaderValue>,
        textures: &mut TextureSet,
        shadow_maps: &mut Vec<ShadowMap>,
        base_dir: Option<&Path>,
    ) -> Result<(ShaderRef, Vec<ParameterWarning>), SurfaceShaderError> {
        let index = self.index_of(
            |s| s.path == path,
            || match super::builtin::shader(path) {
                Some(builtin) => builtin,
                None => SurfaceShader::load(path),
            },
        )?;
        self.add_object(index, kind, values, textures, shadow_maps, base_dir)
    }

    /// Adds an object running `shader`, a shader the host made rather
    /// than read from a file ([`crate::displacement::height_shader`]), as
    /// [`ShaderTable::add`] does; made shaders of the same kind and text
    /// are one, under the first one's name.
    pub fn add_made(
        &mut self,
        shader: SurfaceShader,
        kind: ShaderKind,
        values: &BTreeMap<String, ShaderValue>,
        textures: &mut TextureSet,
        shadow_maps: &mut Vec<ShadowMap>,
    ) -> Result<(ShaderRef, Vec<ParameterWarning>), SurfaceShaderError> {
        let (made_kind, source) = (shader.kind, shader.source.clone());
        let index = self.index_of(|s| s.kind == made_kind && s.source == source, || Ok(shader))?;
        self.add_object(index, kind, values, textures, shadow_maps, None)
    }

    /// The index of the first shader that is `same` as the one wanted, or
    /// of the one `make` makes when none is.
    fn index_of(
        &mut self,
        same: impl Fn(&SurfaceShader) -> bool,
        make: impl FnOnce() -> Result<SurfaceShader, SurfaceShaderError>,
    ) -> Result<usize, SurfaceShaderError> {
        if let Some(index) = self.shaders.iter().position(|s| same(s)) {
            return Ok(index);
        }
        self.shaders.push(Arc::new(make()?));
        Ok(self.shaders.len() - 1)
    }

    /// Adds an object running shader `index` with `values`
    /// ([`ShaderTable::add`]).
    fn add_object(
        &mut self,
        index: usize,
        kind: ShaderKind,
        values: &BTreeMap<String, ShaderValue>,
        textures: &mut TextureSet,
        shadow_maps: &mut Vec<ShadowMap>,
        base_dir: Option<&Path>,
    ) -> Result<(ShaderRef, Vec<ParameterWarning>), SurfaceShaderError> {
        let found = self.shaders[index].kind;
        if found != kind {
            return Err(SurfaceShaderError::WrongKind {
                expected: kind,
                found,
            });
        }
        let in_scene = |file: &Path| match base_dir {
            Some(dir) if file.is_relative() => dir.join(file),
            _ => file.to_path_buf(),
        };
        let shadow_files = &mut self.shadow_files;
        let (slots, warnings) = pack_parameters(
            &self.shaders[index],
            values,
            |name, desc| {
                textures
                    .add(&TextureDesc {
                        path: in_scene(&desc.path),
                        ..desc.clone()
                    })
                    .map(|id| id.0)
                    .map_err(|source| SurfaceShaderError::Texture {
                        name: name.to_owned(),
                        source,
                    })
            },
            |name, desc| {
                let path = in_scene(&desc.path);
                let map = match shadow_files.iter().find(|(file, _)| *file == path) {
                    Some(&(_, map)) => map,
                    None => {
                        let read = read_shadow_map(&path).map_err(|source| {
                            SurfaceShaderError::Shadow {
                                name: name.to_owned(),
                                path: path.clone(),
                                source: Box::new(source),
                            }
                        })?;
                        shadow_maps.push(read);
                        let map = shadow_maps.len() as u32 - 1;
                        shadow_files.push((path, map));
                        map
                    }
                };
                Ok(ShadowSlot::new(map, &shadow_maps[map as usize], &desc.filter()).to_slot())
            },
        )?;
        let reference = ShaderRef {
            shader: index as u32,
            parameters: self.parameters.len() as u32,
        };
        let first = self.parameters.len() as u32;
        self.shadow_slots.extend(
            self.shaders[index]
                .parameters
                .iter()
                .enumerate()
                .filter(|(_, p)| p.kind == ParameterKind::Shadow)
                .map(|(slot, _)| first + slot as u32),
        );
        self.parameters.extend(slots);
        Ok((reference, warnings))
    }

    /// Whether some `ShadowId` parameter names one of `maps` (the frame's
    /// shadow maps): the frame then compiles the lookup in.
    pub fn looks_up_shadow_maps(&self, maps: &[ShadowMap]) -> bool {
        self.shadow_slots.iter().any(|&slot| {
            let map = ShadowSlot::from_slot(self.parameters[slot as usize]).map;
            (map as usize) < maps.len()
        })
    }

    /// [`ShaderTable::parameters`] as the GPU reads them: each `ShadowId`'s
    /// map index `k` replaced by `entry(k)`, where the GPU finds the map's
    /// table entry, for the `map_count` maps of the frame (and by
    /// [`super::NO_SHADOW`] past them: `shadow()` then returns 0, as on the
    /// CPU).
    pub fn gpu_parameters(&self, map_count: usize, entry: impl Fn(u32) -> u32) -> Vec<[f32; 4]> {
        let mut parameters = self.parameters.clone();
        for &slot in &self.shadow_slots {
            let mut shadow = ShadowSlot::from_slot(parameters[slot as usize]);
            shadow.map = if (shadow.map as usize) < map_count {
                entry(shadow.map)
            } else {
                super::NO_SHADOW
            };
            parameters[slot as usize] = shadow.to_slot();
        }
        parameters
    }

    /// The parameter slots of `shader` in the block that starts at slot
    /// `first` (cut short where the table ends).
    pub fn slots(&self, first: u32, shader: &SurfaceShader) -> &[[f32; 4]] {
        let start = (first as usize).min(self.parameters.len());
        let end = (start + shader.parameters.len()).min(self.parameters.len());
        &self.parameters[start..end]
    }
}
