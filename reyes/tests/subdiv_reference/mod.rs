//! An independent Catmull-Clark reference for the subdivision tests: plain
//! uniform refinement of the whole mesh in f64 (every face, every level),
//! with the crease rules (DeRose et al. 1998, OpenSubdiv's "uniform"
//! creasing: sharp edges take the midpoint, fractional sharpness blends,
//! vertex rules smooth / dart / crease / corner with a fractional blend
//! where the rule changes), boundaries as infinitely sharp creases, and the
//! limit stencils that push a refined vertex onto the limit surface.

#![allow(dead_code, reason = "each test uses a different subset")]

use std::collections::{HashMap, HashSet};

use glam::DVec3;
use reyes::subdiv::{BoundaryInterpolation, Mesh};

/// Sharpness at or above which a tag is infinitely sharp.
pub(crate) const INFINITE: f64 = 10.0;

fn child(s: f64) -> f64 {
    if s >= INFINITE { s } else { (s - 1.0).max(0.0) }
}

fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// A whole mesh at one level.
#[derive(Debug, Clone)]
pub(crate) struct RefMesh {
    pub(crate) points: Vec<DVec3>,
    pub(crate) faces: Vec<Vec<usize>>,
    /// Faces without a surface (holes; boundary faces under
    /// `interpolateboundary 0`) and their children.
    pub(crate) hidden: Vec<bool>,
    pub(crate) crease: HashMap<(usize, usize), f64>,
    pub(crate) corner: Vec<f64>,
    /// Edges that are or were sharp (tagged at level 0, or children of
    /// such), for tests that stay away from creases.
    pub(crate) tagged: HashSet<(usize, usize)>,
}

impl RefMesh {
    pub(crate) fn new(mesh: &Mesh) -> RefMesh {
        let mut faces = Vec::new();
        let mut start = 0;
        for &n in &mesh.face_sizes {
            faces.push(
                mesh.face_vertices[start..start + n as usize]
                    .iter()
                    .map(|&v| v as usize)
                    .collect::<Vec<_>>(),
            );
            start += n as usize;
        }
        let mut m = RefMesh {
            points: mesh.positions.iter().map(|p| p.as_dvec3()).collect(),
            hidden: (0..faces.len())
                .map(|f| mesh.holes.contains(&(f as u32)))
                .collect(),
            faces,
            crease: HashMap::new(),
            corner: vec![0.0; mesh.positions.len()],
            tagged: HashSet::new(),
        };
        for c in &mesh.creases {
            for w in c.vertices.windows(2) {
                let s = m
                    .crease
                    .entry(key(w[0] as usize, w[1] as usize))
                    .or_insert(0.0);
                *s = s.max(f64::from(c.sharpness));
            }
        }
        for c in &mesh.corners {
            let s = &mut m.corner[c.vertex as usize];
            *s = s.max(f64::from(c.sharpness));
        }
        m.tagged = m.crease.keys().copied().collect();
        let edge_faces = m.edge_faces();
        let mut boundary = vec![false; m.points.len()];
        for (&(a, b), fs) in &edge_faces {
            if fs.len() == 1 {
                m.crease.insert((a, b), INFINITE);
                boundary[a] = true;
                boundary[b] = true;
            }
        }
        let vertex_faces = m.vertex_faces();
        match mesh.boundary {
            BoundaryInterpolation::None => {
                for (f, face) in m.faces.iter().enumerate() {
                    if face.iter().any(|&v| boundary[v]) {
                        m.hidden[f] = true;
                    }
                }
            }
            BoundaryInterpolation::EdgeAndCorner => {
                for v in 0..m.points.len() {
                    if boundary[v] && vertex_faces[v].len() == 1 {
                        m.corner[v] = INFINITE;
                    }
                }
            }
            BoundaryInterpolation::EdgeOnly => {}
        }
        m
    }

    fn sharpness(&self, a: usize, b: usize) -> f64 {
        self.crease.get(&key(a, b)).copied().unwrap_or(0.0)
    }

