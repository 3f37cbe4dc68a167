//! The interpreter's transform, motion, basis and geometry requests (the
//! quadrics in [`super::quadrics`]).

use std::path::Path;

use glam::{DMat4, DVec2, DVec3};

use super::basis::{self, MeshDir, Wrap};
use super::interp::{Interp, Motion, Prim, RequestError, camera_to_world};
use super::parser::Value;
use super::state;
use super::texcoords::{self, CornerRef, Layout, UNIT_SQUARE};

/// The geometric primitives, supported or not (`ObjectInstance` is
/// `super::instances`').
const GEOMETRY: [&str; 21] = [
    "Patch",
    "PatchMesh",
    "Polygon",
    "Sphere",
    "Cone",
    "Cylinder",
    "Hyperboloid",
    "Paraboloid",
    "Disk",
    "Torus",
    "NuPatch",
    "SubdivisionMesh",
    "Curves",
    "Points",
    "PointsPolygons",
    "PointsGeneralPolygons",
    "GeneralPolygon",
    "Blobby",
    "Procedural",
    "Geometry",
    "TrimCurve",
];

/// The requests that change the current transform.
const TRANSFORMS: [&str; 8] = [
    "Identity",
    "Transform",
    "ConcatTransform",
    "Translate",
    "Rotate",
    "Scale",
    "Skew",
    "CoordSysTransform",
];

/// Whether `name` is a geometry request ([`Interp::geometry_request`]).
pub(super) fn is_geometry(name: &str) -> bool {
    GEOMETRY.contains(&name)
}

/// The primitive variables the geometry reads: positions (`Pw` is refused
/// with its own warning) and texture coordinates.
const READ_VARIABLES: [&str; 5] = ["P", "Pw", "st", "s", "t"];

impl Interp {
    /// Runs geometry request `name`: patches and polygons, the quadrics,
    /// and a warning for the rest.
    pub(super) fn geometry_request(
        &mut self,
        name: &str,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), RequestError> {
        let supported = matches!(
            name,
            "Patch"
                | "PatchMesh"
                | "Polygon"
                | "PointsPolygons"
                | "GeneralPolygon"
                | "PointsGeneralPolygons"
                | "SubdivisionMesh"
        ) || super::quadrics::arity(name).is_some();
        if !supported {
            self.warn(file, line, format!("{name} is not supported yet; skipped"));
            return Ok(());
        }
        // A definition's geometry stays in its own space, so it may come
        // before WorldBegin; its instances may not.
        if self.camera.is_none() && !self.defining_object() {
            return Err("geometry before WorldBegin".to_owned().into());
        }
        if super::quadrics::arity(name).is_some() {
            self.quadric(name, v, file, line)
        } else {
            self.geometry(name, v, file, line)
        }
    }

    /// `MotionBegin [t0 t1]` and `MotionEnd`: the transforms between them
    /// are the samples at shutter open and close.
    pub(super) fn motion_request(
        &mut self,
        name: &str,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        match name {
            "MotionBegin" => {
                if self.motion.is_some() {
                    return Err("nested MotionBegin".into());
                }
                let times =
                    state::all_nums(v, v.iter().map(|x| x.nums().map_or(1, |n| n.len())).sum())?;
                if times.len() != 2 {
                    self.warn(file, line, format!("MotionBegin with {} times: only two (open and close) are supported; the first two samples are used", times.len()));
                }
                if times.len() >= 2 {
                    let t = (times[0], times[1]);
                    match self.opts.motion_times {
                        None => self.opts.motion_times = Some(t),
                        Some(old) if old != t => self.warn(file, line, "MotionBegin times differ from the first block's; the first block's are used".into()),
                        _ => {}
                    }
                }
                self.motion = Some(Motion {
                    base: self.xf,
                    index: 0,
                    line,
                });
            }
            "MotionEnd" => {
                let Some(m) = self.motion.take() else {
                    return Err("without MotionBegin".into());
                };
                if m.index == 1 {
                    // One sample only: the same at open and close.
                    self.xf.close = self.xf.open;
                    self.warn(file, m.line, "MotionBegin block with one sample".into());
                }
            }
            _ => unreachable!("only motion requests"),
        }
        Ok(())
    }

