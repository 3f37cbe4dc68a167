//! The scene's input patches in world space, and the store of patches the
//! GPU keeps: objects whose models are the same (a TOML model used by
//! several objects, RIB `ObjectInstance`s of one definition) share one copy
//! of the model's patches in model space, each with its own placement
//! matrix; every other patch is stored once, in world space.
//!
//! Sharing is found by comparing the models themselves
//! ([`first_of_equal`]), so it does not
//! depend on how the scene was written: two objects share whenever their
//! models hold the same patches and texture coordinates.

use std::collections::HashMap;

use glam::{Mat4, Vec2, Vec3};

use super::{WorldPatch, degenerate_patch};
use crate::model::{Model, first_of_equal};
use crate::scene::{Scene, SceneError, Surface};

/// The patches the GPU stores for a frame (`height_texels`), each once.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PatchStore {
    /// Patches stored, shared and not: [`WorldPatch::stored`] indexes
    /// them.
    pub len: u32,
    /// The patches stored once for several objects, in model space (each
    /// object places them with [`super::PreparedObject::placement`]). The
    /// other stored patches are the world-space points of the
    /// [`WorldPatch`]es that index them.
    pub shared: Vec<SharedPatch>,
}

/// A model's patch stored once for every object that places the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedPatch {
    /// Its index in the store.
    pub stored: u32,
    /// Control points in model space, `points[v * 4 + u]`.
    pub points: [Vec3; 16],
    /// Corner texture coordinates (as [`WorldPatch::st`]).
    pub st: [Vec2; 4],
}

/// What [`place_patches`] makes of the scene's models.
pub(super) struct Placed {
    /// Every drawn patch in world space, in object order.
    pub(super) patches: Vec<WorldPatch>,
    /// The GPU's store.
    pub(super) store: PatchStore,
    /// Per object: its model-to-world matrix when its patches are shared.
    pub(super) placements: Vec<Option<Mat4>>,
    /// Patches without area left out.
    pub(super) skipped_degenerate: usize,
}

/// Places every object's model in world space (see [`super::PreparedScene::new`]
/// for the checks) and decides which objects share their model's patches.
pub(super) fn place_patches(scene: &Scene, models: &[Model]) -> Result<Placed, SceneError> {
    let matrices: Vec<Mat4> = scene.objects.iter().map(|o| o.transform.matrix()).collect();
    let share = sharing_groups(scene, models, &matrices);
    let mut patches = Vec::with_capacity(models.iter().map(|m| m.patches.len()).sum());
    let mut store = PatchStore::default();
    // Per sharing group: each model patch's stored index (`None`: the
    // patch has no area in model space, and none of its instances is drawn).
    let mut group_stored: HashMap<usize, Vec<Option<u32>>> = HashMap::new();
    let mut placements = Vec::with_capacity(scene.objects.len());
    let mut skipped_degenerate = 0;
    for (index, (object, model)) in scene.objects.iter().zip(models).enumerate() {
        let matrix = matrices[index];
        // Where the object is at shutter close (without camera motion,
        // which moves the view, not the world).
        let close = object
            .transform_close
            .as_ref()
            .map(|close| object.transform.interpolate(close, scene.shutter));
        let overflow = |field| SceneError::TransformOverflow {
            index,
            field,
            model: object.model.clone(),
        };
        if let Some(reason) = model.st_problem() {
            return Err(SceneError::InvalidSt {
                index,
                model: object.model.clone(),
                reason,
            });
        }
        let shared = share[index].map(|group| {
            group_stored
                .entry(group)
                .or_insert_with(|| store_model(model, &mut store))
                .as_slice()
        });
        placements.push(shared.map(|_| matrix));
        for (patch_index, patch) in model.patches.iter().enumerate() {
            let points = patch.points.map(|p| matrix.transform_point3(p));
            if !points.iter().all(|p| p.is_finite()) {
                return Err(overflow("transform"));
            }
            if let Some(close) = close
                && !patch
                    .points
                    .iter()
                    .all(|&p| close.transform_point3(p).is_finite())
            {
                return Err(overflow("transform_close"));
            }
            let stored = match shared {
                // Decided once, in model space, for every instance alike.
                Some(stored) => stored[patch_index],
                None if degenerate_patch(&points) => None,
                None => Some(store.len),
            };
            let Some(stored) = stored else {
                skipped_degenerate += 1;
                continue;
            };
            if object.surface == Some(Surface::Null) {
                // Checked for a finite placement above, as every object.
                continue;
            }
            if shared.is_none() {
                store.len += 1;
            }
            patches.push(WorldPatch {
                points,
                object: index as u32,
                st: model.st_of(patch_index),
                stored,
            });
        }
    }
    Ok(Placed {
        patches,
        store,
        placements,
        skipped_degenerate,
    })
}

