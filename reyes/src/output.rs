//! Writing rendered images to disk.

use std::path::{Path, PathBuf};

use image::RgbaImage;

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The parent directory could not be created.
    #[error("cannot create directory {}: {source}", path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// Encoding or writing the PNG failed.
    #[error("cannot write PNG {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The underlying image error (wraps I/O errors).
        #[source]
        source: image::ImageError,
    },
}

/// Writes an image as PNG, creating the parent directory if needed.
pub fn write_png(image: &RgbaImage, path: impl AsRef<Path>) -> Result<(), OutputError> {
    let path = path.as_ref();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| OutputError::CreateDir {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    image
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_and_reports_errors() {
        let dir = std::env::temp_dir().join(format!("reyes-output-test-{}", std::process::id()));
        let path = dir.join("nested").join("img.png");
        let image = RgbaImage::from_pixel(3, 2, image::Rgba([10, 20, 30, 255]));
        write_png(&image, &path).unwrap();
        let back = image::open(&path).unwrap().to_rgba8();
        assert_eq!(back, image);
        // A path whose parent is a file cannot be created.
        let bad = path.join("below-a-file.png");
        assert!(matches!(
            write_png(&image, &bad),
            Err(OutputError::CreateDir { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
