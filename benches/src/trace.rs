//! Traced runs and their pictures (docs/scheduler.md, "Seeing a run"):
//! `scheduler-bench --trace` writes the Chrome trace of one verified,
//! traced run of the Mandelbrot example, and `trace-plot` draws the queue
//! fills of Chrome trace files as PNG charts.

use std::path::Path;

use plotters::prelude::*;
use scheduler::{CompileOptions, ExecutorConfig, Gpu, RunReport, Strategy, TraceOptions};
use serde_json::Value;
use workloads::mandelbrot::{Contraction, Mandelbrot, View, cpu_mariani_silver};

use crate::error::BenchError;

/// One traced run of the Mandelbrot example (Mariani–Silver subdivision of
/// the whole set at `size`² pixels), verified against the CPU under the
/// arithmetic the driver used. The report holds the trace; the contraction
/// says which multiply-adds the driver fused.
pub fn mandelbrot(
    gpu: &Gpu,
    size: u32,
    max_iter: u32,
    chunks: u32,
    strategy: Strategy,
    trace: TraceOptions,
) -> Result<(RunReport, Contraction), BenchError> {
    let view = View::whole_set(size, max_iter);
    let options = CompileOptions {
        chunks_per_batch: chunks,
        ..CompileOptions::with_features(scheduler::recommended_features(&gpu.device))
    }
    .traced(trace);
    let config: ExecutorConfig = workloads::mandelbrot::config(gpu, &view, chunks);
    let cpu = cpu_mariani_silver(&view);
    let mut mandelbrot = Mandelbrot::new(gpu, view, &options, &config)
        .map_err(|e| BenchError::Config(format!("the Mandelbrot graph: {e}")))?;
    let report = mandelbrot.render(strategy)?;
    let counts = mandelbrot.counts()?;
    let matched = crate::mandelbrot::match_scheduled(
        &mandelbrot,
        &report,
        &counts,
        &cpu,
        "traced Mandelbrot",
    )?;
    Ok((report, matched.contraction))
}

/// The queue fills of a Chrome trace: per counter (`fill <procedure>`), its
/// samples as (tick, items), in file order.
pub fn fill_series(trace: &Value) -> Vec<(String, Vec<(u64, u64)>)> {
    let mut series: Vec<(String, Vec<(u64, u64)>)> = Vec::new();
    let events = trace["traceEvents"]
        .as_array()
        .map_or(&[][..], Vec::as_slice);
    for event in events.iter().filter(|e| e["ph"] == "C") {
        let (Some(name), Some(ts), Some(items)) = (
            event["name"].as_str(),
            event["ts"].as_u64(),
            event["args"]["items"].as_u64(),
        ) else {
            continue;
        };
        let name = name.strip_prefix("fill ").unwrap_or(name);
        match series.iter_mut().find(|(n, _)| n == name) {
            Some((_, samples)) => samples.push((ts, items)),
            None => series.push((name.to_owned(), vec![(ts, items)])),
        }
    }
    series
}

/// Draws the fills of `series` over logical time into a `width`×`height`
/// PNG at `path`: a step line per queue, a legend, the axes labelled.
pub fn plot_fills(
    series: &[(String, Vec<(u64, u64)>)],
    title: &str,
    path: &Path,
    (width, height): (u32, u32),
) -> Result<(), BenchError> {
    let plot_error = |e: &dyn std::fmt::Display| BenchError::Config(format!("plotting: {e}"));
    register_font();
    let end = series
        .iter()
        .flat_map(|(_, s)| s.iter().map(|&(t, _)| t))
        .max()
        .unwrap_or(0)
        + 1;
    let top = series
        .iter()
        .flat_map(|(_, s)| s.iter().map(|&(_, v)| v))
        .max()
        .unwrap_or(0)
        .max(1);
    let mut pixels = vec![0u8; 3 * width as usize * height as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0..end, 0..top + top / 20 + 1)
            .map_err(|e| plot_error(&e))?;
        chart
            .configure_mesh()
            .x_desc("logical time (batches begun)")
            .y_desc("items queued")
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(|e| plot_error(&e))?;
        for (i, (name, samples)) in series.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            // A step line: a fill holds until the next sample.
            let mut points = Vec::with_capacity(2 * samples.len() + 1);
            for (j, &(t, v)) in samples.iter().enumerate() {
                if j > 0 {
                    points.push((t, samples[j - 1].1));
                }
                points.push((t, v));
            }
            if let Some(&(_, v)) = samples.last() {
                points.push((end, v));
            }
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(2)))
                .map_err(|e| plot_error(&e))?
                .label(name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| plot_error(&e))?;
        root.present().map_err(|e| plot_error(&e))?;
    }
    image::RgbImage::from_raw(width, height, pixels)
        .ok_or_else(|| BenchError::Config("plotting: the picture's size".into()))?
        .save(path)
        .map_err(|e| BenchError::Config(format!("writing {}: {e}", path.display())))
}

/// The one font the charts use, shipped in a crate (no system fonts needed).
fn register_font() {
    // Registering again replaces the font with itself.
    let _ = plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        epaint_default_fonts::UBUNTU_LIGHT,
    );
}

/// What tracing costs on the Mandelbrot example: the median GPU time (wall
/// time without timestamp queries) of `runs` untraced and `runs` traced
/// megakernel runs, interleaved in one process, in milliseconds.
pub fn mandelbrot_cost(
    gpu: &Gpu,
    size: u32,
    max_iter: u32,
    chunks: u32,
    runs: u32,
) -> Result<(f64, f64), BenchError> {
    let view = View::whole_set(size, max_iter);
    let untraced = CompileOptions {
        chunks_per_batch: chunks,
        ..CompileOptions::with_features(scheduler::recommended_features(&gpu.device))
    };
    let traced = untraced.clone().traced(TraceOptions::default());
    let config = workloads::mandelbrot::config(gpu, &view, chunks);
    let new = |options: &CompileOptions| {
        Mandelbrot::new(gpu, view, options, &config)
            .map_err(|e| BenchError::Config(format!("the Mandelbrot graph: {e}")))
    };
    let mut variants = [new(&untraced)?, new(&traced)?];
    let mut times = [Vec::new(), Vec::new()];
    for _ in 0..runs {
        for (mandelbrot, times) in variants.iter_mut().zip(&mut times) {
            let report = mandelbrot.render(Strategy::Megakernel)?;
            let time = report.gpu_time.unwrap_or(report.wall_time);
            times.push(time.as_secs_f64() * 1e3);
        }
    }
    let [untraced, traced] = times.map(|mut t| {
        t.sort_by(f64::total_cmp);
        t.get(t.len() / 2).copied().unwrap_or(0.0)
    });
    Ok((untraced, traced))
}
