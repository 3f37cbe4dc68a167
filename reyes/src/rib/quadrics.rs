//! The quadrics of the RenderMan Interface (3.2, section 5.3): surfaces
//! swept around the z axis of object space by `theta = u * thetamax`, with a
//! profile in `v`, approximated by bicubic Bezier patches whose distance to
//! the exact surface is bounded (see `docs/rib.md`).
//!
//! A circular arc of angle `phi <= 90` degrees is one cubic Bezier with
//! handles `k = 4/3 tan(phi / 4)` long (per unit radius); its radial error is
//! at most [`arc_error`]`(phi) = 2 sin^6(phi/4) / (27 cos^2(phi/4))`, times
//! the radius (0.027 % at 90 degrees, 4.2e-6 at 45). A patch is the arc
//! in `u` applied (as a complex product in x, y) to the control points of
//! the profile in `v`: a line (cylinder, cone, disk, hyperboloid) or a
//! parabola (paraboloid) exactly, or arcs again (sphere, torus).

use std::path::Path;

use glam::{DMat4, DVec2, DVec3};

use super::interp::{Interp, RequestError};
use super::parser::Value;
use super::state;

/// Most segments per direction (a full turn, or a profile's arc).
pub const MAX_SEGMENTS: usize = 64;
/// The error allowed at the render's resolution, in pixels.
pub const MAX_ERROR_PX: f64 = 0.1;
/// The error bound of a quadric inside an object definition, relative to
/// its size: [`MAX_ERROR_PX`] for an instance 1,000 pixels across (up to
/// [`MAX_SEGMENTS`]).
const DEFINITION_RELATIVE_ERROR: f64 = 1e-4;
/// The pieces per fewest segment (a quarter turn) whose bounding spheres
/// bound the depth of a quadric's visible points: pieces of 22.5 degrees,
/// whose bounding spheres stay within a third of their radius of the surface.
const PROBE_SPLIT: usize = 4;

/// The largest radial error of the cubic Bezier of a unit circular arc of
/// angle `phi` (radians, at most a quarter turn) with the standard handles.
pub fn arc_error(phi: f64) -> f64 {
    let (s, c) = (phi.abs() / 4.0).sin_cos();
    2.0 * s.powi(6) / (27.0 * c * c)
}

/// The Bezier control points of the unit arc from angle `a` to `b`.
pub fn arc(a: f64, b: f64) -> [DVec2; 4] {
    let k = 4.0 / 3.0 * ((b - a) / 4.0).tan();
    let pa = DVec2::from_angle(a);
    let pb = DVec2::from_angle(b);
    [pa, pa + k * pa.perp(), pb - k * pb.perp(), pb]
}

/// The profile of a quadric in its half plane (`y = 0` except for the
/// hyperboloid), in `v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// A cubic Bezier, exact.
    Cubic([DVec3; 4]),
    /// The arc `(center + radius cos phi, 0, radius sin phi)`, `phi` from
    /// `phi0` to `phi1` (radians).
    Arc {
        /// Distance of the centre from the z axis.
        center: f64,
        /// Radius (negative mirrors the arc, as RenderMan's formulas do).
        radius: f64,
        /// Start angle.
        phi0: f64,
        /// End angle.
        phi1: f64,
    },
}

/// A quadric in object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadric {
    /// The profile in `v`.
    pub profile: Profile,
    /// `thetamax` in radians (signed, at most a full turn).
    pub theta: f64,
    /// The largest distance of the profile from the z axis.
    pub reach: f64,
}

fn line(a: DVec3, b: DVec3) -> Profile {
    Profile::Cubic([a, a + (b - a) / 3.0, a + (b - a) * (2.0 / 3.0), b])
}

fn segments_min(angle: f64) -> usize {
    ((angle.abs() / std::f64::consts::FRAC_PI_2 - 1e-9).ceil() as usize).max(1)
}

