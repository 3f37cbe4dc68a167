//! What the command line reads: the scene (a TOML or RIB scene, a bare
//! model or the embedded teapot) and the displacement it asks for.

use std::path::{Path, PathBuf};

use super::BoxError;
use super::args::RenderArgs;
use super::frames::FrameSelection;
use crate::displacement::DisplacementDesc;
use crate::displacement::desc::{SOURCE_BUMPS, SOURCE_IMAGE, SOURCE_SINES, SOURCE_WGSL};
use crate::input::InputKind;
use crate::model::Model;
use crate::output::console::errln;
use crate::scene::Scene;

/// A file a command read, for its [`crate::output::OutputGuard`]: what it
/// is (`scene`, `model`...) and its path.
pub(crate) type ReadFile = (&'static str, PathBuf);

/// The scene named on the command line, before overrides.
pub(crate) struct BaseScene {
    /// The scene.
    pub(crate) scene: Scene,
    /// The models of a scene that brings them in memory (a RIB, a bare
    /// model read once here) rather than by path. A bare model's object
    /// names its file only for messages (a model name is text): the file
    /// is read by its path as given, which need not be UTF-8.
    pub(crate) models: Option<Vec<Model>>,
    /// The files read for it: the scene file, and a RIB's archives. (The
    /// models a scene names by path are read later, see
    /// [`Scene::model_files`].)
    pub(crate) read: Vec<ReadFile>,
    /// Of a RIB frame: where each light was declared (`scene.rib:12`), for
    /// messages; empty otherwise.
    pub(crate) light_origins: Vec<String>,
    /// Of a frame of an animated TOML scene: its shutter is the command
    /// line's already, and its poses at close were made with it, so
    /// `--shutter` must not apply again.
    pub(crate) shutter_applied: bool,
}

/// The scene named on the command line, before overrides; `lenient` reads
/// a RIB's unbalanced structure with warnings ([`crate::rib::RibOptions`]);
/// of a RIB file's frames, the first `selection` names.
/// A scene without objects is warned about (the RIB reader's warnings say
/// it for a RIB).
pub(crate) fn base_scene(
    path: Option<&Path>,
    lenient: bool,
    selection: Option<&FrameSelection>,
) -> Result<BaseScene, BoxError> {
    let Some(path) = path else {
        if let Some(selection) = selection {
            return Err(format!(
                "--frame {selection}: selects frames of a RIB file, not of the teapot"
            )
            .into());
        }
        return Ok(BaseScene {
            scene: Scene::default_teapot(),
            models: None,
            read: Vec::new(),
            light_origins: Vec::new(),
            shutter_applied: false,
        });
    };
    let scene_file = || vec![("scene", path.to_path_buf())];
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if let Some(selection) = selection
        && extension.as_deref() != Some("rib")
    {
        return Err(format!(
            "--frame {selection}: selects frames of a RIB file; {} is none",
            path.display()
        )
        .into());
    }
    match extension.as_deref() {
        Some("toml") => {
            let scene = Scene::load(path)?;
            // An animated scene is seen at its first frame (`reyes render`
            // makes its frames itself, see `super::sequence`).
            let animated = scene.is_animated();
            let scene = if animated { scene.frame(1)? } else { scene };
            if scene.objects.is_empty() {
                errln!(
                    "warning: {}: {}",
                    path.display(),
                    crate::scene::NO_OBJECTS_WARNING
                )?;
            }
            Ok(BaseScene {
                scene,
                models: None,
                read: scene_file(),
                light_origins: Vec::new(),
                shutter_applied: animated,
            })
        }
        Some("rib") => {
            let frames = super::rib_plan::plan_rib(path, lenient)?;
            for warning in frames.requests_not_run() {
                errln!("warning: {warning}")?;
            }
            let selected = super::frames::select(path, &frames, selection)?;
            if selected.len() > 1 {
                errln!(
                    "note: {} frames are selected ({}); this shows the first, {} (select another with --frame N)",
                    selected.len(),
                    frames.list(),
                    frames.frames[selected[0]].label()
                )?;
            }
            let several = frames.frames.len() > 1;
            let (frame, sources) = frames.into_frame(selected[0]).expect("a selected frame");
            let label = frame.number.map(|_| frame.label());
            // The plan kept the models of a file's only frame; of several,
            // the selected one is read again, alone.
            let scene = if several {
                super::rib_plan::Reread::new(path, lenient).frame(selected[0], frame.number)??
            } else {
                frame.scene?
            };
            rib_base(scene, label.as_deref(), &sources)
        }
        Some("bpt" | "bez" | "obj") => {
            let model = Model::load(path).map_err(|e| -> BoxError {
                // Parse errors give only the line; name the file as the
                // read errors already do.
                match e.line() {
                    Some(_) => format!("{}: {e}", path.display()).into(),
                    None => e.into(),
                }
            })?;
            Ok(BaseScene {
                scene: Scene::for_model(path.to_string_lossy(), &model),
                models: Some(vec![model]),
                read: vec![("model", path.to_path_buf())],
                light_origins: Vec::new(),
                shutter_applied: false,
            })
        }
        _ => Err(format!(
            "{}: unknown scene type; expected a .toml or .rib scene or a .bpt/.bez/.obj model",
            path.display()
        )
        .into()),
    }
}

/// The base scene of one frame of a RIB file (`label` names it in the
/// notes when the file has frames), whose files are `sources`: its
/// warnings and its `Display` file are printed.
pub(crate) fn rib_base(
    rib: crate::rib::RibScene,
    label: Option<&str>,
    sources: &[PathBuf],
) -> Result<BaseScene, BoxError> {
    let prefix = label.map(|l| format!("{l}: ")).unwrap_or_default();
    for warning in &rib.warnings {
        errln!("warning: {prefix}{warning}")?;
    }
    if let Some(display) = &rib.display {
        errln!(
            "note: {prefix}the RIB's Display file is {display}: the image goes there unless -o is given"
        )?;
    }
    // The first source is the scene itself, the others archives.
    let read = sources
        .iter()
        .enumerate()
        .map(|(i, path)| (if i == 0 { "scene" } else { "RIB archive" }, path.clone()))
        .collect();
    // The models stay in memory: nothing is written for a render.
    Ok(BaseScene {
        scene: rib.scene,
        models: Some(rib.models),
        read,
        light_origins: rib
            .light_origins
            .iter()
            .map(|(file, line)| format!("{}:{line}", file.display()))
            .collect(),
        shutter_applied: false,
    })
}

/// The `.wgsl` file `--displace` names, if it names one.
pub(crate) fn wgsl_file(args: &RenderArgs) -> Option<&Path> {
    let source = Path::new(args.displace.as_deref()?);
    source
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wgsl"))
        .then_some(source)
}

/// The displacement the command line asks for, if any. A `.wgsl` source is
/// read here; the values are checked with the scene.
pub(crate) fn displacement(args: &RenderArgs) -> Result<Option<DisplacementDesc>, BoxError> {
    let (Some(source), Some(scale)) = (&args.displace, args.displace_scale) else {
        return Ok(None);
    };
    let (source, wgsl, file) = if wgsl_file(args).is_some() {
        let text =
            crate::input::read_text(Path::new(source), InputKind::Wgsl, InputKind::Wgsl.limit())?;
        (SOURCE_WGSL.to_owned(), Some(text), None)
    } else if source == SOURCE_WGSL {
        return Err(format!(
            "--displace {SOURCE_WGSL} needs the function: pass the path of a .wgsl file"
        )
        .into());
    } else if source == SOURCE_BUMPS || source == SOURCE_SINES {
        (source.to_string_lossy().into_owned(), None, None)
    } else {
        // A height map, by its path as given (it need not be UTF-8). A
        // relative path means the current directory, not the scene's: make
        // it absolute so the scene's base directory does not apply.
        let path = std::env::current_dir()?.join(source);
        (SOURCE_IMAGE.to_owned(), None, Some(path))
    };
    Ok(Some(DisplacementDesc {
        source,
        scale,
        bound: args.displace_bound,
        tiling: args.displace_tiling.unwrap_or(1.0),
        wgsl,
        file,
        parameters: Default::default(),
    }))
}
