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
//!
//! A RIB file's requests between frames (`MakeShadow`) run in their place:
//! those before a selected frame run before it is prepared, those after the
//! file's last frame once it is written, if it is selected; a request that
//! fails stops what follows as a failed frame does ([`super::requests`]).
//!
//! A RIB file of several frames is read twice: once to plan (each frame's
//! geometry is dropped as soon as its outputs are known), and again, one
//! frame at a time, to render ([`crate::rib::FrameStream`]), so that memory
//! holds one frame's geometry, not the whole file's.

use std::cell::OnceCell;
use std::path::{Path, PathBuf};

use super::BoxError;
use super::args::RenderArgs;
use super::frames::{frame_path, select};
use super::input::{ReadFile, base_scene, rib_base};
use super::prepare::{Prepared, prepare_base};
use super::render::Backend;
use crate::aov::Aov;
use crate::displacement::desc::{SOURCE_BUMPS, SOURCE_SINES, SOURCE_WGSL};
use crate::output::console::errln;
use crate::output::{OutputGuard, OutputKind, OutputPlan};
use crate::rib::{FrameRequest, FrameStream, RibError, RibFrames, RibOptions, RibScene};

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
}

/// What one `reyes render` does: its frames, the files read to find them
/// (a RIB file and its archives) and the requests after the last frame.
pub(crate) struct Plan {
    jobs: Vec<Job>,
    sources: Vec<ReadFile>,
    requests_after: Vec<FrameRequest>,
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

/// The frames `args` asks for, with their outputs and requests, and the
/// files read to find them (a RIB file and its archives).
pub(crate) fn plan(args: &RenderArgs) -> Result<Plan, BoxError> {
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
            reread: None,
            outputs: Some(outputs),
            requests_before: Vec::new(),
        };
        return Ok(Plan {
            jobs: vec![job],
            sources: Vec::new(),
            requests_after: Vec::new(),
        });
    };
    let frames = plan_rib(path, args.lenient)?;
    let reread = frames.frames.len() > 1;
    let selected = select(path, &frames, args.frame.as_ref())?;
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
        });
    }
    Ok(Plan {
        jobs,
        sources,
        requests_after,
    })
}

/// The frames of the RIB file at `path`, read one at a time and each but
/// a single frame's models dropped (they are read again to render); the
/// file's warnings are printed.
pub(crate) fn plan_rib(path: &Path, lenient: bool) -> Result<RibFrames, BoxError> {
    let mut stream = RibFrames::stream(path, RibOptions { lenient });
    let mut frames = Vec::new();
    for frame in stream.by_ref() {
        // The frame before this one is not the only one: drop its models.
        if let Some(Ok(previous)) = frames
            .last_mut()
            .map(|f: &mut crate::rib::RibFrame| &mut f.scene)
        {
            previous.models = Vec::new();
        }
        frames.push(frame);
    }
    let end = stream.finish()?;
    if frames.len() > 1
        && let Some(Ok(last)) = frames.last_mut().map(|f| &mut f.scene)
    {
        last.models = Vec::new();
    }
    for warning in &end.warnings {
        errln!("warning: {warning}")?;
    }
    Ok(RibFrames {
        frames,
        warnings: end.warnings,
        sources: end.sources,
        requests_after: end.requests_after,
    })
}

/// A RIB file's frames read again in order, each when its turn to render
/// comes.
pub(crate) struct Reread {
    path: PathBuf,
    stream: FrameStream,
    /// The place in the file of the frame the stream gives next.
    next: usize,
}

impl Reread {
    /// The frames of `path` from its start.
    pub(crate) fn new(path: &Path, lenient: bool) -> Reread {
        Reread {
            stream: RibFrames::stream(path, RibOptions { lenient }),
            path: path.to_path_buf(),
            next: 0,
        }
    }

    /// Frame `index` of the file, which the plan found numbered `number`
    /// (the frames before it, not selected, are read and dropped).
    pub(crate) fn frame(
        &mut self,
        index: usize,
        number: Option<u32>,
    ) -> Result<Result<RibScene, RibError>, BoxError> {
        while let Some(frame) = self.stream.next_frame() {
            let at = self.next;
            self.next += 1;
            if at == index && frame.number == number {
                return Ok(frame.scene);
            }
            if at >= index {
                break;
            }
        }
        let which = number.map_or("its scene".to_owned(), |n| format!("its frame {n}"));
        Err(format!(
            "{} changed while its frames were rendered: {which} is not where it was",
            self.path.display(),
        )
        .into())
    }
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

/// Renders the plan's frames in order, each after the requests before it,
/// then runs the requests after the last. A frame or request that fails is
/// reported and stops what follows, unless `--keep-going`; then the run
/// fails with the list of what failed. A run of one frame and no request
/// returns its error as it is.
pub(crate) fn run(args: &RenderArgs, plan: Plan) -> Result<(), BoxError> {
    let Plan {
        mut jobs,
        sources,
        requests_after,
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
    if jobs.len() == 1 && no_requests {
        let label = jobs[0].label.clone();
        return scene_of(&mut jobs[0])
            .and_then(|scene| render_job(args, &mut backend, scene, &jobs, &mut reads))
            .map_err(|e| labelled(label.as_deref(), e));
    }
    let mut failures = super::failures::Failures::default();
    for k in 0..jobs.len() {
        let label = jobs[k].label.clone().unwrap_or_else(|| "the scene".into());
        for request in std::mem::take(&mut jobs[k].requests_before) {
            failures.run_request(args, &request, &reads);
        }
        if failures.stop(args) {
            failures.not_rendered.push(label);
            continue;
        }
        let rendered = scene_of(&mut jobs[k])
            .and_then(|scene| render_job(args, &mut backend, scene, &jobs[k..], &mut reads));
        if let Err(error) = rendered {
            super::print_error(labelled(Some(&label), error).as_ref());
            failures.frames.push(label);
        }
    }
    for request in &requests_after {
        failures.run_request(args, request, &reads);
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