    pub(super) fn basis(&mut self, v: &[Value]) -> Result<(), String> {
        let mut next = 0;
        let one = |next: &mut usize| -> Result<basis::Basis, String> {
            let m = match v.get(*next) {
                Some(Value::Str(s)) => {
                    basis::named(s).ok_or_else(|| format!("unknown basis {s:?}"))?
                }
                Some(Value::Nums(n)) if n.len() == 16 => {
                    let mut m = [[0.0; 4]; 4];
                    for (i, x) in n.iter().enumerate() {
                        m[i / 4][i % 4] = *x;
                    }
                    basis::Basis { m, step: 1 }
                }
                _ => return Err("expected a basis name or 16 numbers".into()),
            };
            let step = state::arg_f(v, *next + 1, "the step")?;
            if !(1.0..=4.0).contains(&step) || step.fract() != 0.0 {
                return Err(format!("step {step} is not 1, 2, 3 or 4"));
            }
            *next += 2;
            Ok(basis::Basis {
                step: step as usize,
                ..m
            })
        };
        let u = one(&mut next)?;
        let vb = one(&mut next)?;
        self.attrs.ubasis = u;
        self.attrs.vbasis = vb;
        Ok(())
    }

    pub(super) fn transform(&mut self, name: &str, v: &[Value]) -> Result<(), String> {
        let m = match name {
            "Identity" => None,
            "Transform" | "ConcatTransform" => {
                let n = state::all_nums(v, 16)?;
                let a: [f64; 16] = n.try_into().expect("16 numbers");
                Some(DMat4::from_cols_array(&a))
            }
            "Translate" => {
                let n = state::all_nums(v, 3)?;
                Some(DMat4::from_translation(DVec3::new(n[0], n[1], n[2])))
            }
            "Rotate" => {
                let n = state::all_nums(v, 4)?;
                let axis = DVec3::new(n[1], n[2], n[3]);
                if axis.length_squared() == 0.0 || !axis.is_finite() {
                    return Err("the axis must be non-zero".into());
                }
                Some(DMat4::from_axis_angle(axis.normalize(), n[0].to_radians()))
            }
            "Scale" => {
                let n = state::all_nums(v, 3)?;
                Some(DMat4::from_scale(DVec3::new(n[0], n[1], n[2])))
            }
            "Skew" => {
                let n = state::all_nums(v, 7)?;
                Some(super::spaces::skew(
                    n[0],
                    DVec3::new(n[1], n[2], n[3]),
                    DVec3::new(n[4], n[5], n[6]),
                )?)
            }
            _ => unreachable!("only transform requests"),
        };
        if m.is_some_and(|m| !m.is_finite()) {
            return Err("the matrix is not finite".into());
        }
        let absolute = matches!(name, "Identity" | "Transform");
        let apply = |base: DMat4| match (absolute, m) {
            (true, m) => m.unwrap_or(DMat4::IDENTITY),
            (false, m) => base * m.unwrap_or(DMat4::IDENTITY),
        };
        match &mut self.motion {
            Some(motion) => {
                match motion.index {
                    0 => self.xf.open = apply(motion.base.open),
                    1 => self.xf.close = apply(motion.base.close),
                    _ => {}
                }
                motion.index += 1;
            }
            None => {
                self.xf.open = apply(self.xf.open);
                self.xf.close = apply(self.xf.close);
            }
        }
        Ok(())
    }

    /// Takes `patches` from the scene's budget before they are made;
    /// `what` says what they are, for the error.
    pub(super) fn take_patches(
        &mut self,
        patches: usize,
        what: impl FnOnce() -> String,
    ) -> Result<(), RequestError> {
        self.patches
            .take(patches as u64)
            .map_err(|e| RequestError::Budget(what(), e))
    }

