//! Texture coordinates `s`, `t`: the `TextureCoordinates` attribute and the
//! `"st"`, `"s"` and `"t"` primitive variables, resolved to the `st` of the
//! four corners `(u, v) = (0,0), (1,0), (0,1), (1,1)` of every Bezier patch
//! a primitive makes (see `docs/rib.md`).
//!
//! A primitive's patches each cover a rectangle of its `(u, v)` square (a
//! patch mesh's and a quadric's `u, v` span the whole primitive). Without
//! `st` variables a corner's `st` is the bilinear blend of the
//! `TextureCoordinates` corners at the corner's `(u, v)`; with them it is
//! the variable's value there, by its storage class: `constant` (one
//! value), `uniform` (one per patch or face), `varying` (one per patch
//! corner of the primitive, bilinear in between), `vertex` (one per
//! control point, through the primitive's basis) or `facevarying` (one per
//! face corner; for patches, as `varying`).

use std::collections::HashMap;

use glam::{DVec2, Vec2};

use super::basis::{self, Basis, MeshDir, Wrap};
use super::interp::Interp;
use super::parser::Value;
use super::state::{self, Decl};

/// The corners of the unit square in patch corner order, RenderMan's
/// default `TextureCoordinates 0 0 1 0 0 1 1 1`.
pub(super) const UNIT_SQUARE: [DVec2; 4] = [
    DVec2::new(0.0, 0.0),
    DVec2::new(1.0, 0.0),
    DVec2::new(0.0, 1.0),
    DVec2::new(1.0, 1.0),
];

/// A primitive variable's storage class.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Class {
    /// One value for the primitive.
    Constant,
    /// One per patch (or face).
    Uniform,
    /// One per patch corner (or polygon vertex).
    Varying,
    /// One per control point.
    Vertex,
    /// One per face corner.
    FaceVarying,
}

impl Class {
    fn parse(word: &str) -> Class {
        match word {
            "constant" => Class::Constant,
            "uniform" => Class::Uniform,
            "vertex" => Class::Vertex,
            "facevarying" => Class::FaceVarying,
            // `parse_decl` accepts nothing else: "varying".
            _ => Class::Varying,
        }
    }
}

/// One texture coordinate given as a primitive variable: its class and its
/// values (one float per element).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Channel {
    /// The storage class.
    pub(super) class: Class,
    /// The values.
    pub(super) values: Vec<f64>,
}

/// The `s` and `t` primitive variables of a request (`"st"` gives both).
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct StVars {
    /// `s`, if given.
    pub(super) s: Option<Channel>,
    /// `t`, if given.
    pub(super) t: Option<Channel>,
}

impl StVars {
    /// Whether neither is given.
    pub(super) fn is_empty(&self) -> bool {
        self.s.is_none() && self.t.is_none()
    }
}

/// Where a corner of a generated patch takes a vertex-class value from:
/// one control point, or the primitive's bicubic basis at the corner.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum VertexRef {
    /// Control point `i`.
    One(usize),
    /// `sum weights[k] * value[points[k]]` (boxed: polygons, which make
    /// the most corners, need only `One`).
    Spline(Box<([usize; 16], [f64; 16])>),
}

/// Where each storage class finds a corner's value.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CornerRef {
    /// The patch's (face's) element.
    pub(super) uniform: usize,
    /// The varying element at the corner.
    pub(super) varying: usize,
    /// The vertex element(s).
    pub(super) vertex: VertexRef,
    /// The face-varying element at the corner.
    pub(super) facevarying: usize,
}

impl CornerRef {
    /// The corner at element `i` for varying, vertex and face-varying
    /// alike, of patch (face) `uniform`.
    pub(super) fn at(uniform: usize, i: usize) -> CornerRef {
        CornerRef {
            uniform,
            varying: i,
            vertex: VertexRef::One(i),
            facevarying: i,
        }
    }
}

