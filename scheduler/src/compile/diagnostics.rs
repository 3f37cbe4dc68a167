//! Parses and validates the generated module with naga, translating errors
//! back to the user's own source (procedure body, library or item declaration).

use std::error::Error as _;

use naga::valid::{ModuleInfo, ValidationFlags, Validator};

use crate::CompileError;
use crate::codegen::module::Rendered;

/// What naga's validator allows a module compiled for a device with
/// `features`: the capabilities wgpu gives such a device. Every generated
/// module is validated with them, here and in the workspace's own checks
/// of the generated code.
pub fn validation_capabilities(features: wgpu::Features) -> naga::valid::Capabilities {
    wgpu_naga_bridge::features_to_naga_capabilities(features, wgpu::DownlevelFlags::all())
}

/// Parses and validates `rendered` for `features`.
pub(crate) fn parse_and_validate(
    rendered: &Rendered,
    features: wgpu::Features,
) -> Result<(naga::Module, ModuleInfo), CompileError> {
    let source = &rendered.text;
    let module = naga::front::wgsl::parse_str(source).map_err(|error| {
        let mut message = error.message().to_owned();
        for (_, label) in error.labels() {
            if !label.is_empty() {
                message.push_str(&format!("; {label}"));
            }
        }
        locate(rendered, error.location(source), message)
    })?;
    let info = Validator::new(ValidationFlags::all(), validation_capabilities(features))
        .validate(&module)
        .map_err(|error| {
            let mut message = error.as_inner().to_string();
            let mut source_error = error.as_inner().source();
            while let Some(inner) = source_error {
                message.push_str(&format!(": {inner}"));
                source_error = inner.source();
            }
            for (_, label) in error.spans() {
                if !label.is_empty() {
                    message.push_str(&format!("; {label}"));
                }
            }
            locate(rendered, error.location(source), message)
        })?;
    Ok((module, info))
}

fn locate(
    rendered: &Rendered,
    location: Option<naga::SourceLocation>,
    message: String,
) -> CompileError {
    let (line, column) = location
        .map(|l| (l.line_number, l.line_position))
        .unwrap_or((0, 0));
    let (origin, line, column) = rendered.locate(line, column);
    CompileError::Wgsl {
        origin,
        line,
        column,
        message,
    }
}
