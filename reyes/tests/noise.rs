//! RenderMan noise on the CPU (`reyes::noise`): range, lattice values,
//! continuity, period, mean, the bounds it normalizes by, and the WGSL
//! text generated from it. The GPU twin is compared in
//! `tests/tests/noise_gpu.rs`.

use glam::{Vec2, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::noise::{
    NOISE1_BOUND, NOISE2_BOUND, NOISE3_BOUND, NOISE4_BOUND, PERMUTATION, noise_wgsl, noise1,
    noise2, noise3, noise4, snoise1, snoise2, snoise3, snoise4, svnoise3, vnoise3,
};

/// A random generator drawn afresh, its seed printed; `TEST_SEED=<seed>`
/// replays it.
fn rng(test: &str) -> StdRng {
    let seed: u64 = std::env::var("TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(rand::random);
    eprintln!("{test} seed = {seed} (replay with TEST_SEED={seed})");
    StdRng::seed_from_u64(seed)
}

/// Every noise at one point (the four scalar ones and `vnoise3`'s three
/// components), from the coordinates `c`.
fn all_noises(c: [f32; 4]) -> [f32; 7] {
    let p = Vec3::new(c[0], c[1], c[2]);
    let v = vnoise3(p);
    [
        noise1(c[0]),
        noise2(Vec2::new(c[0], c[1])),
        noise3(p),
        noise4(p, c[3]),
        v.x,
        v.y,
        v.z,
    ]
}

/// A coordinate: mostly small, sometimes negative and large.
fn coordinate(rng: &mut StdRng) -> f32 {
    match rng.random_range(0..4) {
        0 => rng.random_range(-4.0..4.0),
        1 => rng.random_range(-300.0..300.0),
        2 => rng.random_range(-1.0e5..1.0e5),
        _ => rng.random_range(-1.0e9..1.0e9),
    }
}

#[test]
fn the_table_is_a_permutation() {
    let mut seen = [false; 256];
    for &p in &PERMUTATION {
        assert!(!seen[usize::from(p)], "{p} twice");
        seen[usize::from(p)] = true;
    }
    // Not the identity (nor close to it): a shuffle.
    let fixed = PERMUTATION
        .iter()
        .enumerate()
        .filter(|&(i, &p)| usize::from(p) == i)
        .count();
    assert!(fixed < 10, "{fixed} fixed points");
}

#[test]
fn noise_is_in_the_unit_interval_and_snoise_is_its_signed_twin() {
    let mut rng = rng("noise_range");
    for _ in 0..20_000 {
        let c = [(); 4].map(|_| coordinate(&mut rng));
        let n = all_noises(c);
        assert!(n.iter().all(|x| (0.0..=1.0).contains(x)), "{c:?}: {n:?}");
        let p = Vec3::new(c[0], c[1], c[2]);
        assert_eq!(snoise1(c[0]), 2.0 * n[0] - 1.0);
        assert_eq!(snoise2(Vec2::new(c[0], c[1])), 2.0 * n[1] - 1.0);
        assert_eq!(snoise3(p), 2.0 * n[2] - 1.0);
        assert_eq!(snoise4(p, c[3]), 2.0 * n[3] - 1.0);
        assert_eq!(svnoise3(p), 2.0 * Vec3::new(n[4], n[5], n[6]) - Vec3::ONE);
    }
}

#[test]
fn noise_is_one_half_at_the_lattice_points() {
    let mut rng = rng("noise_lattice");
    for _ in 0..5_000 {
        // Integers, small and large, negative too (all exact in f32).
        let c = [(); 4].map(|_| rng.random_range(-(1 << 24)..=(1 << 24)) as f32);
        let c = if rng.random_bool(0.5) {
            c.map(|x| x % 600.0)
        } else {
            c
        };
        assert_eq!(all_noises(c), [0.5; 7], "{c:?}");
    }
}

#[test]
fn small_steps_make_small_changes() {
    // The raw sums' derivatives are bounded by a few units (gradients at
    // most sqrt(3) long, the fade's slope at most 1.875): a step of 1e-3
    // moves any noise by well under 0.01, also across cell boundaries.
    let mut rng = rng("noise_continuity");
    let step = 1.0e-3;
    for _ in 0..20_000 {
        let mut c = [(); 4].map(|_| rng.random_range(-300.0f32..300.0));
        if rng.random_bool(0.3) {
            // Straddle a cell boundary in one coordinate.
            let k = rng.random_range(0..4);
            c[k] = c[k].round() - step / 2.0;
        }
        let axis = rng.random_range(0..4);
        let mut d = c;
        d[axis] += step;
        let (a, b) = (all_noises(c), all_noises(d));
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 0.01, "{c:?} -> {d:?}: {a:?} vs {b:?}");
        }
    }
}