/// How many elements each storage class has on a primitive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Layout {
    /// Patches or faces.
    pub(super) uniform: usize,
    /// Patch corners (polygon vertices).
    pub(super) varying: usize,
    /// Control points.
    pub(super) vertex: usize,
    /// Face corners.
    pub(super) facevarying: usize,
}

impl Layout {
    /// A single patch (or quadric) with `vertex` control points.
    pub(super) fn patch(vertex: usize) -> Layout {
        Layout {
            uniform: 1,
            varying: 4,
            vertex,
            facevarying: 4,
        }
    }

    fn count(&self, class: Class) -> usize {
        match class {
            Class::Constant => 1,
            Class::Uniform => self.uniform,
            Class::Varying => self.varying,
            Class::Vertex => self.vertex,
            Class::FaceVarying => self.facevarying,
        }
    }
}

fn class_name(class: Class) -> &'static str {
    match class {
        Class::Constant => "constant",
        Class::Uniform => "uniform",
        Class::Varying => "varying",
        Class::Vertex => "vertex",
        Class::FaceVarying => "facevarying",
    }
}

/// The `"st"`, `"s"` and `"t"` variables among the parameters of `values`
/// (after `positional` leading values), with their classes: an inline
/// declaration's, else a `Declare`'s, else RenderMan's standard `varying`.
/// `"st"` takes precedence over `"s"` and `"t"`.
pub(super) fn st_vars(
    values: &[Value],
    positional: usize,
    declared: &HashMap<String, Decl>,
) -> Result<StVars, String> {
    let mut st = None;
    let mut vars = StVars::default();
    for pair in values.get(positional..).unwrap_or_default().chunks(2) {
        let [name, value] = pair else { continue };
        let Some(token) = name.str() else { continue };
        let mut words = token.rsplitn(2, char::is_whitespace);
        let bare = words.next().unwrap_or("");
        if !matches!(bare, "st" | "s" | "t") {
            continue;
        }
        let decl = match words.next().map(str::trim).filter(|d| !d.is_empty()) {
            Some(inline) => Some(state::parse_decl(inline)?),
            None => declared.get(bare).cloned(),
        };
        let class = decl
            .as_ref()
            .map_or(Class::Varying, |d| Class::parse(&d.class));
        if let Some(d) = &decl {
            let len = if bare == "st" { 2 } else { 1 };
            if d.ty != "float" || d.len != len {
                return Err(format!(
                    "{bare:?} is declared {} {}[{}]: texture coordinates are float{}",
                    d.class,
                    d.ty,
                    d.len,
                    if len == 2 { "[2]" } else { "" }
                ));
            }
        }
        let values = value
            .nums()
            .ok_or_else(|| format!("{bare:?} must be numbers"))?;
        match bare {
            "st" => st = Some((class, values)),
            "s" => vars.s = Some(Channel { class, values }),
            _ => vars.t = Some(Channel { class, values }),
        }
    }
    if let Some((class, values)) = st {
        if values.len() % 2 != 0 {
            return Err(format!(
                "\"st\" has {} numbers, not pairs (s t)",
                values.len()
            ));
        }
        let (s, t) = values.chunks(2).map(|p| (p[0], p[1])).unzip();
        vars.s = Some(Channel { class, values: s });
        vars.t = Some(Channel { class, values: t });
    }
    Ok(vars)
}

impl Channel {
    /// Checks the value count against `layout`.
    fn check(&self, name: &str, layout: &Layout) -> Result<(), String> {
        let want = layout.count(self.class);
        if self.values.len() != want {
            return Err(format!(
                "\"{name}\" ({}) has {} values; this primitive needs {want}",
                class_name(self.class),
                self.values.len()
            ));
        }
        Ok(())
    }

    /// The value at `corner`.
    fn at(&self, corner: &CornerRef) -> f64 {
        match self.class {
            Class::Constant => self.values[0],
            Class::Uniform => self.values[corner.uniform],
            Class::Varying => self.values[corner.varying],
            Class::FaceVarying => self.values[corner.facevarying],
            Class::Vertex => match &corner.vertex {
                VertexRef::One(i) => self.values[*i],
                VertexRef::Spline(spline) => spline
                    .0
                    .iter()
                    .zip(&spline.1)
                    .map(|(&i, w)| w * self.values[i])
                    .sum(),
            },
        }
    }
}

