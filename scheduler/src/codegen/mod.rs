//! Generation of the megakernel's WGSL: all of its text is written here,
//! through the typed module of [`module`], from the `plan` layer's data. It
//! never depends on `compile`, which drives it and checks what it writes.

pub(crate) mod bindings;
pub(crate) mod checked;
pub(crate) mod codec;
pub(crate) mod fan_out;
pub(crate) mod generate;
pub(crate) mod globals;
pub(crate) mod graph_constants;
pub(crate) mod helpers;
pub(crate) mod joins;
pub(crate) mod kernels;
pub(crate) mod module;
pub(crate) mod rounds;
pub(crate) mod trace;
pub(crate) mod uniform;
