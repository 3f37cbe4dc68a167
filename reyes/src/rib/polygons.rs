//! `Polygon`, `PointsPolygons` and `GeneralPolygon`: convex polygons (by
//! vertex index), each a fan of patches (see [`super::basis::polygon`]),
//! with where each patch corner finds its primitive variables
//! ([`super::texcoords`]).

use glam::DVec3;

use super::basis;
use super::parser::Value;
use super::state;
use super::texcoords::{CornerRef, Layout, VertexRef};

/// Patches of some polygons.
#[derive(Debug)]
pub(super) struct Polygons {
    /// The patches.
    pub(super) patches: Vec<[DVec3; 16]>,
    /// How many polygons are not convex.
    pub(super) nonconvex: usize,
    /// Per patch, where its corners' primitive variables are.
    pub(super) corners: Vec<[CornerRef; 4]>,
    /// How many elements each storage class has.
    pub(super) layout: Layout,
}

impl Polygons {
    fn new(uniform: usize, vertex: usize, facevarying: usize) -> Polygons {
        Polygons {
            patches: Vec::new(),
            nonconvex: 0,
            corners: Vec::new(),
            layout: Layout {
                uniform,
                varying: vertex,
                vertex,
                facevarying,
            },
        }
    }
}

/// The non-negative integers of positional value `i` of `args`.
pub(super) fn counts(args: &[Value], i: usize, what: &str) -> Result<Vec<usize>, String> {
    state::arg_nums(args, i, what)?
        .into_iter()
        .map(|n| {
            if n < 0.0 || n.fract() != 0.0 || n > f64::from(u32::MAX) {
                Err(format!("{what}: {n} is not a non-negative integer"))
            } else {
                Ok(n as usize)
            }
        })
        .collect()
}

/// The patches request `name` (`PointsPolygons`, `GeneralPolygon` or
/// `PointsGeneralPolygons`) with positional values `args` will make, from
/// its counts alone, before any point is read: one fan
/// ([`basis::fan_patches`]) per polygon of one loop. Counts the request
/// gets wrong are left to its conversion to report (they count 0 here).
pub(super) fn estimate(name: &str, args: &[Value]) -> Result<usize, String> {
    let fans = |n: &[usize]| {
        n.iter()
            .fold(0usize, |a, &n| a.saturating_add(basis::fan_patches(n)))
    };
    Ok(match name {
        "PointsPolygons" => fans(&counts(args, 0, "nverts")?),
        "GeneralPolygon" => match counts(args, 0, "nverts")?.as_slice() {
            [n] => basis::fan_patches(*n),
            _ => 0,
        },
        _ => {
            let nloops = counts(args, 0, "nloops")?;
            let nverts = counts(args, 1, "nverts")?;
            let mut at = 0usize;
            let mut total = 0usize;
            for nl in nloops {
                if nl == 1
                    && let Some(&n) = nverts.get(at)
                {
                    total = total.saturating_add(basis::fan_patches(n));
                }
                at = at.saturating_add(nl);
            }
            total
        }
    })
}

/// Converts one convex polygon, face `face`, counting it if it is not
/// convex; its vertex `k` is point `ids[k]` and face corner `first + k`.
fn convert(poly: &[DVec3], face: usize, ids: &[usize], first: usize, out: &mut Polygons) {
    if !basis::convex(poly) {
        out.nonconvex += 1;
    }
    out.patches.extend(basis::polygon(poly));
    out.corners
        .extend(basis::polygon_fan(poly.len()).into_iter().map(|fan| {
            fan.map(|k| CornerRef {
                uniform: face,
                varying: ids[k],
                vertex: VertexRef::One(ids[k]),
                facevarying: first + k,
            })
        }));
}

/// `PointsPolygons nverts vertids`: polygon `i` has `nverts[i]` (at least
/// 3) vertices, the next ids of `vertids`, each an index into `p`.
pub(super) fn points_polygons(args: &[Value], p: &[DVec3]) -> Result<Polygons, String> {
    let nverts = counts(args, 0, "nverts")?;
    let ids = counts(args, 1, "vertids")?;
    let total = nverts.iter().try_fold(0usize, |a, &n| a.checked_add(n));
    if total != Some(ids.len()) {
        return Err(format!(
            "the nverts add up to {}, but there are {} vertids",
            total.map_or("more than usize".into(), |t| t.to_string()),
            ids.len()
        ));
    }
    if let Some((i, &n)) = nverts.iter().enumerate().find(|(_, n)| **n < 3) {
        return Err(format!("polygon {i} has {n} vertices (at least 3 needed)"));
    }
    if let Some((i, &id)) = ids.iter().enumerate().find(|(_, id)| **id >= p.len()) {
        return Err(format!(
            "vertid {i} is {id}, out of range: \"P\" has {} points",
            p.len()
        ));
    }
    let mut out = Polygons::new(nverts.len(), p.len(), ids.len());
    let mut start = 0;
    for (face, &n) in nverts.iter().enumerate() {
        let poly_ids = &ids[start..start + n];
        let poly: Vec<DVec3> = poly_ids.iter().map(|&id| p[id]).collect();
        convert(&poly, face, poly_ids, start, &mut out);
        start += n;
    }
    Ok(out)
}