    /// Warns, once per name, about the primitive variables given to
    /// request `name` that no part of the renderer reads: per-vertex
    /// colours (`Cs`), opacities (`Os`), normals (`N`, which come from the
    /// surface) and user variables. Positions and texture coordinates are
    /// read.
    pub(super) fn warn_unread_variables(
        &mut self,
        name: &str,
        params: &[state::Param],
        file: &Path,
        line: usize,
    ) {
        for param in params {
            if READ_VARIABLES.contains(&param.name.as_str()) {
                continue;
            }
            let shown = crate::input::excerpt(&param.name);
            self.warn_once(
                &format!("#variable {}", param.name),
                file,
                line,
                format!("{name}: primitive variable {shown:?} is not supported (only P, s and t are read per vertex); ignored"),
            );
        }
    }

    pub(super) fn geometry(
        &mut self,
        name: &str,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), RequestError> {
        let positional = match name {
            "Patch" => 1,
            "PatchMesh" => 5,
            "PointsPolygons" => 2,
            "GeneralPolygon" => 1,
            "PointsGeneralPolygons" => 3,
            "SubdivisionMesh" => super::subdivision::POSITIONAL,
            _ => 0,
        };
        let (args, params, unknown) = state::split_params(v, positional, &self.declared)?;
        for u in unknown {
            self.warn_once(
                &format!("#param {u}"),
                file,
                line,
                format!("{name}: undeclared parameter {u:?} ignored"),
            );
        }
        self.warn_unread_variables(name, &params, file, line);
        if params.iter().any(|p| p.name == "Pw") {
            self.warn(
                file,
                line,
                format!(
                    "{name} with \"Pw\" (rational/homogeneous points) is not supported yet; skipped"
                ),
            );
            return Ok(());
        }
        let Some(p) = state::points(&params)? else {
            return Err("needs \"P\"".to_owned().into());
        };
        let vars = texcoords::st_vars(v, positional, &self.declared)?;
        let coords = self.attrs.texture_coords;
        let (patches, st) = match name {
            "Patch" => match state::arg_str(&args, 0, "the type")? {
                "bicubic" => {
                    self.take_patches(1, String::new)?;
                    let g: [DVec3; 16] = p.try_into().map_err(|p: Vec<DVec3>| {
                        format!("bicubic needs 16 points, found {}", p.len())
                    })?;
                    let (ub, vb) = (&self.attrs.ubasis, &self.attrs.vbasis);
                    let corners = std::array::from_fn(|c| CornerRef {
                        vertex: texcoords::spline_corner(ub, vb, c, |i, j| j * 4 + i),
                        ..CornerRef::at(0, c)
                    });
                    (
                        vec![basis::bicubic_to_bezier(&g, ub, vb)],
                        texcoords::resolve(&vars, &Layout::patch(16), &[corners], &[coords])?,
                    )
                }
                "bilinear" => {
                    self.take_patches(1, String::new)?;
                    let c: [DVec3; 4] = p.try_into().map_err(|p: Vec<DVec3>| {
                        format!("bilinear needs 4 points, found {}", p.len())
                    })?;
                    let corners = std::array::from_fn(|c| CornerRef::at(0, c));
                    (
                        vec![basis::bilinear_to_bezier(&c)],
                        texcoords::resolve(&vars, &Layout::patch(4), &[corners], &[coords])?,
                    )
                }
                other => return Err(format!("unknown patch type {other:?}").into()),
            },
            "PatchMesh" => {
                let bicubic = match state::arg_str(&args, 0, "the type")? {
                    "bicubic" => true,
                    "bilinear" => false,
                    other => return Err(format!("unknown patch type {other:?}").into()),
                };
                let count = |i: usize, what: &str| -> Result<usize, String> {
                    let n = state::arg_f(&args, i, what)?;
                    if n < 1.0 || n.fract() != 0.0 || n > p.len() as f64 {
                        return Err(format!("{what} {n} is not a count of the points given"));
                    }
                    Ok(n as usize)
                };
                let wrap = |i: usize| -> Result<Wrap, String> {
                    match state::arg_str(&args, i, "the wrap mode")? {
                        "periodic" => Ok(Wrap::Periodic),
                        "nonperiodic" => Ok(Wrap::Nonperiodic),
                        other => Err(format!("unknown wrap mode {other:?}")),
                    }
                };
                let u = MeshDir {
                    n: count(1, "nu")?,
                    wrap: wrap(2)?,
                    basis: self.attrs.ubasis,
                };
                let vd = MeshDir {
                    n: count(3, "nv")?,
                    wrap: wrap(4)?,
                    basis: self.attrs.vbasis,
                };
                let (nup, nvp) = basis::patch_mesh_counts(bicubic, u, vd, p.len())?;
                self.take_patches(nup.saturating_mul(nvp), || format!("{nup} x {nvp} patches"))?;
                let patches = basis::patch_mesh(bicubic, u, vd, &p)?;
                let st = texcoords::mesh(&vars, coords, bicubic, u, vd)?;
                (patches, st)
            }
            "SubdivisionMesh" => {
                let Some(made) = self.subdivision_mesh(&args, &p, &vars, file, line)? else {
                    return Ok(());
                };
                made
            }
            "PointsPolygons" | "GeneralPolygon" | "PointsGeneralPolygons" => {
                let estimate = super::polygons::estimate(name, &args)?;
                self.take_patches(estimate, || "their fans".to_owned())?;
                let made = if name == "PointsPolygons" {
                    super::polygons::points_polygons(&args, &p)?
                } else if name == "PointsGeneralPolygons" {
                    let (made, holes) = super::polygons::points_general_polygons(&args, &p)?;
                    if holes > 0 {
                        self.warn(
                            file,
                            line,
                            format!("{name}: {holes} polygon(s) with more than one loop: holes are not supported; those polygons are skipped"),
                        );
                    }
                    made
                } else {
                    let Some(made) = super::polygons::general_polygon(&args, &p)? else {
                        self.warn(
                            file,
                            line,
                            format!(
                                "{name} with more than one loop: holes are not supported; skipped"
                            ),
                        );
                        return Ok(());
                    };
                    made
                };
                if made.nonconvex > 0 {
                    self.warn(
                        file,
                        line,
                        format!("{name}: {} polygon(s) not convex (or not planar): their fans of patches cover a different area", made.nonconvex),
                    );
                }
                // A polygon has no (u, v) of its own: each patch of its fan
                // takes the unit square, whatever `TextureCoordinates` says.
                let defaults = vec![UNIT_SQUARE; made.patches.len()];
                let st = texcoords::resolve(&vars, &made.layout, &made.corners, &defaults)?;
                (made.patches, st)
            }
            _ => {
                if p.len() < 3 {
                    return Err(format!("needs at least 3 points, found {}", p.len()).into());
                }
                self.take_patches(basis::fan_patches(p.len()), || "its fan".to_owned())?;
                let made = super::polygons::polygon(&p);
                if made.nonconvex > 0 {
                    self.warn(
                        file,
                        line,
                        "Polygon is not convex (or not planar): its fan of patches covers a different area"
                            .into(),
                    );
                }
                let defaults = vec![UNIT_SQUARE; made.patches.len()];
                let st = texcoords::resolve(&vars, &made.layout, &made.corners, &defaults)?;
                (made.patches, st)
            }
        };
        self.emit(name, patches, st, file, line)
    }