/// The corner `st` of every patch: `vars` at `corners` where given, else
/// `defaults`. Every reference in `corners` must be below `layout`'s
/// counts, which the variables are checked against first.
pub(super) fn resolve(
    vars: &StVars,
    layout: &Layout,
    corners: &[[CornerRef; 4]],
    defaults: &[[DVec2; 4]],
) -> Result<Vec<[DVec2; 4]>, String> {
    if let Some(s) = &vars.s {
        s.check("s", layout)?;
    }
    if let Some(t) = &vars.t {
        t.check("t", layout)?;
    }
    Ok(corners
        .iter()
        .zip(defaults)
        .map(|(refs, default)| {
            std::array::from_fn(|c| {
                DVec2::new(
                    vars.s.as_ref().map_or(default[c].x, |s| s.at(&refs[c])),
                    vars.t.as_ref().map_or(default[c].y, |t| t.at(&refs[c])),
                )
            })
        })
        .collect())
}

/// The `(s, t)` of `vars` at each of `corners` (a mesh's face vertices),
/// checked against `layout`; `None` without variables. A mesh's face
/// vertices have no default of their own, so one of `s`, `t` alone is
/// refused rather than half used.
pub(super) fn at_corners(
    vars: &StVars,
    layout: &Layout,
    corners: &[CornerRef],
) -> Result<Option<Vec<DVec2>>, String> {
    match (&vars.s, &vars.t) {
        (None, None) => Ok(None),
        (Some(s), Some(t)) => {
            s.check("s", layout)?;
            t.check("t", layout)?;
            Ok(Some(
                corners
                    .iter()
                    .map(|c| DVec2::new(s.at(c), t.at(c)))
                    .collect(),
            ))
        }
        _ => Err("texture coordinates need both \"s\" and \"t\" (or \"st\") here".into()),
    }
}

/// The bilinear blend of `corners` (patch corner order) at `(u, v)`.
pub(super) fn bilerp(corners: &[DVec2; 4], u: f64, v: f64) -> DVec2 {
    corners[0] * ((1.0 - u) * (1.0 - v))
        + corners[1] * (u * (1.0 - v))
        + corners[2] * ((1.0 - u) * v)
        + corners[3] * (u * v)
}

/// The corner `st` of the `nu` x `nv` patches (row by row, `u` fastest)
/// that tile a primitive whose corners have the `st` of `corners`.
pub(super) fn grid(corners: &[DVec2; 4], nu: usize, nv: usize) -> Vec<[DVec2; 4]> {
    let mut out = Vec::with_capacity(nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            out.push(std::array::from_fn(|c| {
                let u = (i + c % 2) as f64 / nu as f64;
                let v = (j + c / 2) as f64 / nv as f64;
                bilerp(corners, u, v)
            }));
        }
    }
    out
}

/// The weights of a bicubic patch's 16 control points (`g[j * 4 + i]`) at
/// corner `c` (patch corner order) in bases `ub`, `vb`, for vertex-class
/// variables, with the control points' indices from `index(i, j)`.
pub(super) fn spline_corner(
    ub: &Basis,
    vb: &Basis,
    c: usize,
    index: impl Fn(usize, usize) -> usize,
) -> VertexRef {
    let wu = ub.weights((c % 2) as f64);
    let wv = vb.weights((c / 2) as f64);
    let points = std::array::from_fn(|k| index(k % 4, k / 4));
    let weights = std::array::from_fn(|k| wu[k % 4] * wv[k / 4]);
    VertexRef::Spline(Box::new((points, weights)))
}

