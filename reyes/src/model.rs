//! Bicubic Bezier patch models.
//!
//! This module holds only the patch types; reading them from files (and the
//! embedded teapot) lives in [`crate::load`], which builds on these types, so
//! that the arrow between the two modules points one way.

use glam::{Vec2, Vec3};

/// One bicubic Bezier patch: 16 control points, row by row.
///
/// `points[v * 4 + u]` is the control point in column `u` (along the patch
/// parameter `u`, or `s` inside a diced grid) and row `v` (parameter `v`/`t`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Patch {
    /// The control points, `points[v * 4 + u]`.
    pub points: [Vec3; 16],
}

impl Patch {
    /// The control point in column `u` and row `v` (both in `0..4`).
    pub fn point(&self, u: usize, v: usize) -> Vec3 {
        self.points[v * 4 + u]
    }
}

/// The texture coordinates `s, t` of a patch's corners `(u, v) = (0,0),
/// (1,0), (0,1), (1,1)` when the model gives none: `s, t = u, v`.
pub const DEFAULT_ST: [Vec2; 4] = [
    Vec2::new(0.0, 0.0),
    Vec2::new(1.0, 0.0),
    Vec2::new(0.0, 1.0),
    Vec2::new(1.0, 1.0),
];

/// A model: a list of bicubic Bezier patches in the model's own space.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Model {
    /// The patches.
    pub patches: Vec<Patch>,
    /// The texture coordinates `s, t` of each patch's corners, in the order
    /// of [`DEFAULT_ST`] (inside a patch they are the bilinear blend of
    /// its corners'); `None`: every patch has [`DEFAULT_ST`]. When present
    /// it has one entry per patch ([`Model::st_of`]; preparing a scene
    /// checks it).
    pub st: Option<Vec<[Vec2; 4]>>,
}

impl Model {
    /// A model of `patches` with the default texture coordinates.
    pub fn new(patches: Vec<Patch>) -> Model {
        Model { patches, st: None }
    }

    /// The corner texture coordinates of patch `index`: the model's, or
    /// [`DEFAULT_ST`] without any (or past their end, which
    /// [`Model::st_problem`] reports).
    pub fn st_of(&self, index: usize) -> [Vec2; 4] {
        self.st
            .as_ref()
            .and_then(|st| st.get(index).copied())
            .unwrap_or(DEFAULT_ST)
    }

    /// Why the texture coordinates do not fit the patches (a count that is
    /// not one per patch, a coordinate that is not finite), if they do not.
    pub fn st_problem(&self) -> Option<String> {
        let st = self.st.as_ref()?;
        if st.len() != self.patches.len() {
            return Some(format!(
                "{} texture coordinate entries for {} patches",
                st.len(),
                self.patches.len()
            ));
        }
        let (index, _) = st
            .iter()
            .enumerate()
            .find(|(_, c)| !c.iter().all(|p| p.is_finite()))?;
        Some(format!(
            "the texture coordinates of patch {index} are not finite"
        ))
    }

    /// The axis-aligned bounding box `(min, max)` of all control points (which
    /// contains the surface, by the convex-hull property of Bezier patches).
    /// An empty model gives `(Vec3::ZERO, Vec3::ZERO)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut points = self.patches.iter().flat_map(|p| p.points.iter().copied());
        let Some(first) = points.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)))
    }
}

/// For each of `models`, the index of the first model equal to it (its
/// own index when none before it is). Candidates are found by a cheap
/// fingerprint (patch count and the first and last control points) and
/// then compared in full, so models that are all different cost one
/// fingerprint each. Scenes share equal models' patches on the GPU
/// (`crate::prepare::PatchStore`), and `reyes convert` writes each once.
pub fn first_of_equal(models: &[Model]) -> Vec<usize> {
    let mut candidates: std::collections::HashMap<Fingerprint, Vec<usize>> =
        std::collections::HashMap::new();
    models
        .iter()
        .enumerate()
        .map(|(index, model)| {
            let firsts = candidates.entry(Fingerprint::of(model)).or_default();
            match firsts.iter().find(|&&first| models[first] == *model) {
                Some(&first) => first,
                None => {
                    firsts.push(index);
                    index
                }
            }
        })
        .collect()
}

/// A model's patch count and the bits of its first and last control
/// points: equal models have equal fingerprints.
#[derive(Debug, PartialEq, Eq, Hash)]
struct Fingerprint {
    patches: usize,
    ends: [u32; 6],
}

impl Fingerprint {
    fn of(model: &Model) -> Fingerprint {
        let point = |p: Option<Vec3>| p.unwrap_or(Vec3::ZERO).to_array().map(f32::to_bits);
        let [a, b, c] = point(model.patches.first().map(|p| p.points[0]));
        let [d, e, f] = point(model.patches.last().map(|p| p.points[15]));
        Fingerprint {
            patches: model.patches.len(),
            ends: [a, b, c, d, e, f],
        }
    }
}
