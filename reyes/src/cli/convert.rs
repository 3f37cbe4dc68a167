//! `reyes convert`: a RenderMan RIB scene to a TOML scene plus `.bpt`
//! models.

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
    let rib = crate::rib::RibScene::load_with(&args.input, options)?;
    for warning in &rib.warnings {
        errln!("warning: {warning}")?;
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
