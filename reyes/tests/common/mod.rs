//! Helpers shared by the integration tests (included with `mod common;`).

#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::path::{Path, PathBuf};

/// `shared/data` next to the workspace (`<workspace>/../shared/data`).
pub(crate) fn shared_data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data")
        .join(name)
}

/// The Killeroo model path, or `None` (with a printed notice) when absent.
pub(crate) fn killeroo_path() -> Option<PathBuf> {
    let path = shared_data("killeroo.bpt");
    if path.exists() {
        Some(path)
    } else {
        println!(
            "NOTICE: {} not found; skipping the Killeroo check",
            path.display()
        );
        None
    }
}

/// `<workspace>/target`.
pub(crate) fn target_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target")
}

/// The names of the entries in `dir`, sorted.
pub(crate) fn dir_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
