//! Wavefront OBJ meshes: `v`, `vt` and `f` statements, read with `tobj`
//! into a [`Mesh`] and subdivided into patches ([`Mesh::to_patches`]).
//!
//! * faces of any valence are kept as they are (not triangulated);
//! * the file is one mesh: objects and groups (`o`, `g`), materials
//!   (`usemtl`, `mtllib`) and smoothing groups (`s`) are read past, so a
//!   vertex that two groups share stays one vertex;
//! * `vt` become the mesh's face-varying texture coordinates when every
//!   face vertex has one, `s = u`, `t = 1 - v` (OBJ's `v` goes up the
//!   image, the renderer's `t` down); when only some have, none are used
//!   (a warning is logged);
//! * the boundary is interpolated (edges and corners sharp,
//!   [`BoundaryInterpolation::EdgeAndCorner`]), as modelling tools that
//!   write OBJ expect;
//! * `l` and `p` (polylines, points) are refused; normals, free-form
//!   curves and surfaces are ignored.
//!
//! Errors name the file and the line; faces and vertices in the messages
//! are numbered from 1 in file order, as OBJ indices are.

use std::collections::HashMap;
use std::io::BufReader;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::LoadError;
use super::obj_scan::{self, Scan};
use crate::budget::PatchBudget;
use crate::model::Model;
use crate::subdiv::{BoundaryInterpolation, Mesh, MeshError, Scheme};

/// An OBJ file's mesh, with where its parts are in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjMesh {
    /// The mesh. Its vertices are the file's vertices that faces use, in
    /// the order faces first use them.
    pub mesh: Mesh,
    /// The 1-based line of each face.
    pub face_lines: Vec<usize>,
    /// The 1-based file number of each mesh vertex.
    pub file_vertices: Vec<u32>,
}

