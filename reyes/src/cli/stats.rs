//! The statistics table that `reyes render --stats` prints.

use crate::output::console::{ConsoleError, outln};
use crate::prepare::PreparedScene;
use crate::stats::{PassStats, RenderStats};

/// Prints the statistics table of a frame rendered by `backend` on standard
/// output.
pub(crate) fn print_stats(
    stats: &RenderStats,
    backend: &str,
    scene: &PreparedScene,
) -> Result<(), ConsoleError> {
    let dicing = format!(
        "{}, {} shading",
        scene.dicing,
        scene.shading_interpolation.name()
    );
    let rows: [(&str, String); 20] = [
        ("input patches", stats.input_patches.to_string()),
        (
            "patches stored",
            format!(
                "{} ({} KiB)",
                scene.store.len,
                crate::gpu::patch_store_bytes(scene).div_ceil(1024)
            ),
        ),
        ("splits", stats.splits.to_string()),
        ("culled patches", stats.culled_patches.to_string()),
        ("depth-guard drops", stats.depth_guard_drops.to_string()),
        ("grids diced", stats.grids_diced.to_string()),
        ("micropolygons", stats.micropolygons.to_string()),
        (
            "grids small/med/large",
            format!(
                "{}/{}/{}",
                stats.grids_by_class[0], stats.grids_by_class[1], stats.grids_by_class[2]
            ),
        ),
        (
            "dice thread util.",
            format!("{:.3}", stats.thread_utilization()),
        ),
        (
            "micropolys per hit",
            format!("{:.3}", stats.micropolygons_per_hit()),
        ),
        ("samples tested", stats.samples_tested.to_string()),
        ("samples hit", stats.samples_hit.to_string()),
        ("samples skipped", stats.samples_skipped.to_string()),
        ("dicing", dicing),
        (
            "sample test effic.",
            format!("{:.4}", stats.sample_test_efficiency()),
        ),
        ("interleave grids", stats.interleave_grids.to_string()),
        (
            "largest micropolygon",
            format!("{:.3} px", stats.largest_micropolygon_px),
        ),
        (
            "beyond displ. bound",
            stats.displacement_bound_exceeded.to_string(),
        ),
        (
            "non-finite dsp/tf/cam",
            format!(
                "{}/{}/{}",
                stats.non_finite_displacement, stats.non_finite_transform, stats.non_finite_camera
            ),
        ),
        (
            "frame time",
            stats
                .frame_time_ms
                .map(|t| format!("{t:.3} ms ({backend})"))
                .unwrap_or_else(|| "-".into()),
        ),
    ];
    outln!("{:<22}{:>24}", "statistic", "value")?;
    for (name, value) in rows {
        outln!("{name:<22}{value:>24}")?;
    }
    print_passes(&stats.passes, backend)
}

/// A frame with automatic shadows: one row per pass (each depth pass from
/// a light, then the frame) with its size, micropolygons and time; the
/// table above counts the frame alone.
fn print_passes(passes: &[PassStats], backend: &str) -> Result<(), ConsoleError> {
    if passes.is_empty() {
        return Ok(());
    }
    outln!("")?;
    outln!(
        "{:<34}{:>11}{:>15}{:>16}",
        "pass",
        "size",
        "micropolygons",
        "time"
    )?;
    for pass in passes {
        let time = pass
            .frame_time_ms
            .map_or_else(|| "-".into(), |t| format!("{t:.3} ms"));
        outln!(
            "{:<34}{:>11}{:>15}{:>16}",
            pass.name,
            format!("{}x{}", pass.width, pass.height),
            pass.micropolygons,
            time
        )?;
    }
    let total: f64 = passes.iter().filter_map(|p| p.frame_time_ms).sum();
    outln!(
        "{:<34}{:>42}",
        "all passes",
        format!("{total:.3} ms ({backend})")
    )?;
    Ok(())
}
