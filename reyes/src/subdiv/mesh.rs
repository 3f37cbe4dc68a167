//! A polygon mesh as given, with its subdivision tags, and its validation.

use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::ops::Range;

use glam::{Vec2, Vec3};

/// Sharpness at or above which a crease or corner is infinitely sharp, as
/// RenderMan and OpenSubdiv define it.
pub const INFINITE_SHARPNESS: f32 = 10.0;

/// The subdivision rules of a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scheme {
    /// Catmull-Clark subdivision: the smooth limit surface.
    #[default]
    CatmullClark,
    /// Bilinear subdivision: every face flat.
    Bilinear,
}

impl Scheme {
    /// The name RIB and the scene file use: `catmull-clark` or `bilinear`.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::CatmullClark => "catmull-clark",
            Scheme::Bilinear => "bilinear",
        }
    }
}

/// What happens at the mesh's boundary (RIB's `interpolateboundary` tag).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoundaryInterpolation {
    /// `interpolateboundary 0` (and no tag): the boundary faces only shape
    /// their neighbours and have no surface of their own.
    #[default]
    None,
    /// `interpolateboundary 2`: boundary edges are infinitely sharp creases;
    /// a boundary vertex of one face is smooth.
    EdgeOnly,
    /// `interpolateboundary 1`: boundary edges are infinitely sharp creases
    /// and a boundary vertex of one face is an infinitely sharp corner.
    EdgeAndCorner,
}

/// A chain of edges `vertices[0] - vertices[1] - ...` with one sharpness
/// (RIB's `crease` tag).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Crease {
    /// The vertices along the chain; consecutive ones share an edge.
    pub vertices: Vec<u32>,
    /// The sharpness: 0 is smooth, fractions blend, [`INFINITE_SHARPNESS`]
    /// or more is a sharp crease at every level.
    pub sharpness: f32,
}

/// A sharp vertex (RIB's `corner` tag).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Corner {
    /// The vertex.
    pub vertex: u32,
    /// Its sharpness, as for [`Crease::sharpness`].
    pub sharpness: f32,
}

/// A polygon mesh to subdivide.
///
/// Face `f` has `face_sizes[f]` vertices, listed in winding order in
/// `face_vertices` after those of the faces before it. `dP/du x dP/dv` of
/// the patches follows the winding, as for RIB polygons.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// The subdivision rules.
    pub scheme: Scheme,
    /// The vertex positions.
    pub positions: Vec<Vec3>,
    /// The number of vertices of each face.
    pub face_sizes: Vec<u32>,
    /// The vertices of all faces, face after face.
    pub face_vertices: Vec<u32>,
    /// The creases.
    pub creases: Vec<Crease>,
    /// The sharp vertices.
    pub corners: Vec<Corner>,
    /// The faces that are holes: they shape their neighbours but have no
    /// surface.
    pub holes: Vec<u32>,
    /// The boundary rule.
    pub boundary: BoundaryInterpolation,
    /// Face-varying texture coordinates `s, t`: one per entry of
    /// `face_vertices`; `None`: the patches get the default ones.
    pub st: Option<Vec<Vec2>>,
}

