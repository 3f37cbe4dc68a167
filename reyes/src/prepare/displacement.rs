//! An object's displacement prepared: its table's source loaded, a shader
//! (a file's, a built-in, or a WGSL height function's) added to the
//! frame's shader table, and the CPU twin of a height function.

use std::path::Path;
use std::sync::Arc;

use super::unknown_parameters::UnknownParameters;
use super::{PreparedScene, SceneError, shader_path};
use crate::displacement::{
    CpuHeight, DisplacementDesc, DisplacementError, PreparedDisplacement, ShaderDisplacement,
    ShaderSource, height_shader,
};
use crate::scene::SceneObject;
use crate::shadow::ShadowMap;
use crate::surface_shader::{ShaderKind, ShaderTable};
use crate::texture::TextureSet;

/// What a displacement shader is added to: the frame's shaders, the
/// textures and shadow maps their parameters name, and the scene file's
/// directory (relative files are found there).
pub(super) struct ShaderTables<'a> {
    pub(super) shaders: &'a mut ShaderTable,
    pub(super) textures: &'a mut TextureSet,
    pub(super) shadow_maps: &'a mut Vec<ShadowMap>,
    pub(super) base_dir: Option<&'a Path>,
    pub(super) unknown_parameters: &'a mut UnknownParameters,
}

/// Object `index`'s displacement `desc` (`object` is the object, `mirrored`
/// whether its transform mirrors), its shader added to `tables`.
pub(super) fn prepare(
    desc: &DisplacementDesc,
    index: usize,
    object: &SceneObject,
    mirrored: bool,
    tables: ShaderTables<'_>,
) -> Result<PreparedDisplacement, SceneError> {
    let ShaderTables {
        shaders,
        textures,
        shadow_maps,
        base_dir,
        unknown_parameters,
    } = tables;
    desc.prepare(base_dir, mirrored, |source| {
        let (path, added) = match source {
            ShaderSource::File { file, parameters } => {
                let path = shader_path(base_dir, file);
                let added = shaders.add(
                    &path,
                    ShaderKind::Displacement,
                    parameters,
                    textures,
                    shadow_maps,
                    base_dir,
                );
                (path, added)
            }
            ShaderSource::Height { wgsl, tiling } => {
                let path = height_shader::shader_name(index);
                let added = height_shader::shader(wgsl, index).and_then(|shader| {
                    shaders.add_made(
                        shader,
                        ShaderKind::Displacement,
                        &height_shader::parameters(tiling),
                        textures,
                        shadow_maps,
                    )
                });
                (path, added)
            }
        };
        let (reference, warnings) = added.map_err(|source| DisplacementError::Shader {
            file: path.clone(),
            source: Box::new(source),
        })?;
        unknown_parameters.warn(index, "displacement", &path, &warnings);
        let shader = &shaders.shaders[reference.shader as usize];
        let own_bound = crate::surface_shader::builtin::displacement_bound(
            &path,
            shaders.slots(reference.parameters, shader),
            textures,
        );
        // N is the front's normal, as RenderMan's Orientation makes it: the
        // model's dP/du x dP/dv unless mirrored or reversed (once). A height
        // function keeps the model's own side, as the built-in height
        // sources do: only a mirroring turns it.
        let flipped = match source {
            ShaderSource::File { .. } => object.reverse_orientation != mirrored,
            ShaderSource::Height { .. } => mirrored,
        };
        let prepared = ShaderDisplacement {
            reference,
            orientation: if flipped { -1.0 } else { 1.0 },
        };
        Ok((prepared, own_bound))
    })
    .map_err(|source| SceneError::Displacement {
        index,
        displacement: desc.source.clone(),
        source,
    })
}

impl PreparedScene {
    /// Gives the WGSL height function of object `object`'s displacement
    /// (`source = "wgsl"`, [`crate::displacement::height_shader`]) its Rust
    /// twin, so that the CPU reference can render it. Every object running
    /// the same function gets it. False when the object has no such
    /// function.
    pub fn set_height_twin(&mut self, object: usize, twin: CpuHeight) -> bool {
        let Some(shader) = self
            .objects
            .get(object)
            .and_then(|o| o.displacement.as_ref())
            .and_then(|d| d.shader())
        else {
            return false;
        };
        let Some(entry) = self
            .shaders
            .shaders
            .get_mut(shader.reference.shader as usize)
        else {
            return false;
        };
        if !height_shader::is_height_shader(&entry.path) {
            return false;
        }
        Arc::make_mut(entry).cpu_displacement = Some(height_shader::twin(twin));
        true
    }
}
