//! The frames one `reyes render` draws: the scene named on the command
//! line, each selected frame of a RIB file ([`super::rib_plan`]), or each
//! frame of a TOML sequence ([`super::sequence`]), with their outputs.
//!
//! Every output of every frame is checked before any work (against the
//! scene and the RIB archives, and against each other). The files a frame
//! reads besides (models, textures, shaders) are known once it is
//! prepared: its outputs and those of the frames after it are checked
//! against them, and against the files every earlier frame read, before it
//! renders. A frame may read what an earlier frame wrote (a depth map
//! made by a first pass), never what it or a later frame writes.
//!
//! A RIB file's requests between frames (`MakeShadow`) run in their place:
//! those before a selected frame run before it is prepared, those after the
//! file's last frame once it is written, if it is selected; a request that
//! fails stops what follows as a failed frame does ([`super::requests`]).
//!
//! A RIB file of several frames is read twice: once to plan (each frame's
//! geometry is dropped as soon as its outputs are known), and again, one
//! frame at a time, to render ([`crate::rib::FrameStream`]), so that memory
//! holds one frame's geometry, not the whole file's. A TOML sequence's
//! frames share the models, read once; the outputs of its first frame are
//! checked against every later frame's, and each later frame's against
//! the files read, which are the same for every frame.

use std::cell::OnceCell;
use std::path::{Path, PathBuf};

use super::BoxError;
use super::args::RenderArgs;
use super::frames::{FrameSelection, frame_path, select};
use super::input::{BaseScene, ReadFile, base_scene, rib_base};
use super::prepare::{Prepared, prepare_base};
use super::render::Backend;
use super::rib_plan::{Reread, plan_rib};
use super::sequence::{SequenceArgs, SequenceReport, SequenceSource, plan_toml};
use crate::aov::Aov;
use crate::displacement::desc::{SOURCE_BUMPS, SOURCE_SINES, SOURCE_WGSL};
use crate::output::console::{errln, outln};
use crate::output::{OutputGuard, OutputKind, OutputPlan};
use crate::rib::{FrameRequest, RibError, RibScene};
use crate::scene::Scene;
use crate::stats::RenderStats;

/// One frame to render and where it goes.
pub(crate) struct Job {
    /// `frame 2` for a frame of a RIB file with frames.
    label: Option<String>,
    /// The frame's scene, or why its requests make none; `None`: the scene
    /// named on the command line, read when its turn comes. Without its
    /// models when `reread` is set.
    scene: Option<Result<RibScene, RibError>>,
    /// The frame's place in its RIB file and its number, when the file has
    /// several frames: its scene is read again when its turn comes.
    reread: Option<(usize, Option<u32>)>,
    /// The image, the statistics JSON and the trace (`None` for a frame
    /// whose scene failed: it writes nothing).
    outputs: Option<Outputs>,
    /// The RIB requests to run before the frame is prepared.
    requests_before: Vec<FrameRequest>,
    /// A frame of a TOML sequence: its still scene ([`Scene::frame`]),
    /// rendered with the models of [`Plan::sequence`].
    still: Option<Box<Scene>>,
    /// The frame's number (a RIB's `FrameBegin n`), which seeds its
    /// samples ([`Scene::sampling_seed`]).
    number: Option<u32>,
}

/// What one `reyes render` does: its frames, the files read to find them
/// (a RIB file and its archives) and the requests after the last frame.
pub(crate) struct Plan {
    jobs: Vec<Job>,
    sources: Vec<ReadFile>,
    requests_after: Vec<FrameRequest>,
    /// Of a TOML sequence: the scene file and its models, read once.
    sequence: Option<SequenceSource>,
}

impl Plan {
    /// The plan of a TOML sequence's `jobs`, which share `source`.
    pub(crate) fn of_sequence(jobs: Vec<Job>, source: SequenceSource) -> Plan {
        Plan {
            jobs,
            sources: vec![("scene", source.path.clone())],
            requests_after: Vec::new(),
            sequence: Some(source),
        }
    }
}

/// The files one frame writes.
pub(crate) struct Outputs {
    image: PathBuf,
    /// The frame writes the depth output (`--aov z`, or a RIB `Display`
    /// of mode `z`).
    depth: bool,
    stats_json: Option<PathBuf>,
    trace: Option<PathBuf>,
}