/// The corner `st` of the patches of a `PatchMesh` (as
/// [`basis::patch_mesh`] makes them, `bicubic` or bilinear, in directions
/// `u` and `v`, whose counts it has checked): the mesh's `(u, v)` spans
/// the whole mesh, so without variables `coords` (`TextureCoordinates`)
/// are the mesh's corners.
pub(super) fn mesh(
    vars: &StVars,
    coords: [DVec2; 4],
    bicubic: bool,
    u: MeshDir,
    v: MeshDir,
) -> Result<Vec<[DVec2; 4]>, String> {
    let (order, ustep, vstep) = if bicubic {
        (4, u.basis.step, v.basis.step)
    } else {
        (2, 1, 1)
    };
    let nup = basis::patch_count(u.n, u.wrap, ustep, order)?;
    let nvp = basis::patch_count(v.n, v.wrap, vstep, order)?;
    let defaults = grid(&coords, nup, nvp);
    if vars.is_empty() {
        return Ok(defaults);
    }
    // Varying values sit at the patch corners; a periodic direction's last
    // corner is its first.
    let corners_along = |n: usize, wrap: Wrap| if wrap == Wrap::Periodic { n } else { n + 1 };
    let (nuv, nvv) = (corners_along(nup, u.wrap), corners_along(nvp, v.wrap));
    let layout = Layout {
        uniform: nup * nvp,
        varying: nuv * nvv,
        vertex: u.n * v.n,
        facevarying: nuv * nvv,
    };
    let point = |i: usize, j: usize| (j % v.n) * u.n + (i % u.n);
    let mut corners = Vec::with_capacity(nup * nvp);
    for pv in 0..nvp {
        for pu in 0..nup {
            corners.push(std::array::from_fn(|c| {
                let (i, j) = (c % 2, c / 2);
                let varying = ((pv + j) % nvv) * nuv + (pu + i) % nuv;
                let vertex = if bicubic {
                    let (i0, j0) = (pu * ustep, pv * vstep);
                    spline_corner(&u.basis, &v.basis, c, |a, b| point(i0 + a, j0 + b))
                } else {
                    VertexRef::One(point(pu + i, pv + j))
                };
                CornerRef {
                    uniform: pv * nup + pu,
                    varying,
                    vertex,
                    facevarying: varying,
                }
            }));
        }
    }
    resolve(vars, &layout, &corners, &defaults)
}

/// The corner `st` of a quadric's `patches` patches, `nu` around (`u`
/// fastest) and the rest along the profile (`v`), each the sub-rectangle
/// of the quadric's `(u, v)` square it covers, mapped through the
/// quadric's corner `st`: its `st` variables (four corners, or one
/// value) or else `coords` (`TextureCoordinates`).
pub(super) fn quadric(
    vars: &StVars,
    coords: [DVec2; 4],
    nu: usize,
    patches: usize,
) -> Result<Vec<[DVec2; 4]>, String> {
    let refs = std::array::from_fn(|c| CornerRef::at(0, c));
    let corners = resolve(vars, &Layout::patch(4), &[refs], &[coords])?[0];
    Ok(grid(&corners, nu, patches / nu.max(1)))
}

/// `st` in f32, or why it does not fit.
pub(super) fn to_f32(st: Vec<[DVec2; 4]>) -> Result<Vec<[Vec2; 4]>, String> {
    st.into_iter()
        .map(|corners| {
            let out = corners.map(|c| c.as_vec2());
            if out.iter().all(|c| c.is_finite()) {
                Ok(out)
            } else {
                Err(format!("texture coordinates {corners:?} are beyond f32"))
            }
        })
        .collect()
}

impl Interp {
    /// `TextureCoordinates s1 t1 s2 t2 s3 t3 s4 t4`: the `st` of the corners
    /// `(u, v) = (0,0), (1,0), (0,1), (1,1)` of the parametric primitives
    /// that follow (an attribute).
    pub(super) fn texture_coordinates(&mut self, v: &[Value]) -> Result<(), String> {
        let n = state::all_nums(v, 8)?;
        if let Some(x) = n.iter().find(|x| !x.is_finite()) {
            return Err(format!("{x} is not finite"));
        }
        self.attrs.texture_coords = std::array::from_fn(|c| DVec2::new(n[2 * c], n[2 * c + 1]));
        Ok(())
    }
}
