//! RIB `MakeCubeFaceEnvironment`: six face pictures made into the
//! latitude-longitude map that `environment()` reads
//! ([`crate::texture::cube_faces`]), written as a float RGBA EXR.

use std::path::{Path, PathBuf};

use image::Rgba32FImage;

use super::{OutputError, OutputKind, single_output, stage_linear_exr};
use crate::texture::TextureError;
use crate::texture::cube_faces::{FACE_NAMES, FacePicture, latlong_from_faces};

/// Why `MakeCubeFaceEnvironment` failed.
#[derive(Debug, thiserror::Error)]
pub enum MakeEnvironmentError {
    /// A face picture cannot be read.
    #[error("face {face}: {source}")]
    Face {
        /// The face (`px`, `nx`, ...).
        face: &'static str,
        /// Why.
        #[source]
        source: TextureError,
    },
    /// The map could not be written.
    #[error(transparent)]
    Write(#[from] OutputError),
}

/// Reads the six face pictures `faces` (`px nx py ny pz nz`, each taken
/// with the full horizontal field of view `fov_degrees`) and writes their
/// latitude-longitude map to `environment`, through a temporary file
/// renamed into place; returns its size. Nothing is written if a face
/// cannot be read.
pub fn make_cube_face_environment(
    faces: &[PathBuf; 6],
    fov_degrees: f32,
    environment: &Path,
) -> Result<(u32, u32), MakeEnvironmentError> {
    let file = single_output(OutputKind::Environment, "environment map", environment)?;
    let mut pictures = Vec::with_capacity(6);
    for (path, face) in faces.iter().zip(FACE_NAMES) {
        pictures.push(
            FacePicture::read(path)
                .map_err(|source| MakeEnvironmentError::Face { face, source })?,
        );
    }
    let pictures: [FacePicture; 6] = pictures.try_into().expect("six faces");
    let map = latlong_from_faces(&pictures, fov_degrees);
    let image = Rgba32FImage::from_fn(map.width, map.height, |x, y| {
        image::Rgba(map.texels[(y * map.width + x) as usize].to_array())
    });
    stage_linear_exr(&image, &file)?.commit()?;
    Ok((map.width, map.height))
}
