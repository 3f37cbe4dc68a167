//! `Surface`: RenderMan's standard surface shaders, mapped onto the
//! renderer's shading.
//!
//! The renderer shades every point as
//! `albedo * (ambient + diffuse) + strength * specular`: one albedo per
//! object, and one ambient term and one specular term (strength and
//! Blinn-Phong exponent) for the whole scene. The standard shaders of the
//! RenderMan Interface 3.2 (appendix A) are
//!
//! * `constant`: `Ci = Cs` (unlit);
//! * `matte`: `Ci = Cs * (Ka * ambient() + Kd * diffuse(N))`;
//! * `metal`: `Ci = Cs * (Ka * ambient() + Ks * specular(N, V, roughness))`;
//! * `plastic`: `Ci = Cs * (Ka * ambient() + Kd * diffuse(N))
//!   + specularcolor * Ks * specular(N, V, roughness)`
//!
//! (`paintedplastic` is `plastic` times a texture). The albedo is
//! `Cs * Kd`, so the diffuse term is exact. The ambient term is
//! `Cs * Kd * ambient` in the renderer, so the scene's ambient is scaled by
//! `Ka / Kd`: exact when every surface has the same ratio, otherwise the
//! mean with a warning. The specular term comes from the last `plastic` or
//! `metal` surface, with `strength = Ks` times the mean of the highlight's
//! colour (`specularcolor`, or `Cs` for metal) and `shininess =
//! 1 / roughness` (RenderMan's `specular()` raises `N.H` to that power).
//! `docs/rib.md` lists what cannot be followed.

use std::collections::HashSet;
use std::path::Path;

use glam::{DVec3, Vec3};

use super::interp::{Interp, Prim};
use super::state::{self, Param, Surface};
use crate::scene::Specular;

/// The smallest `roughness` used (`shininess = 1 / roughness` at most 1000).
const MIN_ROUGHNESS: f64 = 1e-3;
/// The largest `Ka / Kd` ratio used for the scene's ambient scale (a tiny
/// `Kd` would make it arbitrarily large).
const MAX_AMBIENT_SCALE: f64 = 1e3;

/// The parameters each standard shader reads; `None` for other shaders.
fn known_params(shader: &str) -> Option<&'static [&'static str]> {
    Some(match shader {
        "constant" => &[],
        "matte" => &["Ka", "Kd"],
        "metal" => &["Ka", "Ks", "roughness"],
        "plastic" => &["Ka", "Kd", "Ks", "roughness", "specularcolor"],
        "paintedplastic" => &[
            "Ka",
            "Kd",
            "Ks",
            "roughness",
            "specularcolor",
            "texturename",
        ],
        _ => return None,
    })
}

impl Interp {
    /// The surface of a `Surface` request for `shader` with `params`.
    pub(super) fn surface(
        &mut self,
        shader: &str,
        params: &[Param],
        file: &Path,
        line: usize,
    ) -> Result<Surface, String> {
        let shown = crate::input::excerpt(shader);
        // An unknown shader warns below; its parameters are not judged.
        let known = known_params(shader);
        for p in params {
            if known.is_some_and(|k| !k.contains(&p.name.as_str())) {
                self.warn_once(
                    &format!("#surface-param {shader} {}", p.name),
                    file,
                    line,
                    format!(
                        "Surface {shown:?} has no parameter {:?}; ignored",
                        crate::input::excerpt(&p.name)
                    ),
                );
            }
        }
        let surface = match shader {
            "constant" => {
                self.warn_once(
                    "#surface-constant",
                    file,
                    line,
                    "Surface \"constant\" is unlit in RenderMan, but the renderer lights every surface: it is shaded as \"matte\" (Ka 1, Kd 1), its colour exact only where the lights add up to 1 (an ambientlight of intensity 1 alone)".into(),
                );
                Surface::Constant
            }
            "matte" => Surface::Matte {
                ka: self.weight(params, "Ka", 1.0, &shown, file, line)?,
                kd: self.weight(params, "Kd", 1.0, &shown, file, line)?,
            },
            "metal" => {
                self.warn_once(
                    "#surface-metal",
                    file,
                    line,
                    "Surface \"metal\": the renderer's diffuse and ambient terms share the object's colour, so a surface without diffuse is black apart from its highlight (Ka is lost), and the highlight is the lights' colour times the mean of Cs".into(),
                );
                Surface::Metal {
                    ka: self.weight(params, "Ka", 1.0, &shown, file, line)?,
                    ks: self.weight(params, "Ks", 1.0, &shown, file, line)?,
                    roughness: self.roughness(params, &shown, file, line)?,
                }
            }
            "plastic" | "paintedplastic" => {
                if shader == "paintedplastic" {
                    self.warn_once(
                        "#surface-paintedplastic",
                        file,
                        line,
                        "Surface \"paintedplastic\": textures are not supported; shaded as \"plastic\"".into(),
                    );
                }
                Surface::Plastic {
                    ka: self.weight(params, "Ka", 1.0, &shown, file, line)?,
                    kd: self.weight(params, "Kd", 0.5, &shown, file, line)?,
                    ks: self.weight(params, "Ks", 0.5, &shown, file, line)?,
                    roughness: self.roughness(params, &shown, file, line)?,
                    specular_color: state::param_v3(params, "specularcolor", DVec3::ONE)?,
                }
            }
            _ => {
                self.warn(
                    file,
                    line,
                    format!("Surface {shown:?} is not supported; shading as \"matte\""),
                );
                Surface::Matte { ka: 1.0, kd: 1.0 }
            }
        };
        Ok(surface)
    }

