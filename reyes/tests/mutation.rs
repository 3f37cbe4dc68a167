//! Mutation tests: real inputs (the embedded teapot as `.bpt`, the shared
//! `teapot.bez`, OBJ meshes, scene TOML texts with motion, a lens and displacement
//! tables, and the RIB scenes of the tests and the documentation) are
//! mutated at random — byte flips, inserted and deleted runs, duplicated,
//! swapped and deleted lines, numbers replaced by extreme values,
//! truncation — and fed to the `.bpt` loader, the `.bez` loader, the OBJ
//! loader (both subdivision schemes), the TOML
//! scene parser (with [`Scene::validate`] and [`PreparedScene::new`] on
//! what parses) and the RIB tokenizer, parser and interpreter (with
//! [`RibScene::prepare`] on what reads), and user WGSL (the gallery's
//! shaders and the standard ones, checked as a displacement function and
//! as a shader against the shading interface). Nothing may panic, and
//! every error message must stay short.
//!
//! Each test runs for about 2 s. Environment variables:
//!
//! * `MUTATION_SEED=<u64>`: the seed (printed by every run) to replay;
//! * `MUTATION_ITERATION=<n>`: with the seed, run only iteration `n` (a
//!   failure prints both) and print its input (escaped, up to 64 K characters);
//! * `MUTATION_SECONDS=<f64>`: run longer (or shorter);
//! * `MUTATION_EXECUTIONS=<n>`: run exactly `n` executions instead (for a
//!   recorded count, whatever the machine's speed).

mod common;

use std::cell::{Cell, RefCell};
use std::error::Error;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;
use std::time::{Duration, Instant};

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::budget::PatchBudget;
use reyes::load::{bez, bpt, obj};
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::rib::RibScene;
use reyes::scene::Scene;
use reyes::subdiv::Scheme;
use std::path::PathBuf;

/// The longest error message (per level of its source chain) allowed.
const MAX_MESSAGE_BYTES: usize = 4096;
const DEFAULT_SECONDS: f64 = 2.0;
/// Failures collected before a run stops early.
const MAX_FAILURES: usize = 5;
/// The longest mutated input (longer ones are cut), and the most of one
/// printed when replaying it.
const MAX_INPUT_BYTES: usize = 256 * 1024;
/// The most objects of a mutated scene that get a model and are prepared.
const MAX_PREPARED_OBJECTS: usize = 64;

/// Numbers that loaders and validation must survive.
const EXTREME_NUMBERS: &[&str] = &[
    "1e39",
    "-1e39",
    "1e308",
    "1e-400",
    "1e-45",
    "3.4028235e38",
    "-3.4028235e38",
    "-0",
    "-0.0",
    "0",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "+inf",
    "infinity",
    "4294967296",
    "4294967295",
    "2147483648",
    "-2147483649",
    "18446744073709551615",
    "18446744073709551616",
    "-1",
    "1",
    "2",
    "0.5",
    ".5",
    "5.",
    "1_000",
    "0x10",
    "1e",
    "--1",
    "00000000000000000000000000000000000000001",
    "0.000000000000000000000000000000000000000000000000001",
    "340282366920938463463374607431768211456",
    "99999999999999999999999999999999999999999999999999999999999999999999999999999999",
];

/// One thing to fuzz: seed texts, fragments worth inserting, and a check.
struct Target {
    name: &'static str,
    seeds: Vec<String>,
    /// Bytes worth inserting or writing over one byte.
    bytes: &'static [u8],
    /// Fragments worth inserting whole.
    fragments: &'static [&'static str],
    check: fn(&str) -> Verdict,
}

/// What one input did.
enum Verdict {
    /// Parsed (and, for a scene, validated and prepared).
    Accepted,
    /// Rejected: the messages of the error and of each of its sources.
    Rejected(Vec<String>),
    /// An invariant other than "no panic" broke.
    Broken(String),
}

fn messages(error: &dyn Error) -> Vec<String> {
    let mut out = vec![error.to_string()];
    let mut source = error.source();
    while let Some(e) = source {
        out.push(e.to_string());
        source = e.source();
    }
    out
}

// ---------------------------------------------------------------- checks

/// Frames and prepares a model that loaded: what `reyes render model.bpt` does.
fn prepare_model(model: Model) -> Verdict {
    let scene = Scene::for_model("mutated.bpt", &model);
    match PreparedScene::new(&scene, &[model]) {
        Ok(_) => Verdict::Accepted,
        Err(e) => Verdict::Rejected(messages(&e)),
    }
}

/// Parses a model, checks that writing it and parsing again gives it back,
/// then prepares it: the checks of both model formats.
fn check_model(
    text: &str,
    parse: fn(&str) -> Result<Model, reyes::load::LoadError>,
    write: fn(&Model) -> String,
) -> Verdict {
    match parse(text) {
        Ok(model) => {
            match parse(&write(&model)) {
                Ok(again) if again == model => {}
                again => {
                    return Verdict::Broken(format!(
                        "write then parse does not give the model back: {:?}",
                        again.err()
                    ));
                }
            }
            prepare_model(model)
        }
        Err(e) => Verdict::Rejected(messages(&e)),
    }
}

fn check_bpt(text: &str) -> Verdict {
    check_model(text, bpt::parse, bpt::write)
}

fn check_bez(text: &str) -> Verdict {
    check_model(text, bez::parse, bez::write)
}

/// Reads an OBJ text under both schemes (Catmull-Clark, until it is
/// built, is refused as unsupported: only its messages are checked) and
/// prepares the bilinear patches.
fn check_obj(text: &str) -> Verdict {
    let path = std::path::Path::new("mutated.obj");
    let read = |scheme| obj::parse_within(text, path, scheme, &mut PatchBudget::from_setting());
    if let Err(e) = read(Scheme::CatmullClark) {
        let messages = messages(&e);
        if messages.iter().any(|m| m.len() > MAX_MESSAGE_BYTES) {
            return Verdict::Rejected(messages);
        }
    }
    match read(Scheme::Bilinear) {
        Ok(model) => prepare_model(model),
        Err(e) => Verdict::Rejected(messages(&e)),
    }
}

