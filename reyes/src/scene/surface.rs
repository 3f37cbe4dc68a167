//! An object's surface shader (`[objects.surface]`): RenderMan's standard
//! surfaces, as the RenderMan Interface Specification 3.2 defines them
//! (appendix "Standard RenderMan Shaders"). docs/reyes.md ("Surfaces")
//! states their formulas; `crate::reference::shade` evaluates them.

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::Vec3;
use serde::{Deserialize, Serialize};

pub use crate::surface_shader::ShaderValue;

fn one() -> f32 {
    1.0
}
fn half() -> f32 {
    0.5
}
fn tenth() -> f32 {
    0.1
}
fn white() -> Vec3 {
    Vec3::ONE
}
fn default_ka() -> f32 {
    0.2
}
fn default_kd() -> f32 {
    0.8
}

/// A standard surface shader and its parameters, named as in RenderMan
/// (`Ka`, `Kd`, `Ks`, `roughness`, `specularcolor`), with RenderMan's
/// defaults. The object's colour (`color`, RenderMan's `Cs`) is the
/// object's, not the shader's.
///
/// ```toml
/// [[objects]]
/// model = "teapot"
/// color = [0.8, 0.3, 0.2]
/// [objects.surface]
/// shader = "plastic"
/// Ks = 0.8
/// roughness = 0.05
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shader", rename_all = "lowercase", deny_unknown_fields)]
pub enum Surface {
    /// `Ci = Cs`: unlit.
    Constant,
    /// `Ci = Cs * (Ka * ambient() + Kd * diffuse(Nf))`.
    Matte {
        /// Ambient weight (default 1).
        #[serde(rename = "Ka", default = "one")]
        ka: f32,
        /// Diffuse weight (default 1).
        #[serde(rename = "Kd", default = "one")]
        kd: f32,
    },
    /// `Ci = Cs * (Ka * ambient() + Ks * specular(Nf, V, roughness))`.
    Metal {
        /// Ambient weight (default 1).
        #[serde(rename = "Ka", default = "one")]
        ka: f32,
        /// Specular weight (default 1).
        #[serde(rename = "Ks", default = "one")]
        ks: f32,
        /// Roughness (default 0.1): the highlight is `(N.H)^(1/roughness)`.
        #[serde(default = "tenth")]
        roughness: f32,
    },
    /// `Ci = Cs * (Ka * ambient() + Kd * diffuse(Nf))
    ///  + specularcolor * Ks * specular(Nf, V, roughness)`.
    Plastic {
        /// Ambient weight (default 1).
        #[serde(rename = "Ka", default = "one")]
        ka: f32,
        /// Diffuse weight (default 0.5).
        #[serde(rename = "Kd", default = "half")]
        kd: f32,
        /// Specular weight (default 0.5).
        #[serde(rename = "Ks", default = "half")]
        ks: f32,
        /// Roughness (default 0.1).
        #[serde(default = "tenth")]
        roughness: f32,
        /// The highlight's colour (default white).
        #[serde(rename = "specularcolor", default = "white")]
        specular_color: Vec3,
    },
    /// RenderMan's `defaultsurface`, which needs no lights:
    /// `Ci = Cs * (Ka + Kd * d^2)` with `d = normalize(I).normalize(N)`.
    #[serde(rename = "defaultsurface")]
    DefaultSurface {
        /// The constant term (default 0.2).
        #[serde(rename = "Ka", default = "default_ka")]
        ka: f32,
        /// The headlight term (default 0.8).
        #[serde(rename = "Kd", default = "default_kd")]
        kd: f32,
    },
    /// RenderMan's `null`: the object draws nothing into the image.
    Null,
    /// A user's WGSL surface shader (docs/shaders.md):
    ///
    /// ```toml
    /// [objects.surface]
    /// shader = "wgsl"
    /// file = "marble.wgsl"          # relative to the scene file
    /// parameters = { Kd = 0.7, veincolor = [0.2, 0.1, 0.05] }
    /// ```
    Wgsl {
        /// The shader file.
        file: PathBuf,
        /// Values for the shader's `Parameters`, by field name; the others
        /// keep the shader's `DEFAULTS`.
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        parameters: BTreeMap<String, ShaderValue>,
    },
}

