//! Running compiled graphs.

pub(crate) mod advice;
pub(crate) mod config;
pub(crate) mod error;
pub(crate) mod executor;
pub(crate) mod growth;
pub(crate) mod limits;
pub(crate) mod outcome;
pub mod pipeline_cache;
pub mod readback;
pub(crate) mod report;
pub(crate) mod reset;
pub(crate) mod resources;
pub(crate) mod retry;
pub(crate) mod rounds;
pub(crate) mod seeds;
pub(crate) mod state;
pub(crate) mod strategy;
pub(crate) mod trace;
pub(crate) mod trace_chrome;
pub(crate) mod trace_run;
pub(crate) mod warm_up;
