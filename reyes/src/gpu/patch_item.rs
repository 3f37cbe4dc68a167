//! The work items of the Reyes procedures: an input patch, named by its
//! stored index (Bound's), and one piece of a bicubic Bezier patch with
//! its control points (the others').

use crate::prepare::WorldPatch;

/// The work item of Bound: one input patch, named by its stored index
/// ([`WorldPatch::stored`]), WGSL struct `InputPatch`. Bound reads the
/// control points from the patch store and places them with the object's
/// placement when the object shares its model (`load_patch` in
/// `shaders/reyes/dicing.wgsl`), so no input patch's points are uploaded
/// twice, and a queue slot is 8 bytes instead of a [`PatchItem`]'s 240.
#[scheduler::item]
#[derive(Debug, PartialEq)]
pub struct InputPatch {
    /// Index into `objects`.
    pub object: u32,
    /// The stored patch.
    pub input_patch: u32,
}

impl InputPatch {
    /// The seed of `patch`.
    pub fn of(patch: &WorldPatch) -> Self {
        Self {
            object: patch.object,
            input_patch: patch.stored,
        }
    }
}

/// The work item of SplitU, SplitV and DiceShadeSample: one (piece of a)
/// bicubic Bezier patch, WGSL struct `PatchItem`, made by Bound from an
/// [`InputPatch`] and by the splits from their pieces.
#[scheduler::item]
#[derive(Debug, PartialEq)]
pub struct PatchItem {
    /// The 16 world-space control points, point `v * 4 + u` at words
    /// `3 * (v * 4 + u) .. + 3`. Flat f32 words rather than vec3 because a
    /// vec3 array would pad every point to 16 bytes.
    pub p: [f32; 48],
    /// The piece's rectangle (u0, v0, u1, v1) in the input patch's parameters.
    pub uv: glam::Vec4,
    /// Index into `objects`.
    pub object: u32,
    /// Splits from the input patch to this piece (the depth guard's input).
    pub split_depth: u32,
    /// The stored index of the input patch ([`WorldPatch::stored`]),
    /// whose control points rate dicing evaluates (placed by the object's
    /// placement when the patch is shared).
    pub input_patch: u32,
    /// The spacings of the piece's four edges (dicing.wgsl,
    /// reyes::dicing::pack_edges), 8 bits each.
    pub edges: u32,
    /// The grid Bound or Split chose: nu | nv << 8.
    pub grid: u32,
    /// Padding to the struct's 16-byte alignment.
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
    /// Padding.
    pub pad2: u32,
}
