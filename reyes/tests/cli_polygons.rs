//! A RIB `Polygon` of many vertices renders in time proportional to its
//! vertices (issue D22): its patches were a fan from the first vertex, each
//! as long as the polygon, and one of 700,000 vertices along an arc ran
//! past 300 s with `--cpu`, splitting every sliver along its whole length.

mod files;

use std::process::Command;

use files::TempDir;

/// A `Polygon` of `n` vertices along a quarter circle (nearly collinear
/// neighbours), in front of the camera.
fn arc_polygon(n: usize) -> String {
    let points: Vec<String> = (0..n)
        .map(|i| {
            let a = std::f64::consts::FRAC_PI_2 * i as f64 / (n - 1) as f64;
            format!("{:.9} {:.9} 0", a.cos(), a.sin())
        })
        .collect();
    format!(
        "Projection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate -0.5 -0.5 3\nPolygon \"P\" [{}]\nWorldEnd\n",
        points.join(" ")
    )
}

/// A statistic of `reyes render --stats`'s table.
fn statistic(table: &str, name: &str) -> u64 {
    let line = table
        .lines()
        .find(|l| l.starts_with(name))
        .unwrap_or_else(|| panic!("no `{name}` in {table}"));
    line.split_whitespace().last().unwrap().parse().unwrap()
}

#[test]
fn a_polygon_of_many_vertices_splits_little() {
    let dir = TempDir::new("cli-polygon");
    let scene = dir.path("arc.rib");
    std::fs::write(&scene, arc_polygon(6001)).unwrap();
    let out = dir.path("arc.png");
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .args(["render", scene.to_str().unwrap(), "--cpu", "--stats"])
        .args(["--width", "160", "--height", "120", "--spp", "1"])
        .args(["-o", out.to_str().unwrap()])
        .output()
        .expect("reyes starts");
    let table = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let patches = statistic(&table, "input patches");
    let splits = statistic(&table, "splits");
    eprintln!("{patches} patches, {splits} splits");
    assert!(patches >= 2900, "{table}");
    // Patches along the boundary are diced as they are; a fan's slivers
    // were split about 20 times each here.
    assert!(splits < patches / 10, "{table}");
}
