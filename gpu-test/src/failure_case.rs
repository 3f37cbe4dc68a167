//! A declared failure: which adapters a test is known to fail on, how, and
//! why.

use scheduler::wgpu::AdapterInfo;

/// Adapters a test is known to fail on. Every matcher that is `Some` must
/// match; a case with none covers every adapter. Names match as
/// case-insensitive substrings, as in wgpu's own test harness.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FailureCase {
    /// The backend's name as wgpu spells it (`vulkan`, `metal`, `dx12`,
    /// `gl`).
    pub backend: Option<&'static str>,
    /// The PCI vendor id.
    pub vendor: Option<u32>,
    /// A substring of the adapter's name (`AdapterInfo::name`).
    pub adapter: Option<&'static str>,
    /// A substring of the driver's name (`AdapterInfo::driver`: `llvmpipe`
    /// for lavapipe).
    pub driver: Option<&'static str>,
    /// A substring of the panic message the failure must carry; `None`
    /// accepts any panic.
    pub message: Option<&'static str>,
    /// Why the test fails there, printed when it does.
    pub reason: &'static str,
}

impl FailureCase {
    /// A failure on every adapter; narrow it with the other fields.
    pub const fn always(reason: &'static str) -> Self {
        Self {
            backend: None,
            vendor: None,
            adapter: None,
            driver: None,
            message: None,
            reason,
        }
    }

    /// Whether the case covers the adapter `info` describes.
    pub fn covers(&self, info: &AdapterInfo) -> bool {
        let contains = |haystack: &str, needle: &str| {
            haystack
                .to_ascii_lowercase()
                .contains(&needle.to_ascii_lowercase())
        };
        self.backend
            .is_none_or(|backend| info.backend.to_str().eq_ignore_ascii_case(backend))
            && self.vendor.is_none_or(|vendor| info.vendor == vendor)
            && self.adapter.is_none_or(|name| contains(&info.name, name))
            && self
                .driver
                .is_none_or(|driver| contains(&info.driver, driver))
    }

    /// Whether a panic with `message` is the failure this case declares.
    pub fn accepts(&self, message: &str) -> bool {
        self.message
            .is_none_or(|expected| message.contains(expected))
    }
}

#[cfg(test)]
mod tests {
    use scheduler::wgpu::{AdapterInfo, Backend, DeviceType};

    use super::FailureCase;

    fn info(name: &str, driver: &str, vendor: u32, backend: Backend) -> AdapterInfo {
        AdapterInfo {
            name: name.into(),
            driver: driver.into(),
            vendor,
            ..AdapterInfo::new(DeviceType::Cpu, backend)
        }
    }

    fn lavapipe() -> AdapterInfo {
        info(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            "llvmpipe",
            0x10005,
            Backend::Vulkan,
        )
    }

    fn nvidia() -> AdapterInfo {
        info("NVIDIA H200", "NVIDIA", 0x10de, Backend::Vulkan)
    }

    #[test]
    fn a_case_without_matchers_covers_every_adapter() {
        let always = FailureCase::always("everywhere");
        assert!(always.covers(&lavapipe()) && always.covers(&nvidia()));
        assert!(always.accepts("any message"));
    }

    #[test]
    fn names_match_as_case_insensitive_substrings() {
        let by_driver = FailureCase {
            driver: Some("LLVMpipe"),
            ..FailureCase::always("loops")
        };
        assert!(by_driver.covers(&lavapipe()));
        assert!(!by_driver.covers(&nvidia()));
        let by_adapter = FailureCase {
            adapter: Some("h200"),
            ..FailureCase::always("big")
        };
        assert!(by_adapter.covers(&nvidia()));
        assert!(!by_adapter.covers(&lavapipe()));
        // GL's llvmpipe names no driver: only the adapter name tells it.
        let gl = info("llvmpipe (LLVM 15)", "", 0x10005, Backend::Gl);
        assert!(!by_driver.covers(&gl));
        let by_gl_name = FailureCase {
            adapter: Some("llvmpipe"),
            ..FailureCase::always("loops")
        };
        assert!(by_gl_name.covers(&gl) && by_gl_name.covers(&lavapipe()));
    }

    #[test]
    fn every_given_matcher_must_match() {
        let vulkan_lavapipe = FailureCase {
            backend: Some("vulkan"),
            driver: Some("llvmpipe"),
            ..FailureCase::always("loops")
        };
        assert!(vulkan_lavapipe.covers(&lavapipe()));
        let gl_driver = info("llvmpipe (LLVM 15)", "llvmpipe", 0x10005, Backend::Gl);
        assert!(!vulkan_lavapipe.covers(&gl_driver), "backend differs");
        let by_vendor = FailureCase {
            vendor: Some(0x10de),
            ..FailureCase::always("vendor")
        };
        assert!(by_vendor.covers(&nvidia()) && !by_vendor.covers(&lavapipe()));
    }

    #[test]
    fn a_message_narrows_the_accepted_panics() {
        let case = FailureCase {
            message: Some("loop limit"),
            ..FailureCase::always("loops")
        };
        assert!(case.accepts("the run hit the loop limit after 4 attempts"));
        assert!(!case.accepts("queue `Spin` overflowed"));
    }
}
