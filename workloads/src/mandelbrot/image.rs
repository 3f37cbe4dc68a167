//! Pictures of a render's escape counts: an ASCII preview for the terminal
//! and a colour PPM.

use super::View;

/// An ASCII preview, `columns` characters wide.
pub fn ascii_preview(view: &View, counts: &[u32], columns: u32) -> String {
    const RAMP: &[u8] = b" .:-=+*%@";
    let columns = columns.min(view.width);
    // Characters are about twice as tall as wide.
    let rows = (view.height * columns / view.width / 2).max(1);
    let mut s = String::new();
    for r in 0..rows {
        for c in 0..columns {
            let x = c * view.width / columns;
            let y = r * view.height / rows;
            let n = counts[(y * view.width + x) as usize];
            let ch = if n >= view.max_iter {
                '#'
            } else {
                let t = ((n + 1) as f32).ln() / ((view.max_iter + 1) as f32).ln();
                RAMP[((t * (RAMP.len() - 1) as f32) as usize).min(RAMP.len() - 1)] as char
            };
            s.push(ch);
        }
        s.push('\n');
    }
    s
}

/// The colour of an escape count: black in the set, and outside a ramp from
/// deep blue through white to orange over the logarithm of the count.
pub fn colour(view: &View, n: u32) -> [u8; 3] {
    if n >= view.max_iter {
        return [0, 0, 0];
    }
    let t = ((n + 1) as f32).ln() / ((view.max_iter + 1) as f32).ln();
    let stops: [(f32, [f32; 3]); 4] = [
        (0.0, [0.0, 7.0, 100.0]),
        (0.4, [32.0, 107.0, 203.0]),
        (0.7, [237.0, 255.0, 255.0]),
        (1.0, [255.0, 170.0, 0.0]),
    ];
    let k = stops
        .iter()
        .rposition(|&(at, _)| at <= t)
        .unwrap_or(0)
        .min(2);
    let ((a, ca), (b, cb)) = (stops[k], stops[k + 1]);
    let u = ((t - a) / (b - a)).clamp(0.0, 1.0);
    [0, 1, 2].map(|i| (ca[i] + u * (cb[i] - ca[i])).round() as u8)
}

/// The image as a binary PPM (`P6`), which most image viewers open.
pub fn ppm(view: &View, counts: &[u32]) -> Vec<u8> {
    let mut bytes = format!("P6\n{} {}\n255\n", view.width, view.height).into_bytes();
    bytes.extend(counts.iter().flat_map(|&n| colour(view, n)));
    bytes
}
