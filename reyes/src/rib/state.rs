//! The graphics state of the interpreter: options, attributes, transforms,
//! and parameter-list helpers.

use std::collections::HashMap;

use glam::{DMat4, DVec2, DVec3};

use super::basis::{self, Basis};
use super::parser::Value;
use crate::scene::Surface;

/// The attributes the renderer uses.
#[derive(Debug, Clone, PartialEq)]
pub struct Attributes {
    /// `Color`.
    pub color: DVec3,
    /// `Surface` (RenderMan's default: `defaultsurface`).
    pub surface: Surface,
    /// `ShadingRate` set inside the world block (`None`: the frame's).
    pub shading_rate: Option<f64>,
    /// `Sides`: 1 or 2.
    pub sides: u8,
    /// The orientation is left-handed (the initial `"outside"` at identity).
    pub orientation_lh: bool,
    /// `Basis` in u.
    pub ubasis: Basis,
    /// `Basis` in v.
    pub vbasis: Basis,
    /// Bit `i`: light `i` is on (`LightSource` turns it on, `Illuminate`
    /// switches it, `AttributeEnd` restores the enclosing block's set).
    pub lights_on: u64,
    /// `TextureCoordinates`: the `st` of the corners `(u, v) = (0,0), (1,0),
    /// (0,1), (1,1)` of parametric primitives.
    pub texture_coords: [DVec2; 4],
    /// `Displacement`: the shader, its bound still unset.
    pub displacement: Option<crate::displacement::DisplacementDesc>,
    /// `Attribute "displacementbound"`, in the renderer's world units.
    pub displacement_bound: Option<f64>,
}

impl Default for Attributes {
    fn default() -> Self {
        Attributes {
            color: DVec3::ONE,
            surface: Surface::DEFAULT_SURFACE,
            shading_rate: None,
            sides: 2,
            orientation_lh: true,
            ubasis: basis::BEZIER,
            vbasis: basis::BEZIER,
            lights_on: 0,
            texture_coords: super::texcoords::UNIT_SQUARE,
            displacement: None,
            displacement_bound: None,
        }
    }
}

/// The current transform at shutter open and close (equal when not moving).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Xform {
    /// At shutter open.
    pub open: DMat4,
    /// At shutter close.
    pub close: DMat4,
    /// The request from which on the transform to camera space leaves f32,
    /// if it does (saved and restored with the transform, so it names the
    /// request of the transform in force).
    pub overflow: Option<Origin>,
}

impl Default for Xform {
    fn default() -> Self {
        Xform {
            open: DMat4::IDENTITY,
            close: DMat4::IDENTITY,
            overflow: None,
        }
    }
}

/// A request, for messages about what it caused later: its name, its file
/// (an index into the interpreter's list of files) and its line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Origin {
    /// The request.
    pub request: &'static str,
    /// The file's index.
    pub file: usize,
    /// 1-based line.
    pub line: usize,
}

/// One `"name" value` pair of a parameter list.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// The bare name (`"uniform float Kd"` gives `Kd`).
    pub name: String,
    /// The value.
    pub value: Value,
}

/// The declared (or inline-declared) type of a parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decl {
    /// Storage class (`uniform` unless given).
    pub class: String,
    /// Type name.
    pub ty: String,
    /// Array length (`float[2]` gives 2; 1 when no array).
    pub len: usize,
}

const CLASSES: [&str; 5] = ["constant", "uniform", "varying", "vertex", "facevarying"];
const TYPES: [&str; 10] = [
    "float", "integer", "int", "point", "vector", "normal", "color", "string", "matrix", "hpoint",
];

/// Parses a declaration `"[class] type[n]"` (without the name).
pub fn parse_decl(text: &str) -> Result<Decl, String> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let (class, ty) = match words.as_slice() {
        [ty] => ("uniform", *ty),
        [class, ty] => (*class, *ty),
        _ => {
            return Err(format!(
                "malformed declaration {:?}",
                crate::input::excerpt(text)
            ));
        }
    };
    if !CLASSES.contains(&class) {
        return Err(format!(
            "unknown storage class {:?}",
            crate::input::excerpt(class)
        ));
    }
    let (base, len) = match ty.split_once('[') {
        Some((base, rest)) => {
            let n = rest
                .strip_suffix(']')
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|n| (1..=1 << 16).contains(n))
                .ok_or_else(|| format!("malformed array type {:?}", crate::input::excerpt(ty)))?;
            (base, n)
        }
        None => (ty, 1),
    };
    if !TYPES.contains(&base) {
        return Err(format!("unknown type {:?}", crate::input::excerpt(base)));
    }
    Ok(Decl {
        class: class.to_owned(),
        ty: base.to_owned(),
        len,
    })
}

