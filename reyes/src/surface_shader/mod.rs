//! Surface and displacement shaders written by users in WGSL
//! (docs/shaders.md).
//!
//! A surface shader is a `.wgsl` file that defines
//! `fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput`
//! (or `fn surface(ctx: ShadingContext) -> SurfaceOutput` without
//! parameters); a displacement shader defines
//! `fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32>`
//! (the displaced `P`) instead. Either may declare a `struct Parameters` of `f32`, `i32`, `u32`,
//! `bool` and `vecN<f32>` fields, and `const DEFAULTS = Parameters(...)`
//! with their defaults. It is written against the interface in
//! `shaders/reyes/surface_api.wgsl`, as the standard shaders are
//! (`shaders/reyes/surfaces_standard.wgsl`).
//!
//! - `check`: naga's checks on the user's text with the interface, errors
//!   at the user's line, and the reflection of the parameters;
//! - `rename`: the prefix that keeps shaders apart in one module;
//! - `values`: the scene's parameter values, typed against the shader;
//! - `codegen`: what the megakernel compiles in for a frame's shaders.

pub mod builtin;
mod check;
mod codegen;
mod cpu;
mod rename;
mod shadow_param;
mod table;
mod values;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use check::{DEFAULTS, DISPLACEMENT_ENTRY, ENTRY, NO_TEXTURE, PARAMETERS, interface_wgsl};
pub use codegen::megakernel_wgsl;
pub use cpu::{
    CpuDisplacement, CpuDisplacementFn, CpuSurface, CpuSurfaceFn, ShadingContext, ShadingHost,
    SurfaceOutput,
};
pub use shadow_param::{NO_SHADOW, ShadowDesc, ShadowSlot};
pub use table::{ShaderRef, ShaderTable};
pub use values::{ParameterWarning, pack_parameters};

use crate::input::{InputError, InputKind, read_text};
use crate::user_wgsl::UserWgslError;

/// What a shader computes, known from the function it defines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaderKind {
    /// `fn surface(...) -> SurfaceOutput`: the colour at a shading point.
    Surface,
    /// `fn displacement(...) -> vec3<f32>`: the displaced position.
    Displacement,
}

impl ShaderKind {
    /// The function a shader of this kind defines.
    pub fn entry(self) -> &'static str {
        match self {
            ShaderKind::Surface => ENTRY,
            ShaderKind::Displacement => DISPLACEMENT_ENTRY,
        }
    }

    /// The kind's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            ShaderKind::Surface => "surface",
            ShaderKind::Displacement => "displacement",
        }
    }
}

/// What a shader parameter holds, from its WGSL type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterKind {
    /// `f32`.
    Float,
    /// `i32`.
    Int,
    /// `u32`.
    Uint,
    /// `bool`.
    Bool,
    /// `vec2<f32>`.
    Vec2,
    /// `vec3<f32>` (a colour or a point).
    Vec3,
    /// `vec4<f32>`.
    Vec4,
    /// `TextureId`: the scene gives the texture's file.
    Texture,
    /// `ShadowId`: the scene gives a shadow map's file and its filter.
    Shadow,
}

impl ParameterKind {
    /// The WGSL type.
    pub fn wgsl(self) -> &'static str {
        match self {
            ParameterKind::Float => "f32",
            ParameterKind::Int => "i32",
            ParameterKind::Uint => "u32",
            ParameterKind::Bool => "bool",
            ParameterKind::Vec2 => "vec2<f32>",
            ParameterKind::Vec3 => "vec3<f32>",
            ParameterKind::Vec4 => "vec4<f32>",
            ParameterKind::Texture => "TextureId",
            ParameterKind::Shadow => "ShadowId",
        }
    }
}

/// One field of a shader's `Parameters`.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaderParameter {
    /// The field's name.
    pub name: String,
    /// Its type.
    pub kind: ParameterKind,
    /// Its default from `DEFAULTS`, as its slot stores it: four f32 words,
    /// integers and booleans by their bits (zero without `DEFAULTS`).
    pub default: [f32; 4],
}

/// A checked user shader: a surface shader, or a displacement shader
/// ([`SurfaceShader::kind`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceShader {
    /// The file it came from (as the scene names it, for messages).
    pub path: PathBuf,
    /// The user's text.
    pub source: String,
    /// The parameters, in declaration order: parameter `k` is in slot `k`
    /// of the object's block of `shader_parameters`.
    pub parameters: Vec<ShaderParameter>,
    /// Whether the entry function takes the parameters.
    pub takes_parameters: bool,
    /// Surface or displacement: which function the file defines.
    pub kind: ShaderKind,
    /// A Rust twin of a surface shader for the CPU reference (only through
    /// the API): without one, the reference cannot render objects with
    /// this shader.
    pub cpu: Option<CpuSurface>,
    /// A Rust twin of a displacement shader, likewise.
    pub cpu_displacement: Option<CpuDisplacement>,
}

impl SurfaceShader {
    /// Checks `source`, the text of the shader file `path`.
    pub fn from_source(path: &Path, source: String) -> Result<Self, SurfaceShaderError> {
        let checked = check::check(&source)?;
        Ok(Self {
            path: path.to_path_buf(),
            source,
            parameters: checked.parameters,
            takes_parameters: checked.takes_parameters,
            kind: checked.kind,
            cpu: None,
            cpu_displacement: None,
        })
    }

    /// Reads (within the WGSL input limit) and checks the shader file `path`.
    pub fn load(path: &Path) -> Result<Self, SurfaceShaderError> {
        let source = read_text(path, InputKind::Shader, InputKind::Shader.limit())
            .map_err(SurfaceShaderError::Read)?;
        Self::from_source(path, source)
    }