    /// Why points through the current transform leave f32 (for messages):
    /// the camera transform, the current transform (each with the request
    /// from which on it does), or the points.
    pub(super) fn overflow_cause(&self) -> String {
        let camera = camera_to_world() * self.camera.unwrap_or(DMat4::IDENTITY);
        if !camera.as_mat4().is_finite() {
            format!(
                "the camera transform (the transforms before WorldBegin) overflows f32{}",
                self.origin_text(self.camera_overflow)
            )
        } else if !(camera * self.xf.open).as_mat4().is_finite() {
            format!(
                "the current transform overflows f32{}",
                self.origin_text(self.xf.overflow)
            )
        } else {
            "the points through the current transform overflow f32".to_owned()
        }
    }

    /// ` (from the Scale at scene.rib:2 on)`, or nothing without an origin.
    fn origin_text(&self, origin: Option<state::Origin>) -> String {
        origin.map_or_else(String::new, |o| {
            let file = self
                .origin_files
                .get(o.file)
                .map_or_else(|| "?".to_owned(), |f| f.display().to_string());
            format!(" (from the {} at {file}:{} on)", o.request, o.line)
        })
    }

    /// Records in the current transform the request `name` at `line` of
    /// `file` if the transform to camera space leaves f32 there (keeping
    /// an earlier one), or clears it when it is back within f32. Before
    /// `WorldBegin` the current transform is the camera's; after, an
    /// overflowing camera is named by its own origin instead.
    pub(super) fn track_overflow(&mut self, name: &str, file: &Path, line: usize) {
        let fits = |m: DMat4| m.as_mat4().is_finite();
        let camera = camera_to_world() * self.camera.unwrap_or(DMat4::IDENTITY);
        if !fits(camera) {
            self.xf.overflow = None;
            return;
        }
        if fits(camera * self.xf.open) && fits(camera * self.xf.close) {
            self.xf.overflow = None;
        } else if self.xf.overflow.is_none() {
            let request = TRANSFORMS
                .iter()
                .copied()
                .find(|t| *t == name)
                .unwrap_or("transform");
            let index = match self.origin_files.iter().position(|f| f == file) {
                Some(i) => i,
                None => {
                    self.origin_files.push(file.to_path_buf());
                    self.origin_files.len() - 1
                }
            };
            self.xf.overflow = Some(state::Origin {
                request,
                file: index,
                line,
            });
        }
    }