impl Quadric {
    /// The quadric of request `name` with its positional numbers `n`; an
    /// error says why it is empty or invalid (the caller warns and skips).
    pub fn new(name: &str, n: &[f64]) -> Result<Quadric, String> {
        let theta = n[n.len() - 1].clamp(-360.0, 360.0).to_radians();
        if theta == 0.0 {
            return Err("thetamax is 0: the surface is empty".into());
        }
        let (profile, reach) = match name {
            "Sphere" => {
                let r = n[0];
                let phi = |z: f64| (z / r).clamp(-1.0, 1.0).asin();
                (
                    Profile::Arc {
                        center: 0.0,
                        radius: r,
                        phi0: phi(n[1]),
                        phi1: phi(n[2]),
                    },
                    r.abs(),
                )
            }
            "Torus" => (
                Profile::Arc {
                    center: n[0],
                    radius: n[1],
                    phi0: n[2].clamp(-360.0, 360.0).to_radians(),
                    phi1: n[3].clamp(-360.0, 360.0).to_radians(),
                },
                n[0].abs() + n[1].abs(),
            ),
            "Cylinder" => (
                line(DVec3::new(n[0], 0.0, n[1]), DVec3::new(n[0], 0.0, n[2])),
                n[0].abs(),
            ),
            "Cone" => (
                line(DVec3::new(n[1], 0.0, 0.0), DVec3::new(0.0, 0.0, n[0])),
                n[1].abs(),
            ),
            "Disk" => (
                line(DVec3::new(n[1], 0.0, n[0]), DVec3::new(0.0, 0.0, n[0])),
                n[1].abs(),
            ),
            "Hyperboloid" => {
                let (a, b) = (DVec3::new(n[0], n[1], n[2]), DVec3::new(n[3], n[4], n[5]));
                (line(a, b), a.truncate().length().max(b.truncate().length()))
            }
            "Paraboloid" => {
                let (rmax, zmin, zmax) = (n[0], n[1], n[2]);
                if zmax == 0.0 || zmin / zmax < 0.0 {
                    return Err(format!(
                        "zmin {zmin} and zmax {zmax} must have the same sign, zmax not 0"
                    ));
                }
                // z = zmax (r / rmax)^2 is quadratic in r: r linear in v
                // gives the same surface as an exact Bezier.
                let r0 = rmax * (zmin / zmax).sqrt();
                let mid = DVec3::new((r0 + rmax) / 2.0, 0.0, zmax * r0 / rmax);
                let (a, b) = (DVec3::new(r0, 0.0, zmin), DVec3::new(rmax, 0.0, zmax));
                (
                    Profile::Cubic([a, (a + 2.0 * mid) / 3.0, (2.0 * mid + b) / 3.0, b]),
                    r0.abs().max(rmax.abs()),
                )
            }
            _ => unreachable!("only quadrics"),
        };
        let empty = reach == 0.0
            || match profile {
                Profile::Arc {
                    radius, phi0, phi1, ..
                } => radius == 0.0 || phi0 == phi1,
                Profile::Cubic(p) => p[0] == p[3],
            };
        if empty {
            return Err("the surface is empty (a zero size)".into());
        }
        Ok(Quadric {
            profile,
            theta,
            reach,
        })
    }

    /// The profile in `nv` segments.
    fn profile(&self, nv: usize) -> Vec<[DVec3; 4]> {
        match self.profile {
            Profile::Cubic(p) => vec![p],
            Profile::Arc {
                center,
                radius,
                phi0,
                phi1,
            } => (0..nv)
                .map(|s| {
                    let at = |s: usize| phi0 + (phi1 - phi0) * s as f64 / nv as f64;
                    arc(at(s), at(s + 1))
                        .map(|c| DVec3::new(center + radius * c.x, 0.0, radius * c.y))
                })
                .collect(),
        }
    }

    /// The Bezier patches (object space, `points[v * 4 + u]`, `u` along
    /// theta) with `nu` segments around and `nv` along an arc profile.
    pub fn patches(&self, nu: usize, nv: usize) -> Vec<[DVec3; 16]> {
        let mut out = Vec::new();
        for q in self.profile(nv) {
            for s in 0..nu {
                let at = |s: usize| self.theta * s as f64 / nu as f64;
                let c = arc(at(s), at(s + 1));
                out.push(std::array::from_fn(|k| {
                    let p = q[k / 4];
                    c[k % 4].rotate(p.truncate()).extend(p.z)
                }));
            }
        }
        out
    }

    /// The arc profile's radius and angle, if the profile is an arc.
    fn arc_profile(&self) -> Option<(f64, f64)> {
        match self.profile {
            Profile::Arc {
                radius, phi0, phi1, ..
            } => Some((radius.abs(), phi1 - phi0)),
            Profile::Cubic(_) => None,
        }
    }

    /// The fewest segments in `u` and `v`.
    pub fn min_segments(&self) -> (usize, usize) {
        let nv = self.arc_profile().map_or(1, |(_, a)| segments_min(a));
        (segments_min(self.theta), nv)
    }

