//! Loader tests: the bundled models, every error variant, and round trips.

mod common;

use glam::Vec3;
use rand::{Rng, SeedableRng, rngs::StdRng};
use reyes::load::{LoadError, bez, bpt};
use reyes::model::{Model, Patch};

#[test]
fn teapot_bpt_and_bez_agree() {
    let embedded = Model::teapot();
    assert_eq!(embedded.patches.len(), 32);
    let bez_path = common::shared_data("teapot.bez");
    let bpt_path = common::shared_data("teapot.bpt");
    if !bez_path.exists() {
        println!(
            "NOTICE: {} not found; skipping the .bez comparison",
            bez_path.display()
        );
        return;
    }
    let from_bez = Model::load(&bez_path).unwrap();
    assert_eq!(
        from_bez, embedded,
        ".bez and embedded .bpt control points differ"
    );
    if bpt_path.exists() {
        assert_eq!(Model::load(&bpt_path).unwrap(), embedded);
    }
}

#[test]
fn teapot_bounds() {
    let (lo, hi) = Model::teapot().bounds();
    assert!(lo.z >= -1e-6 && hi.z > 3.0, "{lo} {hi}");
    assert!((hi.x - lo.x) > 6.0 && (hi.x - lo.x) < 7.0, "{lo} {hi}");
    assert_eq!(Model::default().bounds(), (Vec3::ZERO, Vec3::ZERO));
}

#[test]
fn killeroo_patch_count() {
    let Some(path) = common::killeroo_path() else {
        return;
    };
    let model = Model::load(path).unwrap();
    assert_eq!(model.patches.len(), 11_532);
}

fn bpt_err(text: &str) -> LoadError {
    bpt::parse(text).expect_err("expected a parse error")
}

fn bez_err(text: &str) -> LoadError {
    bez::parse(text).expect_err("expected a parse error")
}

/// A valid one-patch `.bpt` text, as lines, for corrupting.
fn one_patch_bpt() -> Vec<String> {
    let mut lines = vec!["1".to_string(), "3 3".to_string()];
    for k in 0..16 {
        lines.push(format!("{} {} {}", k % 4, k / 4, 0.5));
    }
    lines
}

fn with_line(mut lines: Vec<String>, index: usize, text: &str) -> String {
    lines[index] = text.to_string();
    lines.join("\n")
}

#[test]
fn bpt_valid_with_blank_lines_and_whitespace() {
    let text = format!("\n  {}  \n\n", one_patch_bpt().join("\n\n\t"));
    let model = bpt::parse(&text).unwrap();
    assert_eq!(model.patches.len(), 1);
    assert_eq!(model.patches[0].point(1, 2), Vec3::new(1.0, 2.0, 0.5));
    assert_eq!(bpt::parse("0\n").unwrap().patches.len(), 0);
}

#[test]
fn bpt_missing_count() {
    let e = bpt_err("");
    assert!(
        matches!(
            e,
            LoadError::MissingCount {
                line: 1,
                what: "patch count"
            }
        ),
        "{e}"
    );
    let e = bpt_err("\n\n  \n");
    assert!(
        matches!(e, LoadError::MissingCount { line: 4, .. }),
        "{e:?}"
    );
}

#[test]
fn bpt_invalid_count() {
    for bad in ["abc", "-1", "1.5", "2 3"] {
        let e = bpt_err(&format!("{bad}\n3 3\n"));
        assert!(
            matches!(&e, LoadError::InvalidCount { line: 1, what: "patch count", found } if found == bad),
            "{e:?}"
        );
    }
}

#[test]
fn bpt_unsupported_degree() {
    for bad in ["2 3", "3", "3 3 3", "x y"] {
        let e = bpt_err(&with_line(one_patch_bpt(), 1, bad));
        assert!(
            matches!(e, LoadError::UnsupportedDegree { line: 2, .. }),
            "{bad}: {e:?}"
        );
    }
    assert!(
        bpt_err(&with_line(one_patch_bpt(), 1, "2 3"))
            .to_string()
            .contains("3 3")
    );
}

#[test]
fn bpt_wrong_coordinate_count() {
    let e = bpt_err(&with_line(one_patch_bpt(), 5, "1 2"));
    assert!(
        matches!(e, LoadError::WrongCoordinateCount { line: 6, found: 2 }),
        "{e:?}"
    );
    let e = bpt_err(&with_line(one_patch_bpt(), 17, "1 2 3 4"));
    assert!(
        matches!(e, LoadError::WrongCoordinateCount { line: 18, found: 4 }),
        "{e:?}"
    );
}

#[test]
fn bpt_invalid_number() {
    let e = bpt_err(&with_line(one_patch_bpt(), 3, "1 2,5 3"));
    assert!(
        matches!(&e, LoadError::InvalidNumber { line: 4, token } if token == "2,5"),
        "{e:?}"
    );
}