fn check_scene(text: &str) -> Verdict {
    let scene = match Scene::from_toml_str(text) {
        Ok(scene) => scene,
        Err(e) => return Verdict::Rejected(messages(&e)),
    };
    if let Err(e) = scene.validate() {
        return Verdict::Broken(format!(
            "from_toml_str accepted a scene that validate rejects: {e}"
        ));
    }
    // What parsed serializes and parses back.
    let written = scene.to_toml_string();
    if let Err(e) = Scene::from_toml_str(&written) {
        return Verdict::Broken(format!(
            "the scene's own TOML does not parse back: {e}\n--- written:\n{}",
            excerpt(&written, 0, 600)
        ));
    }
    if scene.objects.len() > MAX_PREPARED_OBJECTS {
        return Verdict::Accepted;
    }
    let models = vec![Model::teapot(); scene.objects.len()];
    match PreparedScene::new(&scene, &models) {
        Ok(_) => Verdict::Accepted,
        Err(e) => Verdict::Rejected(messages(&e)),
    }
}

/// Warnings the scene builder may add after the interpreter's capped list
/// (one per option it adjusts, and the count of those not kept).
const MAX_BUILD_WARNINGS: usize = 16;

/// The name a mutated RIB is read under: its `ReadArchive "parts/..."`
/// requests resolve against the archive test scene's directory, so the
/// archive seed reads its real parts.
fn rib_name() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/rib/archive/mutated.rib")
}

fn check_rib(text: &str) -> Verdict {
    let rib = match RibScene::from_text(text, rib_name()) {
        Ok(rib) => rib,
        Err(e) => return Verdict::Rejected(messages(&e)),
    };
    if rib.models.len() != rib.scene.objects.len() {
        return Verdict::Broken(format!(
            "{} models for {} objects",
            rib.models.len(),
            rib.scene.objects.len()
        ));
    }
    // At most the kept warnings plus the one that counts the rest.
    if rib.warnings.len() > reyes::rib::interp::MAX_WARNINGS + MAX_BUILD_WARNINGS {
        return Verdict::Broken(format!("{} warnings kept", rib.warnings.len()));
    }
    if let Some(long) = rib
        .warnings
        .iter()
        .map(ToString::to_string)
        .find(|w| w.len() >= MAX_MESSAGE_BYTES)
    {
        return Verdict::Broken(format!(
            "warning of {} bytes: {}",
            long.len(),
            excerpt(&long, 0, 300)
        ));
    }
    if rib.scene.objects.len() > MAX_PREPARED_OBJECTS {
        return Verdict::Accepted;
    }
    match rib.prepare() {
        Ok(_) => Verdict::Accepted,
        Err(e) => Verdict::Rejected(messages(&e)),
    }
}

// ------------------------------------------------------------- mutations

/// A mutated input and what was done to it.
struct Mutant {
    text: String,
    seed_index: usize,
    log: Vec<String>,
    /// Byte offset of the last mutation (for the excerpt).
    at: usize,
}

/// Byte spans of the numbers in `bytes`.
fn number_spans(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        let starts = b.is_ascii_digit()
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if !starts {
            i += 1;
            continue;
        }
        let mut start = i;
        while start > 0 && matches!(bytes[start - 1], b'-' | b'+' | b'.') {
            start -= 1;
        }
        let mut end = i;
        while end < bytes.len() {
            match bytes[end] {
                b'0'..=b'9' | b'.' | b'e' | b'E' | b'_' => end += 1,
                b'-' | b'+' if matches!(bytes[end - 1], b'e' | b'E') => end += 1,
                _ => break,
            }
        }
        spans.push((start, end));
        i = end;
    }
    spans
}

/// Splits into lines, each keeping its `\n`.
fn lines(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes
        .split_inclusive(|&b| b == b'\n')
        .map(<[u8]>::to_vec)
        .collect()
}

