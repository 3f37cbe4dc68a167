//! Geometry for the subdivision tests: surfaces as triangles (patches
//! tessellated, the reference mesh's limit quads), bucketed for nearest
//! distances.

use std::collections::HashMap;

use glam::DVec3;
use reyes::bezier;
use reyes::model::Model;

use crate::subdiv_reference::RefMesh;

/// A triangle and where it came from: the patch and the `u, v` of its
/// corners (for patches), or nothing (reference).
#[derive(Clone, Copy)]
pub(crate) struct Triangle {
    pub(crate) corners: [DVec3; 3],
    pub(crate) patch: usize,
    pub(crate) uv: [(f64, f64); 3],
}

pub(crate) fn closest_on_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> (DVec3, [f64; 3]) {
    // Ericson, Real-Time Collision Detection, 5.1.5.
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

/// Triangles bucketed by the cells their bounds (grown by `reach`) touch.
pub(crate) struct Buckets {
    pub(crate) triangles: Vec<Triangle>,
    pub(crate) cell: f64,
    pub(crate) map: HashMap<(i64, i64, i64), Vec<u32>>,
}

impl Buckets {
    pub(crate) fn new(triangles: Vec<Triangle>, cell: f64, reach: f64) -> Buckets {
        let mut map: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
        for (i, t) in triangles.iter().enumerate() {
            let lo = t.corners[0].min(t.corners[1]).min(t.corners[2]) - DVec3::splat(reach);
            let hi = t.corners[0].max(t.corners[1]).max(t.corners[2]) + DVec3::splat(reach);
            let (lo, hi) = ((lo / cell).floor(), (hi / cell).floor());
            for x in lo.x as i64..=hi.x as i64 {
                for y in lo.y as i64..=hi.y as i64 {
                    for z in lo.z as i64..=hi.z as i64 {
                        map.entry((x, y, z)).or_default().push(i as u32);
                    }
                }
            }
        }
        Buckets {
            triangles,
            cell,
            map,
        }
    }

    /// The nearest triangle within reach of `p`: distance, triangle,
    /// barycentric coordinates of the nearest point.
    pub(crate) fn nearest(&self, p: DVec3) -> Option<(f64, Triangle, [f64; 3])> {
        let c = (p / self.cell).floor();
        let list = self.map.get(&(c.x as i64, c.y as i64, c.z as i64))?;
        list.iter()
            .map(|&i| {
                let t = self.triangles[i as usize];
                let (q, bary) = closest_on_triangle(p, t.corners);
                ((q - p).length(), t, bary)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }
}

/// Each patch as `2 n^2` triangles.
pub(crate) fn patch_triangles(model: &Model, n: usize) -> Vec<Triangle> {
    let mut out = Vec::new();
    for (index, patch) in model.patches.iter().enumerate() {
        let at = |i: usize, j: usize| {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            (
                bezier::position(&patch.points, u as f32, v as f32).as_dvec3(),
                (u, v),
            )
        };
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                for [x, y, z] in [[a, b, c], [a, c, d]] {
                    // Collapsed edges (fan patches meet at a point) make
                    // triangles of no area: nothing to measure against.
                    if (y.0 - x.0).cross(z.0 - x.0).length() < 1e-14 {
                        continue;
                    }
                    out.push(Triangle {
                        corners: [x.0, y.0, z.0],
                        patch: index,
                        uv: [x.1, y.1, z.1],
                    });
                }
            }
        }
    }
    out
}

/// The visible faces of the refined reference, with limit positions, as
/// triangles.
pub(crate) fn reference_triangles(reference: &RefMesh, limit: &[DVec3]) -> Vec<Triangle> {
    let mut out = Vec::new();
    for (f, face) in reference.faces.iter().enumerate() {
        if reference.hidden[f] {
            continue;
        }
        let p = |k: usize| limit[face[k]];
        for corners in [[p(0), p(1), p(2)], [p(0), p(2), p(3)]] {
            out.push(Triangle {
                corners,
                patch: 0,
                uv: [(0.0, 0.0); 3],
            });
        }
    }
    out
}
