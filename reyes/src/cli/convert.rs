//! `reyes convert`: a RenderMan RIB scene (one frame of it) to a TOML
//! scene plus `.bpt` models.

use std::path::PathBuf;

use super::BoxError;
use crate::output::console::{errln, outln};
use crate::output::{OutputGuard, OutputKind};

/// The arguments of `reyes convert`.
#[derive(Debug, clap::Args)]
pub(crate) struct ConvertArgs {
    /// The ASCII RIB file.
    pub(crate) input: PathBuf,
    /// The TOML scene to write (`.toml`; the models go beside it).
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Read a RIB whose block structure is unbalanced or truncated (a
    /// missing `WorldEnd`, an unclosed `AttributeBegin`, an `AttributeEnd`
    /// without its begin) with warnings instead of an error, and convert
    /// what was read.
    #[arg(long)]
    pub(crate) lenient: bool,
    /// Most bicubic patches the scene may make, in all (default 1048576 =
    /// 2^20; see `reyes render --help`).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub(crate) max_patches: Option<u64>,
    /// The frame to convert (`FrameBegin N`): a TOML scene holds one, so a
    /// RIB file of several frames needs it; without it such a file is an
    /// error that lists its frames.
    #[arg(long, value_name = "N")]
    pub(crate) frame: Option<u32>,
}

/// `reyes convert`: RIB to TOML plus `.bpt` files.
pub(crate) fn convert(args: &ConvertArgs) -> Result<(), BoxError> {
    // Before the RIB is read: a TOML path that is the RIB itself, has
    // another extension or is no file is refused at once.
    // [`crate::rib::RibScene::write`] checks every output again against
    // every file the RIB read (its archives).
    super::args::set_patch_budget(args.max_patches);
    let mut guard = OutputGuard::new();
    guard.add_input("RIB scene", &args.input)?;
    guard.add_output(OutputKind::Toml, "TOML scene", &args.output)?;
    let options = crate::rib::RibOptions {
        lenient: args.lenient,
    };
    let frames = crate::rib::RibFrames::load_with(&args.input, options)?;
    let selection = args
        .frame
        .map(|n| super::frames::parse_frames(&n.to_string()))
        .transpose()?;
    let selected = super::frames::select(&args.input, &frames, selection.as_ref())?;
    if selected.len() > 1 {
        return Err(format!(
            "{} has {} frames ({}): a TOML scene holds one; choose it with --frame N",
            args.input.display(),
            frames.frames.len(),
            frames.list()
        )
        .into());
    }
    for warning in frames.warnings.iter().chain(&frames.requests_not_run()) {
        errln!("warning: {warning}")?;
    }
    let (frame, sources) = frames.into_frame(selected[0]).expect("a selected frame");
    let label = frame.number.map(|_| frame.label());
    let mut rib = frame.scene?;
    // Every file the RIB read, also after the frame, is no output.
    rib.sources = sources;
    for warning in &rib.warnings {
        errln!("warning: {warning}")?;
    }
    if let Some(label) = label {
        outln!("converting {label} of {}", args.input.display())?;
    }
    let written = rib.write(&args.output)?;
    for path in &written {
        outln!("wrote {}", path.display())?;
    }
    if let Some(display) = &rib.display {
        outln!(
            "the RIB's Display file is {display}: reyes render writes the image there unless -o is given"
        )?;
    }
    Ok(())
}
