//! `SubdivisionMesh scheme nverts vertids tags nargs intargs floatargs
//! ...params`: a polygon mesh (`PointsPolygons`' `nverts` and `vertids`)
//! to subdivide, with its tags, as a [`Mesh`] ([`crate::subdiv`] makes
//! its patches).
//!
//! Tags (each takes `nargs[2i]` integers and `nargs[2i+1]` floats, in
//! order, from `intargs` and `floatargs`):
//!
//! * `crease` `[n 1]`: a chain of `n` vertices and its sharpness;
//! * `corner` `[n n]` (or `[n 1]`, one sharpness for all): `n` vertices
//!   and their sharpnesses;
//! * `hole` `[n 0]`: `n` faces without surface;
//! * `interpolateboundary` `[0 0]` or `[1 0]` with 0, 1 or 2: 1 (and no
//!   integer) makes the boundary edges sharp creases and the vertices of
//!   one face sharp corners, 2 the edges only, 0 (and no tag) neither:
//!   RenderMan's rule;
//! * any other tag: skipped, its arguments consumed, with a warning.
//!
//! `"st"` (or `"s"` and `"t"`) of any class become the face vertices'
//! texture coordinates: a `vertex` or `varying` value is taken at each
//! face corner, so it is interpolated as a face-varying one.

use std::collections::HashMap;

use std::path::Path;

use glam::{DVec2, DVec3, Vec2, Vec3};

use super::interp::{Interp, RequestError};
use super::parser::Value;
use super::polygons::counts;
use super::state::{self, Decl};
use super::texcoords::{self, CornerRef, Layout, StVars, UNIT_SQUARE, VertexRef};
use crate::subdiv::{BoundaryInterpolation, Corner, Crease, Mesh, Scheme};

/// The positional values of `SubdivisionMesh`.
pub const POSITIONAL: usize = 7;

/// A `SubdivisionMesh` request read.
#[derive(Debug, Clone, PartialEq)]
pub struct SubdivisionMesh {
    /// The mesh (not yet validated).
    pub mesh: Mesh,
    /// The tags that were skipped, in order (not supported).
    pub skipped_tags: Vec<String>,
}

/// Reads the values of a `SubdivisionMesh` request (after its name), with
/// the `Declare`d names `declared`; undeclared parameters are ignored.
pub fn parse(values: &[Value], declared: &HashMap<String, Decl>) -> Result<SubdivisionMesh, String> {
    let (args, params, _) = state::split_params(values, POSITIONAL, declared)?;
    let Some(p) = state::points(&params)? else {
        return Err("needs \"P\"".to_owned());
    };
    let vars = texcoords::st_vars(values, POSITIONAL, declared)?;
    mesh(&args, &p, &vars)
}

/// The patches the mesh of positional values `args` will make under the
/// bilinear scheme (a quad 1, an `n`-gon `n`), from `nverts` alone: the
/// estimate taken from the budget before anything is made (a lower
/// bound for Catmull-Clark, whose extra patches are taken once made).
pub fn estimate(args: &[Value]) -> Result<usize, String> {
    Ok(counts(args, 1, "nverts")?
        .iter()
        .map(|&n| if n == 4 { 1 } else { n })
        .fold(0usize, usize::saturating_add))
}

/// The mesh of `args` (the positional values), points `p` and texture
/// coordinates `vars`.
pub(super) fn mesh(args: &[Value], p: &[DVec3], vars: &StVars) -> Result<SubdivisionMesh, String> {
    let scheme = match state::arg_str(args, 0, "the scheme")? {
        "catmull-clark" => Scheme::CatmullClark,
        "bilinear" => Scheme::Bilinear,
        other => {
            return Err(format!(
                "scheme {:?} is not supported (\"catmull-clark\" or \"bilinear\")",
                crate::input::excerpt(other)
            ));
        }
    };
    let nverts = counts(args, 1, "nverts")?;
    let vertids = counts(args, 2, "vertids")?;
    let total = nverts.iter().try_fold(0usize, |a, &n| a.checked_add(n));
    if total != Some(vertids.len()) {
        return Err(format!(
            "the nverts add up to {}, but there are {} vertids",
            total.map_or("more than usize".into(), |t| t.to_string()),
            vertids.len()
        ));
    }
    let positions = p
        .iter()
        .enumerate()
        .map(|(i, q)| {
            let f = q.as_vec3();
            if f.is_finite() {
                Ok(f)
            } else {
                Err(format!("\"P\" point {i} ({q}) is not finite in f32"))
            }
        })
        .collect::<Result<Vec<Vec3>, String>>()?;
    let mut mesh = Mesh {
        scheme,
        positions,
        face_sizes: nverts.iter().map(|&n| n as u32).collect(),
        face_vertices: vertids.iter().map(|&v| v as u32).collect(),
        ..Mesh::default()
    };
    let skipped_tags = tags(args, &mut mesh)?;
    mesh.st = st(vars, &nverts, &vertids, p.len())?;
    Ok(SubdivisionMesh { mesh, skipped_tags })
}

