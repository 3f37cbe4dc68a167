//! The unit of work of the split/dice loop: a (piece of a) patch.

use glam::{Vec3, Vec4};

use crate::bezier::{self, SplitDirection};
use crate::dicing::PieceEdges;

/// A patch, or a piece of one produced by splitting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkItem {
    /// The piece's control points in world space (`points[v * 4 + u]`).
    pub points: [Vec3; 16],
    /// The piece's rectangle `(u0, v0, u1, v1)` in the input patch's
    /// parameter space; `(0, 0, 1, 1)` for an input patch.
    pub uv: Vec4,
    /// The object the patch belongs to.
    pub object: u32,
    /// Number of splits from the input patch to this piece.
    pub split_depth: u32,
    /// Index of the input patch in [`crate::prepare::PreparedScene::patches`]:
    /// rate dicing evaluates grid points on it.
    pub patch: u32,
    /// The vertex spacings of the piece's four edges (rate dicing; see
    /// [`crate::dicing`]).
    pub edges: PieceEdges,
}

impl WorkItem {
    /// An input patch: the whole parameter square, split depth 0, with the
    /// spacings of its edges.
    pub fn new(points: [Vec3; 16], object: u32, patch: u32, edges: PieceEdges) -> WorkItem {
        WorkItem {
            points,
            uv: Vec4::new(0.0, 0.0, 1.0, 1.0),
            object,
            split_depth: 0,
            patch,
            edges,
        }
    }

    /// The two halves (De Casteljau at 1/2 in `direction`), each one split
    /// deeper, with the parent's edge spacings (the caller replaces them,
    /// see [`crate::reference::bound::split_edges`]). The first half covers
    /// the lower half of the parameter range.
    pub fn split(&self, direction: SplitDirection) -> [WorkItem; 2] {
        let (first, second) = bezier::split(&self.points, direction);
        let [u0, v0, u1, v1] = self.uv.to_array();
        let (uv_first, uv_second) = match direction {
            SplitDirection::U => {
                let um = (u0 + u1) * 0.5;
                (Vec4::new(u0, v0, um, v1), Vec4::new(um, v0, u1, v1))
            }
            SplitDirection::V => {
                let vm = (v0 + v1) * 0.5;
                (Vec4::new(u0, v0, u1, vm), Vec4::new(u0, vm, u1, v1))
            }
        };
        let child = |points, uv| WorkItem {
            points,
            uv,
            split_depth: self.split_depth + 1,
            ..*self
        };
        [child(first, uv_first), child(second, uv_second)]
    }
}
