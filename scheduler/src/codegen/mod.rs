//! Generation of the megakernel's WGSL.

pub(crate) mod bindings;
pub(crate) mod checked;
pub(crate) mod generate;
pub(crate) mod globals;
pub(crate) mod helpers;
pub(crate) mod kernels;
pub(crate) mod module;
pub(crate) mod uniform;
