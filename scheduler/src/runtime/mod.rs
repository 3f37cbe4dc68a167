//! Running compiled graphs.

pub(crate) mod config;
pub(crate) mod executor;
pub(crate) mod report;
pub(crate) mod resources;
pub(crate) mod seeds;
pub(crate) mod state;
pub(crate) mod strategy;
