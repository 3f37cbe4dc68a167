//! Matching the GPU's counts to the arithmetic its driver used: the checks
//! stay exact, but against the CPU reference under the [`Contraction`] that
//! explains the counts, since a driver may fuse the escape loop's
//! multiply-adds and the CPU does not unless asked.
//!
//! The plain reference is tried first, and when it matches nothing else is
//! computed. Otherwise each other variant is tried on the pixels where the
//! plain reference differs only (a few escape counts each, or for the
//! subdivision the decisions of the tiles above them), and a variant that
//! gives the GPU's counts there is verified on every pixel (and, for the
//! subdivision, on the scheduler's counters). The first that matches
//! everything explains the run; if none does, the error lists the
//! disagreements with the plain reference.

use std::collections::HashMap;
use std::fmt;

use super::{
    Contraction, Decision, ROOT_SIZE, Subdivision, Tile, View, cpu_brute_force_with,
    cpu_mariani_silver_with, decide_with, escape_count_with, quarters,
};

/// GPU counts explained: the contraction under which the CPU reference
/// equals them, and that reference.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Matched<R> {
    /// The multiply-adds the driver fused ([`Contraction::PLAIN`] when the
    /// plain reference matched).
    pub contraction: Contraction,
    /// The CPU reference under [`Self::contraction`].
    pub reference: R,
}

/// GPU counts that no contraction explains: a wrong result.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unexplained {
    /// Every disagreement with the plain CPU reference.
    pub mismatches: Vec<String>,
}

impl fmt::Display for Unexplained {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "no fusing of the escape loop's multiply-adds explains the GPU's counts; \
             against the plain CPU reference: {}",
            self.mismatches.join("; ")
        )
    }
}

impl std::error::Error for Unexplained {}

/// The pixels where `counts` differs from `expected`, described with up to
/// eight examples; `None` when they are equal.
pub fn pixel_mismatches(view: &View, counts: &[u32], expected: &[u32]) -> Option<String> {
    if counts.len() != expected.len() {
        return Some(format!(
            "{} counts for {} pixels",
            counts.len(),
            expected.len()
        ));
    }
    let wrong: Vec<usize> = differing(counts, expected);
    if wrong.is_empty() {
        return None;
    }
    let width = view.width as usize;
    let examples: Vec<String> = wrong
        .iter()
        .take(8)
        .map(|&i| {
            format!(
                "({}, {}): GPU {}, CPU {}",
                i % width,
                i / width,
                counts[i],
                expected[i]
            )
        })
        .collect();
    Some(format!(
        "{} of {} pixels differ, e.g. {}",
        wrong.len(),
        expected.len(),
        examples.join("; ")
    ))
}

/// Matches a brute-force image (every pixel's own escape count, as the flat
/// dispatch computes it) with `plain`, the plain [`cpu_brute_force`] of
/// `view`, or else with the brute force under another contraction.
///
/// [`cpu_brute_force`]: super::cpu_brute_force
pub fn match_brute_force(
    view: &View,
    counts: &[u32],
    plain: &[u32],
) -> Result<Matched<Vec<u32>>, Unexplained> {
    let width = view.width as usize;
    find(
        counts,
        plain,
        plain,
        |reference: &[u32]| {
            pixel_mismatches(view, counts, reference)
                .into_iter()
                .collect()
        },
        |contraction, pixels| {
            pixels
                .iter()
                .map(|&i| {
                    escape_count_with(view, (i % width) as u32, (i / width) as u32, contraction)
                })
                .collect()
        },
        |contraction| cpu_brute_force_with(view, contraction),
    )
}

/// Matches a subdivision's image and counters with `plain`, the plain
/// [`cpu_mariani_silver`] of `view`, or else with the subdivision under
/// another contraction (its decisions, and so its counters, recomputed).
/// `counters` lists the disagreements of the run's counters with a CPU
/// subdivision (none when they agree).
///
/// [`cpu_mariani_silver`]: super::cpu_mariani_silver
pub fn match_subdivision(
    view: &View,
    counts: &[u32],
    plain: &Subdivision,
    counters: impl Fn(&Subdivision) -> Vec<String>,
) -> Result<Matched<Subdivision>, Unexplained> {
    find(
        counts,
        plain,
        &plain.counts,
        |reference: &Subdivision| {
            pixel_mismatches(view, counts, &reference.counts)
                .into_iter()
                .chain(counters(reference))
                .collect()
        },
        |contraction, pixels| subdivision_pixels(view, contraction, pixels),
        |contraction| cpu_mariani_silver_with(view, contraction),
    )
}

