//! Subdivision surfaces: polygon meshes (from RIB `SubdivisionMesh` or OBJ
//! files) turned into the bicubic Bezier patches the rest of the pipeline
//! splits, dices and shades.
//!
//! * [`Mesh`]: the mesh as given: positions, faces of any valence, the
//!   `crease`, `corner` and `hole` tags, the boundary rule and face-varying
//!   texture coordinates; [`Mesh::validate`] refuses what has no surface
//!   ([`MeshError`], naming the face).
//! * [`Scheme::Bilinear`]: every face is flat (`bilinear`): quads become
//!   bilinear patches, other faces are first cut into quads at their
//!   centroid.
//! * [`Scheme::CatmullClark`]: the Catmull-Clark limit surface, by
//!   feature-adaptive subdivision: regular faces become their B-spline
//!   patches exactly, irregular ones are refined locally down to
//!   [`ISOLATION_LEVEL`] and what is left is approximated, its error
//!   measured; neighbouring patches share their edge curves bit for bit or
//!   as De Casteljau halves (`docs/reyes.md`, "Subdivision surfaces").

mod approximate;
mod bilinear;
mod catmull_clark;
mod level;
mod mesh;
mod refine;
mod regular;
mod stitch;
mod transition;

pub use catmull_clark::{ISOLATION_LEVEL, MAX_PATCHES};
pub use mesh::{
    BoundaryInterpolation, Corner, Crease, INFINITE_SHARPNESS, Mesh, MeshError, Scheme,
};

use crate::model::Model;

/// What a mesh became: its patches and how they were made.
#[derive(Debug, Clone, PartialEq)]
pub struct Subdivided {
    /// The patches (and their corner texture coordinates when the mesh has
    /// any).
    pub model: Model,
    /// How the patches were made.
    pub report: SubdivisionReport,
}

/// How a mesh's patches were made.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SubdivisionReport {
    /// The mesh's faces (holes included).
    pub faces: usize,
    /// Patches that are the limit surface exactly (every bilinear patch; a
    /// Catmull-Clark patch over a regular neighbourhood).
    pub exact_patches: usize,
    /// Patches that approximate the limit surface (next to extraordinary
    /// vertices after the deepest isolation level).
    pub approximate_patches: usize,
    /// Patches of the fans that replace a coarse exact patch next to finer
    /// ones (so that no edge is a T-junction); they interpolate it.
    pub transition_patches: usize,
    /// The deepest subdivision level used to isolate irregular features.
    pub max_level: u32,
    /// The largest distance, in the model's units, measured between an
    /// approximate patch and the limit surface, or a transition patch and
    /// the exact patch it replaces (0 when all are exact).
    pub max_error: f32,
}

impl Mesh {
    /// The patches of the mesh's surface under its [`Scheme`], after
    /// [`Mesh::validate`].
    pub fn to_patches(&self) -> Result<Subdivided, MeshError> {
        self.to_patches_within(MAX_PATCHES)
    }

    /// [`Mesh::to_patches`] making at most `limit` patches (capped at
    /// [`MAX_PATCHES`]): [`MeshError::TooManyPatches`] with that limit once
    /// refinement would pass it, before the patches past it are made (what
    /// a patch budget has left).
    pub fn to_patches_within(&self, limit: usize) -> Result<Subdivided, MeshError> {
        self.validate()?;
        let limit = limit.min(MAX_PATCHES);
        match self.scheme {
            Scheme::Bilinear => {
                let subdivided = bilinear::patches(self);
                if subdivided.model.patches.len() > limit {
                    return Err(MeshError::TooManyPatches { limit });
                }
                Ok(subdivided)
            }
            Scheme::CatmullClark => catmull_clark::patches_within(self, limit),
        }
    }
}
