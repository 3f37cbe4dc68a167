//! The frame's lights as shading takes them: the illuminating lights with
//! their shadow maps read, and the ambient light summed.

use glam::Vec3;

use crate::scene::{LightKind, Scene, SceneError, ShadowMaps};
use crate::shading::{PreparedLight, PreparedShadow};
use crate::shadow::{ShadowFilter, ShadowMap};

/// A shadow the renderer renders before the frame (`shadows = true`):
/// the map of light `light` (an index into
/// [`super::PreparedScene::lights`]), `map_size` texels on its longer side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PendingShadow {
    /// The light, in [`super::PreparedScene::lights`].
    pub light: usize,
    /// The light in the scene's `lights`.
    pub scene_light: usize,
    /// The map's longer side in texels.
    pub map_size: u32,
    /// The lookup's filter once the map is there.
    pub filter: ShadowFilter,
}

/// What [`prepare_lights`] gives the prepared scene.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct PreparedLights {
    pub(super) lights: Vec<PreparedLight>,
    pub(super) ambient: Vec3,
    pub(super) shadow_maps: Vec<ShadowMap>,
    pub(super) pending_shadows: Vec<PendingShadow>,
}

/// The lights of `scene`: map files are read (relative to the scene's
/// directory); automatic shadows are left pending, for the renderer.
pub(super) fn prepare_lights(scene: &Scene) -> Result<PreparedLights, SceneError> {
    let mut prepared = PreparedLights {
        lights: Vec::new(),
        ambient: Vec3::splat(scene.ambient),
        shadow_maps: Vec::new(),
        pending_shadows: Vec::new(),
    };
    for (index, light) in scene.lights.iter().enumerate() {
        if light.kind == LightKind::Ambient {
            prepared.ambient += light.color * light.intensity;
            continue;
        }
        let Some(mut shading) = PreparedLight::new(light) else {
            continue;
        };
        match light.shadow.as_ref().map(|s| (&s.maps, s.filter)) {
            None => {}
            Some((ShadowMaps::Automatic { map_size }, filter)) => {
                prepared.pending_shadows.push(PendingShadow {
                    light: prepared.lights.len(),
                    scene_light: index,
                    map_size: *map_size,
                    filter,
                });
            }
            Some((ShadowMaps::Files(files), filter)) => {
                let first_map = prepared.shadow_maps.len() as u32;
                for file in files {
                    let path = match &scene.base_dir {
                        Some(dir) => dir.join(file),
                        None => file.clone(),
                    };
                    let map = crate::shadow::read_shadow_map(&path).map_err(|source| {
                        SceneError::ShadowMap {
                            light: index,
                            kind: light.kind.name(),
                            path: path.clone(),
                            source,
                        }
                    })?;
                    prepared.shadow_maps.push(map);
                }
                shading.shadow = Some(PreparedShadow {
                    first_map,
                    map_count: files.len() as u32,
                    filter,
                });
            }
        }
        prepared.lights.push(shading);
    }
    Ok(prepared)
}