/// Stores `model`'s patches with area once, in model space, and returns
/// each patch's stored index.
fn store_model(model: &Model, store: &mut PatchStore) -> Vec<Option<u32>> {
    model
        .patches
        .iter()
        .enumerate()
        .map(|(index, patch)| {
            if degenerate_patch(&patch.points) {
                return None;
            }
            let stored = store.len;
            store.len += 1;
            store.shared.push(SharedPatch {
                stored,
                points: patch.points,
                st: model.st_of(index),
            });
            Some(stored)
        })
        .collect()
}

/// Per object, the group of objects it shares its model's patches with
/// (the index of the group's first object, [`first_of_equal`]), or `None`
/// when it stores its own. Objects share when their models are equal,
/// at least two of them can share, and each places its model with an
/// invertible, finite matrix (`matrices`) and draws it (a `null` surface
/// draws nothing).
fn sharing_groups(scene: &Scene, models: &[Model], matrices: &[Mat4]) -> Vec<Option<usize>> {
    let can_share = |index: usize| {
        let determinant = matrices[index].determinant();
        scene.objects[index].surface != Some(Surface::Null)
            && !models[index].patches.is_empty()
            && matrices[index].is_finite()
            && determinant.is_finite()
            && determinant != 0.0
    };
    let firsts = first_of_equal(models);
    let sharing: Vec<bool> = (0..models.len()).map(can_share).collect();
    let mut members: HashMap<usize, usize> = HashMap::new();
    for (index, &first) in firsts.iter().enumerate() {
        if sharing[index] {
            *members.entry(first).or_default() += 1;
        }
    }
    // A model placed once is stored in world space, as before sharing.
    firsts
        .iter()
        .enumerate()
        .map(|(index, &first)| (sharing[index] && members[&first] >= 2).then_some(first))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneObject, Transform};

    fn objects(scene: &mut Scene, placements: &[Vec3]) {
        let template = scene.objects[0].clone();
        scene.objects = placements
            .iter()
            .map(|&translate| SceneObject {
                transform: Transform {
                    translate,
                    ..Transform::default()
                },
                ..template.clone()
            })
            .collect();
    }

    #[test]
    fn equal_models_share_one_store_and_others_keep_their_own() {
        let mut scene = Scene::default_teapot();
        objects(
            &mut scene,
            &[Vec3::ZERO, Vec3::X * 4.0, Vec3::Y * 4.0, Vec3::Z * 4.0],
        );
        let teapot = crate::model::Model::teapot();
        let mut other = teapot.clone();
        other.patches[3].points[5].x += 0.25;
        let models = [teapot.clone(), teapot.clone(), other, teapot.clone()];
        let placed = place_patches(&scene, &models).unwrap();
        let per_model = teapot.patches.len();
        // Three teapots share one copy; the changed one stores its own.
        assert_eq!(placed.store.shared.len(), per_model);
        assert_eq!(placed.store.len as usize, 2 * per_model);
        assert_eq!(placed.patches.len(), 4 * per_model);
        assert!(placed.placements[0].is_some() && placed.placements[2].is_none());
        // Every world patch is its stored patch placed by its object.
        for patch in &placed.patches {
            let Some(placement) = placed.placements[patch.object as usize] else {
                continue;
            };
            let shared = placed
                .store
                .shared
                .iter()
                .find(|s| s.stored == patch.stored)
                .unwrap();
            let placed_points = shared.points.map(|p| placement.transform_point3(p));
            assert_eq!(placed_points, patch.points);
        }
    }

    #[test]
    fn a_model_placed_once_or_flattened_is_not_shared() {
        let mut scene = Scene::default_teapot();
        objects(&mut scene, &[Vec3::ZERO, Vec3::X * 4.0]);
        scene.objects[1].transform.scale = crate::scene::Scale::PerAxis(Vec3::new(1.0, 0.0, 1.0));
        let teapot = crate::model::Model::teapot();
        let placed = place_patches(&scene, &[teapot.clone(), teapot]).unwrap();
        assert!(placed.store.shared.is_empty());
        assert_eq!(placed.placements, [None, None]);
    }
}