fn mutate(rng: &mut StdRng, target: &Target) -> Mutant {
    let seed_index = rng.random_range(0..target.seeds.len());
    let mut bytes = target.seeds[seed_index].as_bytes().to_vec();
    let mut log = Vec::new();
    let mut at = 0;
    // Mostly a few mutations, sometimes many.
    let count = if rng.random_ratio(1, 8) {
        rng.random_range(8..40)
    } else {
        rng.random_range(1..5)
    };
    for _ in 0..count {
        // Duplicated long lines compound: keep inputs small enough to be quick.
        if bytes.len() > MAX_INPUT_BYTES {
            bytes.truncate(MAX_INPUT_BYTES);
            log.push(format!("cap at {MAX_INPUT_BYTES}"));
        }
        let len = bytes.len();
        at = rng.random_range(0..len.max(1));
        match rng.random_range(0..12) {
            0 if len > 0 => {
                let bit = rng.random_range(0..8);
                bytes[at] ^= 1 << bit;
                log.push(format!("flip bit {bit} @{at}"));
            }
            1 if len > 0 => {
                let b = if rng.random_ratio(1, 3) {
                    rng.random()
                } else {
                    target.bytes[rng.random_range(0..target.bytes.len())]
                };
                bytes[at] = b;
                log.push(format!("set @{at} = {:?}", b as char));
            }
            2 => {
                // A run of inserted bytes; sometimes a very long one.
                let n = if rng.random_ratio(1, 10) {
                    rng.random_range(100..6000)
                } else {
                    rng.random_range(1..16)
                };
                let same = rng.random_bool(0.5);
                let first = target.bytes[rng.random_range(0..target.bytes.len())];
                let run: Vec<u8> = (0..n)
                    .map(|_| {
                        if same {
                            first
                        } else {
                            target.bytes[rng.random_range(0..target.bytes.len())]
                        }
                    })
                    .collect();
                let at = at.min(len);
                bytes.splice(at..at, run);
                log.push(format!("insert {n} bytes @{at} (from {:?})", first as char));
            }
            3 => {
                let fragment = target.fragments[rng.random_range(0..target.fragments.len())];
                let at = at.min(len);
                bytes.splice(at..at, fragment.bytes());
                log.push(format!("insert {fragment:?} @{at}"));
            }
            4 if len > 0 => {
                let end = (at + rng.random_range(1..64)).min(len);
                bytes.drain(at..end);
                log.push(format!("delete {at}..{end}"));
            }
            5 if len > 0 => {
                // Copy a chunk elsewhere.
                let end = (at + rng.random_range(1..80)).min(len);
                let chunk = bytes[at..end].to_vec();
                let to = rng.random_range(0..=len);
                bytes.splice(to..to, chunk);
                log.push(format!("copy {at}..{end} to @{to}"));
                at = to;
            }
            6 | 7 => {
                let spans = number_spans(&bytes);
                if spans.is_empty() {
                    continue;
                }
                let (start, end) = spans[rng.random_range(0..spans.len())];
                let value = EXTREME_NUMBERS[rng.random_range(0..EXTREME_NUMBERS.len())];
                let old = String::from_utf8_lossy(&bytes[start..end]).into_owned();
                let value = if rng.random_ratio(1, 12) {
                    // A huge digit string.
                    "9".repeat(rng.random_range(40..5000))
                } else {
                    value.to_string()
                };
                log.push(format!(
                    "number @{start} {old:?} -> {}",
                    excerpt(&value, 0, 40)
                ));
                bytes.splice(start..end, value.into_bytes());
                at = start;
            }
            8 => {
                let mut l = lines(&bytes);
                if l.is_empty() {
                    continue;
                }
                let from = rng.random_range(0..l.len());
                let to = rng.random_range(0..=l.len());
                let times = if rng.random_ratio(1, 10) {
                    rng.random_range(2..200)
                } else {
                    1
                };
                let line = l[from].clone();
                for _ in 0..times {
                    l.insert(to, line.clone());
                }
                log.push(format!(
                    "duplicate line {} x{times} to {}",
                    from + 1,
                    to + 1
                ));
                bytes = l.concat();
            }
            9 => {
                let mut l = lines(&bytes);
                if l.len() < 2 {
                    continue;
                }
                let (a, b) = (rng.random_range(0..l.len()), rng.random_range(0..l.len()));
                l.swap(a, b);
                log.push(format!("swap lines {} and {}", a + 1, b + 1));
                bytes = l.concat();
            }
            10 => {
                let mut l = lines(&bytes);
                if l.is_empty() {
                    continue;
                }
                let i = rng.random_range(0..l.len());
                l.remove(i);
                log.push(format!("delete line {}", i + 1));
                bytes = l.concat();
            }
            11 if rng.random_ratio(1, 3) => {
                let keep = rng.random_range(0..=len);
                bytes.truncate(keep);
                log.push(format!("truncate to {keep}"));
                at = keep;
            }
            _ => {}
        }
    }
    if bytes.len() > MAX_INPUT_BYTES {
        bytes.truncate(MAX_INPUT_BYTES);
        log.push(format!("cap at {MAX_INPUT_BYTES}"));
    }
    Mutant {
        text: String::from_utf8_lossy(&bytes).into_owned(),
        seed_index,
        log,
        at,
    }
}

// ---------------------------------------------------------------- runner

thread_local! {
    /// Whether this thread is inside a check (its panics are recorded, not printed).
    static CAPTURING: Cell<bool> = const { Cell::new(false) };
    static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// A panic hook that records the message and location of panics inside a
/// check, and leaves every other panic to the default hook.
fn install_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if CAPTURING.with(Cell::get) {
                let payload = info.payload();
                let message = payload
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_string())
                    .or_else(|| payload.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "(non-string payload)".to_string());
                let location = info.location().map(ToString::to_string).unwrap_or_default();
                LAST_PANIC.with(|p| *p.borrow_mut() = Some(format!("{message} at {location}")));
            } else {
                previous(info);
            }
        }));
    });
}

/// Runs `check` on `text`: `Err` with the panic's message if it panicked.
fn guarded(check: fn(&str) -> Verdict, text: &str) -> Result<Verdict, String> {
    CAPTURING.with(|c| c.set(true));
    let result = panic::catch_unwind(AssertUnwindSafe(|| check(text)));
    CAPTURING.with(|c| c.set(false));
    result.map_err(|_| {
        LAST_PANIC
            .with(|p| p.borrow_mut().take())
            .unwrap_or_else(|| "(no message)".to_string())
    })
}

/// What one input did, as the runner counts it.
struct Outcome {
    accepted: bool,
    /// What is wrong, if anything.
    problem: Option<String>,
}

/// Runs `check` on `text` and judges the outcome.
fn outcome(check: fn(&str) -> Verdict, text: &str) -> Outcome {
    let (accepted, problem) = match guarded(check, text) {
        Err(panic) => (false, Some(format!("panicked: {panic}"))),
        Ok(Verdict::Broken(why)) => (false, Some(why)),
        Ok(Verdict::Rejected(messages)) => {
            match messages.iter().find(|m| m.len() >= MAX_MESSAGE_BYTES) {
                None => (false, None),
                Some(m) => (
                    false,
                    Some(format!(
                        "error message of {} bytes (limit {MAX_MESSAGE_BYTES}): {}",
                        m.len(),
                        excerpt(m, 0, 300)
                    )),
                ),
            }
        }
        Ok(Verdict::Accepted) => (true, None),
    };
    Outcome { accepted, problem }
}

