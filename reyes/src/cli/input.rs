//! What the command line reads: the scene (a TOML or RIB scene, a bare
//! model or the embedded teapot) and the displacement it asks for.

use std::path::Path;

use super::BoxError;
use super::args::RenderArgs;
use crate::displacement::DisplacementDesc;
use crate::displacement::desc::{SOURCE_BUMPS, SOURCE_SINES, SOURCE_WGSL};
use crate::input::InputKind;
use crate::model::Model;
use crate::scene::Scene;

/// The scene named on the command line, before overrides, and the models
/// of a scene that brings them in memory (RIB) rather than by path.
pub(crate) fn base_scene(path: Option<&Path>) -> Result<(Scene, Option<Vec<Model>>), BoxError> {
    let Some(path) = path else {
        return Ok((Scene::default_teapot(), None));
    };
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("toml") => Ok((Scene::load(path)?, None)),
        Some("rib") => {
            let rib = crate::rib::RibScene::load(path)?;
            for warning in &rib.warnings {
                eprintln!("warning: {warning}");
            }
            if let Some(display) = &rib.display {
                eprintln!(
                    "note: the RIB's Display file is {display}: the image goes there unless -o is given"
                );
            }
            // The models stay in memory: nothing is written for a render.
            Ok((rib.scene, Some(rib.models)))
        }
        Some("bpt" | "bez") => {
            let model = Model::load(path).map_err(|e| -> BoxError {
                // Parse errors give only the line; name the file as the
                // read errors already do.
                match e.line() {
                    Some(_) => format!("{}: {e}", path.display()).into(),
                    None => e.into(),
                }
            })?;
            Ok((Scene::for_model(path.to_string_lossy(), &model), None))
        }
        _ => Err(format!(
            "{}: unknown scene type; expected a .toml or .rib scene or a .bpt/.bez model",
            path.display()
        )
        .into()),
    }
}

/// The displacement the command line asks for, if any. A `.wgsl` source is
/// read here; the values are checked with the scene.
pub(crate) fn displacement(args: &RenderArgs) -> Result<Option<DisplacementDesc>, BoxError> {
    let (Some(source), Some(scale)) = (&args.displace, args.displace_scale) else {
        return Ok(None);
    };
    let is_wgsl = Path::new(source)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wgsl"));
    let (source, wgsl) = if is_wgsl {
        let text =
            crate::input::read_text(Path::new(source), InputKind::Wgsl, InputKind::Wgsl.limit())?;
        (SOURCE_WGSL.to_owned(), Some(text))
    } else if source == SOURCE_WGSL {
        return Err(format!(
            "--displace {SOURCE_WGSL} needs the function: pass the path of a .wgsl file"
        )
        .into());
    } else {
        // A relative PNG path means the current directory, not the scene's:
        // make it absolute so the scene's base directory does not apply.
        let path = Path::new(source);
        let source = if source == SOURCE_BUMPS || source == SOURCE_SINES || path.is_absolute() {
            source.clone()
        } else {
            std::env::current_dir()?
                .join(path)
                .to_string_lossy()
                .into_owned()
        };
        (source, None)
    };
    Ok(Some(DisplacementDesc {
        source,
        scale,
        bound: args.displace_bound,
        tiling: args.displace_tiling.unwrap_or(1.0),
        wgsl,
    }))
}