/// The names every renderer knows without a `Declare`.
const STANDARD: [&str; 26] = [
    "P",
    "Pw",
    "Pz",
    "N",
    "Np",
    "Cs",
    "Os",
    "s",
    "t",
    "st",
    "Ka",
    "Kd",
    "Ks",
    "Kr",
    "roughness",
    "specularcolor",
    "intensity",
    "lightcolor",
    "from",
    "to",
    "fov",
    "coneangle",
    "conedeltaangle",
    "beamdistribution",
    "texturename",
    "width",
];

/// The positional values, the parameters and the unknown parameter names
/// of a request ([`split_params`]).
pub type Split = (Vec<Value>, Vec<Param>, Vec<String>);

/// Splits `values` into `positional` leading values and a parameter list.
/// Inline declarations are checked and stripped; the names of parameters
/// neither declared nor standard are returned as the second list.
pub fn split_params(
    values: &[Value],
    positional: usize,
    declared: &HashMap<String, Decl>,
) -> Result<Split, String> {
    if values.len() < positional {
        return Err(format!(
            "expected at least {positional} argument{}, found {}",
            if positional == 1 { "" } else { "s" },
            values.len()
        ));
    }
    let (head, rest) = values.split_at(positional);
    if rest.len() % 2 != 0 {
        return Err("the parameter list is not \"name\" value pairs (odd count)".into());
    }
    let mut params = Vec::new();
    let mut unknown = Vec::new();
    for pair in rest.chunks(2) {
        let Some(token) = pair[0].str() else {
            return Err("a parameter name must be a string".into());
        };
        let mut words = token.rsplitn(2, char::is_whitespace);
        let name = words.next().unwrap_or("").to_owned();
        let inline = words.next().map(str::trim).filter(|d| !d.is_empty());
        if name.is_empty() {
            return Err("empty parameter name".into());
        }
        if let Some(decl) = inline {
            parse_decl(decl)
                .map_err(|e| format!("parameter {:?}: {e}", crate::input::excerpt(token)))?;
        } else if !declared.contains_key(&name) && !STANDARD.contains(&name.as_str()) {
            unknown.push(name.clone());
        }
        params.push(Param {
            name,
            value: pair[1].clone(),
        });
    }
    Ok((head.to_vec(), params, unknown))
}

/// The numbers of parameter `name`, if present.
pub fn param_nums(params: &[Param], name: &str) -> Option<Result<Vec<f64>, String>> {
    params.iter().find(|p| p.name == name).map(|p| {
        p.value
            .nums()
            .ok_or_else(|| format!("parameter {name:?} must be numbers"))
    })
}

/// Parameter `name` as one number (the first), or `default`.
pub fn param_f(params: &[Param], name: &str, default: f64) -> Result<f64, String> {
    match param_nums(params, name) {
        None => Ok(default),
        Some(v) => v?
            .first()
            .copied()
            .ok_or_else(|| format!("parameter {name:?} is empty")),
    }
}

/// Parameter `name` as three numbers, or `default`.
pub fn param_v3(params: &[Param], name: &str, default: DVec3) -> Result<DVec3, String> {
    match param_nums(params, name) {
        None => Ok(default),
        Some(v) => {
            let v = v?;
            if v.len() != 3 {
                return Err(format!(
                    "parameter {name:?} needs 3 numbers, found {}",
                    v.len()
                ));
            }
            Ok(DVec3::new(v[0], v[1], v[2]))
        }
    }
}

/// The `"P"` points of a primitive: a multiple of 3 numbers.
pub fn points(params: &[Param]) -> Result<Option<Vec<DVec3>>, String> {
    let Some(v) = param_nums(params, "P") else {
        return Ok(None);
    };
    let v = v?;
    if v.len() % 3 != 0 {
        return Err(format!(
            "\"P\" has {} numbers, not a multiple of 3",
            v.len()
        ));
    }
    Ok(Some(
        v.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect(),
    ))
}

/// The numbers of positional value `i` of `args`.
pub fn arg_nums(args: &[Value], i: usize, what: &str) -> Result<Vec<f64>, String> {
    args.get(i)
        .and_then(Value::nums)
        .ok_or_else(|| format!("{what} must be a number"))
}

/// Positional value `i` as one number.
pub fn arg_f(args: &[Value], i: usize, what: &str) -> Result<f64, String> {
    match arg_nums(args, i, what)?.as_slice() {
        [x] => Ok(*x),
        _ => Err(format!("{what} must be a single number")),
    }
}

/// Positional value `i` as a string.
pub fn arg_str<'a>(args: &'a [Value], i: usize, what: &str) -> Result<&'a str, String> {
    args.get(i)
        .and_then(Value::str)
        .ok_or_else(|| format!("{what} must be a string"))
}

/// All positional values as `n` numbers (bare or in one array).
pub fn all_nums(values: &[Value], n: usize) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    for v in values {
        out.extend(v.nums().ok_or_else(|| format!("expected {n} numbers"))?);
    }
    if out.len() != n {
        return Err(format!("expected {n} numbers, found {}", out.len()));
    }
    Ok(out)
}
