//! One subdivision level of a mesh: its vertices (with where each came
//! from), its faces, the sharpness of its edges and vertices, and the
//! adjacency the rules and the patch gathering walk.
//!
//! Level 0 is the whole mesh as given. A deeper level holds only the part
//! of the surface that still needs refining (see `refine.rs`): a vertex is
//! `complete` when every face around it is present, and only complete
//! vertices are ever refined, classified or pushed to the limit.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::mesh::{BoundaryInterpolation, INFINITE_SHARPNESS, Mesh};

/// A vertex's name across levels: the level where it first appeared (in
/// the top bits) and its index there. The vertex point of a vertex keeps
/// the key of its parent, since both have the same limit position.
pub(super) type Key = u64;

/// The key of vertex `index` first made at `level`.
pub(super) fn key(level: usize, index: u32) -> Key {
    ((level as u64) << 40) | u64::from(index)
}

/// Where a vertex of a level comes from in the level above it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Origin {
    /// A vertex of the mesh as given (level 0).
    Given,
    /// The vertex point of a parent vertex.
    Vertex(u32),
    /// The edge point of the parent edge between these two vertices
    /// (smaller first).
    Edge(u32, u32),
    /// The face point of a parent face.
    Face(u32),
}

/// Whether a sharpness is infinite (a crease or corner at every level).
pub(super) fn is_infinite(sharpness: f32) -> bool {
    sharpness >= INFINITE_SHARPNESS
}

/// The sharpness one level down: one less ("uniform" rule), infinite ones
/// kept.
pub(super) fn child_sharpness(sharpness: f32) -> f32 {
    if is_infinite(sharpness) {
        sharpness
    } else {
        (sharpness - 1.0).max(0.0)
    }
}

