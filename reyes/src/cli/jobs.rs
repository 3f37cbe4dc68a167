//! The frames one `reyes render` draws: the scene named on the command
//! line, or each selected frame of a RIB file, with their outputs.
//!
//! Every output of every frame is checked before any work (against the
//! scene and the RIB archives, and against each other). The files a frame
//! reads besides (models, textures, shaders) are known once it is
//! prepared: its outputs and those of the frames after it are checked
//! against them, and against the files every earlier frame read, before it
//! renders. A frame may read what an earlier frame wrote (a depth map
//! made by a first pass), never what it or a later frame writes.

use std::cell::OnceCell;
use std::path::PathBuf;

use super::BoxError;
use super::args::RenderArgs;
use super::frames::{frame_path, select};
use super::input::{ReadFile, base_scene, load_rib, rib_base};
use super::prepare::{Prepared, prepare_base};
use super::render::Backend;
use crate::aov::Aov;
use crate::displacement::desc::{SOURCE_BUMPS, SOURCE_SINES, SOURCE_WGSL};
use crate::output::{OutputGuard, OutputKind, OutputPlan};
use crate::rib::{RibError, RibScene};

/// One frame to render and where it goes.
pub(crate) struct Job {
    /// `frame 2` for a frame of a RIB file with frames.
    label: Option<String>,
    /// The frame's scene, or why its requests make none; `None`: the scene
    /// named on the command line, read when its turn comes.
    scene: Option<Result<RibScene, RibError>>,
    /// The image, the statistics JSON and the trace (`None` for a frame
    /// whose scene failed: it writes nothing).
    outputs: Option<Outputs>,
}

/// The files one frame writes.
struct Outputs {
    image: PathBuf,
    /// The frame writes the depth output (`--aov z`, or a RIB `Display`
    /// of mode `z`).
    depth: bool,
    stats_json: Option<PathBuf>,
    trace: Option<PathBuf>,
}

impl Job {
    /// Records the frame's outputs in `guard`; the plan of its image and
    /// statistics.
    fn add_outputs(&self, guard: &mut OutputGuard) -> Result<Option<OutputPlan>, BoxError> {
        let Some(outputs) = &self.outputs else {
            return Ok(None);
        };
        let label = self.label.as_deref();
        let (image, stats_json) = (&outputs.image, outputs.stats_json.as_deref());
        let plan = if outputs.depth {
            OutputPlan::of_depth_frame(guard, label, image, stats_json)?
        } else {
            OutputPlan::of_frame(guard, label, image, stats_json)?
        };
        if let Some(trace) = &outputs.trace {
            let what = label.map_or("trace".to_owned(), |l| format!("trace of {l}"));
            guard.add_output(OutputKind::Json, what, trace)?;
        }
        Ok(Some(plan))
    }
}

/// The frames `args` asks for, with their outputs, and the files read to
/// find them (a RIB file and its archives).
pub(crate) fn plan(args: &RenderArgs) -> Result<(Vec<Job>, Vec<ReadFile>), BoxError> {
    let rib = args
        .scene
        .as_deref()
        .filter(|s| s.extension().is_some_and(|e| e.eq_ignore_ascii_case("rib")));
    let Some(path) = rib else {
        if let Some(selection) = &args.frame {
            return Err(format!(
                "--frame {selection}: selects frames of a RIB file; {} has none",
                args.scene
                    .as_deref()
                    .map_or("the teapot".to_owned(), |s| s.display().to_string())
            )
            .into());
        }
        let depth = args.aov == Some(Aov::Z);
        let outputs = outputs(args, None, None, false, depth)?;
        let job = Job {
            label: None,
            scene: None,
            outputs: Some(outputs),
        };
        return Ok((vec![job], Vec::new()));
    };
    let frames = load_rib(path, args.lenient)?;
    let selected = select(path, &frames, args.frame.as_ref())?;
    let several = selected.len() > 1;
    let sources = frames
        .sources
        .iter()
        .enumerate()
        .map(|(i, p)| (if i == 0 { "scene" } else { "RIB archive" }, p.clone()))
        .collect();
    let mut jobs = Vec::new();
    for (i, frame) in frames.frames.into_iter().enumerate() {
        if !selected.contains(&i) {
            continue;
        }
        let label = frame.number.map(|_| frame.label());
        let outputs = match &frame.scene {
            Ok(scene) => {
                let display = scene.display.as_deref();
                if several && args.output.is_none() && display.is_none() {
                    return Err(format!(
                        "{}: {} has no Display file, and several frames are selected: name the images with -o, e.g. -o out.####.png (the #s take the frame number)",
                        path.display(),
                        frame.label()
                    )
                    .into());
                }
                let depth = args.aov.unwrap_or(scene.scene.aov) == Aov::Z;
                Some(self::outputs(args, display, frame.number, several, depth)?)
            }
            Err(_) => None,
        };
        jobs.push(Job {
            label,
            scene: Some(frame.scene),
            outputs,
        });
    }
    Ok((jobs, sources))
}