#[test]
fn noise_repeats_every_256_along_each_axis() {
    let mut rng = rng("noise_period");
    for _ in 0..5_000 {
        // Multiples of 2^-10 below 2^11: the shifted sum is exact.
        let c = [(); 4].map(|_| rng.random_range(-1_000_000i32..1_000_000) as f32 / 1024.0);
        let axis = rng.random_range(0..4);
        let turns = [-2.0, -1.0, 1.0, 3.0][rng.random_range(0..4)];
        let mut d = c;
        d[axis] += 256.0 * turns;
        assert_eq!(all_noises(c), all_noises(d), "{c:?} vs {d:?}");
    }
}

#[test]
fn noise_averages_one_half_and_spreads() {
    let mut rng = rng("noise_mean");
    let n = 200_000;
    let mut sum = [0.0f64; 7];
    let mut lo = [1.0f32; 7];
    let mut hi = [0.0f32; 7];
    let mut products = [0.0f64; 3];
    for _ in 0..n {
        let c = [(); 4].map(|_| rng.random_range(-256.0f32..256.0));
        let v = all_noises(c);
        for i in 0..7 {
            sum[i] += f64::from(v[i]);
            lo[i] = lo[i].min(v[i]);
            hi[i] = hi[i].max(v[i]);
        }
        let centred = [v[4], v[5], v[6]].map(|x| f64::from(x) - 0.5);
        products[0] += centred[0] * centred[1];
        products[1] += centred[1] * centred[2];
        products[2] += centred[0] * centred[2];
    }
    for i in 0..7 {
        let mean = sum[i] / f64::from(n);
        // The spread of a noise is about 0.1: the mean of 200000 samples
        // is within 0.001 of 0.5 but for a one-in-a-million chance.
        assert!((mean - 0.5).abs() < 0.005, "noise {i}: mean {mean}");
        assert!(lo[i] < 0.3 && hi[i] > 0.7, "noise {i}: only {lo:?}..{hi:?}");
    }
    // vnoise3's components are unrelated: their covariance is far below
    // their variance (about 0.01).
    for (k, p) in products.iter().enumerate() {
        let covariance = p / f64::from(n);
        assert!(
            covariance.abs() < 5.0e-4,
            "pair {k}: covariance {covariance}"
        );
    }
}

/// `6t^5 - 15t^4 + 10t^3`, in f64.
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The largest gradient sum any table could give at `x` in a cell of
/// `x.len()` dimensions, when each corner's gradient dotted with the
/// corner's offset `d` is at most the sum of the `k` largest `|d_i|` (the
/// gradients have `k` components `+-1`, the others 0; in 1D, `|d|`).
fn worst_sum(x: &[f64], k: usize) -> f64 {
    let dim = x.len();
    (0..1usize << dim)
        .map(|corner| {
            let mut weight = 1.0;
            let mut d: Vec<f64> = (0..dim)
                .map(|a| {
                    let at_one = corner >> a & 1 == 1;
                    let s = fade(x[a]);
                    weight *= if at_one { s } else { 1.0 - s };
                    if at_one { 1.0 - x[a] } else { x[a] }
                })
                .collect();
            d.sort_by(|a, b| b.total_cmp(a));
            weight * d[..k].iter().sum::<f64>()
        })
        .sum()
}

