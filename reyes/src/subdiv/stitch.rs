//! Making the patches meet bit for bit.
//!
//! Patches made from different neighbourhoods compute the same corner or
//! edge curve with different rounding. This pass gives every corner (by
//! vertex key) and every edge (by its two keys) one value, the first one
//! registered, coarse patches first and exact ones before approximate
//! ones, and writes them into every patch:
//! * a patch edge that is half of an edge of the level above whose curve
//!   is known (a coarse regular patch next to a refined face) gets the De
//!   Casteljau half of that curve, computed with [`bezier::split_cubic`],
//!   the function the splitter uses; a quarter is the half of the half;
//! * any other edge gets the first curve registered for it (between its
//!   canonical corners), reversed as the patch runs.
//!
//! So two patches on an edge share its curve exactly, or the finer one's
//! is a De Casteljau half (quarter, ...) of the coarser one's.

use std::collections::{HashMap, HashSet};

use glam::Vec3;

use super::level::{Key, Level, Origin};
use crate::bezier::split_cubic;

/// A patch made for a face of a level.
#[derive(Debug, Clone)]
pub(super) struct Emitted {
    /// The level.
    pub level: usize,
    /// The face in it.
    pub face: u32,
    /// Whether the patch is the limit surface exactly.
    pub exact: bool,
    /// The Bezier points, `[v * 4 + u]`.
    pub points: [Vec3; 16],
}

/// The control points of a patch's four edges, each running from corner
/// `k` to corner `k + 1` (`v0 v1 v2 v3` = `(0,0) (1,0) (1,1) (0,1)`).
pub(super) const EDGES: [[usize; 4]; 4] = [
    [0, 1, 2, 3],
    [3, 7, 11, 15],
    [15, 14, 13, 12],
    [12, 8, 4, 0],
];

fn reversed(c: [Vec3; 4]) -> [Vec3; 4] {
    [c[3], c[2], c[1], c[0]]
}

struct Stitcher<'a> {
    levels: &'a [Level],
    corners: HashMap<Key, Vec3>,
    /// Curves from the smaller key to the larger.
    curves: HashMap<(Key, Key), [Vec3; 4]>,
}

impl Stitcher<'_> {
    fn get(&self, a: Key, b: Key) -> Option<[Vec3; 4]> {
        if a < b {
            self.curves.get(&(a, b)).copied()
        } else {
            self.curves.get(&(b, a)).copied().map(reversed)
        }
    }

    fn put(&mut self, a: Key, b: Key, curve: [Vec3; 4]) {
        if a < b {
            self.curves.insert((a, b), curve);
        } else {
            self.curves.insert((b, a), reversed(curve));
        }
    }

    /// The curve from `a` to `b` (vertices of `levels[level]`): known, or
    /// the De Casteljau half of a known curve of an ancestor edge.
    fn derived(&mut self, level: usize, a: u32, b: u32) -> Option<[Vec3; 4]> {
        let levels = self.levels;
        let here = &levels[level];
        let (ka, kb) = (here.keys[a as usize], here.keys[b as usize]);
        if let Some(c) = self.get(ka, kb) {
            return Some(c);
        }
        let half_of = |end: Origin, mid: Origin| match (end, mid) {
            (Origin::Vertex(p), Origin::Edge(x, y)) if p == x => Some((p, y)),
            (Origin::Vertex(p), Origin::Edge(x, y)) if p == y => Some((p, x)),
            _ => None,
        };
        let (oa, ob) = (here.origins[a as usize], here.origins[b as usize]);
        let (end, far, mid_is_b) = if let Some((end, far)) = half_of(oa, ob) {
            (end, far, true)
        } else if let Some((end, far)) = half_of(ob, oa) {
            (end, far, false)
        } else {
            return None;
        };
        let parent = self.derived(level - 1, end, far)?;
        let (half, _) = split_cubic(parent);
        let mid_key = if mid_is_b { kb } else { ka };
        self.corners.entry(mid_key).or_insert(half[3]);
        let curve = if mid_is_b { half } else { reversed(half) };
        self.put(ka, kb, curve);
        Some(curve)
    }
}

/// The shared curves after stitching.
pub(super) struct Stitched {
    /// Every registered curve, from the smaller key to the larger.
    pub curves: HashMap<(Key, Key), [Vec3; 4]>,
    /// The edges (smaller key first) that are an edge of some patch.
    pub used: HashSet<(Key, Key)>,
}

impl Stitched {
    /// The curve from `a` to `b`, if one is registered.
    pub(super) fn curve(&self, a: Key, b: Key) -> Option<[Vec3; 4]> {
        if a < b {
            self.curves.get(&(a, b)).copied()
        } else {
            self.curves.get(&(b, a)).copied().map(reversed)
        }
    }
}

/// Gives the patches shared corners and edge curves (see the module
/// documentation), sorting them coarse first.
pub(super) fn stitch(levels: &[Level], patches: &mut [Emitted]) -> Stitched {
    patches.sort_by_key(|p| (p.level, !p.exact));
    let mut s = Stitcher {
        levels,
        corners: HashMap::new(),
        curves: HashMap::new(),
    };
    let corner_keys = |p: &Emitted| -> [u32; 4] { levels[p.level].quad(p.face) };
    let mut start = 0;
    while start < patches.len() {
        let level = patches[start].level;
        let end = start + patches[start..].partition_point(|p| p.level == level);
        let group = &mut patches[start..end];
        let keys = &levels[level].keys;
        // Halves of known coarser curves first: they fix their midpoints.
        for p in group.iter() {
            let q = corner_keys(p);
            for k in 0..4 {
                s.derived(level, q[k], q[(k + 1) % 4]);
            }
        }
        for p in group.iter() {
            let q = corner_keys(p);
            for (k, &index) in [0usize, 3, 15, 12].iter().enumerate() {
                s.corners
                    .entry(keys[q[k] as usize])
                    .or_insert(p.points[index]);
            }
        }
        for p in group.iter() {
            let q = corner_keys(p);
            for (k, edge) in EDGES.iter().enumerate() {
                let (a, b) = (keys[q[k] as usize], keys[q[(k + 1) % 4] as usize]);
                if s.get(a, b).is_none() {
                    let mut curve = edge.map(|i| p.points[i]);
                    curve[0] = s.corners[&a];
                    curve[3] = s.corners[&b];
                    s.put(a, b, curve);
                }
            }
        }
        for p in group.iter_mut() {
            let q = corner_keys(p);
            for (k, edge) in EDGES.iter().enumerate() {
                let (a, b) = (keys[q[k] as usize], keys[q[(k + 1) % 4] as usize]);
                let curve = s.get(a, b).expect("every edge has a curve by now");
                for (&i, point) in edge.iter().zip(curve) {
                    p.points[i] = point;
                }
            }
        }
        start = end;
    }
    let mut used = HashSet::new();
    for p in patches.iter() {
        let q = corner_keys(p);
        let keys = &levels[p.level].keys;
        for k in 0..4 {
            let (a, b) = (keys[q[k] as usize], keys[q[(k + 1) % 4] as usize]);
            used.insert((a.min(b), a.max(b)));
        }
    }
    Stitched {
        curves: s.curves,
        used,
    }
}
