//! The comparison as a text table.

use std::fmt::Write;

use crate::suite::{Row, SuiteReport, Variant, budget_label};
use crate::workload::FLAT_WORKGROUP_SIZE;

/// Formats the rows as one table: one line per variant, grouped by work.
pub fn format_table(report: &SuiteReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:>5}  {:<11}{:>6}{:>7}{:>10}{:>7}  {:>11}{:>11}{:>11}{:>10}  {:>11}{:>8}{:>11}{:>6}  timer",
        "work",
        "variant",
        "wg",
        "chunks",
        "capacity",
        "budget",
        "median ms",
        "min ms",
        "max ms",
        "wall ms",
        "items/s",
        "ratio",
        "high-water",
        "disp",
    );
    for row in &report.rows {
        let _ = writeln!(s, "{}", format_row(row));
    }
    s
}

/// One table line.
pub fn format_row(row: &Row) -> String {
    let ms = |d: std::time::Duration| format!("{:.3}", d.as_secs_f64() * 1e3);
    let (name, workgroups, chunks, capacity, budget) = match row.variant {
        Variant::Flat => (
            "flat",
            row.workload
                .items()
                .div_ceil(FLAT_WORKGROUP_SIZE)
                .to_string(),
            "-".to_owned(),
            "-".to_owned(),
            "-".to_owned(),
        ),
        Variant::Megakernel {
            workgroups,
            capacity,
            iteration_budget,
            chunks,
        } => (
            "megakernel",
            workgroups.to_string(),
            chunks.to_string(),
            capacity.to_string(),
            budget_label(iteration_budget),
        ),
        Variant::Rounds {
            workgroups,
            capacity,
            chunks,
        } => (
            "rounds",
            workgroups.to_string(),
            chunks.to_string(),
            capacity.to_string(),
            "-".to_owned(),
        ),
    };
    format!(
        "{:>5}  {:<11}{:>6}{:>7}{:>10}{:>7}  {:>11}{:>11}{:>11}{:>10}  {:>11.3e}{:>8.3}{:>11}{:>6}  {}",
        row.workload.work,
        name,
        workgroups,
        chunks,
        capacity,
        budget,
        ms(row.timings.median),
        ms(row.timings.min),
        ms(row.timings.max),
        ms(row.timings.wall_median),
        row.items_per_second,
        row.ratio_to_flat,
        row.high_water.map_or("-".to_owned(), |h| h.to_string()),
        row.dispatches.map_or("-".to_owned(), |d| d.to_string()),
        row.timings.source.label(),
    )
}
