//! The requests a RIB file runs between its frames (`MakeShadow`,
//! `MakeCubeFaceEnvironment`), run by
//! `reyes render` in their place: after the frames before them are
//! written, before the next frame is prepared ([`crate::rib::FrameRequest`]).

use super::BoxError;
use super::input::ReadFile;
use crate::output::console::outln;
use crate::output::{OutputError, OutputGuard, OutputKind};
use crate::rib::FrameRequest;

/// The label of the shadow maps a frame reads, in its list of files read.
pub(crate) const SHADOW_MAP_READ: &str = "shadow map";

/// A request that failed, named by its file, line and arguments.
#[derive(Debug, thiserror::Error)]
#[error("{request}: {source}")]
struct RequestError {
    request: String,
    #[source]
    source: BoxError,
}

/// The label of a request's output in the run's [`OutputGuard`].
const MADE_BY: &str = " made by ";

/// Records the maps `requests` make as outputs of the run, before any
/// work: a frame's `Display` must not replace one of them. Several
/// requests may remake one map (a file remakes its maps between frames).
pub(crate) fn add_outputs<'a>(
    guard: &mut OutputGuard,
    requests: impl IntoIterator<Item = &'a FrameRequest>,
) -> Result<(), BoxError> {
    for request in requests {
        let made = match request {
            FrameRequest::MakeShadow { .. } => "shadow map",
            FrameRequest::MakeCubeFaceEnvironment { .. } => "environment map",
        };
        let label = format!("{made}{MADE_BY}{}", request.describe());
        match guard.add_output(output_kind(request), label, request.output()) {
            Err(OutputError::SameFile { first, .. }) if first.contains(MADE_BY) => {}
            other => {
                other?;
            }
        }
    }
    Ok(())
}

/// What a request writes, for the guard.
fn output_kind(request: &FrameRequest) -> OutputKind {
    match request {
        FrameRequest::MakeShadow { .. } => OutputKind::Depth,
        FrameRequest::MakeCubeFaceEnvironment { .. } => OutputKind::Environment,
    }
}

/// The label of what a request remakes, among the files the run reads: a
/// file may remake a map an earlier frame read.
fn remade_label(request: &FrameRequest) -> &'static str {
    match request {
        FrameRequest::MakeShadow { .. } => SHADOW_MAP_READ,
        FrameRequest::MakeCubeFaceEnvironment { .. } => "texture",
    }
}

/// Runs `request`. Its output may not replace a file the run reads
/// (`reads`: the scene, its archives, models, textures...), other than a
/// map of its kind an earlier frame read: a file may remake a map between
/// frames.
pub(crate) fn run_request(request: &FrameRequest, reads: &[ReadFile]) -> Result<(), BoxError> {
    let run = || -> Result<(), BoxError> {
        let mut guard = OutputGuard::new();
        let remade = remade_label(request);
        guard.add_inputs(
            reads
                .iter()
                .filter(|(label, _)| *label != remade)
                .map(|(label, path)| (*label, path)),
        )?;
        match request {
            FrameRequest::MakeShadow {
                picture, shadow, ..
            } => {
                guard.add_output(OutputKind::Depth, "shadow map", shadow)?;
                let map = crate::output::make_shadow(picture, shadow)?;
                outln!(
                    "wrote shadow map {} ({}x{}, from {})",
                    shadow.display(),
                    map.width,
                    map.height,
                    picture.display()
                )?;
            }
            FrameRequest::MakeCubeFaceEnvironment {
                faces,
                environment,
                fov,
                ..
            } => {
                guard.add_output(OutputKind::Environment, "environment map", environment)?;
                let (width, height) =
                    crate::output::make_cube_face_environment(faces, *fov, environment)?;
                outln!(
                    "wrote environment map {} ({width}x{height}, from the cube faces {} ...)",
                    environment.display(),
                    faces[0].display()
                )?;
            }
        }
        Ok(())
    };
    run().map_err(|source| {
        Box::new(RequestError {
            request: request.describe(),
            source,
        }) as BoxError
    })
}