    /// Adds the primitive of request `name` made of `patches` (already
    /// taken from the budget) at `line` of `file`, with the corner texture
    /// coordinates `st` (one entry per patch).
    pub(super) fn emit(
        &mut self,
        name: &str,
        patches: Vec<[DVec3; 16]>,
        st: Vec<[DVec2; 4]>,
        file: &Path,
        line: usize,
    ) -> Result<(), RequestError> {
        debug_assert_eq!(patches.len(), st.len(), "one st per patch");
        let st = texcoords::to_f32(st)?;
        let camera = self.camera.unwrap_or(DMat4::IDENTITY);
        let (open, close) = if self.defining_object() {
            // An object definition keeps its own space; its instances
            // place it (`super::instances`).
            if self.xf.open != self.xf.close {
                self.warn_once(
                    "#definition-motion",
                    file,
                    line,
                    "motion inside ObjectBegin is not supported: the definition keeps its shape at shutter open (move the instances instead)".into(),
                );
            }
            (self.xf.open, self.xf.open)
        } else {
            (
                camera_to_world() * camera * self.xf.open,
                camera_to_world() * camera * self.xf.close,
            )
        };
        let mut out = Vec::with_capacity(patches.len());
        let mut out_st = Vec::with_capacity(patches.len());
        for (patch, st) in patches.iter().zip(st) {
            let pts = patch.map(|p| open.transform_point3(p).as_vec3());
            if pts.iter().all(|p| p.is_finite()) {
                out.push(pts);
                out_st.push(st);
            }
        }
        // One warning per primitive, naming the transform that overflows
        // when one does.
        let skipped = patches.len() - out.len();
        if skipped > 0 {
            let cause = self.overflow_cause();
            self.warn(
                file,
                line,
                format!(
                    "{skipped} of the primitive's {} patches have control points beyond f32 in camera space: {cause}; skipped",
                    patches.len()
                ),
            );
        }
        // The budget took them all before they were made.
        self.patches.give_back(skipped as u64);
        if !self.defining_object() {
            self.lights_for_primitive();
        }
        let moving = (open != close).then(|| close * open.inverse());
        self.prims.push(Prim {
            patches: out,
            st: out_st,
            attrs: self.attrs.clone(),
            close: moving,
            request: GEOMETRY
                .iter()
                .copied()
                .chain(["ObjectInstance"])
                .find(|g| *g == name)
                .unwrap_or("primitive"),
            file: file.to_path_buf(),
            line,
            placement: None,
        });
        Ok(())
    }
}