/// Why a mesh has no surface. Faces and vertices are 0-based indices into
/// the mesh as given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The face sizes do not add up to the number of face vertices.
    #[error("the face sizes add up to {expected} vertices but {found} are listed")]
    CountMismatch {
        /// The sum of the face sizes.
        expected: u64,
        /// The length of the vertex list.
        found: usize,
    },
    /// A face has fewer than 3 vertices.
    #[error("face {face} has {size} vertices (at least 3 are needed)")]
    FaceTooSmall {
        /// The face.
        face: usize,
        /// Its vertex count.
        size: u32,
    },
    /// A face lists a vertex that does not exist.
    #[error("face {face} uses vertex {vertex}, but the mesh has {count} vertices")]
    VertexOutOfRange {
        /// The face.
        face: usize,
        /// The vertex it lists.
        vertex: u32,
        /// How many vertices there are.
        count: usize,
    },
    /// A face lists one vertex twice.
    #[error("face {face} lists vertex {vertex} more than once")]
    RepeatedVertex {
        /// The face.
        face: usize,
        /// The vertex.
        vertex: u32,
    },
    /// A vertex position is NaN or infinite.
    #[error("vertex {vertex} has a position that is not finite ({position})")]
    NonFinitePosition {
        /// The vertex.
        vertex: usize,
        /// Its position.
        position: Vec3,
    },
    /// Two faces list the same vertices.
    #[error("face {face} repeats face {first} (the same vertices)")]
    DuplicateFace {
        /// The later face.
        face: usize,
        /// The earlier one.
        first: usize,
    },
    /// Two faces run along an edge in the same direction: their windings
    /// disagree, so the surface has no consistent side.
    #[error(
        "faces {first} and {face} both run from vertex {from} to vertex {to}: their windings disagree"
    )]
    InconsistentWinding {
        /// The later face.
        face: usize,
        /// The earlier one.
        first: usize,
        /// The edge's first vertex.
        from: u32,
        /// Its second vertex.
        to: u32,
    },
    /// More than two faces share an edge.
    #[error(
        "face {face} is the third face on the edge between vertices {from} and {to} (non-manifold)"
    )]
    NonManifoldEdge {
        /// The third face.
        face: usize,
        /// The edge's first vertex.
        from: u32,
        /// Its second vertex.
        to: u32,
    },
    /// A hole names a face that does not exist.
    #[error("hole {face} names a face that does not exist (the mesh has {count} faces)")]
    HoleOutOfRange {
        /// The face named.
        face: u32,
        /// How many faces there are.
        count: usize,
    },
    /// A crease is not a chain of mesh edges.
    #[error("crease {crease}: {problem}")]
    BadCrease {
        /// The crease (its position in the list).
        crease: usize,
        /// What is wrong with it.
        problem: String,
    },
    /// A corner names a vertex that does not exist, or has a bad sharpness.
    #[error("corner {corner}: {problem}")]
    BadCorner {
        /// The corner (its position in the list).
        corner: usize,
        /// What is wrong with it.
        problem: String,
    },
    /// The texture coordinates do not fit the faces.
    #[error("texture coordinates: {problem}")]
    BadTextureCoordinates {
        /// What is wrong with them.
        problem: String,
    },
    /// The surface needs more patches than one mesh may make.
    #[error("the surface needs more than {limit} patches (the most one mesh may make)")]
    TooManyPatches {
        /// The bound.
        limit: usize,
    },
    /// Something the mesh asks for is not built.
    #[error("{what} is not supported")]
    Unsupported {
        /// What is not supported.
        what: &'static str,
    },
}

impl Mesh {
    /// The number of faces.
    pub fn face_count(&self) -> usize {
        self.face_sizes.len()
    }

    /// The ranges of `face_vertices` (and of `st`) of each face, in order.
    /// Meaningful after [`Mesh::validate`].
    pub fn faces(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        self.face_sizes.iter().scan(0usize, |start, &size| {
            let range = *start..*start + size as usize;
            *start = range.end;
            Some(range)
        })
    }

    /// Whether face `face` is a hole.
    pub fn is_hole(&self, face: usize) -> bool {
        self.holes.iter().any(|&h| h as usize == face)
    }

    /// Checks that the mesh describes a surface: counts that agree, faces of
    /// at least 3 distinct existing vertices, finite positions, every edge
    /// on at most two faces with opposite windings, no face twice, and tags
    /// that name existing faces, vertices and edges with finite,
    /// non-negative sharpness.
    pub fn validate(&self) -> Result<(), MeshError> {
        let expected: u64 = self.face_sizes.iter().map(|&s| u64::from(s)).sum();
        if expected != self.face_vertices.len() as u64 {
            return Err(MeshError::CountMismatch {
                expected,
                found: self.face_vertices.len(),
            });
        }
        if let Some((vertex, &position)) = self
            .positions
            .iter()
            .enumerate()
            .find(|(_, p)| !p.is_finite())
        {
            return Err(MeshError::NonFinitePosition { vertex, position });
        }
        self.validate_faces()?;
        self.validate_edges()?;
        self.validate_tags()?;
        self.validate_st()
    }