/// Reads the tags into `mesh`; gives the names of those skipped.
fn tags(args: &[Value], mesh: &mut Mesh) -> Result<Vec<String>, String> {
    let names: Vec<String> = match args.get(3) {
        Some(Value::Strs(s)) => s.clone(),
        Some(Value::Str(s)) => vec![s.clone()],
        Some(Value::Nums(n)) if n.is_empty() => Vec::new(),
        _ => return Err("the tags must be strings".into()),
    };
    let nargs = counts(args, 4, "nargs")?;
    let ints = state::arg_nums(args, 5, "intargs")?;
    let floats = state::arg_nums(args, 6, "floatargs")?;
    if nargs.len() != 2 * names.len() {
        return Err(format!(
            "{} tags need {} nargs (an integer and a float count per tag), found {}",
            names.len(),
            2 * names.len(),
            nargs.len()
        ));
    }
    let sum = |step: usize| {
        nargs
            .iter()
            .skip(step)
            .step_by(2)
            .try_fold(0usize, |a, &n| a.checked_add(n))
    };
    if sum(0) != Some(ints.len()) || sum(1) != Some(floats.len()) {
        return Err(format!(
            "the nargs ask for {} intargs and {} floatargs, but {} and {} are given",
            sum(0).map_or("more than usize".into(), |t| t.to_string()),
            sum(1).map_or("more than usize".into(), |t| t.to_string()),
            ints.len(),
            floats.len()
        ));
    }
    let (mut at_int, mut at_float) = (0, 0);
    let mut skipped = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let (ni, nf) = (nargs[2 * i], nargs[2 * i + 1]);
        let int_args = &ints[at_int..at_int + ni];
        let float_args = &floats[at_float..at_float + nf];
        at_int += ni;
        at_float += nf;
        let shown = crate::input::excerpt(name);
        let wrong = |expected: &str| {
            format!("tag {i} ({shown:?}) takes {expected} arguments, found [{ni} {nf}]")
        };
        let ids = || -> Result<Vec<u32>, String> {
            int_args
                .iter()
                .map(|&x| {
                    if x >= 0.0 && x.fract() == 0.0 && x <= f64::from(u32::MAX) {
                        Ok(x as u32)
                    } else {
                        Err(format!(
                            "tag {i} ({shown:?}): {x} is not a vertex or face index"
                        ))
                    }
                })
                .collect()
        };
        match name.as_str() {
            "crease" => {
                if nf != 1 {
                    return Err(wrong("[n 1]"));
                }
                mesh.creases.push(Crease {
                    vertices: ids()?,
                    sharpness: float_args[0] as f32,
                });
            }
            "corner" => {
                if !(nf == ni || nf == 1) {
                    return Err(wrong("[n n] or [n 1]"));
                }
                for (k, vertex) in ids()?.into_iter().enumerate() {
                    let sharpness = float_args[if nf == 1 { 0 } else { k }] as f32;
                    mesh.corners.push(Corner { vertex, sharpness });
                }
            }
            "hole" => {
                if nf != 0 {
                    return Err(wrong("[n 0]"));
                }
                mesh.holes.extend(ids()?);
            }
            "interpolateboundary" => {
                mesh.boundary = match (int_args, nf) {
                    ([], 0) | ([1.0], 0) => BoundaryInterpolation::EdgeAndCorner,
                    ([0.0], 0) => BoundaryInterpolation::None,
                    ([2.0], 0) => BoundaryInterpolation::EdgeOnly,
                    ([x], 0) => {
                        return Err(format!(
                            "tag {i} (\"interpolateboundary\"): {x} is not 0, 1 or 2"
                        ));
                    }
                    _ => return Err(wrong("[0 0] or [1 0]")),
                };
            }
            _ => skipped.push(shown),
        }
    }
    Ok(skipped)
}