/// At most `max` characters of `text` around byte `at`, escaped.
fn excerpt(text: &str, at: usize, max: usize) -> String {
    let at = at.min(text.len());
    let mut start = at.saturating_sub(max / 2);
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let cut: String = text[start..].chars().take(max).collect();
    let more = if start + cut.len() < text.len() {
        "…"
    } else {
        ""
    };
    let less = if start > 0 { "…" } else { "" };
    format!("{less}{cut:?}{more}")
}

/// The kind of a problem, which minimising keeps: a panic, a long message
/// or the problem's first words.
fn kind(problem: &str) -> String {
    if problem.starts_with("panicked") {
        "panicked".to_string()
    } else if problem.starts_with("error message of") {
        "long message".to_string()
    } else {
        problem.chars().take(40).collect()
    }
}

/// Greedily drops lines, then ever smaller runs of characters, while `text`
/// still has the same kind of problem, for at most a few seconds.
fn minimise(check: fn(&str) -> Verdict, text: &str, problem_kind: &str) -> String {
    let deadline = Instant::now() + Duration::from_secs(5);
    let same = |candidate: &str| {
        outcome(check, candidate)
            .problem
            .is_some_and(|p| kind(&p) == problem_kind)
    };
    let mut l: Vec<String> = text.split_inclusive('\n').map(str::to_string).collect();
    let mut i = 0;
    while i < l.len() && Instant::now() < deadline {
        let mut candidate = l.clone();
        candidate.remove(i);
        if same(&candidate.concat()) {
            l = candidate;
        } else {
            i += 1;
        }
    }
    let mut chars: Vec<char> = l.concat().chars().collect();
    let mut run = chars.len() / 2;
    while run > 0 && Instant::now() < deadline {
        let mut at = 0;
        while at + run <= chars.len() && Instant::now() < deadline {
            let mut candidate = chars.clone();
            candidate.drain(at..at + run);
            if same(&candidate.iter().collect::<String>()) {
                chars = candidate;
            } else {
                at += run;
            }
        }
        run /= 2;
    }
    chars.into_iter().collect()
}

fn env_parse<T: std::str::FromStr>(name: &str) -> Option<T> {
    let value = std::env::var(name).ok()?;
    match value.trim().parse() {
        Ok(v) => Some(v),
        Err(_) => panic!("{name}={value:?} does not parse"),
    }
}