    pub(crate) fn edge_faces(&self) -> HashMap<(usize, usize), Vec<usize>> {
        let mut map: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
        for (f, face) in self.faces.iter().enumerate() {
            for k in 0..face.len() {
                map.entry(key(face[k], face[(k + 1) % face.len()]))
                    .or_default()
                    .push(f);
            }
        }
        map
    }

    pub(crate) fn vertex_faces(&self) -> Vec<Vec<usize>> {
        let mut out = vec![Vec::new(); self.points.len()];
        for (f, face) in self.faces.iter().enumerate() {
            for &v in face {
                out[v].push(f);
            }
        }
        out
    }

    /// The neighbours of each vertex (each once).
    pub(crate) fn neighbours(&self) -> Vec<Vec<usize>> {
        let mut out: Vec<Vec<usize>> = vec![Vec::new(); self.points.len()];
        for face in &self.faces {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                if !out[a].contains(&b) {
                    out[a].push(b);
                }
                if !out[b].contains(&a) {
                    out[b].push(a);
                }
            }
        }
        out
    }

    /// One uniform Catmull-Clark step.
    pub(crate) fn refine(&self) -> RefMesh {
        let nv = self.points.len();
        let centroid =
            |f: &Vec<usize>| f.iter().map(|&v| self.points[v]).sum::<DVec3>() / f.len() as f64;
        let face_points: Vec<DVec3> = self.faces.iter().map(centroid).collect();
        let edge_faces = self.edge_faces();
        let mut edges: Vec<(usize, usize)> = edge_faces.keys().copied().collect();
        edges.sort();
        let edge_index: HashMap<(usize, usize), usize> = edges
            .iter()
            .enumerate()
            .map(|(i, &e)| (e, nv + i))
            .collect();
        let mut points = vec![DVec3::ZERO; nv + edges.len() + self.faces.len()];
        for &(a, b) in &edges {
            let mid = (self.points[a] + self.points[b]) / 2.0;
            let s = self.sharpness(a, b);
            let fs = &edge_faces[&(a, b)];
            points[edge_index[&(a, b)]] = if s >= 1.0 || fs.len() < 2 {
                mid
            } else {
                let smooth =
                    (self.points[a] + self.points[b] + face_points[fs[0]] + face_points[fs[1]])
                        / 4.0;
                smooth + (mid - smooth) * s
            };
        }
        let vertex_faces = self.vertex_faces();
        let neighbours = self.neighbours();
        for v in 0..nv {
            if vertex_faces[v].is_empty() {
                points[v] = self.points[v];
                continue;
            }
            let p = self.points[v];
            let ns = &neighbours[v];
            let sharp_ends = |childwise: bool| -> Vec<usize> {
                ns.iter()
                    .copied()
                    .filter(|&w| {
                        let s = self.sharpness(v, w);
                        (if childwise { child(s) } else { s }) > 0.0
                    })
                    .collect()
            };
            let vs = self.corner[v];
            let mask = |childwise: bool| -> DVec3 {
                let ends = sharp_ends(childwise);
                let sharp_vertex = (if childwise { child(vs) } else { vs }) > 0.0;
                if sharp_vertex || ends.len() > 2 {
                    p
                } else if ends.len() == 2 {
                    (self.points[ends[0]] + p * 6.0 + self.points[ends[1]]) / 8.0
                } else {
                    let n = ns.len() as f64;
                    let q = vertex_faces[v]
                        .iter()
                        .map(|&f| face_points[f])
                        .sum::<DVec3>()
                        / vertex_faces[v].len() as f64;
                    let r = ns
                        .iter()
                        .map(|&w| (p + self.points[w]) / 2.0)
                        .sum::<DVec3>()
                        / n;
                    (q + r * 2.0 + p * (n - 3.0)) / n
                }
            };
            let kind = |childwise: bool| {
                let ends = sharp_ends(childwise).len();
                let sharp_vertex = (if childwise { child(vs) } else { vs }) > 0.0;
                if sharp_vertex || ends > 2 {
                    2
                } else if ends == 2 {
                    1
                } else {
                    0
                }
            };
            let (parent_kind, child_kind) = (kind(false), kind(true));
            points[v] = if parent_kind == child_kind || parent_kind == 0 {
                mask(false)
            } else {
                let mut sum = 0.0;
                let mut count = 0.0;
                if vs > 0.0 && child(vs) == 0.0 {
                    sum += vs;
                    count += 1.0;
                }
                for &w in ns {
                    let s = self.sharpness(v, w);
                    if s > 0.0 && child(s) == 0.0 {
                        sum += s;
                        count += 1.0;
                    }
                }
                let w = if count > 0.0 {
                    (sum / count).min(1.0)
                } else {
                    0.0
                };
                mask(false) * w + mask(true) * (1.0 - w)
            };
        }
        let face_base = nv + edges.len();
        for (f, &c) in face_points.iter().enumerate() {
            points[face_base + f] = c;
        }
        let mut faces = Vec::new();
        let mut hidden = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            let n = face.len();
            for k in 0..n {
                let (v, next, prev) = (face[k], face[(k + 1) % n], face[(k + n - 1) % n]);
                faces.push(vec![
                    v,
                    edge_index[&key(v, next)],
                    face_base + f,
                    edge_index[&key(prev, v)],
                ]);
                hidden.push(self.hidden[f]);
            }
        }
        let mut crease = HashMap::new();
        for (&(a, b), &s) in &self.crease {
            let c = child(s);
            if c > 0.0 && edge_index.contains_key(&(a, b)) {
                let m = edge_index[&(a, b)];
                crease.insert(key(a, m), c);
                crease.insert(key(b, m), c);
            }
        }
        let mut tagged = HashSet::new();
        for &(a, b) in &self.tagged {
            if let Some(&m) = edge_index.get(&(a, b)) {
                tagged.insert(key(a, m));
                tagged.insert(key(b, m));
            }
        }
        let mut corner = vec![0.0; points.len()];
        for (out, &c) in corner.iter_mut().zip(&self.corner) {
            *out = child(c);
        }
        RefMesh {
            points,
            faces,
            hidden,
            crease,
            corner,
            tagged,
        }
    }

    /// The limit position of every vertex (of an all-quad mesh whose
    /// sharpness is 0 or infinite everywhere).
    pub(crate) fn limit(&self) -> Vec<DVec3> {
        let vertex_faces = self.vertex_faces();
        let neighbours = self.neighbours();
        (0..self.points.len())
            .map(|v| {
                let p = self.points[v];
                let ends: Vec<usize> = neighbours[v]
                    .iter()
                    .copied()
                    .filter(|&w| self.sharpness(v, w) > 0.0)
                    .collect();
                if vertex_faces[v].is_empty() || self.corner[v] > 0.0 || ends.len() > 2 {
                    return p;
                }
                if ends.len() == 2 {
                    return (self.points[ends[0]] + p * 4.0 + self.points[ends[1]]) / 6.0;
                }
                let n = vertex_faces[v].len() as f64;
                let mut sum = p * n * n;
                for &f in &vertex_faces[v] {
                    let face = &self.faces[f];
                    let k = face.iter().position(|&w| w == v).unwrap();
                    sum += self.points[face[(k + 1) % 4]] * 4.0 + self.points[face[(k + 2) % 4]];
                }
                sum / (n * (n + 5.0))
            })
            .collect()
    }

    /// The limit normal (unnormalised, following the winding) at each
    /// vertex from the central differences of the limit positions around
    /// it: `sum over faces of (next - v) x (prev - v)`, which for a valence-4
    /// vertex is `(e0 - e2) x (e1 - e3)`.
    pub(crate) fn normals(&self, limit: &[DVec3]) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; self.points.len()];
        for face in &self.faces {
            let n = face.len();
            for k in 0..n {
                let (v, next, prev) = (face[k], face[(k + 1) % n], face[(k + n - 1) % n]);
                out[v] += (limit[next] - limit[v]).cross(limit[prev] - limit[v]);
            }
        }
        out
    }
}
