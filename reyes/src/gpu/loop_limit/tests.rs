//! Tests of [`super`].

use super::*;

fn context() -> LoopLimitContext {
    LoopLimitContext {
        spp: 1,
        sampling: Sampling::Bbox,
        blurred: false,
        dicing: Dicing::Fixed,
        dice_threshold: DEFAULT_DICE_THRESHOLD,
        shading_rate: DEFAULT_SHADING_RATE,
        max_split_depth: 24,
        user_displacement: false,
        depth_guard_drops: 0,
        largest_micropolygon_px: 1.0,
    }
}

fn message(context: LoopLimitContext, rasterization: u32, waits: u32) -> String {
    LoopLimitError::new(rasterization, waits, 3, 2, Some(1), (1, 1), context).to_string()
}

#[test]
fn the_schedulers_loop_limit_gives_the_facts() {
    let report = scheduler::RunReport {
        attempts: 6,
        workgroups: 2,
        ..scheduler::RunReport::default()
    };
    let error = RunError::LoopLimit {
        waits: 1,
        body_loops: 4,
        advice: String::new(),
        report: Box::new(report),
    };
    let error = LoopLimitError::from_run(error, Some(1), (2, 3), context()).unwrap();
    assert_eq!(
        (
            error.rasterization,
            error.waits,
            error.runs,
            error.workgroups
        ),
        (4, 1, 6, 2)
    );
    assert_eq!((error.iteration_budget, error.batch), (Some(1), (2, 3)));
    let other = RunError::Gpu("lost".into());
    assert!(LoopLimitError::from_run(other, None, (1, 1), context()).is_err());
}

#[test]
fn the_facts_are_always_given() {
    let error = LoopLimitError::new(5, 2, 3, 16, Some(1), (2, 7), context());
    let text = error.to_string();
    for fact in [
        "5 rasterization loop(s)",
        "2 queue wait(s)",
        "3 attempt(s)",
        "16 workgroups",
        "1 batch(es) per dispatch",
        "input batch 2 of 7",
    ] {
        assert!(text.contains(fact), "{fact:?} missing from: {text}");
    }
    let text = LoopLimitError::new(5, 0, 1, 4, None, (1, 1), context()).to_string();
    assert!(text.contains("default iteration budget"), "{text}");
    assert!(!text.contains("input batch"), "{text}");
}

#[test]
fn a_small_dice_threshold_asks_for_a_larger_one() {
    let text = message(
        LoopLimitContext {
            dice_threshold: 0.5,
            ..context()
        },
        3,
        0,
    );
    assert!(text.contains("LARGER dice threshold"), "{text}");
    assert!(!text.contains("smaller dice threshold"), "{text}");
    assert!(!text.contains("samples per pixel"), "{text}");
    assert!(!text.contains("displacement function"), "{text}");
}

#[test]
fn a_small_shading_rate_asks_for_a_larger_one() {
    let text = message(
        LoopLimitContext {
            dicing: Dicing::Rate,
            shading_rate: 0.1,
            ..context()
        },
        0,
        4,
    );
    assert!(text.contains("LARGER shading rate"), "{text}");
    assert!(!text.contains("dice threshold"), "{text}");
}

#[test]
fn a_user_function_is_named_first() {
    let error = LoopLimitError::new(
        0,
        1,
        3,
        2,
        Some(1),
        (1, 1),
        LoopLimitContext {
            user_displacement: true,
            dice_threshold: 0.5,
            ..context()
        },
    );
    assert_eq!(error.hints[0], LoopLimitHint::UserDisplacement);
    let text = error.to_string();
    assert!(text.contains("user displacement function"), "{text}");
    assert!(text.contains("endless"), "{text}");
    assert!(text.contains("most likely first"), "{text}");
}

#[test]
fn depth_guard_drops_name_max_split_depth() {
    // A model scaled by 1e38 or splitting without end.
    let text = message(
        LoopLimitContext {
            depth_guard_drops: 12,
            largest_micropolygon_px: 0.0,
            ..context()
        },
        0,
        2,
    );
    assert!(text.contains("max_split_depth = 24"), "{text}");
    assert!(text.contains("dropped 12"), "{text}");
    assert!(!text.contains("dice threshold"), "{text}");
    assert!(
        !text.contains("Contention") && !text.contains("idle machine"),
        "{text}"
    );
}

#[test]
fn long_sample_loops_keep_the_sampling_advice() {
    let text = message(
        LoopLimitContext {
            spp: 64,
            blurred: true,
            largest_micropolygon_px: 20.0,
            ..context()
        },
        7,
        0,
    );
    assert!(text.contains("samples per pixel") && text.contains("Interleave"));
    assert!(text.contains("depth of field"), "{text}");
    assert!(text.contains("smaller dice threshold"), "{text}");
    assert!(!text.contains("LARGER"), "{text}");
}

#[test]
fn waits_alone_point_at_contention() {
    let text = message(context(), 0, 3);
    assert!(text.contains("only queue waits"), "{text}");
    assert!(text.contains("2 workgroups"), "{text}");
}