impl Job {
    /// Frame `label` of a TOML sequence, whose scene is `still`.
    pub(crate) fn of_sequence(label: String, outputs: Outputs, still: Scene) -> Job {
        Job {
            label: Some(label),
            scene: None,
            reread: None,
            outputs: Some(outputs),
            requests_before: Vec::new(),
            number: Some(still.sampling_seed),
            still: Some(Box::new(still)),
        }
    }

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

/// The frames `args` asks for (those of `selection`, `--frame` or
/// `--frames`), with their outputs and requests, and the files read to
/// find them (a RIB file and its archives).
pub(crate) fn plan(
    args: &RenderArgs,
    selection: Option<&FrameSelection>,
) -> Result<Plan, BoxError> {
    let has_extension = |extension: &str| {
        args.scene.as_deref().filter(|s| {
            s.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case(extension))
        })
    };
    if let Some(path) = has_extension("toml")
        && let Some(plan) = plan_toml(args, path, selection)?
    {
        return Ok(plan);
    }
    let Some(path) = has_extension("rib") else {
        if let Some(selection) = selection {
            return Err(format!(
                "--frame {selection}: selects frames of a RIB file or a TOML scene; {} is neither",
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
            reread: None,
            outputs: Some(outputs),
            requests_before: Vec::new(),
            still: None,
            number: None,
        };
        return Ok(Plan {
            jobs: vec![job],
            sources: Vec::new(),
            requests_after: Vec::new(),
            sequence: None,
        });
    };
    let frames = plan_rib(path, args.lenient)?;
    let reread = frames.frames.len() > 1;
    let selected = select(path, &frames, selection)?;
    let several = selected.len() > 1;
    let sources = frames
        .sources
        .iter()
        .enumerate()
        .map(|(i, p)| (if i == 0 { "scene" } else { "RIB archive" }, p.clone()))
        .collect();
    // The requests after the last frame run once it is written.
    let last_selected = selected.last() == Some(&(frames.frames.len() - 1));
    let requests_after = if last_selected {
        frames.requests_after
    } else {
        Vec::new()
    };
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
            reread: reread.then_some((i, frame.number)),
            scene: Some(frame.scene),
            outputs,
            requests_before: frame.requests_before,
            still: None,
            number: frame.number,
        });
    }
    Ok(Plan {
        jobs,
        sources,
        requests_after,
        sequence: None,
    })
}