#[test]
fn bpt_rejects_nan_and_infinity() {
    for bad in ["NaN", "nan", "inf", "-inf", "infinity", "1e39"] {
        let e = bpt_err(&with_line(one_patch_bpt(), 2, &format!("0 {bad} 0")));
        assert!(
            matches!(&e, LoadError::NonFiniteCoordinate { line: 3, token } if token == bad),
            "{bad}: {e:?}"
        );
    }
}

#[test]
fn bpt_truncated() {
    // Fewer points than 16.
    let mut lines = one_patch_bpt();
    lines.truncate(10);
    let e = bpt_err(&lines.join("\n"));
    assert!(
        matches!(&e, LoadError::Truncated { line: 11, expected } if expected.contains("control point 9")),
        "{e:?}"
    );
    // Fewer patches than declared.
    let mut lines = one_patch_bpt();
    lines[0] = "2".to_string();
    let e = bpt_err(&lines.join("\n"));
    assert!(
        matches!(&e, LoadError::Truncated { line: 19, expected } if expected.contains("patch 2")),
        "{e:?}"
    );
}

#[test]
fn bpt_trailing_garbage() {
    let text = format!("{}\n\nextra stuff\n", one_patch_bpt().join("\n"));
    let e = bpt_err(&text);
    assert!(
        matches!(&e, LoadError::TrailingGarbage { line: 20, text } if text == "extra stuff"),
        "{e:?}"
    );
}

/// A valid one-patch `.bez` text (16 distinct vertices), as lines.
fn one_patch_bez() -> Vec<String> {
    let indices: Vec<String> = (1..=16).map(|i| i.to_string()).collect();
    let mut lines = vec!["1".to_string(), indices.join(","), "16".to_string()];
    for k in 0..16 {
        lines.push(format!("{},{},{}", k % 4, k / 4, 0.25));
    }
    lines
}

#[test]
fn bez_valid_with_whitespace() {
    let mut lines = one_patch_bez();
    lines[1] = lines[1].replace(',', " , ");
    lines[4] = " 1 , 0 ,0.25 ".to_string();
    lines[5] = "2 0 0.25".to_string();
    let model = bez::parse(&lines.join("\n\n")).unwrap();
    assert_eq!(model.patches[0].point(2, 3), Vec3::new(2.0, 3.0, 0.25));
    assert_eq!(model.patches[0].points[1], Vec3::new(1.0, 0.0, 0.25));
}

