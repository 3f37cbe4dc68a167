//! The GPU test harness on the adapter at hand: `#[gpu_test]` hands tests
//! the shared device, a declared failure that happens passes, and one that
//! does not happen (or happens otherwise) fails. The matching of adapters
//! is unit-tested in the `gpu-test` crate.

use gpu_test::gpu_test;

#[gpu_test]
fn the_test_gets_the_shared_device(gpu: &scheduler::Gpu) {
    assert!(std::ptr::eq(gpu, tests::gpu()));
}

#[gpu_test(expect_fail(
    message = "deliberate failure",
    reason = "declared for every adapter, this one included"
))]
fn a_declared_failure_that_happens_passes() {
    panic!("deliberate failure on {}", tests::gpu().describe());
}

#[gpu_test(expect_fail(reason = "declared for every adapter, this one included"))]
#[should_panic(expected = "where it is declared to fail")]
fn a_declared_failure_that_does_not_happen_fails() {}

#[gpu_test(expect_fail(
    message = "deliberate failure",
    reason = "declared for every adapter, this one included"
))]
#[should_panic(expected = "but not as declared")]
fn a_failure_with_another_message_fails() {
    panic!("another failure");
}

#[gpu_test(expect_fail(
    driver = "no such driver",
    reason = "declared for a driver this adapter is not"
))]
fn a_failure_declared_for_another_driver_leaves_the_test_plain() {}