/// The face vertices' `st` from `vars`, for faces `nverts` of `vertids`
/// over `points` points.
fn st(
    vars: &StVars,
    nverts: &[usize],
    vertids: &[usize],
    points: usize,
) -> Result<Option<Vec<Vec2>>, String> {
    if vars.is_empty() {
        return Ok(None);
    }
    let layout = Layout {
        uniform: nverts.len(),
        varying: points,
        vertex: points,
        facevarying: vertids.len(),
    };
    // Ids past the points would index past vertex values: the mesh's
    // validation names the face; no texture coordinates are read then.
    if vertids.iter().any(|&id| id >= points) {
        return Ok(None);
    }
    let mut corners = Vec::with_capacity(vertids.len());
    for (face, &n) in nverts.iter().enumerate() {
        let start = corners.len();
        for (k, &id) in vertids[start..start + n].iter().enumerate() {
            corners.push(CornerRef {
                uniform: face,
                varying: id,
                vertex: VertexRef::One(id),
                facevarying: start + k,
            });
        }
    }
    let Some(st) = texcoords::at_corners(vars, &layout, &corners)? else {
        return Ok(None);
    };
    st.iter()
        .map(|c| {
            let f = c.as_vec2();
            if f.is_finite() {
                Ok(f)
            } else {
                Err(format!("texture coordinates {c} are not finite in f32"))
            }
        })
        .collect::<Result<Vec<Vec2>, String>>()
        .map(Some)
}

impl Interp {
    /// The patches and corner `st` of a `SubdivisionMesh` with positional
    /// values `args`, points `p` and texture coordinates `vars`, taken
    /// from the budget; `None` (with a warning) for a valid mesh whose
    /// scheme the subdivision code refuses as unsupported.
    #[expect(
        clippy::type_complexity,
        reason = "the same pair every geometry arm makes"
    )]
    pub(super) fn subdivision_mesh(
        &mut self,
        args: &[Value],
        p: &[DVec3],
        vars: &StVars,
        file: &Path,
        line: usize,
    ) -> Result<Option<(Vec<[DVec3; 16]>, Vec<[DVec2; 4]>)>, RequestError> {
        let estimate = estimate(args)?;
        self.take_patches(estimate, || "its faces' patches".to_owned())?;
        let read = mesh(args, p, vars)?;
        for tag in &read.skipped_tags {
            self.warn(
                file,
                line,
                format!("SubdivisionMesh: tag {tag:?} is not supported; skipped"),
            );
        }
        // At most what the budget has left, so that a mesh past it is
        // refused before its patches are made.
        let allowed = estimate.saturating_add(self.patches.remaining() as usize);
        let subdivided = match read.mesh.to_patches_within(allowed) {
            Ok(subdivided) => subdivided,
            Err(crate::subdiv::MeshError::TooManyPatches { limit }) if limit == allowed => {
                let past = self.patches.refusal((allowed + 1 - estimate) as u64);
                return Err(RequestError::Budget(
                    format!("over {allowed} patches once subdivided"),
                    past,
                ));
            }
            Err(crate::subdiv::MeshError::Unsupported { what }) => {
                self.patches.give_back(estimate as u64);
                self.warn(
                    file,
                    line,
                    format!("SubdivisionMesh: {what} is not supported yet; skipped"),
                );
                return Ok(None);
            }
            Err(e) => return Err(e.to_string().into()),
        };
        let model = subdivided.model;
        let made = model.patches.len();
        if made > estimate {
            self.take_patches(made - estimate, || {
                format!(
                    "its {made} patches ({} more than its faces' count)",
                    made - estimate
                )
            })?;
        } else {
            self.patches.give_back((estimate - made) as u64);
        }
        let patches = model
            .patches
            .iter()
            .map(|patch| patch.points.map(|q| q.as_dvec3()))
            .collect();
        // Without texture coordinates each patch takes the unit square,
        // as a polygon's patches do.
        let st = match model.st {
            Some(st) => st.iter().map(|c| c.map(|x| x.as_dvec2())).collect(),
            None => vec![UNIT_SQUARE; made],
        };
        Ok(Some((patches, st)))
    }
}
