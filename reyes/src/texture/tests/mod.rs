//! Unit tests of [`super`]: the formats and their errors (`formats`), the
//! filtering (`filtering`, and `anisotropy` against a box integral),
//! environment lookups (`environment`), and the
//! WGSL twin's declarations (`wgsl`).

mod anisotropy;
mod environment;
mod filtering;
mod formats;
mod wgsl;

use std::path::{Path, PathBuf};

use glam::Vec4;
use half::f16;

use super::*;

/// A fresh, empty, canonical directory under the system temp directory.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("reyes-texture-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::canonicalize(dir).unwrap()
}

/// Level-0 texel `(x, y)` of texture `id`, as stored.
fn stored(set: &TextureSet, id: TextureId, x: u32, y: u32) -> Vec4 {
    let info = set.info(id).unwrap();
    mipmap::unpack(set.texels[(info.offset + y * info.width + x) as usize])
}

/// Asserts `got` is `expected` up to f16 rounding (half an f16 ulp, with
/// room for the f32 arithmetic before it).
fn assert_f16_close(got: f32, expected: f64, what: &str) {
    let tolerance = expected.abs() * f64::powi(2.0, -11) + 1e-7;
    assert!(
        (f64::from(got) - expected).abs() <= tolerance,
        "{what}: {got} stored, {expected} expected"
    );
}

/// Adds `path` with `color_space`, periodic.
fn add(
    set: &mut TextureSet,
    path: &Path,
    color_space: ColorSpace,
) -> Result<TextureId, TextureError> {
    set.add(&TextureDesc {
        color_space,
        ..TextureDesc::new(path)
    })
}