    fn validate_faces(&self) -> Result<(), MeshError> {
        let count = self.positions.len();
        for (face, range) in self.faces().enumerate() {
            let size = self.face_sizes[face];
            if size < 3 {
                return Err(MeshError::FaceTooSmall { face, size });
            }
            let vertices = &self.face_vertices[range];
            for (i, &vertex) in vertices.iter().enumerate() {
                if vertex as usize >= count {
                    return Err(MeshError::VertexOutOfRange {
                        face,
                        vertex,
                        count,
                    });
                }
                if vertices[..i].contains(&vertex) {
                    return Err(MeshError::RepeatedVertex { face, vertex });
                }
            }
        }
        Ok(())
    }

    /// Every directed edge once; every undirected edge on at most two faces.
    fn validate_edges(&self) -> Result<(), MeshError> {
        let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
        let mut undirected: HashMap<(u32, u32), u8> = HashMap::new();
        for (face, range) in self.faces().enumerate() {
            let vertices = &self.face_vertices[range];
            for (i, &from) in vertices.iter().enumerate() {
                let to = vertices[(i + 1) % vertices.len()];
                let uses = undirected.entry((from.min(to), from.max(to))).or_insert(0);
                *uses += 1;
                if *uses > 2 {
                    return Err(MeshError::NonManifoldEdge { face, from, to });
                }
                match directed.entry((from, to)) {
                    Entry::Occupied(first) => {
                        let first = *first.get();
                        return Err(if self.same_vertices(first, face) {
                            MeshError::DuplicateFace { face, first }
                        } else {
                            MeshError::InconsistentWinding {
                                face,
                                first,
                                from,
                                to,
                            }
                        });
                    }
                    Entry::Vacant(slot) => {
                        slot.insert(face);
                    }
                }
            }
        }
        Ok(())
    }

    fn same_vertices(&self, a: usize, b: usize) -> bool {
        let sorted = |face: usize| {
            let range = self.faces().nth(face).unwrap_or(0..0);
            let mut v = self.face_vertices[range].to_vec();
            v.sort_unstable();
            v
        };
        sorted(a) == sorted(b)
    }