    /// A bound on the distance (object space) from the patches with `nu`,
    /// `nv` segments to the exact surface: the arc in `u` errs by at most
    /// `arc_error` times the distance from the axis of the (approximated)
    /// profile, and the profile's arc by `arc_error` times its radius.
    pub fn error_bound(&self, nu: usize, nv: usize) -> f64 {
        let (ev, rv) = self
            .arc_profile()
            .map_or((0.0, 0.0), |(r, a)| (arc_error(a / nv as f64), r));
        self.reach * (1.0 + ev) * arc_error(self.theta / nu as f64) + rv * ev
    }

    /// The fewest segments whose [`Quadric::error_bound`] is at most `tol`,
    /// each clamped to [`MAX_SEGMENTS`], and whether one was clamped.
    pub fn segments(&self, tol: f64) -> (usize, usize, bool) {
        let (nu0, nv0) = self.min_segments();
        let arc = self.arc_profile();
        let share = if arc.is_some() { tol / 2.0 } else { tol };
        let worst = 1.0 + arc_error(std::f64::consts::FRAC_PI_2);
        let pick = |n0: usize, err: &dyn Fn(usize) -> f64| {
            (n0..=MAX_SEGMENTS.max(n0))
                .find(|&n| err(n) <= share)
                .map_or((MAX_SEGMENTS.max(n0), true), |n| (n, false))
        };
        let (nu, cu) = pick(nu0, &|n| {
            self.reach * worst * arc_error(self.theta / n as f64)
        });
        let (nv, cv) = match arc {
            Some((r, a)) => pick(nv0, &|n| r * arc_error(a / n as f64)),
            None => (1, false),
        };
        (nu, nv, cu || cv)
    }
}

/// The positional numbers of each quadric.
pub fn arity(name: &str) -> Option<usize> {
    Some(match name {
        "Sphere" | "Cylinder" | "Paraboloid" => 4,
        "Cone" | "Disk" => 3,
        "Torus" => 5,
        "Hyperboloid" => 7,
        _ => return None,
    })
}

impl Interp {
    /// Runs quadric request `name` (after `WorldBegin`).
    pub(super) fn quadric(
        &mut self,
        name: &str,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), RequestError> {
        let count = arity(name).expect("a quadric");
        // The positional numbers, bare or in arrays, before the parameters.
        let head = v.iter().take_while(|x| x.nums().is_some()).count();
        let nums: Vec<f64> = v[..head].iter().flat_map(|x| x.nums().unwrap()).collect();
        if nums.len() != count {
            return Err(format!("expected {count} numbers, found {}", nums.len()).into());
        }
        let (_, params, unknown) = state::split_params(&v[head..], 0, &self.declared)?;
        self.warn_unread_variables(name, &params, file, line);
        let vars = super::texcoords::st_vars(&v[head..], 0, &self.declared)?;
        for u in unknown {
            self.warn_once(
                &format!("#param {u}"),
                file,
                line,
                format!("{name}: undeclared parameter {u:?} ignored"),
            );
        }
        let quadric = match Quadric::new(name, &nums) {
            Ok(q) => q,
            Err(why) => {
                self.warn(file, line, format!("{name}: {why}; skipped"));
                return Ok(());
            }
        };
        if self.defining_object() {
            // Where its instances will be is not known yet: fine enough for
            // an instance 1,000 pixels across, and shared by them all.
            let (nu, nv, _) = quadric.segments(quadric.reach * DEFINITION_RELATIVE_ERROR);
            self.take_patches(nu * nv, || format!("{nu} x {nv} segments"))?;
            let patches = quadric.patches(nu, nv);
            let st = super::texcoords::quadric(&vars, self.attrs.texture_coords, nu, patches.len())?;
            return self.emit(name, patches, st, file, line);
        }
        let to_camera = self.camera.unwrap_or(DMat4::IDENTITY) * self.xf.open;
        let (nu0, nv0) = quadric.min_segments();
        let Some(px) = self.world_per_pixel(to_camera, &quadric) else {
            // Behind the camera: not seen.
            self.take_patches(nu0 * nv0, || format!("{nu0} x {nv0} segments"))?;
            let patches = quadric.patches(nu0, nv0);
            let st = super::texcoords::quadric(&vars, self.attrs.texture_coords, nu0, patches.len())?;
            return self.emit(name, patches, st, file, line);
        };
        let (nu, nv, clamped) = quadric.segments(MAX_ERROR_PX * px);
        // Counted before they are made: 64 x 64 segments are 4096 patches.
        self.take_patches(nu * nv, || format!("{nu} x {nv} segments"))?;
        if clamped {
            let error = quadric.error_bound(nu, nv) / px;
            self.warn(
                file,
                line,
                format!(
                    "{name}: {nu} x {nv} segments (the most) bound its error by {error:.3} pixels, more than {MAX_ERROR_PX}"
                ),
            );
        }
        let patches = quadric.patches(nu, nv);
        let st = super::texcoords::quadric(&vars, self.attrs.texture_coords, nu, patches.len())?;
        self.emit(name, patches, st, file, line)
    }

