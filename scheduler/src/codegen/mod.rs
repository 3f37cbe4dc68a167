//! Generation of the megakernel's WGSL.

pub(crate) mod generate;
pub(crate) mod module;