/// The outputs of the frame numbered `number` whose `Display` file is
/// `display`: `-o` (a pattern takes the number), else the `Display` file,
/// else `reyes.png` (`reyes.exr` for a depth frame); the statistics and the trace as their flags say.
pub(crate) fn outputs(
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

/// Renders the plan's frames in order, each after the requests before it,
/// then runs the requests after the last. A frame or request that fails is
/// reported and stops what follows, unless `--keep-going`; then the run
/// fails with the list of what failed. A run of one frame and no request
/// returns its error as it is. `--skip-existing` skips the frames whose
/// image exists; of a TOML sequence, a line on stderr announces each frame
/// (unless `--quiet`), and a table on stdout sums the run up.
pub(crate) fn run(args: &RenderArgs, sequence: &SequenceArgs, plan: Plan) -> Result<(), BoxError> {
    let Plan {
        mut jobs,
        sources,
        requests_after,
        sequence: source,
    } = plan;
    // Every output, checked before any work: a render must not run for
    // minutes towards an output it cannot write, or overwrite its inputs.
    let mut reads = command_line_inputs(args);
    reads.extend(sources);
    let mut guard = OutputGuard::new();
    guard.add_inputs(reads.iter().map(|(l, p)| (*l, p)))?;
    for job in &jobs {
        job.add_outputs(&mut guard)?;
    }
    let requests = jobs.iter().flat_map(|j| &j.requests_before);
    super::requests::add_outputs(&mut guard, requests.chain(&requests_after))?;
    if source.is_some() {
        // A sequence's files are all known: an output directory that takes
        // no files fails the run before its first frame, not at it.
        guard.prepare_dirs()?;
    }
    let gpu = OnceCell::new();
    let mut backend = Backend::new(args, &gpu);
    let mut reread = jobs
        .iter()
        .any(|j| j.reread.is_some())
        .then(|| Reread::new(args.scene.as_deref().unwrap_or(Path::new("")), args.lenient));
    let mut scene_of = |job: &mut Job| -> Result<_, BoxError> {
        match (job.reread, reread.as_mut()) {
            (Some((index, number)), Some(reread)) => Ok(Some(reread.frame(index, number)?)),
            _ => Ok(job.scene.take()),
        }
    };
    let no_requests =
        requests_after.is_empty() && jobs.iter().all(|j| j.requests_before.is_empty());
    if jobs.len() == 1 && no_requests && source.is_none() && !sequence.skip_existing {
        let label = jobs[0].label.clone();
        return scene_of(&mut jobs[0])
            .and_then(|scene| {
                render_job(args, &mut backend, scene, &jobs, &mut reads, None).map(|_| ())
            })
            .map_err(|e| labelled(label.as_deref(), e));
    }
    let mut failures = super::failures::Failures::default();
    let mut report = source.as_ref().map(|_| SequenceReport::new(jobs.len()));
    for k in 0..jobs.len() {
        let label = jobs[k].label.clone().unwrap_or_else(|| "the scene".into());
        for request in std::mem::take(&mut jobs[k].requests_before) {
            failures.run_request(args, &request, &reads);
        }
        if failures.stop(args) {
            failures.not_rendered.push(label);
            continue;
        }
        // An image is written whole or not at all: one that exists is a
        // finished frame.
        let image = jobs[k].outputs.as_ref().map(|o| o.image.as_path());
        if let Some(image) = image.filter(|i| sequence.skip_existing && i.is_file()) {
            outln!(
                "{label}: {} exists: skipped (--skip-existing)",
                image.display()
            )?;
            if let Some(report) = report.as_mut() {
                report.skipped(&label);
            }
            continue;
        }
        if let Some(report) = report.as_ref()
            && !args.quiet
        {
            errln!("{}", report.start_line(&label))?;
        }
        // Of a sequence, the first frame's outputs are checked against
        // every later frame's; the later frames read the same files.
        let end = match &source {
            Some(_) if k > 0 => k + 1,
            _ => jobs.len(),
        };
        let started = std::time::Instant::now();
        let rendered = scene_of(&mut jobs[k]).and_then(|scene| {
            let checked = &jobs[k..end];
            render_job(
                args,
                &mut backend,
                scene,
                checked,
                &mut reads,
                source.as_ref(),
            )
        });
        match rendered {
            Ok(stats) => {
                if let Some(report) = report.as_mut() {
                    report.rendered(&label, started.elapsed(), stats.micropolygons);
                }
            }
            Err(error) => {
                super::print_error(labelled(Some(&label), error).as_ref());
                if let Some(report) = report.as_mut() {
                    report.failed(&label, started.elapsed());
                }
                failures.frames.push(label);
            }
        }
    }
    for request in &requests_after {
        failures.run_request(args, request, &reads);
    }
    if let Some(report) = &report {
        report.print()?;
    }
    failures.into_result(jobs.len())
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
    sequence: Option<&SequenceSource>,
) -> Result<RenderStats, BoxError> {
    let job = &jobs[0];
    let label = job.label.as_deref();
    let base = match (scene, &job.still, sequence) {
        (_, Some(still), Some(source)) => BaseScene {
            scene: Scene::clone(still),
            models: Some(source.models.clone()),
            read: std::iter::once(("scene", source.path.clone()))
                .chain(source.model_files.iter().map(|p| ("model", p.clone())))
                .collect(),
            light_origins: Vec::new(),
            shutter_applied: source.animated,
        },
        (None, _, _) => base_scene(args.scene.as_deref(), args.lenient, None)?,
        (Some(rib), _, _) => {
            let rib = rib?;
            let sources = rib.sources.clone();
            let mut base = rib_base(rib, label, &sources)?;
            // A frame renders the same alone or with the file's others.
            base.scene.sampling_seed = job.number.unwrap_or(0);
            base
        }
    };
    let Prepared { scene, read } = prepare_base(args, base)?;
    for file in read {
        // A sequence's frames read the same files: each is recorded once.
        if !reads.contains(&file) {
            reads.push(file);
        }
    }
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
pub(crate) fn labelled(label: Option<&str>, error: BoxError) -> BoxError {
    match label {
        Some(label) => Box::new(FrameError {
            label: label.to_owned(),
            source: error,
        }),
        None => error,
    }
}