/// Reads the OBJ `text` (the file at `path`, for messages) into a mesh
/// under `scheme`.
pub fn parse_mesh(text: &str, path: &Path, scheme: Scheme) -> Result<ObjMesh, LoadError> {
    let scan = obj_scan::scan(text, path)?;
    let filtered;
    let text = if scan.has_grouping {
        filtered = obj_scan::without_grouping(text);
        filtered.as_str()
    } else {
        crate::input::strip_bom(text)
    };
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: false,
        ignore_lines: false,
    };
    // Materials are not read: no file beside the OBJ is opened.
    let (models, _) = tobj::load_obj_buf(&mut BufReader::new(text.as_bytes()), &options, |_| {
        Ok((Vec::new(), HashMap::new()))
    })
    .map_err(|e| LoadError::ObjRead {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    build(models, &scan, path, scheme)
}

/// The mesh of `tobj`'s `models` (one, as the grouping is blanked; any
/// more are appended with their indices offset).
fn build(
    models: Vec<tobj::Model>,
    scan: &Scan,
    path: &Path,
    scheme: Scheme,
) -> Result<ObjMesh, LoadError> {
    let mut mesh = Mesh {
        scheme,
        boundary: BoundaryInterpolation::EdgeAndCorner,
        ..Mesh::default()
    };
    let mut st = Vec::new();
    for model in models {
        let m = model.mesh;
        let offset = mesh.positions.len() as u32;
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if m.face_arities.is_empty() {
            // tobj leaves the arities empty when every face is a triangle.
            mesh.face_sizes
                .extend(std::iter::repeat_n(3, m.indices.len() / 3));
        } else {
            mesh.face_sizes.extend(&m.face_arities);
        }
        mesh.face_vertices
            .extend(m.indices.iter().map(|&i| i + offset));
        if scan.all_st {
            st.extend(m.texcoord_indices.iter().map(|&i| {
                let i = i as usize * 2;
                Vec2::new(m.texcoords[i], 1.0 - m.texcoords[i + 1])
            }));
        }
    }
    if scan.all_st {
        mesh.st = Some(st);
    } else if scan.some_st {
        log::warn!(
            "{}: some faces have texture coordinates (vt) and some not: none are used",
            path.display()
        );
    }
    // The file's vertex behind each mesh vertex, from the two orders.
    let mut file_vertices = vec![0u32; mesh.positions.len()];
    for (&mesh_vertex, &file_vertex) in mesh.face_vertices.iter().zip(&scan.face_vertices) {
        if let Some(slot) = file_vertices.get_mut(mesh_vertex as usize) {
            *slot = file_vertex + 1;
        }
    }
    if mesh.face_sizes != scan.face_sizes || mesh.face_vertices.len() != scan.face_vertices.len() {
        // The pass and tobj read the faces alike; a difference is a defect
        // of this reader, reported rather than rendered wrong.
        return Err(LoadError::ObjRead {
            path: path.to_path_buf(),
            message: format!(
                "tobj read {} faces where {} are written",
                mesh.face_sizes.len(),
                scan.face_sizes.len()
            ),
        });
    }
    Ok(ObjMesh {
        mesh,
        face_lines: scan.face_lines.clone(),
        file_vertices,
    })
}

/// Reads the OBJ `text` (the file at `path`) and makes its patches under
/// `scheme`, taking them from `budget`: the bilinear count (a lower bound
/// for Catmull-Clark) before anything is built, the rest once the
/// patches are made.
pub fn parse_within(
    text: &str,
    path: &Path,
    scheme: Scheme,
    budget: &mut PatchBudget,
) -> Result<Model, LoadError> {
    let estimate = obj_scan::bilinear_patch_estimate(text);
    let budget_error = |source| LoadError::PatchBudgetOf {
        path: path.to_path_buf(),
        source,
    };
    budget.take(estimate).map_err(budget_error)?;
    let obj = parse_mesh(text, path, scheme)?;
    // At most what the budget has left: a mesh past it is refused before
    // its patches are made.
    let allowed = estimate.saturating_add(budget.remaining());
    let limit = usize::try_from(allowed).unwrap_or(usize::MAX);
    let subdivided = match obj.mesh.to_patches_within(limit) {
        Err(MeshError::TooManyPatches { limit: hit }) if hit == limit => {
            return Err(budget_error(budget.refusal(allowed + 1 - estimate)));
        }
        other => other.map_err(|e| obj.file_error(path, e))?,
    };
    let made = subdivided.model.patches.len() as u64;
    if made > estimate {
        budget.take(made - estimate).map_err(budget_error)?;
    } else {
        budget.give_back(estimate - made);
    }
    Ok(subdivided.model)
}

impl ObjMesh {
    /// `error` about this mesh in the file's terms: faces and vertices
    /// numbered from 1 in file order, with the line of the face.
    pub fn file_error(&self, path: &Path, error: MeshError) -> LoadError {
        let vertex = |v: u32| self.file_vertices.get(v as usize).copied().unwrap_or(v + 1);
        let face = |f: usize| f + 1;
        let line = |f: usize| self.face_lines.get(f).copied();
        let (source, line) = match error {
            MeshError::FaceTooSmall { face: f, size } => (
                MeshError::FaceTooSmall {
                    face: face(f),
                    size,
                },
                line(f),
            ),
            MeshError::VertexOutOfRange {
                face: f,
                vertex: v,
                count,
            } => (
                MeshError::VertexOutOfRange {
                    face: face(f),
                    vertex: vertex(v),
                    count,
                },
                line(f),
            ),
            MeshError::RepeatedVertex { face: f, vertex: v } => (
                MeshError::RepeatedVertex {
                    face: face(f),
                    vertex: vertex(v),
                },
                line(f),
            ),
            MeshError::DuplicateFace { face: f, first } => (
                MeshError::DuplicateFace {
                    face: face(f),
                    first: face(first),
                },
                line(f),
            ),
            MeshError::InconsistentWinding {
                face: f,
                first,
                from,
                to,
            } => (
                MeshError::InconsistentWinding {
                    face: face(f),
                    first: face(first),
                    from: vertex(from),
                    to: vertex(to),
                },
                line(f),
            ),
            MeshError::NonManifoldEdge { face: f, from, to } => (
                MeshError::NonManifoldEdge {
                    face: face(f),
                    from: vertex(from),
                    to: vertex(to),
                },
                line(f),
            ),
            MeshError::NonFinitePosition {
                vertex: v,
                position,
            } => (
                MeshError::NonFinitePosition {
                    vertex: vertex(v as u32) as usize,
                    position,
                },
                None,
            ),
            other => (other, None),
        };
        LoadError::Mesh {
            path: path.to_path_buf(),
            line,
            source,
        }
    }
}
