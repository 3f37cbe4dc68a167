//! Running one GPU test against its declared failures.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Mutex, PoisonError};

use scheduler::Gpu;

use crate::FailureCase;

/// Held by the GPU test that runs, when the adapter is GL.
static GL_TURN: Mutex<()> = Mutex::new(());

/// One GPU test and the failures declared for it; `#[gpu_test]` builds it.
#[derive(Debug)]
pub struct GpuTest {
    name: &'static str,
    failures: Vec<FailureCase>,
}

/// How a run ended, against the failures declared for the adapter.
#[derive(Debug, PartialEq, Eq)]
enum Verdict {
    /// No failure was declared for this adapter and the test passed, or a
    /// declared failure happened.
    Pass,
    /// A declared failure did not happen: the message says which.
    Fail(String),
}

impl GpuTest {
    /// The test called `name` (its module path), with no failure declared.
    pub fn new(name: &'static str) -> Self {
        Self {
            name,
            failures: Vec::new(),
        }
    }

    /// Declares a failure.
    pub fn expect_fail(mut self, case: FailureCase) -> Self {
        self.failures.push(case);
        self
    }

    /// Runs `test` on the shared device ([`crate::gpu`]).
    ///
    /// # Panics
    /// When the test fails on an adapter no declared case covers; when a
    /// case covers the adapter and the test passes, or panics with a
    /// message no covering case accepts.
    pub fn run(self, test: impl FnOnce(&'static Gpu)) {
        let gpu = crate::gpu();
        let info = gpu.adapter.get_info();
        // wgpu's GL backend makes every GL call under one lock on the
        // adapter's context, and panics ("Could not lock adapter context")
        // when a thread waits for it over a second, as tests on other
        // threads holding it for a long dispatch or compile make it: on GL
        // the tests take turns.
        let _turn = (info.backend == scheduler::wgpu::Backend::Gl)
            .then(|| GL_TURN.lock().unwrap_or_else(PoisonError::into_inner));
        // Each test's own output names the adapter and backend, so that a
        // failure says where it happened whichever test made the device.
        eprintln!("{} on {}", self.name, gpu.describe());
        let expected: Vec<FailureCase> = self
            .failures
            .iter()
            .filter(|case| case.covers(&info))
            .copied()
            .collect();
        if expected.is_empty() {
            test(gpu);
            return;
        }
        let panic = catch_unwind(AssertUnwindSafe(|| test(gpu))).err();
        let message = panic.as_deref().map(panic_message);
        let adapter = format!("{} ({})", info.name, info.driver);
        match verdict(self.name, &adapter, &expected, message.as_deref()) {
            Verdict::Pass => {}
            Verdict::Fail(why) => panic!("{why}"),
        }
    }
}

/// Judges a run that ended with the panic `message` (`None`: it passed) on
/// `adapter`, where the cases `expected` were declared to cover it.
fn verdict(test: &str, adapter: &str, expected: &[FailureCase], message: Option<&str>) -> Verdict {
    let reasons = || {
        expected
            .iter()
            .map(|case| case.reason)
            .collect::<Vec<_>>()
            .join("; ")
    };
    let Some(message) = message else {
        return Verdict::Fail(format!(
            "{test} passed on {adapter}, where it is declared to fail ({}): \
             narrow or remove the expectation",
            reasons()
        ));
    };
    match expected.iter().find(|case| case.accepts(message)) {
        Some(case) => {
            eprintln!("{test} failed on {adapter} as declared: {}", case.reason);
            Verdict::Pass
        }
        None => {
            let messages: Vec<&str> = expected.iter().filter_map(|case| case.message).collect();
            Verdict::Fail(format!(
                "{test} failed on {adapter}, but not as declared ({}): expected a panic \
                 containing {messages:?}, got: {message}",
                reasons()
            ))
        }
    }
}

/// The text of a panic's payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_owned()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "(a panic without a message)".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::{FailureCase, Verdict, panic_message, verdict};

    const LOOPS: FailureCase = FailureCase {
        message: Some("loop limit"),
        ..FailureCase::always("llvmpipe caps loops")
    };

    #[test]
    fn a_declared_failure_that_happens_passes() {
        let message = Some("the run hit the loop limit");
        assert_eq!(verdict("t", "llvmpipe", &[LOOPS], message), Verdict::Pass);
        let any_panic = FailureCase::always("anything goes");
        assert_eq!(
            verdict("t", "llvmpipe", &[any_panic], Some("boom")),
            Verdict::Pass
        );
    }

    #[test]
    fn an_unexpected_pass_fails() {
        let Verdict::Fail(why) = verdict("t", "llvmpipe", &[LOOPS], None) else {
            panic!("a pass where a failure is declared must fail");
        };
        assert!(why.contains("passed on llvmpipe") && why.contains("llvmpipe caps loops"));
    }

    #[test]
    fn a_failure_with_another_message_fails() {
        let Verdict::Fail(why) = verdict("t", "llvmpipe", &[LOOPS], Some("queue overflowed"))
        else {
            panic!("an undeclared failure must fail");
        };
        assert!(why.contains("not as declared") && why.contains("queue overflowed"));
    }

    #[test]
    fn any_covering_case_may_accept_the_failure() {
        let chunks = FailureCase {
            message: Some("chunks per batch"),
            ..FailureCase::always("slow compiles")
        };
        assert_eq!(
            verdict(
                "t",
                "llvmpipe",
                &[LOOPS, chunks],
                Some("8 chunks per batch")
            ),
            Verdict::Pass
        );
    }

    #[test]
    fn panic_payloads_give_their_text() {
        let text: Box<dyn std::any::Any + Send> = Box::new("static");
        assert_eq!(panic_message(text.as_ref()), "static");
        let formatted: Box<dyn std::any::Any + Send> = Box::new(format!("n = {}", 3));
        assert_eq!(panic_message(formatted.as_ref()), "n = 3");
    }
}