/// The outputs of the frame numbered `number` whose `Display` file is
/// `display`: `-o` (a pattern takes the number), else the `Display` file,
/// else `reyes.png` (`reyes.exr` for a depth frame); the statistics and the trace as their flags say.
fn outputs(
    args: &RenderArgs,
    display: Option<&str>,
    number: Option<u32>,
    several: bool,
    depth: bool,
) -> Result<Outputs, BoxError> {
    let image = match (&args.output, display) {
        (Some(output), _) => frame_path(output, "-o", number, several)?,
        // A relative name is relative to the current directory, as in
        // RenderMan.
        (None, Some(display)) => PathBuf::from(display),
        (None, None) if depth => PathBuf::from("reyes.exr"),
        (None, None) => PathBuf::from("reyes.png"),
    };
    let per_frame = |path: &Option<PathBuf>, flag: &str| {
        path.as_deref()
            .map(|p| frame_path(p, flag, number, several))
            .transpose()
    };
    Ok(Outputs {
        image,
        depth,
        stats_json: per_frame(&args.stats_json, "--stats-json")?,
        trace: per_frame(&args.trace, "--trace")?,
    })
}

/// The files named on the command line that the run reads: the scene and
/// a displacement height map or `.wgsl` function (the built-in sources are
/// no file).
fn command_line_inputs(args: &RenderArgs) -> Vec<ReadFile> {
    let mut inputs = Vec::new();
    if let Some(scene) = &args.scene {
        inputs.push(("scene", scene.clone()));
    }
    if let Some(source) = args.displace.as_deref()
        && source != SOURCE_BUMPS
        && source != SOURCE_SINES
        && source != SOURCE_WGSL
    {
        inputs.push(("displacement", PathBuf::from(source)));
    }
    inputs
}

/// Renders `jobs` in order. A frame that fails is reported and stops the
/// later ones, unless `--keep-going`; then the run fails with the list of
/// failed frames. A run of one frame returns its error as it is.
pub(crate) fn run(
    args: &RenderArgs,
    mut jobs: Vec<Job>,
    sources: Vec<ReadFile>,
) -> Result<(), BoxError> {
    // Every output, checked before any work: a render must not run for
    // minutes towards an output it cannot write, or overwrite its inputs.
    let mut reads = command_line_inputs(args);
    reads.extend(sources);
    let mut guard = OutputGuard::new();
    guard.add_inputs(reads.iter().map(|(l, p)| (*l, p)))?;
    for job in &jobs {
        job.add_outputs(&mut guard)?;
    }
    let gpu = OnceCell::new();
    let mut backend = Backend::new(args, &gpu);
    if jobs.len() == 1 {
        let label = jobs[0].label.clone();
        let scene = jobs[0].scene.take();
        return render_job(args, &mut backend, scene, &jobs, &mut reads)
            .map_err(|e| labelled(label.as_deref(), e));
    }
    let mut failed = Vec::new();
    let mut not_rendered = Vec::new();
    for k in 0..jobs.len() {
        let label = jobs[k].label.clone().unwrap_or_default();
        if !failed.is_empty() && !args.keep_going {
            not_rendered.push(label);
            continue;
        }
        let scene = jobs[k].scene.take();
        if let Err(error) = render_job(args, &mut backend, scene, &jobs[k..], &mut reads) {
            super::print_error(labelled(Some(&label), error).as_ref());
            failed.push(label);
        }
    }
    if failed.is_empty() {
        return Ok(());
    }
    let mut message = format!(
        "{} of {} frames failed: {}",
        failed.len(),
        jobs.len(),
        failed.join(", ")
    );
    if !not_rendered.is_empty() {
        message.push_str(&format!(
            "; not rendered: {} (a failed frame stops the later ones; --keep-going renders them)",
            not_rendered.join(", ")
        ));
    }
    Err(message.into())
}

/// Prepares and renders the first of `jobs` (whose scene is `scene`) and
/// writes it, once its outputs and those of the later `jobs` are checked
/// against every file read so far (`reads`, to which it adds its own).
fn render_job(
    args: &RenderArgs,
    backend: &mut Backend<'_>,
    scene: Option<Result<RibScene, RibError>>,
    jobs: &[Job],
    reads: &mut Vec<ReadFile>,
) -> Result<(), BoxError> {
    let job = &jobs[0];
    let label = job.label.as_deref();
    let base = match scene {
        None => base_scene(args.scene.as_deref(), args.lenient, None)?,
        Some(rib) => {
            let rib = rib?;
            let sources = rib.sources.clone();
            rib_base(rib, label, &sources)?
        }
    };
    let Prepared { scene, read } = prepare_base(args, base)?;
    reads.extend(read);
    let mut guard = OutputGuard::new();
    guard.add_inputs(reads.iter().map(|(l, p)| (*l, p)))?;
    let plan = job
        .add_outputs(&mut guard)?
        .expect("a frame with a scene has outputs");
    for later in &jobs[1..] {
        later.add_outputs(&mut guard)?;
    }
    guard.prepare_dirs()?;
    let outputs = job.outputs.as_ref().expect("checked above");
    let paths = (outputs.image.as_path(), outputs.trace.as_deref());
    backend.render_and_write(args, &scene, &plan, paths, label)
}

/// A frame's error, named by the frame.
#[derive(Debug, thiserror::Error)]
#[error("{label}: {source}")]
struct FrameError {
    label: String,
    #[source]
    source: BoxError,
}

/// `error`, prefixed with the frame's `label` if it has one.
fn labelled(label: Option<&str>, error: BoxError) -> BoxError {
    match label {
        Some(label) => Box::new(FrameError {
            label: label.to_owned(),
            source: error,
        }),
        None => error,
    }
}