/// An undirected edge: its two vertices, smaller first.
pub(super) fn edge(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// One level of the mesh (see the module documentation).
#[derive(Debug, Default)]
pub(super) struct Level {
    /// The vertex positions.
    pub positions: Vec<Vec3>,
    /// Each vertex's key.
    pub keys: Vec<Key>,
    /// Each vertex's origin in the level above.
    pub origins: Vec<Origin>,
    /// Whether every face around the vertex is in this level.
    pub complete: Vec<bool>,
    /// Each vertex's corner sharpness.
    pub vertex_sharpness: Vec<f32>,
    /// Face `f`'s vertices are `face_vertices[face_offsets[f]..face_offsets[f + 1]]`.
    pub face_offsets: Vec<u32>,
    /// The faces' vertices, in winding order.
    pub face_vertices: Vec<u32>,
    /// Faces without a surface of their own (holes, and boundary faces
    /// under [`BoundaryInterpolation::None`]), and their children.
    pub hidden: Vec<bool>,
    /// Face-varying texture coordinates, one per entry of `face_vertices`.
    pub st: Option<Vec<Vec2>>,
    /// The sharpness of each sharp edge (boundary edges are infinitely
    /// sharp); an edge not listed is smooth.
    pub edge_sharpness: HashMap<(u32, u32), f32>,
    /// The parent vertex -> its vertex point here.
    pub from_vertex: HashMap<u32, u32>,
    /// The parent edge -> its edge point here.
    pub from_edge: HashMap<(u32, u32), u32>,
    /// The parent face -> its face point here.
    pub from_face: HashMap<u32, u32>,
    vertex_face_offsets: Vec<u32>,
    vertex_faces: Vec<u32>,
    directed: HashMap<(u32, u32), (u32, u32)>,
}

impl Level {
    /// Level 0: the validated mesh with its tags.
    pub(super) fn from_mesh(mesh: &Mesh) -> Level {
        let count = mesh.positions.len();
        let mut face_offsets = vec![0u32];
        for &size in &mesh.face_sizes {
            face_offsets.push(face_offsets[face_offsets.len() - 1] + size);
        }
        let mut level = Level {
            positions: mesh.positions.clone(),
            keys: (0..count as u32).map(|i| key(0, i)).collect(),
            origins: vec![Origin::Given; count],
            complete: vec![true; count],
            vertex_sharpness: vec![0.0; count],
            face_offsets,
            face_vertices: mesh.face_vertices.clone(),
            hidden: (0..mesh.face_count()).map(|f| mesh.is_hole(f)).collect(),
            st: mesh.st.clone(),
            ..Level::default()
        };
        level.finish();
        for corner in &mesh.corners {
            let s = &mut level.vertex_sharpness[corner.vertex as usize];
            *s = s.max(corner.sharpness);
        }
        for crease in &mesh.creases {
            for pair in crease.vertices.windows(2) {
                if crease.sharpness > 0.0 {
                    let s = level
                        .edge_sharpness
                        .entry(edge(pair[0], pair[1]))
                        .or_insert(0.0);
                    *s = s.max(crease.sharpness);
                }
            }
        }
        let boundary: Vec<(u32, u32)> = level
            .directed
            .keys()
            .filter(|&&(a, b)| !level.directed.contains_key(&(b, a)))
            .copied()
            .collect();
        let mut on_boundary = vec![false; count];
        for &(a, b) in &boundary {
            level.edge_sharpness.insert(edge(a, b), INFINITE_SHARPNESS);
            on_boundary[a as usize] = true;
            on_boundary[b as usize] = true;
        }
        match mesh.boundary {
            BoundaryInterpolation::None => {
                for f in 0..level.face_count() {
                    if level
                        .face(f as u32)
                        .iter()
                        .any(|&v| on_boundary[v as usize])
                    {
                        level.hidden[f] = true;
                    }
                }
            }
            BoundaryInterpolation::EdgeAndCorner => {
                for (v, &boundary) in on_boundary.iter().enumerate() {
                    if boundary && level.faces_of(v as u32).len() == 1 {
                        level.vertex_sharpness[v] = INFINITE_SHARPNESS;
                    }
                }
            }
            BoundaryInterpolation::EdgeOnly => {}
        }
        level
    }

    /// Builds the adjacency once the faces are in place.
    pub(super) fn finish(&mut self) {
        let vertices = self.positions.len();
        let mut counts = vec![0u32; vertices + 1];
        for &v in &self.face_vertices {
            counts[v as usize + 1] += 1;
        }
        for i in 0..vertices {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut vertex_faces = vec![0u32; self.face_vertices.len()];
        let mut directed = HashMap::with_capacity(self.face_vertices.len());
        for f in 0..self.face_count() as u32 {
            let vs = self.face(f);
            for (k, &v) in vs.iter().enumerate() {
                vertex_faces[fill[v as usize] as usize] = f;
                fill[v as usize] += 1;
                let next = vs[(k + 1) % vs.len()];
                directed.insert((v, next), (f, k as u32));
            }
        }
        self.directed = directed;
        self.vertex_face_offsets = counts;
        self.vertex_faces = vertex_faces;
    }

    /// The number of faces.
    pub(super) fn face_count(&self) -> usize {
        self.face_offsets.len() - 1
    }

    /// The vertices of face `f` in winding order.
    pub(super) fn face(&self, f: u32) -> &[u32] {
        let f = f as usize;
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// The texture coordinates of face `f`'s corners, if the mesh has any.
    pub(super) fn face_st(&self, f: u32) -> Option<&[Vec2]> {
        let f = f as usize;
        let range = self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize;
        self.st.as_ref().map(|st| &st[range])
    }

    /// The four vertices of quad `f`.
    pub(super) fn quad(&self, f: u32) -> [u32; 4] {
        let q = self.face(f);
        [q[0], q[1], q[2], q[3]]
    }

    /// The faces around vertex `v` (present in this level).
    pub(super) fn faces_of(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.vertex_faces
            [self.vertex_face_offsets[v] as usize..self.vertex_face_offsets[v + 1] as usize]
    }

    /// The face that runs from `from` to `to`, and the corner of `from` in it.
    pub(super) fn face_with_edge(&self, from: u32, to: u32) -> Option<(u32, usize)> {
        self.directed
            .get(&(from, to))
            .map(|&(f, k)| (f, k as usize))
    }

    /// The sharpness of the edge between `a` and `b`.
    pub(super) fn sharpness(&self, a: u32, b: u32) -> f32 {
        self.edge_sharpness.get(&edge(a, b)).copied().unwrap_or(0.0)
    }

    /// The corner of vertex `v` in face `f`.
    pub(super) fn corner_of(&self, f: u32, v: u32) -> usize {
        self.face(f).iter().position(|&w| w == v).unwrap_or(0)
    }

    /// The vertices sharing an edge with `v`, each once, with the edge's
    /// sharpness.
    pub(super) fn edges_of(&self, v: u32) -> Vec<(u32, f32)> {
        let mut out: Vec<(u32, f32)> = Vec::with_capacity(8);
        for &f in self.faces_of(v) {
            let vs = self.face(f);
            let k = self.corner_of(f, v);
            for other in [vs[(k + 1) % vs.len()], vs[(k + vs.len() - 1) % vs.len()]] {
                if !out.iter().any(|&(w, _)| w == other) {
                    out.push((other, self.sharpness(v, other)));
                }
            }
        }
        out
    }

    /// The centroid of face `f`.
    pub(super) fn centroid(&self, f: u32) -> Vec3 {
        let vs = self.face(f);
        vs.iter().map(|&v| self.positions[v as usize]).sum::<Vec3>() / vs.len() as f32
    }
}
