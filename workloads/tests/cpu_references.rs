//! The workloads' CPU references on their own, without a GPU: the
//! properties the GPU runs are checked against must hold for them first.

use workloads::{bfs, mandelbrot, quadrature};

#[test]
fn mandelbrot_subdivision_writes_every_pixel_and_counts_its_tiles() {
    let view = mandelbrot::View::whole_set(128, 64);
    let cpu = mandelbrot::cpu_mariani_silver(&view);
    assert!(cpu.counts.iter().all(|&n| n != mandelbrot::UNWRITTEN));
    assert!(cpu.counts.iter().all(|&n| n <= view.max_iter));
    let roots = view.roots().len() as u64;
    assert_eq!(cpu.tiles, roots + 4 * cpu.split);
    assert_eq!(cpu.tiles, cpu.filled + cpu.split + cpu.blocks);
    assert_eq!(mandelbrot::cpu_brute_force(&view).len(), view.pixels());
}

#[test]
fn mandelbrot_ppm_has_a_header_and_three_bytes_per_pixel() {
    let view = mandelbrot::View::whole_set(64, 32);
    let counts = mandelbrot::cpu_brute_force(&view);
    let header = b"P6\n64 64\n255\n";
    let ppm = mandelbrot::ppm(&view, &counts);
    assert!(ppm.starts_with(header));
    assert_eq!(ppm.len(), header.len() + 3 * view.pixels());
    assert_eq!(mandelbrot::colour(&view, view.max_iter), [0, 0, 0]);
}

#[test]
fn quadrature_reference_is_close_to_the_dense_sum() {
    let problem = quadrature::Problem::random(7, 100, 16);
    let (tally, processed) = quadrature::cpu_reference(&problem);
    assert!(processed >= quadrature::roots(&problem).len() as u64);
    assert!(tally.intervals() <= processed);
    let (adaptive, dense) = (tally.integral(), quadrature::dense_simpson(&problem));
    assert!(
        (adaptive - dense).abs() / dense < 1e-5,
        "{adaptive} vs {dense}"
    );
}

#[test]
fn bfs_levels_start_at_the_sources_and_step_by_one() {
    let problem = bfs::Problem::random(7, 2000, 3);
    let levels = bfs::cpu_levels(&problem);
    for &s in &problem.sources {
        assert_eq!(levels[s as usize], 0);
    }
    for u in 0..problem.graph.nodes() {
        for &v in problem.graph.neighbours(u) {
            let (lu, lv) = (levels[u as usize], levels[v as usize]);
            if lu != bfs::UNREACHED {
                assert!(lv <= lu + 1, "edge {u}-{v}: levels {lu}, {lv}");
            }
        }
    }
}