/// The seed of iteration `n` of a run seeded with `seed` (splitmix64).
fn iteration_seed(seed: u64, n: u64) -> u64 {
    let mut z = seed.wrapping_add(n.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn fuzz(target: &Target) {
    install_hook();
    // The seeds themselves must be accepted: mutations start from valid inputs.
    for (i, seed) in target.seeds.iter().enumerate() {
        match guarded(target.check, seed) {
            Ok(Verdict::Accepted) => {}
            Ok(Verdict::Rejected(m)) => panic!("{} seed {i} is rejected: {m:?}", target.name),
            Ok(Verdict::Broken(why)) => panic!("{} seed {i}: {why}", target.name),
            Err(p) => panic!("{} seed {i} panics: {p}", target.name),
        }
    }
    let seed = env_parse::<u64>("MUTATION_SEED").unwrap_or_else(rand::random);
    let only = env_parse::<u64>("MUTATION_ITERATION");
    let seconds = env_parse::<f64>("MUTATION_SECONDS").unwrap_or(DEFAULT_SECONDS);
    let count = env_parse::<u64>("MUTATION_EXECUTIONS");
    match count {
        Some(n) => println!(
            "{}: MUTATION_SEED={seed} MUTATION_EXECUTIONS={n}",
            target.name
        ),
        None => println!(
            "{}: MUTATION_SEED={seed} MUTATION_SECONDS={seconds}",
            target.name
        ),
    }
    let start = Instant::now();
    let deadline = start + Duration::from_secs_f64(seconds.max(0.0));
    let (mut executions, mut accepted) = (0u64, 0u64);
    let mut slowest = (Duration::ZERO, 0u64);
    let mut failures = Vec::new();
    let mut iteration = only.unwrap_or(0);
    loop {
        let done = match (only, count) {
            (Some(n), _) => iteration > n,
            (None, Some(n)) => executions >= n,
            (None, None) => Instant::now() >= deadline,
        };
        if done {
            break;
        }
        let mut rng = StdRng::seed_from_u64(iteration_seed(seed, iteration));
        let mutant = mutate(&mut rng, target);
        if only.is_some() {
            println!(
                "iteration {iteration}: seed text {}, mutations {:?}\n--- input ({} bytes):\n{}\n---",
                mutant.seed_index,
                mutant.log,
                mutant.text.len(),
                excerpt(&mutant.text, 0, MAX_INPUT_BYTES / 4)
            );
        }
        let began = Instant::now();
        let Outcome {
            accepted: ok,
            problem: found,
        } = outcome(target.check, &mutant.text);
        let took = began.elapsed();
        if took > slowest.0 {
            slowest = (took, iteration);
        }
        executions += 1;
        match found {
            None => accepted += u64::from(ok),
            Some(why) => {
                let small = minimise(target.check, &mutant.text, &kind(&why));
                let report = format!(
                    "{}: MUTATION_SEED={seed} MUTATION_ITERATION={iteration}: {why}\n  \
                     seed text {}, mutations {:?}\n  excerpt: {}\n  minimised ({} bytes): {}",
                    target.name,
                    mutant.seed_index,
                    mutant.log,
                    excerpt(&mutant.text, mutant.at, 240),
                    small.len(),
                    excerpt(&small, 0, 600),
                );
                println!("{report}");
                failures.push(report);
                if failures.len() >= MAX_FAILURES {
                    break;
                }
            }
        }
        iteration += 1;
    }
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{}: {executions} executions in {secs:.1} s ({:.0}/s), {accepted} accepted; \
         slowest {:.1} ms (iteration {})",
        target.name,
        executions as f64 / secs.max(1e-9),
        slowest.0.as_secs_f64() * 1e3,
        slowest.1
    );
    assert!(
        failures.is_empty(),
        "{} failing input(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        only.is_some() || executions > 10,
        "only {executions} executions"
    );
}

// ----------------------------------------------------------------- seeds

const MODEL_BYTES: &[u8] = b"0123456789.-+eE \t\n\r,;:nafi\x00\x7f\xc3\xa9";
const BPT_FRAGMENTS: &[&str] = &[
    "3 3\n",
    "3 4\n",
    "0 0 0\n",
    "1e39 0 0\n",
    "nan",
    "inf",
    "\u{feff}",
    "\r\n",
    "\n\n",
    "32\n",
    "-1\n",
    "4294967296\n",
    "18446744073709551616\n",
];
const BEZ_FRAGMENTS: &[&str] = &[
    "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n",
    "0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n",
    "306,306,306,306,306,306,306,306,306,306,306,306,306,306,306,306\n",
    "0.0,0.0,0.0\n",
    "1e39,0,0\n",
    ",",
    ",,",
    "nan",
    "inf",
    "\u{feff}",
    "\r\n",
    "32\n",
    "4294967296\n",
    "18446744073709551616\n",
];
const SCENE_BYTES: &[u8] = b"[]{}=\"'#.,-+_0123456789eE \n\t\\:ntfrue";
const SCENE_FRAGMENTS: &[&str] = &[
    "[[objects]]\nmodel = \"teapot\"\n",
    "[[lights]]\ndirection = [0, 0, -1]\n",
    "[camera]\neye = [0, -10, 0]\ntarget = [0, 0, 0]\n",
    "[camera_close]\neye = [1, -10, 0]\ntarget = [0, 0, 0]\n",
    "[lens]\naperture = 0.1\n",
    "transform_close = { rotate_degrees = [0, 0, 90] }\n",
    "transform = { scale = [1, 0, 1] }\n",
    "displacement = { source = \"sines\", scale = 0.1 }\n",
    "[objects.displacement]\nsource = \"wgsl\"\nscale = 1\nbound = 1\nwgsl = \"fn displacement_user(u: f32, v: f32) -> f32 { return u; }\"\n",
    "sampling = \"nearest\"\n",
    "sampling = \"adaptive\"\n",
    "shutter = 0.5\n",
    "spp = 64\n",
    "max_split_depth = 64\n",
    "dicing = \"fixed\"\n",
    "aov = \"depth\"\n",
    "[resolution]\nwidth = 1\nheight = 4294967295\n",
    "\"\"\"",
    "'''",
    "\\u0000",
    "\\U0010FFFF",
    "nan",
    "-inf",
    "true",
    "1979-05-27T07:32:00Z",
    "{}",
    "[]",
];

/// A moving camera and a moving object, with a stochastic sampling mode.
const MOTION_SCENE: &str = r#"spp = 16
sampling = "interval"
jitter = true
shutter = 0.75

[resolution]
width = 320
height = 240

[camera]
eye = [4.0, -12.0, 7.0]
target = [0.2, 0.0, 1.5]
up = [0.0, 0.0, 1.0]
fov_y_degrees = 40.0
near = 0.1
far = 1000.0

[camera_close]
eye = [4.5, -12.0, 7.0]
target = [0.7, 0.0, 1.5]

[[objects]]
model = "teapot"
color = [0.8, 0.36, 0.18]
sides = 1
reverse_orientation = true
transform = { translate = [0.0, 0.0, 0.0], rotate_degrees = [0.0, 0.0, 0.0], scale = 1.0 }
transform_close = { translate = [1.0, 0.0, 0.5], rotate_degrees = [0.0, 0.0, 30.0], scale = [1.0, 1.0, 1.5] }

[[lights]]
direction = [0.4, 0.8, -1.0]
color = [1.0, 1.0, 1.0]
intensity = 1.0
"#;

/// A lens, two displaced objects and two lights.
const LENS_DISPLACEMENT_SCENE: &str = r#"spp = 9
sampling = "adaptive"
background = [0.05, 0.05, 0.07]
ambient = 0.1
dicing = "fixed"
dice_threshold = 16.0
shading_rate = 1.0
shading_interpolation = "constant"
aov = "normal"
max_split_depth = 24

[lens]
aperture = 0.2
focus_distance = 12.5

[specular]
strength = 0.25
shininess = 32.0

[[objects]]
model = "teapot"
color = [0.8, 0.8, 0.8]
[objects.transform]
translate = [0.0, 0.0, 0.0]
rotate_degrees = [10.0, 0.0, 45.0]
scale = [1.0, -1.0, 2.0]
[objects.displacement]
source = "bumps"
scale = 0.05
bound = 0.05
tiling = 4.0

[[objects]]
model = "teapot"
color = [0.3, 0.5, 0.8]
transform = { translate = [7.0, 0.0, 0.0], scale = 0.5 }
displacement = { source = "sines", scale = -0.1, tiling = 2.0 }

[[lights]]
direction = [0.4, 0.8, -1.0]

[[lights]]
direction = [-1.0, 0.0, 0.0]
color = [0.2, 0.3, 1.0]
intensity = 0.5
"#;

/// A user WGSL displacement function (checked with naga on the host).
const WGSL_SCENE: &str = r#"[[objects]]
model = "teapot"
color = [0.8, 0.36, 0.18]
[objects.displacement]
source = "wgsl"
scale = 0.1
bound = 0.1
tiling = 4.0
wgsl = """
fn displacement_user(u: f32, v: f32) -> f32 {
    let d = vec2<f32>(fract(u), fract(v)) - vec2<f32>(0.5);
    return max(0.0, 1.0 - 8.0 * dot(d, d));
}"""
"#;

/// User WGSL: the seeds of [`check_wgsl`] (a displacement function, the
/// gallery's surface shaders and the built-in standard shaders).
fn wgsl_seeds() -> Vec<String> {
    vec![
        "fn displacement_user(u: f32, v: f32) -> f32 {\n    let d = vec2<f32>(fract(u), fract(v)) - vec2<f32>(0.5);\n    var h = 0.0;\n    for (var i = 0; i < 4; i += 1) {\n        h += sin(f32(i) * d.x) * cos(d.y);\n    }\n    return max(0.0, 1.0 - 8.0 * dot(d, d)) + h;\n}\n".to_owned(),
        include_str!("../../docs/shaders/marble.wgsl").to_owned(),
        include_str!("../../docs/shaders/ripples.wgsl").to_owned(),
        include_str!("../../shaders/reyes/standard/paintedplastic.wgsl").to_owned(),
        include_str!("../../shaders/reyes/standard/shinymetal.wgsl").to_owned(),
        include_str!("../../shaders/reyes/standard/bumpy.wgsl").to_owned(),
    ]
}

/// Bytes worth writing into WGSL.
const WGSL_BYTES: &[u8] = b"0123456789.-+eE(){}[]<>;:,=!&|*/%@ \t\nfuvlrtixa_";
/// WGSL worth inserting whole: what user code may not do (barriers,
/// `discard`, directives, module-scope variables, the renderer's names,
/// huge arrays, endless loops) and what it may.
const WGSL_FRAGMENTS: &[&str] = &[
    "enable f16;\n",
    "requires readonly_and_readwrite_storage_textures;\n",
    "diagnostic(off, derivative_uniformity);\n",
    "workgroupBarrier();\n",
    "storageBarrier();\n",
    "discard;\n",
    "var<private> state: u32;\n",
    "var<workgroup> shared_floats: array<f32, 64>;\n",
    "atomicAdd(&stats[0], 1u);\n",
    "let big = array<f32, 1000000>();\n",
    "var a: array<vec4<f32>, 100000>;\n",
    "loop { }\n",
    "while (true) { continue; }\n",
    "for (var i = 0u; i >= 0u; i += 1u) { }\n",
    "const K: f32 = 1e39;\n",
    "fn displacement_user(u: f32, v: f32) -> f32 { return u; }\n",
    "fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput { return SurfaceOutput(ctx.Cs, ctx.Os); }\n",
    "struct Parameters { Kd: f32, map: TextureId, }\n",
    "const DEFAULTS = Parameters(1.0, TextureId(0u));\n",
    "texture(ctx, params.map, ctx.s, ctx.t)",
    "environment(ctx, params.map, ctx.N)",
    "illuminance(ctx, i)",
    "noise(ctx.P)",
    "f32(",
    "vec3<f32>(",
    "}\n",
];

/// A mutated WGSL source checked as a scene's user code is, on the host:
/// as a displacement function (`user_wgsl::check`) and as a surface or
/// displacement shader against the shading interface
/// (`SurfaceShader::from_source`). Accepted when either accepts it.
fn check_wgsl(text: &str) -> Verdict {
    let path = std::path::Path::new("mutated.wgsl");
    let shader = reyes::surface_shader::SurfaceShader::from_source(path, text.to_owned());
    let function = reyes::user_wgsl::check(text);
    match (shader, function) {
        (Ok(_), _) | (_, Ok(())) => Verdict::Accepted,
        (Err(shader), Err(function)) => {
            let mut all = messages(&shader);
            all.extend(messages(&function));
            Verdict::Rejected(all)
        }
    }
}

fn scene_seeds() -> Vec<String> {
    vec![
        Scene::default_teapot().to_toml_string(),
        "[[objects]]\nmodel = \"teapot\"\n".to_string(),
        MOTION_SCENE.to_string(),
        LENS_DISPLACEMENT_SCENE.to_string(),
        WGSL_SCENE.to_string(),
    ]
}

/// OBJ seeds: a cube of quads with texture coordinates in groups, and a
/// mesh of a triangle, a quad and a pentagon with relative indices.
const OBJ_SEEDS: [&str; 2] = [
    "# cube\nmtllib cube.mtl\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
     vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\no cube\ng bottom\nusemtl grey\nf 1/1/1 4/2/1 3/3/1 2/4/1\n\
     g top\ns 1\nf 5/1/1 6/2/1 7/3/1 8/4/1\nf 1/1/1 2/2/1 6/3/1 5/4/1\nf 2/1/1 3/2/1 7/3/1 6/4/1\n\
     f 3/1/1 4/2/1 8/3/1 7/4/1\nf 4/1/1 1/2/1 5/3/1 8/4/1\n",
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 3 0.5 0\nv 0.5 2 0\n\
     f 1 2 3 4\nf -5 -6 -1\nf 2 5 7 6 3\n",
];
const OBJ_BYTES: &[u8] = b"0123456789.-+eE \t\n\r/#fvtnglpo\x00\xc3\xa9";
const OBJ_FRAGMENTS: &[&str] = &[
    "v 0 0 0\n",
    "v 1e39 0 0\n",
    "v 1 2 3 0\n",
    "vt 0.5 0.5\n",
    "vn 0 0 1\n",
    "f 1 2 3\n",
    "f 1 2 3 4\n",
    "f 3 2 1\n",
    "f 1/1 2/2 3/3\n",
    "f 1//1 2//1 3//1\n",
    "f -1 -2 -3\n",
    "f 0 1 2\n",
    "f 1 2\n",
    "f\n",
    "l 1 2\n",
    "p 1\n",
    "g group\n",
    "o\n",
    "usemtl m\n",
    "/",
    "//",
    "-1",
];

const RIB_BYTES: &[u8] = b"[]\"#-+.eE0123456789 \n\t\\PWorldBeginEndAttribute";
const RIB_FRAGMENTS: &[&str] = &[
    "SubdivisionMesh \"bilinear\" [4 3] [0 1 2 3 1 4 2] [\"hole\" \"crease\"] [1 0 2 1] [1 0 1] [2] \"P\" [0 0 0 1 0 0 1 1 0 0 1 0 2 0 0]\n",
    "SubdivisionMesh \"catmull-clark\" [4] [0 1 2 3] [\"interpolateboundary\"] [1 0] [2] [] \"P\" [0 0 0 1 0 0 1 1 0 0 1 0] \"st\" [0 0 1 0 1 1 0 1]\n",
    "WorldBegin\n",
    "WorldEnd\n",
    "AttributeBegin\n",
    "AttributeEnd\n",
    "TransformBegin\n",
    "TransformEnd\n",
    "MotionBegin [0 1]\n",
    "MotionEnd\n",
    "Translate 0 0 5\n",
    "Scale -1 1 1\n",
    "Scale 0 0 0\n",
    "Rotate 90 0 0 1\n",
    "Skew 45 0 1 0 1 0 0\n",
    "Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 0]\n",
    "Sphere 1 -1 1 360\n",
    "Torus 1 0.25 0 360 360\n",
    "Hyperboloid 1 0 0 0 1 1 360\n",
    "Polygon \"P\" [0 0 5 0 1 5 1 1 5]\n",
    "PointsPolygons [3] [0 1 2] \"P\" [0 0 5 0 1 5 1 1 5]\n",
    "GeneralPolygon [3] \"P\" [0 0 5 0 1 5 1 1 5]\n",
    "Patch \"bilinear\" \"P\" [0 0 5 0 1 5 1 0 5 1 1 5]\n",
    "PatchMesh \"bicubic\" 4 \"periodic\" 4 \"periodic\" \"P\" [",
    "Basis \"catmull-rom\" 1 \"b-spline\" 1\n",
    "Basis [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1] 3 \"power\" 4\n",
    "Surface \"plastic\" \"Ks\" [0.5] \"roughness\" [0]\n",
    "Surface \"metal\" \"uniform float Ks\" 1\n",
    "Surface \"constant\"\n",
    "LightSource \"distantlight\" 1 \"from\" [0 0 0] \"to\" [0 0 0]\n",
    "LightSource \"pointlight\" 2 \"intensity\" [1e39]\n",
    "LightSource \"ambientlight\" 3 \"lightcolor\" [1 0 0]\n",
    "Illuminate 1 0\n",
    "Declare \"x\" \"varying float[4]\"\n",
    "CoordinateSystem \"a\"\nCoordSysTransform \"a\"\n",
    "ReadArchive \"parts/square.rib\"\n",
    "ReadArchive \"mutated.rib\"\n",
    "ObjectBegin 1\n",
    "ObjectBegin \"thing\"\nSphere 1 -1 1 360\nObjectEnd\n",
    "ObjectEnd\n",
    "ObjectInstance 1\n",
    "ObjectInstance \"thing\"\n",
    "Projection \"perspective\" \"fov\" [179.9]\n",
    "Format 1 100000 1\n",
    "PixelSamples 100 0\n",
    "Shutter 1 0\n",
    "DepthOfField 0 0 0\n",
    "Clipping 1e30 1e-30\n",
    "Display \"out.tif\" \"file\" \"rgb\"\n",
    "\"",
    "[",
    "]",
    "#",
    "\\\n",
];

/// The RIB scenes of the tests and the documentation.
fn rib_seeds() -> Vec<String> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut paths = vec![
        root.join("tests/rib/scene.rib"),
        root.join("tests/rib/quadrant.rib"),
        root.join("tests/rib/archive/main.rib"),
        root.join("../docs/scenes/gallery.rib"),
        root.join("tests/rib/subdivision.rib"),
        root.join("tests/rib/instances.rib"),
    ];
    if let Ok(dir) = std::fs::read_dir(root.join("tests/data/rib_golden")) {
        let mut golden: Vec<PathBuf> = dir
            .map(|e| e.expect("directory entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "rib"))
            .collect();
        // The archive scenes' relative names resolve against another
        // directory under the mutated name (see `rib_name`).
        golden
            .retain(|p| std::fs::read_to_string(p).is_ok_and(|text| !text.contains("ReadArchive")));
        golden.sort();
        paths.extend(golden);
    }
    paths
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())))
        .collect()
}

