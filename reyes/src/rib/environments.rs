//! `MakeTexture`: texture names for the shaders' `texturename`;
//! `MakeLatLongEnvironment` and `MakeCubeFaceEnvironment`: environment map
//! names for `shinymetal`'s `texturename`.
//!
//! For `MakeTexture` and `MakeLatLongEnvironment` nothing is written: the
//! name stands for its picture, which the renderer mipmaps itself, and the
//! filter and its widths are not followed (every lookup is the anisotropic
//! trilinear filter of `crate::texture`). A latitude-longitude picture is
//! read by `environment()` in RenderMan's convention
//! (`crate::texture::environment`). `MakeCubeFaceEnvironment` runs between
//! frames, as `MakeShadow` does: it writes the latitude-longitude map of
//! its six faces (`crate::texture::cube_faces`) under its name.

use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};

use super::interp::Interp;
use super::parser::Value;
use super::state;
use crate::texture::cube_faces::FACE_NAMES;

impl Interp {
    /// `MakeTexture picturename texturename swrap twrap filter swidth
    /// twidth ...`: `texturename` stands for the picture (beside the RIB
    /// file), with its wrap modes. Not scoped: later frames use it too.
    pub(super) fn make_texture(&mut self, v: &[Value], file: &Path) -> Result<(), String> {
        let (args, _, _) = state::split_params(v, 7, &self.declared)?;
        let picture = state::arg_str(&args, 0, "the picture")?;
        let texture = state::arg_str(&args, 1, "the texture name")?;
        let mut wraps = [crate::texture::Wrap::Periodic; 2];
        for (k, what) in [(2, "swrap"), (3, "twrap")] {
            let wrap = state::arg_str(&args, k, what)?;
            wraps[k - 2] = match wrap {
                "periodic" => crate::texture::Wrap::Periodic,
                "clamp" => crate::texture::Wrap::Clamp,
                "black" => crate::texture::Wrap::Black,
                other => {
                    return Err(format!(
                        "MakeTexture: {what} {:?} is not a wrap mode (\"periodic\", \"clamp\" or \"black\")",
                        crate::input::excerpt(other)
                    ));
                }
            };
        }
        let path = file.parent().unwrap_or(Path::new("")).join(picture);
        let desc = crate::texture::TextureDesc {
            wrap_s: wraps[0],
            wrap_t: wraps[1],
            ..crate::texture::TextureDesc::new(path)
        };
        self.made_textures.insert(texture.to_owned(), desc);
        Ok(())
    }

    /// `MakeLatLongEnvironment picturename texturename filter swidth twidth
    /// ...`: `texturename` stands for the picture (beside the RIB file).
    pub(super) fn make_latlong_environment(
        &mut self,
        v: &[Value],
        file: &Path,
    ) -> Result<(), String> {
        let (args, _, _) = state::split_params(v, 5, &self.declared)?;
        let picture = state::arg_str(&args, 0, "the picture")?;
        let texture = state::arg_str(&args, 1, "the texture name")?;
        let path = file.parent().unwrap_or(Path::new("")).join(picture);
        self.made_textures
            .insert(texture.to_owned(), crate::texture::TextureDesc::new(path));
        Ok(())
    }

    /// `MakeCubeFaceEnvironment px nx py ny pz nz texturename fov filter
    /// swidth twidth ...`: handed over to run before the next frame
    /// ([`super::FrameRequest::MakeCubeFaceEnvironment`]), which writes
    /// `texturename` as the latitude-longitude map of the six faces; the
    /// name then stands for that map. Names are relative to the current
    /// directory, as `MakeShadow`'s: the faces are often what earlier
    /// frames' `Display`s wrote. The filter and its widths are not used
    /// (the faces are resampled bilinearly).
    pub(super) fn make_cube_face_environment(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        let (args, _, _) = state::split_params(v, 11, &self.declared)?;
        let mut faces: [PathBuf; 6] = Default::default();
        for (k, (face, name)) in faces.iter_mut().zip(FACE_NAMES).enumerate() {
            let picture = state::arg_str(&args, k, &format!("the {name} picture"))?;
            if picture.is_empty() {
                return Err(format!("the {name} picture is empty"));
            }
            *face = PathBuf::from(picture);
        }
        let texture = state::arg_str(&args, 6, "the texture name")?;
        if texture.is_empty() {
            return Err("the texture name is empty".into());
        }
        let fov = state::arg_f(&args, 7, "the field of view")?;
        if !(90.0..180.0).contains(&fov) {
            return Err(format!(
                "the field of view must be at least 90 degrees (the faces meet at 90) and less than 180, not {fov}"
            ));
        }
        self.warn_once(
            "MakeCubeFaceEnvironment filter",
            file,
            line,
            "MakeCubeFaceEnvironment's filter and widths are not used: the faces are resampled bilinearly, and environment() filters the map itself".into(),
        );
        let environment = PathBuf::from(texture);
        // Where the request writes it, whatever directory the scene is
        // read from later.
        let written = std::env::current_dir()
            .map(|dir| dir.join(&environment))
            .unwrap_or_else(|_| environment.clone());
        self.made_textures.insert(
            texture.to_owned(),
            crate::texture::TextureDesc {
                color_space: crate::texture::ColorSpace::Linear,
                ..crate::texture::TextureDesc::new(written)
            },
        );
        self.requests
            .push(super::FrameRequest::MakeCubeFaceEnvironment {
                faces,
                environment,
                fov: fov as f32,
                file: file.to_path_buf(),
                line,
            });
        Ok(())
    }
}

impl Interp {
    /// RenderMan's `vtransform("current", "world")` for the renderer's world
    /// space, which is RenderMan's camera space with x mirrored
    /// ([`super::interp::camera_to_world`]): the images of the renderer's
    /// x, y and z axes in RenderMan's world space. Before `WorldBegin` (no
    /// camera yet), or with a camera transform that cannot be inverted
    /// (warned), world space is taken as camera space.
    pub(super) fn world_axes(&mut self, file: &Path, line: usize) -> [DVec3; 3] {
        let camera = self.camera.unwrap_or(DMat4::IDENTITY);
        let mut to_world = camera.inverse() * super::interp::camera_to_world();
        if !to_world.is_finite() {
            self.warn(
                file,
                line,
                "the camera transform cannot be inverted: the environment map is read in camera space".into(),
            );
            to_world = super::interp::camera_to_world();
        }
        [DVec3::X, DVec3::Y, DVec3::Z].map(|axis| to_world.transform_vector3(axis))
    }
}