#[test]
fn the_bounds_hold_for_every_table_and_are_tight() {
    // On a grid of each cell, plus random points: the worst case over all
    // gradient choices never exceeds the bound the noise divides by, and
    // comes within 1% of it (the bound wastes no range).
    let mut rng = rng("noise_bounds");
    for (dim, k, bound, n) in [
        (1, 1, NOISE1_BOUND, 1001),
        (2, 2, NOISE2_BOUND, 201),
        (3, 2, NOISE3_BOUND, 41),
        (4, 3, NOISE4_BOUND, 17),
    ] {
        let mut worst = 0.0f64;
        let mut at = vec![0usize; dim];
        loop {
            let x: Vec<f64> = at.iter().map(|&i| i as f64 / (n - 1) as f64).collect();
            worst = worst.max(worst_sum(&x, k));
            let Some(a) = at.iter().position(|&i| i + 1 < n) else {
                break;
            };
            at[a] += 1;
            at[..a].iter_mut().for_each(|i| *i = 0);
        }
        for _ in 0..20_000 {
            // Random points near the centre, where the maxima are.
            let x: Vec<f64> = (0..dim).map(|_| rng.random_range(0.3..0.7)).collect();
            worst = worst.max(worst_sum(&x, k));
        }
        let bound = f64::from(bound);
        assert!(worst <= bound, "{dim}D: {worst} > {bound}");
        assert!(
            worst >= 0.99 * bound,
            "{dim}D: {worst} is far below {bound}"
        );
    }
}

#[test]
fn the_wgsl_carries_the_table_and_validates() {
    let wgsl = noise_wgsl();
    // The table, read back from the text: four entries to a word, the
    // first in the low byte.
    let start = wgsl.find("array<u32, 64>(").expect("the table") + "array<u32, 64>(".len();
    let end = start + wgsl[start..].find(");").expect("the table's end");
    let words: Vec<u32> = wgsl[start..end]
        .split(',')
        .map(str::trim)
        .filter(|w| !w.is_empty())
        .map(|w| u32::from_str_radix(w.trim_start_matches("0x").trim_end_matches('u'), 16).unwrap())
        .collect();
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    assert_eq!(bytes, PERMUTATION);
    let module = naga::front::wgsl::parse_str(&wgsl).unwrap_or_else(|e| {
        panic!("{}", e.emit_to_string(&wgsl));
    });
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{e:?}"));
    for name in [
        "noise1", "noise2", "noise3", "noise4", "snoise1", "snoise2", "snoise3", "snoise4",
        "vnoise3", "svnoise3",
    ] {
        assert!(
            module
                .functions
                .iter()
                .any(|(_, f)| f.name.as_deref() == Some(name)),
            "{name} is missing"
        );
    }
}

#[test]
fn the_wgsl_names_collide_with_no_other_renderer_shader() {
    let wgsl = noise_wgsl();
    let module = naga::front::wgsl::parse_str(&wgsl).expect("valid WGSL");
    let mut names: Vec<String> = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .collect();
    names.extend(module.constants.iter().filter_map(|(_, c)| c.name.clone()));
    assert!(names.len() > 20, "{names:?}");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders/reyes");
    let standard = dir.join("standard");
    let files = std::fs::read_dir(&dir)
        .unwrap()
        .chain(std::fs::read_dir(&standard).unwrap());
    for entry in files {
        let path = entry.unwrap().path();
        if path.is_dir() || path.file_name() == Some("library_noise.wgsl".as_ref()) {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        for name in &names {
            for declaration in [
                format!("fn {name}("),
                format!("const {name}:"),
                format!("const {name} "),
                format!("var<private> {name}"),
                format!("struct {name} "),
            ] {
                assert!(
                    !text.contains(&declaration),
                    "{} declares {name}",
                    path.display()
                );
            }
        }
    }
    // The generated declarations of the Rust side (`gpu::graph`'s
    // constants) use other prefixes; the noise's own all start with
    // `noise`, `snoise`, `vnoise`, `svnoise`, `NOISE` or `VNOISE`.
    for name in &names {
        assert!(
            ["noise", "snoise", "vnoise", "svnoise", "NOISE", "VNOISE"]
                .iter()
                .any(|p| name.starts_with(p)),
            "{name}"
        );
    }
}
