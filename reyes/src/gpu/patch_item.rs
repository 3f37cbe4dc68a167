//! The work item every Reyes procedure runs on: one piece of a bicubic
//! Bezier patch.

use crate::dicing::pack_edges;
use crate::prepare::WorldPatch;

/// The work item of Bound, SplitU, SplitV and DiceShadeSample: one (piece
/// of a) bicubic Bezier patch, WGSL struct `PatchItem`.
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
    /// Index of the input patch, whose control points rate dicing evaluates.
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

impl PatchItem {
    /// Input patch `index`: the whole parameter square at split depth 0
    /// (Bound measures its edges and grid).
    pub fn input(patch: &WorldPatch, index: u32) -> Self {
        let mut p = [0.0; 48];
        for (i, point) in patch.points.iter().enumerate() {
            p[3 * i..3 * i + 3].copy_from_slice(&point.to_array());
        }
        Self {
            p,
            uv: glam::Vec4::new(0.0, 0.0, 1.0, 1.0),
            object: patch.object,
            split_depth: 0,
            input_patch: index,
            edges: pack_edges(&[Default::default(); 4]),
            grid: 0,
            pad0: 0,
            pad1: 0,
            pad2: 0,
        }
    }
}
