//! The requests a RIB file runs between its frames (`MakeShadow`), run by
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
const MADE_MAP: &str = "shadow map made by";

/// Records the maps `requests` make as outputs of the run, before any
/// work: a frame's `Display` must not replace one of them. Several
/// requests may remake one map (a file remakes its maps between frames).
pub(crate) fn add_outputs<'a>(
    guard: &mut OutputGuard,
    requests: impl IntoIterator<Item = &'a FrameRequest>,
) -> Result<(), BoxError> {
    for request in requests {
        let FrameRequest::MakeShadow { shadow, .. } = request;
        let label = format!("{MADE_MAP} {}", request.describe());
        match guard.add_output(OutputKind::Depth, label, shadow) {
            Err(OutputError::SameFile { first, .. }) if first.starts_with(MADE_MAP) => {}
            other => {
                other?;
            }
        }
    }
    Ok(())
}

/// Runs `request`. Its output may not replace a file the run reads
/// (`reads`: the scene, its archives, models, textures...), other than a
/// shadow map an earlier frame read: a file may remake a map between
/// frames.
pub(crate) fn run_request(request: &FrameRequest, reads: &[ReadFile]) -> Result<(), BoxError> {
    let run = || -> Result<(), BoxError> {
        let FrameRequest::MakeShadow {
            picture, shadow, ..
        } = request;
        let mut guard = OutputGuard::new();
        guard.add_inputs(
            reads
                .iter()
                .filter(|(label, _)| *label != SHADOW_MAP_READ)
                .map(|(label, path)| (*label, path)),
        )?;
        guard.add_output(OutputKind::Depth, "shadow map", shadow)?;
        let map = crate::output::make_shadow(picture, shadow)?;
        outln!(
            "wrote shadow map {} ({}x{}, from {})",
            shadow.display(),
            map.width,
            map.height,
            picture.display()
        )?;
        Ok(())
    };
    run().map_err(|source| {
        Box::new(RequestError {
            request: request.describe(),
            source,
        }) as BoxError
    })
}