    fn validate_tags(&self) -> Result<(), MeshError> {
        let count = self.face_count();
        if let Some(&face) = self.holes.iter().find(|&&h| h as usize >= count) {
            return Err(MeshError::HoleOutOfRange { face, count });
        }
        let mut edges = std::collections::HashSet::new();
        for range in self.faces() {
            let vertices = &self.face_vertices[range];
            for (i, &a) in vertices.iter().enumerate() {
                let b = vertices[(i + 1) % vertices.len()];
                edges.insert((a.min(b), a.max(b)));
            }
        }
        for (crease, c) in self.creases.iter().enumerate() {
            let problem = |problem: String| MeshError::BadCrease { crease, problem };
            if !(c.sharpness.is_finite() && c.sharpness >= 0.0) {
                return Err(problem(format!(
                    "sharpness {} is not a finite non-negative number",
                    c.sharpness
                )));
            }
            if c.vertices.len() < 2 {
                return Err(problem(format!(
                    "{} vertices (at least 2 are needed)",
                    c.vertices.len()
                )));
            }
            for pair in c.vertices.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                if !edges.contains(&(a.min(b), a.max(b))) {
                    return Err(problem(format!(
                        "vertices {a} and {b} do not share an edge of the mesh"
                    )));
                }
            }
        }
        for (corner, c) in self.corners.iter().enumerate() {
            let problem = |problem: String| MeshError::BadCorner { corner, problem };
            if c.vertex as usize >= self.positions.len() {
                return Err(problem(format!(
                    "vertex {} does not exist (the mesh has {})",
                    c.vertex,
                    self.positions.len()
                )));
            }
            if !(c.sharpness.is_finite() && c.sharpness >= 0.0) {
                return Err(problem(format!(
                    "sharpness {} is not a finite non-negative number",
                    c.sharpness
                )));
            }
        }
        Ok(())
    }

    fn validate_st(&self) -> Result<(), MeshError> {
        let Some(st) = &self.st else { return Ok(()) };
        if st.len() != self.face_vertices.len() {
            return Err(MeshError::BadTextureCoordinates {
                problem: format!(
                    "{} coordinates for {} face vertices",
                    st.len(),
                    self.face_vertices.len()
                ),
            });
        }
        if let Some(i) = st.iter().position(|c| !c.is_finite()) {
            return Err(MeshError::BadTextureCoordinates {
                problem: format!("face vertex {i} has coordinates that are not finite"),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quads(faces: &[[u32; 4]], vertices: usize) -> Mesh {
        Mesh {
            positions: (0..vertices).map(|i| Vec3::splat(i as f32)).collect(),
            face_sizes: vec![4; faces.len()],
            face_vertices: faces.iter().flatten().copied().collect(),
            ..Mesh::default()
        }
    }

    #[test]
    fn a_consistent_mesh_is_valid() {
        assert_eq!(quads(&[[0, 1, 2, 3], [1, 4, 5, 2]], 6).validate(), Ok(()));
    }

    #[test]
    fn each_defect_names_its_face() {
        let mut m = quads(&[[0, 1, 2, 3]], 4);
        m.face_sizes = vec![2, 2];
        assert!(matches!(
            m.validate(),
            Err(MeshError::FaceTooSmall { face: 0, size: 2 })
        ));
        let m = quads(&[[0, 1, 2, 3], [1, 4, 5, 9]], 6);
        assert!(matches!(
            m.validate(),
            Err(MeshError::VertexOutOfRange {
                face: 1,
                vertex: 9,
                ..
            })
        ));
        let m = quads(&[[0, 1, 2, 1]], 4);
        assert!(matches!(
            m.validate(),
            Err(MeshError::RepeatedVertex { face: 0, vertex: 1 })
        ));
        let m = quads(&[[0, 1, 2, 3], [1, 2, 3, 0]], 4);
        assert!(matches!(
            m.validate(),
            Err(MeshError::DuplicateFace { face: 1, first: 0 })
        ));
        let m = quads(&[[0, 1, 2, 3], [0, 1, 5, 4]], 6);
        assert!(matches!(
            m.validate(),
            Err(MeshError::InconsistentWinding {
                face: 1,
                first: 0,
                ..
            })
        ));
        let m = quads(&[[0, 1, 2, 3], [1, 0, 4, 5], [6, 7, 0, 1]], 8);
        assert!(matches!(
            m.validate(),
            Err(MeshError::NonManifoldEdge { face: 2, .. })
        ));
        let mut m = quads(&[[0, 1, 2, 3]], 4);
        m.positions[2].y = f32::NAN;
        assert!(matches!(
            m.validate(),
            Err(MeshError::NonFinitePosition { vertex: 2, .. })
        ));
    }

    #[test]
    fn tags_must_name_what_exists() {
        let mut m = quads(&[[0, 1, 2, 3]], 4);
        m.holes = vec![1];
        assert!(matches!(
            m.validate(),
            Err(MeshError::HoleOutOfRange { face: 1, count: 1 })
        ));
        let mut m = quads(&[[0, 1, 2, 3]], 4);
        m.creases = vec![Crease {
            vertices: vec![0, 2],
            sharpness: 1.0,
        }];
        assert!(matches!(
            m.validate(),
            Err(MeshError::BadCrease { crease: 0, .. })
        ));
        m.creases = vec![Crease {
            vertices: vec![0, 1, 2],
            sharpness: f32::NAN,
        }];
        assert!(matches!(
            m.validate(),
            Err(MeshError::BadCrease { crease: 0, .. })
        ));
        m.creases = vec![Crease {
            vertices: vec![0, 1, 2],
            sharpness: 2.5,
        }];
        m.corners = vec![Corner {
            vertex: 7,
            sharpness: 1.0,
        }];
        assert!(matches!(
            m.validate(),
            Err(MeshError::BadCorner { corner: 0, .. })
        ));
        m.corners.clear();
        m.st = Some(vec![Vec2::ZERO; 3]);
        assert!(matches!(
            m.validate(),
            Err(MeshError::BadTextureCoordinates { .. })
        ));
    }
}