    /// Whether the CPU reference can run this shader (it has the twin of
    /// its kind).
    pub fn has_twin(&self) -> bool {
        match self.kind {
            ShaderKind::Surface => self.cpu.is_some(),
            ShaderKind::Displacement => self.cpu_displacement.is_some(),
        }
    }

    /// The parameter called `name`, with its slot.
    pub fn parameter(&self, name: &str) -> Option<(usize, &ShaderParameter)> {
        self.parameters
            .iter()
            .enumerate()
            .find(|(_, p)| p.name == name)
    }
}

/// Why a surface shader is refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SurfaceShaderError {
    /// The file cannot be read.
    #[error(transparent)]
    Read(InputError),
    /// naga refuses the source, or it reaches outside the interface.
    #[error(transparent)]
    Wgsl(#[from] UserWgslError),
    /// No `surface` or `displacement` function.
    #[error(
        "the shader defines no `fn {ENTRY}(ctx: ShadingContext, params: {PARAMETERS}) -> SurfaceOutput` (a surface shader) and no `fn {DISPLACEMENT_ENTRY}(ctx: ShadingContext, params: {PARAMETERS}) -> vec3<f32>` (a displacement shader); `params` is left out without `struct {PARAMETERS}`"
    )]
    MissingEntry,
    /// Both entry functions.
    #[error(
        "the shader defines both `fn {ENTRY}` and `fn {DISPLACEMENT_ENTRY}`; a file is one shader, of one kind"
    )]
    TwoEntries,
    /// The entry function has another signature.
    #[error(
        "`fn {}` must take `ctx: ShadingContext` (and `params: {PARAMETERS}`, if the shader declares it) and return `{}`",
        kind.entry(),
        match kind { ShaderKind::Surface => "SurfaceOutput", ShaderKind::Displacement => "vec3<f32>" }
    )]
    Signature {
        /// The kind the function's name makes the shader.
        kind: ShaderKind,
    },
    /// `Parameters` is not a struct.
    #[error("`{PARAMETERS}` must be a struct of the shader's parameters")]
    ParametersNotStruct,
    /// A shader of one kind where the scene needs the other.
    #[error(
        "the file is a {} shader (it defines `fn {}`), but the object uses it as its {} shader",
        found.name(),
        found.entry(),
        expected.name()
    )]
    WrongKind {
        /// What the scene uses the file as.
        expected: ShaderKind,
        /// What the file defines.
        found: ShaderKind,
    },
    /// An error in the interface's declarations, most likely caused by a
    /// user declaration of one of its names.
    #[error(
        "{message} (the shader may redefine a name of the shader interface: ShadingContext, SurfaceOutput, LightSample, ambient, diffuse, specular, illuminance, ...)"
    )]
    Interface {
        /// naga's message.
        message: String,
    },
    /// A parameter of a type parameters cannot have.
    #[error(
        "line {line}: parameter `{name}` must be f32, i32, u32, bool, vec2<f32>, vec3<f32>, vec4<f32>, TextureId or ShadowId"
    )]
    ParameterType {
        /// The field.
        name: String,
        /// The struct's line.
        line: u32,
    },
    /// `DEFAULTS` is not a constant `Parameters(...)` of literals.
    #[error(
        "line {line}: `{DEFAULTS}` must be `const {DEFAULTS} = {PARAMETERS}(...)` with one literal (or vector of literals) per field"
    )]
    Defaults {
        /// Its line.
        line: u32,
    },
    /// A texture parameter's file cannot be used.
    #[error("parameter `{name}`: {source}")]
    Texture {
        /// The parameter.
        name: String,
        /// Why.
        #[source]
        source: crate::texture::TextureError,
    },
    /// A shadow map parameter's file cannot be used.
    #[error("parameter `{name}`: shadow map {}: {source}", path.display())]
    Shadow {
        /// The parameter.
        name: String,
        /// The map's file.
        path: PathBuf,
        /// Why (boxed: the error is large, and rare).
        #[source]
        source: Box<crate::shadow::ShadowFileError>,
    },
    /// A shadow map parameter's filter cannot be used.
    #[error("parameter `{name}`: {problem}")]
    ShadowFilter {
        /// The parameter.
        name: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A scene value that does not fit its parameter.
    #[error("parameter `{name}` is {expected}, but the scene gives {given}")]
    Value {
        /// The parameter.
        name: String,
        /// Its WGSL type.
        expected: &'static str,
        /// What the scene gives.
        given: String,
    },
}

/// A value for a user shader's parameter: a boolean, a number (`f32`,
/// `i32`, `u32`), an array of 2 to 4 numbers (`vecN<f32>`), a string (a
/// `TextureId`'s or a `ShadowId`'s file), a texture table for a
/// `TextureId` (`{ path = "wood.png", color_space = "linear", wrap_s =
/// "clamp", wrap_t = "clamp" }`), or a shadow table for a `ShadowId`
/// (`{ path = "key.shad", blur = 0.01, bias = 0.05 }`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ShaderValue {
    /// `true` or `false`.
    Bool(bool),
    /// A number.
    Number(f64),
    /// An array of numbers.
    Numbers(Vec<f64>),
    /// A string.
    Text(String),
    /// A texture with its colour space and wrap modes (also a shadow map
    /// given as `{ path = ... }` alone).
    Texture(crate::texture::TextureDesc),
    /// A shadow map with its filter.
    Shadow(ShadowDesc),
}

#[cfg(test)]
mod tests;