impl Surface {
    /// RenderMan's `plastic` with its defaults.
    pub const PLASTIC: Surface = Surface::Plastic {
        ka: 1.0,
        kd: 0.5,
        ks: 0.5,
        roughness: 0.1,
        specular_color: Vec3::ONE,
    };

    /// RenderMan's `defaultsurface` with its defaults.
    pub const DEFAULT_SURFACE: Surface = Surface::DefaultSurface { ka: 0.2, kd: 0.8 };

    /// The shader's name, as RenderMan spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Surface::Constant => "constant",
            Surface::Matte { .. } => "matte",
            Surface::Metal { .. } => "metal",
            Surface::Plastic { .. } => "plastic",
            Surface::DefaultSurface { .. } => "defaultsurface",
            Surface::Null => "null",
            Surface::Wgsl { .. } => "wgsl",
        }
    }

    /// The shader's parameters by name, for validation messages.
    pub fn params(&self) -> Vec<(&'static str, f32)> {
        match self.clone() {
            Surface::Constant | Surface::Null | Surface::Wgsl { .. } => Vec::new(),
            Surface::Matte { ka, kd } | Surface::DefaultSurface { ka, kd } => {
                vec![("Ka", ka), ("Kd", kd)]
            }
            Surface::Metal { ka, ks, roughness } => {
                vec![("Ka", ka), ("Ks", ks), ("roughness", roughness)]
            }
            Surface::Plastic {
                ka,
                kd,
                ks,
                roughness,
                specular_color,
            } => vec![
                ("Ka", ka),
                ("Kd", kd),
                ("Ks", ks),
                ("roughness", roughness),
                ("specularcolor[0]", specular_color.x),
                ("specularcolor[1]", specular_color.y),
                ("specularcolor[2]", specular_color.z),
            ],
        }
    }

    /// The surface of an object that names none in a TOML scene: `plastic`
    /// lit by the scene-wide terms (`ambient` scales the ambient light,
    /// `[specular]` gives `Ks` and `roughness = 1 / shininess`), with the
    /// whole colour diffuse (`Kd = 1`), as the scene files before per-object
    /// surfaces were shaded.
    pub fn scene_default(specular_strength: f32, shininess: f32) -> Surface {
        Surface::Plastic {
            ka: 1.0,
            kd: 1.0,
            ks: specular_strength,
            roughness: if shininess > 0.0 {
                1.0 / shininess
            } else {
                f32::INFINITY
            },
            specular_color: Vec3::ONE,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct Holder {
        surface: Surface,
    }

    fn parse(text: &str) -> Result<Surface, toml::de::Error> {
        toml::from_str::<Holder>(text).map(|h| h.surface)
    }

    #[test]
    fn shaders_parse_with_renderman_names_and_defaults() {
        assert_eq!(
            parse("[surface]\nshader = \"plastic\"").unwrap(),
            Surface::PLASTIC
        );
        assert_eq!(
            parse("[surface]\nshader = \"defaultsurface\"").unwrap(),
            Surface::DEFAULT_SURFACE
        );
        assert_eq!(
            parse("[surface]\nshader = \"metal\"\nKs = 0.3\nroughness = 0.2").unwrap(),
            Surface::Metal {
                ka: 1.0,
                ks: 0.3,
                roughness: 0.2
            }
        );
        assert_eq!(
            parse("[surface]\nshader = \"null\"").unwrap(),
            Surface::Null
        );
    }

    #[test]
    fn unknown_shaders_and_parameters_are_errors() {
        let e = parse("[surface]\nshader = \"glass\"").unwrap_err();
        assert!(e.to_string().contains("glass"), "{e}");
        let e = parse("[surface]\nshader = \"matte\"\nKs = 1.0").unwrap_err();
        assert!(e.to_string().contains("Ks"), "{e}");
    }
}