    /// The object-space length of a pixel (a bound on how far a step of
    /// that length moves in the image) at a lower bound of the depth of the
    /// points of `quadric` that are in view under `to_camera`; `None` if it
    /// is all behind the near plane.
    ///
    /// The depth bound is the larger of two: the nearest depth of the
    /// bounding sphere of the whole quadric, and the nearest over its
    /// pieces ([`PROBE_SPLIT`] per fewest segment) of what each piece's
    /// bounding sphere allows. A point in view at distance `D` from the eye
    /// has `z >= D / sqrt(1 + tx^2 + ty^2)`, so a piece at distance `D`
    /// cannot be nearer in depth than that even when the whole quadric
    /// surrounds the eye (a large sphere around the camera, whose bounding
    /// sphere reaches the near plane: bounding the error there asked for
    /// the most segments, 4096 patches, at any radius).
    fn world_per_pixel(&self, to_camera: DMat4, quadric: &Quadric) -> Option<f64> {
        let (nu0, nv0) = quadric.min_segments();
        let (nu, nv) = (nu0 * PROBE_SPLIT, nv0 * PROBE_SPLIT);
        let pieces = quadric.patches(nu, nv);
        // Object space to camera space stretches by at most the Frobenius
        // norm of the linear part.
        let m = glam::DMat3::from_mat4(to_camera);
        let stretch =
            (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared())
                .sqrt();
        if stretch.is_nan() || stretch <= 0.0 {
            return None;
        }
        // The exact surface is within this of the pieces (camera space).
        let slack = quadric.error_bound(nu, nv) * stretch;
        let near = self
            .opts
            .clipping
            .map_or(0.1, |(n, _)| n.max(f64::from(crate::params::NEAR_EPS)));
        let (w, h) = self.opts.image_size();
        let (w, h) = (f64::from(w), f64::from(h));
        let [_, _, bottom, top] = self.opts.screen_window_or_default();
        // tan of half the vertical field of view, and the image's half
        // extents over the depth.
        let fov = self.opts.fov.filter(|f| *f > 0.0 && *f < 180.0);
        let tan_y = (fov.unwrap_or(90.0).to_radians() / 2.0).tan() * (top - bottom) / 2.0;
        let (tx, ty) = (tan_y * w / h, tan_y);
        let slope = (1.0 + tx * tx + ty * ty).sqrt();
        let sphere = |points: &mut dyn Iterator<Item = DVec3>| {
            let points: Vec<DVec3> = points.map(|p| to_camera.transform_point3(p)).collect();
            let lo = points.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
            let hi = points.iter().fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
            let center = (lo + hi) / 2.0;
            let radius = points
                .iter()
                .fold(0.0f64, |a, &p| a.max(p.distance(center)));
            (center, radius + slack)
        };
        let (center, radius) = sphere(&mut pieces.iter().flatten().copied());
        if center.z + radius < near {
            return None;
        }
        let whole = center.z - radius;
        let pieces_depth = pieces
            .iter()
            .map(|piece| sphere(&mut piece.iter().copied()))
            .filter(|(c, r)| c.z + r >= near)
            .map(|(c, r)| (c.z - r).max((c.length() - r) / slope))
            .fold(f64::INFINITY, f64::min);
        let depth = whole.max(pieces_depth).max(near);
        let camera_px = if self.opts.perspective {
            // A step d at depth z moves the projection (x/z, y/z) by at most
            // |d| sqrt(1 + tx^2 + ty^2) / z, tx, ty the image's half extents.
            depth * 2.0 * tan_y / (h * slope)
        } else {
            // Orthographic: a pixel is the same size at every depth.
            (top - bottom) / h
        };
        Some(camera_px / stretch)
    }
}