// ----------------------------------------------------------------- tests

#[test]
fn number_spans_find_numbers() {
    let text = b"a1 = -1.5e-3, x2y [4294967296,.5] 7";
    let spans: Vec<&[u8]> = number_spans(text)
        .into_iter()
        .map(|(s, e)| &text[s..e])
        .collect();
    assert_eq!(
        spans,
        [&b"-1.5e-3"[..], &b"4294967296"[..], &b".5"[..], &b"7"[..]]
    );
}

#[test]
fn panics_in_a_check_are_caught_and_named() {
    install_hook();
    fn boom(text: &str) -> Verdict {
        panic!("boom on {} bytes", text.len());
    }
    let problem = outcome(boom, "abc").problem.expect("a panic is a problem");
    assert!(
        problem.starts_with("panicked: boom on 3 bytes at "),
        "{problem}"
    );
    assert!(minimise(boom, "a\nb\n", "panicked").is_empty());
}

#[test]
fn mutated_bpt_never_panics() {
    fuzz(&Target {
        name: "mutated_bpt_never_panics",
        seeds: vec![bpt::write(&Model::teapot())],
        bytes: MODEL_BYTES,
        fragments: BPT_FRAGMENTS,
        check: check_bpt,
    });
}

#[test]
fn mutated_bez_never_panics() {
    let path = common::shared_data("teapot.bez");
    let Ok(text) = std::fs::read_to_string(&path) else {
        println!(
            "NOTICE: {} not found; mutating the embedded teapot written as .bez only",
            path.display()
        );
        fuzz(&Target {
            name: "mutated_bez_never_panics",
            seeds: vec![bez::write(&Model::teapot())],
            bytes: MODEL_BYTES,
            fragments: BEZ_FRAGMENTS,
            check: check_bez,
        });
        return;
    };
    fuzz(&Target {
        name: "mutated_bez_never_panics",
        seeds: vec![text, bez::write(&Model::teapot())],
        bytes: MODEL_BYTES,
        fragments: BEZ_FRAGMENTS,
        check: check_bez,
    });
}