/// The search both matchers share. `check` lists the disagreements of the
/// GPU's run with a reference; `pixels` computes the given pixels (indices,
/// row by row) under a contraction; `full` computes a whole reference.
fn find<R: ToOwned + ?Sized>(
    counts: &[u32],
    plain: &R,
    plain_counts: &[u32],
    check: impl Fn(&R) -> Vec<String>,
    pixels: impl Fn(Contraction, &[usize]) -> Vec<u32>,
    full: impl Fn(Contraction) -> R::Owned,
) -> Result<Matched<R::Owned>, Unexplained>
where
    R::Owned: std::borrow::Borrow<R>,
{
    use std::borrow::Borrow as _;
    let mismatches = check(plain);
    if mismatches.is_empty() {
        return Ok(Matched {
            contraction: Contraction::PLAIN,
            reference: plain.to_owned(),
        });
    }
    if counts.len() != plain_counts.len() {
        return Err(Unexplained { mismatches });
    }
    let wrong = differing(counts, plain_counts);
    let wanted: Vec<u32> = wrong.iter().map(|&i| counts[i]).collect();
    for contraction in Contraction::all().into_iter().filter(|c| !c.is_plain()) {
        if pixels(contraction, &wrong) != wanted {
            continue;
        }
        let reference = full(contraction);
        if check(reference.borrow()).is_empty() {
            return Ok(Matched {
                contraction,
                reference,
            });
        }
    }
    Err(Unexplained { mismatches })
}

/// The indices where `a` and `b` differ (of the shorter's length).
fn differing(a: &[u32], b: &[u32]) -> Vec<usize> {
    a.iter()
        .zip(b)
        .enumerate()
        .filter(|(_, (x, y))| x != y)
        .map(|(i, _)| i)
        .collect()
}