    /// A weight (`Ka`, `Kd`, `Ks`): a negative one is taken as 0, with a
    /// warning (the renderer's terms only add light).
    fn weight(
        &mut self,
        params: &[Param],
        name: &str,
        default: f64,
        shader: &str,
        file: &Path,
        line: usize,
    ) -> Result<f64, String> {
        let k = state::param_f(params, name, default)?;
        if k < 0.0 {
            self.warn(
                file,
                line,
                format!("Surface {shader:?}: {name} {k} is negative; using 0"),
            );
            return Ok(0.0);
        }
        Ok(k)
    }

    fn roughness(
        &mut self,
        params: &[Param],
        shader: &str,
        file: &Path,
        line: usize,
    ) -> Result<f64, String> {
        let r = state::param_f(params, "roughness", 0.1)?;
        if r < MIN_ROUGHNESS {
            self.warn(
                file,
                line,
                format!(
                    "Surface {shader:?}: roughness {r} is below {MIN_ROUGHNESS}; using {MIN_ROUGHNESS}"
                ),
            );
            return Ok(MIN_ROUGHNESS);
        }
        Ok(r)
    }
}

/// The albedo of a primitive with colour `cs` and surface `surface`: the
/// weight of its diffuse term.
pub(super) fn albedo(cs: DVec3, surface: Surface) -> DVec3 {
    match surface {
        Surface::Constant => cs,
        Surface::Matte { kd, .. } | Surface::Plastic { kd, .. } => cs * kd,
        // No diffuse term: black (see the metal warning).
        Surface::Metal { .. } => DVec3::ZERO,
    }
}

/// `Ka / Kd` of a surface with a diffuse term: the scale its ambient term
/// needs on top of the albedo. `None` for metal and for `Kd = 0` (no
/// albedo to scale).
fn ambient_scale(surface: Surface) -> Option<f64> {
    match surface {
        Surface::Constant => Some(1.0),
        Surface::Matte { ka, kd } | Surface::Plastic { ka, kd, .. } if kd > 0.0 => {
            Some((ka / kd).min(MAX_AMBIENT_SCALE))
        }
        _ => None,
    }
}

/// The scene-wide shading the surfaces of `prims` ask for.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SceneShading {
    /// The factor on the sum of the ambient lights (`Ka / Kd`).
    pub ambient_scale: f64,
    /// The specular term.
    pub specular: Specular,
    /// What could not be followed.
    pub warnings: Vec<String>,
}

/// The specular term a surface asks for (strength 0 for none).
fn specular_of(cs: DVec3, surface: Surface) -> (Specular, Option<String>) {
    let mean = |c: DVec3| (c.x + c.y + c.z) / 3.0;
    let grey = |c: DVec3| (c.x - c.y).abs() <= 1e-6 && (c.y - c.z).abs() <= 1e-6;
    let (ks, roughness, tint, what) = match surface {
        Surface::Constant | Surface::Matte { .. } => {
            return (
                Specular {
                    strength: 0.0,
                    shininess: 10.0,
                },
                None,
            );
        }
        Surface::Metal { ks, roughness, .. } => (ks, roughness, cs, "metal's colour Cs"),
        Surface::Plastic {
            ks,
            roughness,
            specular_color,
            ..
        } => (ks, roughness, specular_color, "plastic's specularcolor"),
    };
    let warning = (!grey(tint)).then(|| {
        format!(
            "the renderer's highlight has the lights' colour: the {what} [{} {} {}] is taken as its mean, {}",
            tint.x,
            tint.y,
            tint.z,
            mean(tint)
        )
    });
    (
        Specular {
            strength: (ks * mean(tint).max(0.0)) as f32,
            shininess: (1.0 / roughness.max(MIN_ROUGHNESS)) as f32,
        },
        warning,
    )
}

/// The scene-wide ambient scale and specular term of `prims`' surfaces.
pub(super) fn scene_shading(prims: &[Prim]) -> SceneShading {
    let mut warnings = Vec::new();
    let mut tints = HashSet::new();
    let mut specular = None;
    let mut wanted = Vec::<Specular>::new();
    let (mut lo, mut hi, mut sum, mut count) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize);
    for prim in prims.iter().filter(|p| !p.patches.is_empty()) {
        let surface = prim.attrs.surface;
        if let Some(scale) = ambient_scale(surface) {
            lo = lo.min(scale);
            hi = hi.max(scale);
            sum += scale;
            count += 1;
        }
        let (s, warning) = specular_of(prim.attrs.color, surface);
        if let Some(w) = warning
            && tints.insert(w.clone())
            && tints.len() <= 4
        {
            warnings.push(w);
        }
        if matches!(surface, Surface::Metal { .. } | Surface::Plastic { .. }) {
            specular = Some(s);
        }
        if !wanted.contains(&s) {
            wanted.push(s);
        }
    }
    if wanted.len() > 1 {
        warnings.push("the renderer has one specular term for the whole scene: it is taken from the last \"plastic\" or \"metal\" surface".into());
    }
    let ambient_scale = if count == 0 { 1.0 } else { sum / count as f64 };
    if count > 0 && hi - lo > 1e-9 * hi.abs().max(1.0) {
        warnings.push(format!(
            "the renderer has one ambient term for the whole scene: Ka / Kd goes from {lo} to {hi} over the surfaces; using the mean, {ambient_scale}"
        ));
    }
    SceneShading {
        ambient_scale,
        specular: specular.unwrap_or(Specular {
            strength: 0.0,
            shininess: 10.0,
        }),
        warnings,
    }
}

/// [`albedo`] of a primitive, as the object's colour.
pub(super) fn object_color(prim: &Prim) -> Vec3 {
    albedo(prim.attrs.color, prim.attrs.surface).as_vec3()
}