#[test]
fn mutated_obj_never_panics() {
    fuzz(&Target {
        name: "mutated_obj_never_panics",
        seeds: OBJ_SEEDS.map(str::to_owned).to_vec(),
        bytes: OBJ_BYTES,
        fragments: OBJ_FRAGMENTS,
        check: check_obj,
    });
}

#[test]
fn mutated_scene_toml_never_panics() {
    fuzz(&Target {
        name: "mutated_scene_toml_never_panics",
        seeds: scene_seeds(),
        bytes: SCENE_BYTES,
        fragments: SCENE_FRAGMENTS,
        check: check_scene,
    });
}

#[test]
fn mutated_rib_never_panics() {
    fuzz(&Target {
        name: "mutated_rib_never_panics",
        seeds: rib_seeds(),
        bytes: RIB_BYTES,
        fragments: RIB_FRAGMENTS,
        check: check_rib,
    });
}

#[test]
fn mutated_user_wgsl_never_panics() {
    fuzz(&Target {
        name: "mutated_user_wgsl_never_panics",
        seeds: wgsl_seeds(),
        bytes: WGSL_BYTES,
        fragments: WGSL_FRAGMENTS,
        check: check_wgsl,
    });
}

/// Minimised from `mutated_scene_toml_never_panics`: a user WGSL function
/// with a long token gives an error message that quotes the token whole
/// (naga's message, passed on by `user_wgsl::check`), so a
/// scene's error message is not bounded by its size.
#[test]
fn user_wgsl_error_quotes_long_tokens_whole() {
    let messages = [
        // "numeric literal not representable by target type: `999…`"
        format!(
            "fn displacement_user(u: f32, v: f32) -> f32 {{ return {}; }}",
            "9".repeat(5000)
        ),
        // "expected `;`, found \"nnn…\""
        format!(
            "fn displacement_user(u: f32, v: f32) -> f32 {{ return 1.0 {}; }}",
            "n".repeat(5000)
        ),
    ]
    .map(|wgsl| {
        let text = format!(
            "[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\n\
             source = \"wgsl\"\nscale = 0.1\nbound = 0.1\nwgsl = \"{wgsl}\"\n"
        );
        Scene::from_toml_str(&text)
            .expect_err("the WGSL is invalid")
            .to_string()
    });
    let long: Vec<String> = messages
        .iter()
        .filter(|m| m.len() >= MAX_MESSAGE_BYTES)
        .map(|m| format!("{} bytes: {}", m.len(), excerpt(m, 0, 200)))
        .collect();
    assert!(long.is_empty(), "{long:#?}");
}