#[test]
fn bez_missing_and_invalid_counts() {
    let e = bez_err("");
    assert!(
        matches!(
            e,
            LoadError::MissingCount {
                line: 1,
                what: "patch count"
            }
        ),
        "{e:?}"
    );
    let e = bez_err("x");
    assert!(
        matches!(
            e,
            LoadError::InvalidCount {
                line: 1,
                what: "patch count",
                ..
            }
        ),
        "{e:?}"
    );
    let lines = one_patch_bez();
    let e = bez_err(&lines[..2].join("\n"));
    assert!(
        matches!(
            e,
            LoadError::MissingCount {
                line: 3,
                what: "vertex count"
            }
        ),
        "{e:?}"
    );
    let e = bez_err(&with_line(one_patch_bez(), 2, "sixteen"));
    assert!(
        matches!(
            e,
            LoadError::InvalidCount {
                line: 3,
                what: "vertex count",
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn bez_wrong_index_count() {
    let e = bez_err(&with_line(one_patch_bez(), 1, "1,2,3"));
    assert!(
        matches!(e, LoadError::WrongIndexCount { line: 2, found: 3 }),
        "{e:?}"
    );
    let seventeen: Vec<String> = (1..=17).map(|i| i.to_string()).collect();
    let e = bez_err(&with_line(one_patch_bez(), 1, &seventeen.join(",")));
    assert!(
        matches!(e, LoadError::WrongIndexCount { line: 2, found: 17 }),
        "{e:?}"
    );
}

#[test]
fn bez_index_out_of_range() {
    let mut indices: Vec<String> = (1..=16).map(|i| i.to_string()).collect();
    indices[5] = "0".to_string();
    let e = bez_err(&with_line(one_patch_bez(), 1, &indices.join(",")));
    assert!(
        matches!(
            e,
            LoadError::VertexIndexOutOfRange {
                line: 2,
                index: 0,
                vertex_count: 16
            }
        ),
        "{e:?}"
    );
    indices[5] = "17".to_string();
    let e = bez_err(&with_line(one_patch_bez(), 1, &indices.join(",")));
    assert!(
        matches!(
            e,
            LoadError::VertexIndexOutOfRange {
                line: 2,
                index: 17,
                vertex_count: 16
            }
        ),
        "{e:?}"
    );
}

#[test]
fn bez_invalid_numbers_and_coordinates() {
    let mut indices: Vec<String> = (1..=16).map(|i| i.to_string()).collect();
    indices[3] = "-4".to_string();
    let e = bez_err(&with_line(one_patch_bez(), 1, &indices.join(",")));
    assert!(
        matches!(&e, LoadError::InvalidNumber { line: 2, token } if token == "-4"),
        "{e:?}"
    );
    let e = bez_err(&with_line(one_patch_bez(), 6, "1,two,3"));
    assert!(
        matches!(&e, LoadError::InvalidNumber { line: 7, token } if token == "two"),
        "{e:?}"
    );
    let e = bez_err(&with_line(one_patch_bez(), 6, "1,2"));
    assert!(
        matches!(e, LoadError::WrongCoordinateCount { line: 7, found: 2 }),
        "{e:?}"
    );
    let e = bez_err(&with_line(one_patch_bez(), 6, "1,NaN,3"));
    assert!(
        matches!(e, LoadError::NonFiniteCoordinate { line: 7, .. }),
        "{e:?}"
    );
    let e = bez_err(&with_line(one_patch_bez(), 6, "inf,0,3"));
    assert!(
        matches!(e, LoadError::NonFiniteCoordinate { line: 7, .. }),
        "{e:?}"
    );
}

#[test]
fn bez_truncated_and_trailing() {
    let lines = one_patch_bez();
    let e = bez_err(&lines[..10].join("\n"));
    assert!(
        matches!(&e, LoadError::Truncated { line: 11, expected } if expected.contains("vertex 8 of 16")),
        "{e:?}"
    );
    let e = bez_err("2\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n");
    assert!(matches!(e, LoadError::Truncated { line: 3, .. }), "{e:?}");
    let e = bez_err(&format!("{}\n1,2,3", lines.join("\n")));
    assert!(
        matches!(e, LoadError::TrailingGarbage { line: 20, .. }),
        "{e:?}"
    );
}

#[test]
fn load_by_path_errors() {
    let e = Model::load("model.stl").unwrap_err();
    assert!(matches!(e, LoadError::UnknownExtension { .. }), "{e:?}");
    let e = Model::load("no-extension").unwrap_err();
    assert!(matches!(e, LoadError::UnknownExtension { .. }), "{e:?}");
    assert_eq!(e.line(), None);
    let e = Model::load("/definitely/not/here.bpt").unwrap_err();
    assert!(
        matches!(&e, LoadError::Io { path, .. } if path.ends_with("here.bpt")),
        "{e:?}"
    );
    assert!(e.to_string().contains("/definitely/not/here.bpt"));
    let e = Model::load("/definitely/not/here.BEZ").unwrap_err();
    assert!(
        matches!(e, LoadError::Io { .. }),
        "extension match is case-insensitive: {e:?}"
    );
}

#[test]
fn error_messages_carry_line_numbers() {
    let e = bpt_err(&with_line(one_patch_bpt(), 5, "1 2"));
    assert_eq!(e.line(), Some(6));
    assert!(e.to_string().starts_with("line 6:"), "{e}");
}

fn random_model(rng: &mut StdRng) -> Model {
    let patches = (0..rng.random_range(0..20))
        .map(|_| Patch {
            points: std::array::from_fn(|_| {
                // Mix ordinary values, exact small integers (shared vertices in
                // .bez), and extreme magnitudes, to exercise number formatting.
                match rng.random_range(0..4) {
                    0 => Vec3::new(
                        rng.random_range(-2..3) as f32,
                        rng.random_range(-2..3) as f32,
                        0.0,
                    ),
                    1 => Vec3::new(
                        rng.random::<f32>() * 1e-30,
                        -rng.random::<f32>() * 1e30,
                        rng.random::<f32>(),
                    ),
                    _ => Vec3::new(
                        rng.random_range(-100.0..100.0),
                        rng.random_range(-100.0..100.0),
                        rng.random_range(-100.0..100.0),
                    ),
                }
            }),
        })
        .collect();
    Model::new(patches)
}

#[test]
fn random_models_round_trip() {
    let seed: u64 = rand::random();
    println!("random_models_round_trip seed = {seed}");
    let mut rng = StdRng::seed_from_u64(seed);
    for _ in 0..200 {
        let model = random_model(&mut rng);
        assert_eq!(
            bpt::parse(&bpt::write(&model)).unwrap(),
            model,
            "seed {seed}"
        );
        assert_eq!(
            bez::parse(&bez::write(&model)).unwrap(),
            model,
            "seed {seed}"
        );
    }
}

#[test]
fn teapot_round_trips_through_both_formats() {
    let teapot = Model::teapot();
    assert_eq!(bez::parse(&bez::write(&teapot)).unwrap(), teapot);
    assert_eq!(bpt::parse(&bpt::write(&teapot)).unwrap(), teapot);
}
