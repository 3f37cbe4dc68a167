//! Randomness for the unit tests: drawn afresh on every run, with the seed
//! printed so that a failure can be replayed.

use glam::Vec3;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// A generator seeded afresh for `test` (or from `TEST_SEED`, to replay a
/// failure), and its seed (printed, and for the failure messages).
pub(crate) fn fresh_rng(test: &str) -> (u64, StdRng) {
    let seed: u64 = std::env::var("TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(rand::random);
    eprintln!("{test} seed = {seed} (replay with TEST_SEED={seed})");
    (seed, StdRng::seed_from_u64(seed))
}

/// A vector with each coordinate uniform in `(-range, range)`.
pub(crate) fn random_vec3(rng: &mut StdRng, range: f32) -> Vec3 {
    Vec3::new(
        rng.random_range(-range..range),
        rng.random_range(-range..range),
        rng.random_range(-range..range),
    )
}