/// The subdivision's counts of the given pixels under `contraction`, without
/// the rest of the image: each pixel follows the decisions from its root
/// tile down to the tile that fills it or the block that computes it. Tiles
/// the pixels share are decided once.
fn subdivision_pixels(view: &View, contraction: Contraction, pixels: &[usize]) -> Vec<u32> {
    let width = view.width as usize;
    let mut decisions: HashMap<(u32, u32, u32), Decision> = HashMap::new();
    pixels
        .iter()
        .map(|&i| {
            let (px, py) = ((i % width) as u32, (i / width) as u32);
            let mut tile = Tile {
                x: px / ROOT_SIZE * ROOT_SIZE,
                y: py / ROOT_SIZE * ROOT_SIZE,
                size: ROOT_SIZE,
            };
            loop {
                let decision = *decisions
                    .entry((tile.x, tile.y, tile.size))
                    .or_insert_with(|| decide_with(view, &tile, contraction));
                match decision {
                    Decision::Fill(n) => break n,
                    Decision::Block => break escape_count_with(view, px, py, contraction),
                    Decision::Split => {
                        let half = tile.size / 2;
                        let right = usize::from(px - tile.x >= half);
                        let below = usize::from(py - tile.y >= half);
                        tile = quarters(&tile)[right + 2 * below];
                    }
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::{cpu_brute_force, cpu_mariani_silver};
    use super::*;

    /// The fusing NVIDIA's Vulkan driver (H200, driver 580.159.04) applied
    /// to the flat dispatch.
    const BOTH_UPDATES: Contraction = Contraction {
        real: true,
        imaginary: true,
        ..Contraction::PLAIN
    };

    /// The benchmark's image, on which the H200's flat dispatch was seen
    /// to differ from the plain CPU.
    fn bench_view() -> View {
        View::whole_set(512, 1024)
    }

    /// The counters of a run as the closure `match_subdivision` takes:
    /// what differs from `gpu`'s tile counts.
    fn counters(gpu: &Subdivision) -> impl Fn(&Subdivision) -> Vec<String> + '_ {
        |cpu: &Subdivision| {
            let (g, c) = (
                (gpu.tiles, gpu.split, gpu.blocks),
                (cpu.tiles, cpu.split, cpu.blocks),
            );
            if g == c {
                Vec::new()
            } else {
                vec![format!("tiles, split, blocks: GPU {g:?}, CPU {c:?}")]
            }
        }
    }

    #[test]
    fn plain_counts_match_the_plain_contraction() {
        let view = View::whole_set(128, 256);
        let brute = cpu_brute_force(&view);
        let matched = match_brute_force(&view, &brute, &brute).unwrap();
        assert_eq!(matched.contraction, Contraction::PLAIN);
        assert_eq!(matched.reference, brute);

        let plain = cpu_mariani_silver(&view);
        let matched = match_subdivision(&view, &plain.counts, &plain, counters(&plain)).unwrap();
        assert_eq!(matched.contraction, Contraction::PLAIN);
        assert_eq!(matched.reference, plain);
    }

    /// The H200's error message: "532 entries differ from the CPU
    /// reference; first at out[50542]: expected 0x0000015d, got
    /// 0x0000014a". Fusing both updates reproduces it, so a fused variant
    /// does differ from the plain one on this image.
    #[test]
    fn fusing_both_updates_gives_the_h200_flat_dispatch_counts() {
        let view = bench_view();
        let plain = cpu_brute_force(&view);
        let fused = cpu_brute_force_with(&view, BOTH_UPDATES);
        let wrong = differing(&fused, &plain);
        assert_eq!(wrong.len(), 532);
        assert_eq!(wrong[0], 50542);
        assert_eq!((plain[50542], fused[50542]), (0x15d, 0x14a));
    }

    #[test]
    fn fused_brute_force_counts_are_matched_and_named() {
        let view = bench_view();
        let plain = cpu_brute_force(&view);
        let fused = cpu_brute_force_with(&view, BOTH_UPDATES);
        assert_ne!(fused, plain);
        let matched = match_brute_force(&view, &fused, &plain).unwrap();
        assert_eq!(matched.contraction, BOTH_UPDATES);
        assert_eq!(matched.reference, fused);
        assert_eq!(
            matched.contraction.to_string(),
            "the real update (fma(zr - zi, zr + zi, cr)), the imaginary update (fma(2 zr, zi, ci))"
        );
    }

    #[test]
    fn fused_counts_with_one_pixel_off_by_one_are_rejected() {
        let view = bench_view();
        let plain = cpu_brute_force(&view);
        let fused = cpu_brute_force_with(&view, BOTH_UPDATES);
        // One of the pixels fusing changed, and one it did not.
        for (pixel, differ) in [(50542, 532), (0, 533)] {
            let mut counts = fused.clone();
            counts[pixel] += 1;
            let error = match_brute_force(&view, &counts, &plain).unwrap_err();
            assert_eq!(error.mismatches.len(), 1, "{error}");
            assert!(
                error.mismatches[0].starts_with(&format!("{differ} of 262144 pixels differ")),
                "{error}"
            );
        }
    }

    #[test]
    fn a_fused_subdivision_is_matched_with_its_decisions_and_counters() {
        let view = bench_view();
        let plain = cpu_mariani_silver(&view);
        let fused = cpu_mariani_silver_with(&view, BOTH_UPDATES);
        assert_ne!(fused.counts, plain.counts);
        let matched = match_subdivision(&view, &fused.counts, &plain, counters(&fused)).unwrap();
        assert_eq!(matched.contraction, BOTH_UPDATES);
        assert_eq!(matched.reference, fused);

        // One pixel off by one.
        let mut counts = fused.counts.clone();
        let pixel = differing(&fused.counts, &plain.counts)[0];
        counts[pixel] += 1;
        let error = match_subdivision(&view, &counts, &plain, counters(&fused)).unwrap_err();
        assert!(error.mismatches[0].contains("pixels differ"), "{error}");

        // The right pixels, but one tile too many.
        let extra_tile = Subdivision {
            tiles: fused.tiles + 1,
            ..fused.clone()
        };
        let error =
            match_subdivision(&view, &fused.counts, &plain, counters(&extra_tile)).unwrap_err();
        assert!(
            error
                .mismatches
                .iter()
                .any(|m| m.starts_with("tiles, split")),
            "{error}"
        );
    }

    /// The cheap per-pixel test agrees with the whole subdivision.
    #[test]
    fn subdivision_pixels_equal_the_whole_subdivision() {
        let view = View::whole_set(256, 256);
        let every: Vec<usize> = (0..view.pixels()).collect();
        for contraction in [Contraction::PLAIN, BOTH_UPDATES] {
            assert_eq!(
                subdivision_pixels(&view, contraction, &every),
                cpu_mariani_silver_with(&view, contraction).counts,
                "{contraction}"
            );
        }
    }

    #[test]
    fn counts_of_the_wrong_length_are_rejected() {
        let view = View::whole_set(64, 16);
        let plain = cpu_brute_force(&view);
        let error = match_brute_force(&view, &plain[1..], &plain).unwrap_err();
        assert_eq!(error.mismatches, ["4095 counts for 4096 pixels"]);
    }
}