/// Found by `mutated_scene_toml_never_panics` (MUTATION_SECONDS=60): an
/// image displacement source that cannot be read is quoted whole twice
/// (`SceneError::Displacement` names the source, and
/// `DisplacementError`'s "cannot read height map" names the path), so the
/// message grows with the scene's text.
#[test]
fn long_displacement_source_is_quoted_whole() {
    let text = format!(
        "[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\nsource = \"{}\"\nscale = 0.1\n",
        "-".repeat(2100)
    );
    let scene = Scene::from_toml_str(&text).expect("valid until the PNG is read");
    let message = PreparedScene::new(&scene, &[Model::teapot()])
        .expect_err("no such height map")
        .to_string();
    assert!(
        message.len() < MAX_MESSAGE_BYTES,
        "{} bytes: {}",
        message.len(),
        excerpt(&message, 0, 300)
    );
}

/// Found by `mutated_rib_never_panics`: names from the input were quoted
/// whole in warnings (an unknown request, a light shader) and in request
/// errors (an unknown basis or wrap mode, a `ReadArchive` name that cannot
/// be read), so a message grew with the scene's text.
#[test]
fn long_rib_names_are_quoted_cut() {
    let long = |c: &str| c.repeat(5000);
    let warned = [
        format!("WorldBegin\n{}\nWorldEnd\n", long("W")),
        format!("WorldBegin\nLightSource \"{}\" 1\nWorldEnd\n", long("A")),
        format!("WorldBegin\nSurface \"{}\"\nWorldEnd\n", long("s")),
    ];
    for text in &warned {
        let rib = RibScene::from_text(text, rib_name()).expect("only warnings");
        assert!(!rib.warnings.is_empty());
        for w in &rib.warnings {
            let shown = w.to_string();
            assert!(
                shown.len() < 1024,
                "{} bytes: {}",
                shown.len(),
                excerpt(&shown, 0, 200)
            );
        }
    }
    let refused = [
        format!(
            "WorldBegin\nReadArchive \"parts/{}\"\nWorldEnd\n",
            long("-")
        ),
        format!(
            "WorldBegin\nBasis \"b-spl{}\" 1 \"bezier\" 3\nWorldEnd\n",
            long("4")
        ),
        format!(
            "WorldBegin\nPatchMesh \"bicubic\" 4 \"non{}\" 4 \"nonperiodic\" \"P\" [0 0 0]\nWorldEnd\n",
            long("9")
        ),
    ];
    for text in &refused {
        let error = RibScene::from_text(text, rib_name())
            .expect_err("invalid")
            .to_string();
        assert!(
            error.len() < 1024,
            "{} bytes: {}",
            error.len(),
            excerpt(&error, 0, 200)
        );
    }
}
