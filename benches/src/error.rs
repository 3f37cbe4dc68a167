//! The one error type of the benchmarks. A wrong result is an error, never a
//! warning: a benchmark of wrong code measures nothing.

use std::fmt;

/// Why a benchmark could not produce a trustworthy number.
#[derive(Debug)]
pub enum BenchError {
    /// No adapter or device.
    Device(scheduler::DeviceError),
    /// A benchmark's graph did not compile.
    Compile(scheduler::CompileError),
    /// The megakernel (or a read-back) failed.
    Run(scheduler::RunError),
    /// The device rejected the flat pipeline or a buffer.
    Gpu(String),
    /// The benchmark configuration is unusable.
    Config(String),
    /// A variant's `out` array differs from the CPU reference.
    Mismatch {
        /// Which variant, e.g. `megakernel (256 workgroups), work 64`.
        variant: String,
        /// Number of differing entries.
        wrong: usize,
        /// The first differing index with (expected, actual).
        first: (usize, u32, u32),
    },
    /// The megakernel's counters disagree with the tree (items lost or duplicated).
    Counters {
        /// Which variant.
        variant: String,
        /// What was wrong.
        detail: String,
    },
}

impl fmt::Display for BenchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Device(e) => write!(f, "no usable GPU: {e}"),
            Self::Compile(e) => write!(f, "the graph did not compile: {e}"),
            Self::Run(e) => write!(f, "megakernel run failed: {e}"),
            Self::Gpu(e) => write!(f, "GPU error: {e}"),
            Self::Config(e) => write!(f, "bad configuration: {e}"),
            Self::Mismatch {
                variant,
                wrong,
                first: (index, expected, actual),
            } => write!(
                f,
                "WRONG RESULTS from {variant}: {wrong} entries differ from the CPU reference; \
                 first at out[{index}]: expected {expected:#010x}, got {actual:#010x}"
            ),
            Self::Counters { variant, detail } => {
                write!(f, "WRONG COUNTERS from {variant}: {detail}")
            }
        }
    }
}

impl std::error::Error for BenchError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Device(e) => Some(e),
            Self::Compile(e) => Some(e),
            Self::Run(e) => Some(e),
            _ => None,
        }
    }
}

impl From<scheduler::DeviceError> for BenchError {
    fn from(e: scheduler::DeviceError) -> Self {
        Self::Device(e)
    }
}

impl From<scheduler::CompileError> for BenchError {
    fn from(e: scheduler::CompileError) -> Self {
        Self::Compile(e)
    }
}

impl From<scheduler::RunError> for BenchError {
    fn from(e: scheduler::RunError) -> Self {
        Self::Run(e)
    }
}