/// `GeneralPolygon nverts`: loop `i` has `nverts[i]` (at least 3) of the
/// points of `p`, in order, which must be all of them. `None` when there is
/// more than one loop (holes, not supported).
pub(super) fn general_polygon(args: &[Value], p: &[DVec3]) -> Result<Option<Polygons>, String> {
    let nverts = counts(args, 0, "nverts")?;
    if nverts.is_empty() {
        return Err("nverts is empty (no loops)".into());
    }
    let total = nverts.iter().try_fold(0usize, |a, &n| a.checked_add(n));
    if total != Some(p.len()) {
        return Err(format!(
            "the nverts add up to {}, but \"P\" has {} points",
            total.map_or("more than usize".into(), |t| t.to_string()),
            p.len()
        ));
    }
    if let Some((i, &n)) = nverts.iter().enumerate().find(|(_, n)| **n < 3) {
        return Err(format!("loop {i} has {n} vertices (at least 3 needed)"));
    }
    if nverts.len() > 1 {
        return Ok(None);
    }
    Ok(Some(polygon(p)))
}

/// `Polygon "P"`: one convex polygon of the points `p` (at least 3), every
/// class of primitive variable one value per point (uniform: one).
pub(super) fn polygon(p: &[DVec3]) -> Polygons {
    let mut out = Polygons::new(1, p.len(), p.len());
    let ids: Vec<usize> = (0..p.len()).collect();
    convert(p, 0, &ids, 0, &mut out);
    out
}

/// `PointsGeneralPolygons nloops nverts vertids`: polygon `i` has
/// `nloops[i]` loops, each of the next `nverts` (at least 3) ids of
/// `vertids`. The polygons with one loop are converted; those with holes
/// are counted (the second value) and skipped.
pub(super) fn points_general_polygons(
    args: &[Value],
    p: &[DVec3],
) -> Result<(Polygons, usize), String> {
    let nloops = counts(args, 0, "nloops")?;
    let nverts = counts(args, 1, "nverts")?;
    let ids = counts(args, 2, "vertids")?;
    let sum = |n: &[usize]| n.iter().try_fold(0usize, |a, &n| a.checked_add(n));
    if sum(&nloops) != Some(nverts.len()) {
        return Err(format!(
            "the nloops do not add up to the {} nverts",
            nverts.len()
        ));
    }
    if sum(&nverts) != Some(ids.len()) {
        return Err(format!(
            "the nverts do not add up to the {} vertids",
            ids.len()
        ));
    }
    if let Some(i) = nloops.iter().position(|&n| n == 0) {
        return Err(format!("polygon {i} has no loops"));
    }
    if let Some((i, &n)) = nverts.iter().enumerate().find(|(_, n)| **n < 3) {
        return Err(format!("loop {i} has {n} vertices (at least 3 needed)"));
    }
    if let Some((i, &id)) = ids.iter().enumerate().find(|(_, id)| **id >= p.len()) {
        return Err(format!(
            "vertid {i} is {id}, out of range: \"P\" has {} points",
            p.len()
        ));
    }
    let mut out = Polygons::new(nloops.len(), p.len(), ids.len());
    let mut holes = 0;
    let (mut loop_at, mut id_at) = (0, 0);
    for (face, &nl) in nloops.iter().enumerate() {
        let len: usize = nverts[loop_at..loop_at + nl].iter().sum();
        if nl > 1 {
            holes += 1;
        } else {
            let poly_ids = &ids[id_at..id_at + len];
            let poly: Vec<DVec3> = poly_ids.iter().map(|&id| p[id]).collect();
            convert(&poly, face, poly_ids, id_at, &mut out);
        }
        loop_at += nl;
        id_at += len;
    }
    Ok((out, holes))
}
