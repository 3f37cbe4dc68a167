//! Requests that act on files between frames: `MakeShadow` and
//! `MakeCubeFaceEnvironment`.
//!
//! The interpreter reads ahead of the renderer ([`super::stream`]), so it
//! cannot run a request that reads what an earlier frame writes. It hands
//! such a request over with the frame that follows it in the file
//! ([`super::RibFrame::requests_before`]), or with the end of the file
//! ([`super::RibFrames::requests_after`]); whoever renders the frames runs
//! it in its place (`reyes render`: after the frames before it are
//! written, before the next frame is prepared).
//!
//! Names are relative to the current directory, as `Display`'s are: the
//! picture is what a frame's `Display` wrote, and a shadowed light's
//! `shadowname` names the map as `MakeShadow` wrote it.

use std::path::{Path, PathBuf};

use super::interp::Interp;
use super::parser::Value;
use super::state;

/// A request to run between frames, where it stands in the file.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum FrameRequest {
    /// `MakeShadow picturename texturename`: make the shadow map `shadow`
    /// from the depth image `picture` ([`crate::output::make_shadow`]).
    MakeShadow {
        /// The depth image a frame wrote (`Display ... "z"`).
        picture: PathBuf,
        /// The shadow map to write.
        shadow: PathBuf,
        /// The RIB file of the request (an archive, for one inside it).
        file: PathBuf,
        /// Its line.
        line: usize,
    },
    /// `MakeCubeFaceEnvironment px nx py ny pz nz texturename fov ...`:
    /// make the latitude-longitude map `environment` from six face
    /// pictures ([`crate::output::make_cube_face_environment`]).
    MakeCubeFaceEnvironment {
        /// The face pictures, `px nx py ny pz nz`.
        faces: [PathBuf; 6],
        /// The map to write.
        environment: PathBuf,
        /// The faces' full horizontal field of view, in degrees.
        fov: f32,
        /// The RIB file of the request.
        file: PathBuf,
        /// Its line.
        line: usize,
    },
}

impl FrameRequest {
    /// `scene.rib:12: MakeShadow "a.z" "a.shad"`: how messages name it.
    pub fn describe(&self) -> String {
        match self {
            FrameRequest::MakeShadow {
                picture,
                shadow,
                file,
                line,
            } => format!(
                "{}:{line}: MakeShadow {:?} {:?}",
                file.display(),
                picture.display().to_string(),
                shadow.display().to_string()
            ),
            FrameRequest::MakeCubeFaceEnvironment {
                environment,
                file,
                line,
                ..
            } => format!(
                "{}:{line}: MakeCubeFaceEnvironment ... {:?}",
                file.display(),
                environment.display().to_string()
            ),
        }
    }

    /// The request's name (`MakeShadow`, ...).
    pub fn name(&self) -> &'static str {
        match self {
            FrameRequest::MakeShadow { .. } => "MakeShadow",
            FrameRequest::MakeCubeFaceEnvironment { .. } => "MakeCubeFaceEnvironment",
        }
    }

    /// The RIB file and line of the request.
    pub fn origin(&self) -> (&Path, usize) {
        match self {
            FrameRequest::MakeShadow { file, line, .. }
            | FrameRequest::MakeCubeFaceEnvironment { file, line, .. } => (file, *line),
        }
    }

    /// The file the request writes.
    pub fn output(&self) -> &Path {
        match self {
            FrameRequest::MakeShadow { shadow, .. } => shadow,
            FrameRequest::MakeCubeFaceEnvironment { environment, .. } => environment,
        }
    }
}

impl Interp {
    /// `MakeShadow picturename texturename [params]`: handed over to run
    /// before the next frame (the parameters, a filter for the depths in
    /// other renderers, are not used: the map is the picture's depths).
    pub(super) fn make_shadow(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        let (args, params, _) = state::split_params(v, 2, &self.declared)?;
        let picture = state::arg_str(&args, 0, "the picture")?;
        let shadow = state::arg_str(&args, 1, "the shadow map's name")?;
        for (name, what) in [(picture, "picture"), (shadow, "shadow map's name")] {
            if name.is_empty() {
                return Err(format!("the {what} is empty"));
            }
        }
        if !params.is_empty() {
            self.warn_once(
                "MakeShadow parameters",
                file,
                line,
                "MakeShadow's parameters are not used: the map holds the picture's depths as they are".into(),
            );
        }
        self.requests.push(FrameRequest::MakeShadow {
            picture: PathBuf::from(picture),
            shadow: PathBuf::from(shadow),
            file: file.to_path_buf(),
            line,
        });
        Ok(())
    }
}
