//! Scene validation: every value checked before anything is prepared.
//!
//! [`Scene::validate`] runs one named check per concern, in a fixed order
//! (the first problem found is the one reported).

use glam::Vec3;

#[cfg(doc)]
use crate::camera::Camera;
use crate::camera::{Projection, pose_problem};
#[cfg(doc)]
use crate::displacement::DisplacementDesc;
use crate::params::{MAX_SHADING_RATE, MAX_SPLIT_DEPTH_LIMIT, VALID_SPP};

use super::error::{colour, finite, invalid};
use super::{
    CameraDesc, Light, LightKind, LightShadow, MAX_SHADOW_MAP_SIZE, Resolution, Scene, SceneError,
    SceneObject, ShadowMaps, Surface, Transform,
};

impl Scene {
    /// Checks every value: resolution > 0, spp in `VALID_SPP`, all numbers
    /// finite, `near > 0`, `far > near`, fov in (0, 180), `eye != target`,
    /// `up` not parallel to the view direction (at open, and at close for a
    /// `camera_close`, which needs a `camera`), no motion or lens with
    /// `nearest` sampling, `dice_threshold > 0`, `shading_rate` in `(0, 1024]`, `max_split_depth <= 64`,
    /// `shininess >= 0`, non-zero light directions, and every displacement table ([`DisplacementDesc::validate`]), with at
    /// most one distinct user WGSL function per scene (it becomes part of
    /// the one megakernel).
    ///
    /// What the camera derives is checked too, not only what is written:
    /// the eye's and target's squared lengths and the squared distance
    /// between them must fit `f32` without overflow or underflow, so that
    /// the view direction can be normalized
    /// (`crate::camera::pose_problem`), and the view, projection and
    /// world-to-clip matrices must be finite
    /// (`Camera::matrix_problem`). What depends on the models (the
    /// transformed control points, an automatically framed camera) is
    /// checked when the scene is prepared ([`crate::prepare::PreparedScene::new`]).
    pub fn validate(&self) -> Result<(), SceneError> {
        self.check_image()?;
        self.check_shutter_and_lens()?;
        self.check_blur_sampling()?;
        self.check_finite_shading_numbers()?;
        self.check_dicing()?;
        self.check_specular()?;
        self.check_camera()?;
        self.check_camera_close()?;
        self.check_animation()?;
        for (i, object) in self.objects.iter().enumerate() {
            check_object(i, object)?;
        }
        for (i, light) in self.lights.iter().enumerate() {
            check_light(i, light)?;
        }
        self.check_shadow_map_space()?;
        Ok(())
    }

    /// `shadow_map_space`: finite and invertible, as moving the maps needs
    /// its inverse.
    fn check_shadow_map_space(&self) -> Result<(), SceneError> {
        let Some(space) = self.shadow_map_space else {
            return Ok(());
        };
        finite("shadow_map_space", space.to_cols_array())?;
        let inverse = space.inverse();
        if space.determinant() == 0.0 || !inverse.is_finite() {
            return Err(invalid(
                "shadow_map_space",
                "must be invertible (the maps' space is moved into the scene's by its inverse)",
            ));
        }
        Ok(())
    }

    /// The image: its size, samples per pixel, Interleave UVT's tile side
    /// and permutations, the background colour, the pixel filter and the
    /// 8-bit encoding (exposure and quantization).
    fn check_image(&self) -> Result<(), SceneError> {
        let Resolution { width, height } = self.resolution;
        if width == 0 || height == 0 {
            return Err(SceneError::InvalidResolution { width, height });
        }
        if !VALID_SPP.contains(&self.spp) {
            return Err(SceneError::InvalidSpp { spp: self.spp });
        }
        if !crate::uvt::INTERLEAVE_TILES.contains(&self.interleave_tile) {
            return Err(invalid(
                "interleave_tile",
                "must be 2, 3 or 4 (Interleave UVT's tile side in pixels)",
            ));
        }
        let permutations = self.interleave_permutations;
        if !(1..=crate::uvt::MAX_INTERLEAVE_PERMUTATIONS).contains(&permutations) {
            return Err(SceneError::InvalidInterleavePermutations { permutations });
        }
        colour("background", self.background)?;
        if let Some(problem) = self.pixel_filter.problem() {
            return Err(invalid("pixel_filter", &problem));
        }
        if let Some(problem) = self.exposure.problem() {
            return Err(invalid("exposure", &problem));
        }
        if let Some(problem) = self.quantize.problem() {
            return Err(invalid("quantize", &problem));
        }
        Ok(())
    }

    /// The shutter fraction and the thin lens.
    fn check_shutter_and_lens(&self) -> Result<(), SceneError> {
        finite("shutter", [self.shutter])?;
        if !(0.0..=1.0).contains(&self.shutter) {
            return Err(invalid("shutter", "must be in [0, 1]"));
        }
        finite("lens.aperture", [self.lens.aperture])?;
        if self.lens.aperture < 0.0 {
            return Err(invalid(
                "lens.aperture",
                "must be >= 0 (a lens radius in world units)",
            ));
        }
        if self.lens.aperture > 0.0
            && self
                .camera
                .is_some_and(|c| c.projection == Projection::Orthographic)
        {
            return Err(invalid(
                "lens.aperture",
                "must be 0 with an orthographic camera (the thin lens needs a perspective one)",
            ));
        }
        if let Some(focus) = self.lens.focus_distance {
            finite("lens.focus_distance", [focus])?;
            if focus <= 0.0 {
                return Err(invalid("lens.focus_distance", "must be > 0"));
            }
        }
        Ok(())
    }

    /// Motion blur and depth of field need a sampling mode that samples
    /// time and lens.
    fn check_blur_sampling(&self) -> Result<(), SceneError> {
        let moving =
            self.camera_close.is_some() || self.objects.iter().any(|o| o.transform_close.is_some());
        if !self.sampling.supports_blur() && (moving || self.lens.aperture > 0.0) {
            return Err(invalid(
                "sampling",
                "\"nearest\" samples neither time nor lens: use another mode for motion blur or depth of field",
            ));
        }
        Ok(())
    }

    /// The ambient, dicing and specular numbers are finite (checked before
    /// their ranges).
    fn check_finite_shading_numbers(&self) -> Result<(), SceneError> {
        finite("ambient", [self.ambient])?;
        finite("dice_threshold", [self.dice_threshold])?;
        finite("specular.strength", [self.specular.strength])?;
        finite("specular.shininess", [self.specular.shininess])
    }

    /// The dicing controls: the fixed dice threshold, the shading rate and
    /// the split depth.
    fn check_dicing(&self) -> Result<(), SceneError> {
        if self.dice_threshold <= 0.0 {
            return Err(invalid("dice_threshold", "must be > 0 pixels"));
        }
        finite("shading_rate", [self.shading_rate])?;
        if !(self.shading_rate > 0.0 && self.shading_rate <= MAX_SHADING_RATE) {
            return Err(invalid(
                "shading_rate",
                &format!("must be in (0, {MAX_SHADING_RATE}] square pixels"),
            ));
        }
        if self.max_split_depth > MAX_SPLIT_DEPTH_LIMIT {
            return Err(invalid(
                "max_split_depth",
                &format!("must be <= {MAX_SPLIT_DEPTH_LIMIT}"),
            ));
        }
        Ok(())
    }

    /// The Blinn-Phong exponent.
    fn check_specular(&self) -> Result<(), SceneError> {
        if self.specular.shininess < 0.0 {
            return Err(invalid("specular.shininess", "must be >= 0"));
        }
        Ok(())
    }

    /// The camera as written, and the matrices it derives at open (and at
    /// close, for a `camera_close` whose fields are finite).
    fn check_camera(&self) -> Result<(), SceneError> {
        let Some(camera) = &self.camera else {
            return Ok(());
        };
        camera.validate()?;
        // What the camera derives must be finite too: its matrices.
        let Resolution { width, height } = self.resolution;
        let built = camera.camera(width, height);
        if let Some(reason) = built.matrix_problem() {
            return Err(SceneError::InvalidCamera {
                reason: reason.to_string(),
            });
        }
        // Non-finite fields of the pose at close are named by
        // `check_camera_close`, each by its own field; this checks what
        // finite fields derive.
        if let Some(close) = self
            .camera_close
            .as_ref()
            .filter(|c| c.eye.is_finite() && c.target.is_finite())
        {
            let up = close.up.unwrap_or(camera.up);
            if let Some(reason) = built.looking(close.eye, close.target, up).matrix_problem() {
                return Err(invalid("camera_close", reason));
            }
        }
        Ok(())
    }

    /// The camera's pose at shutter close: it needs a camera at open, finite
    /// fields, and a view direction `f32` can compute.
    fn check_camera_close(&self) -> Result<(), SceneError> {
        let Some(close) = &self.camera_close else {
            return Ok(());
        };
        let Some(camera) = &self.camera else {
            return Err(invalid(
                "camera_close",
                "needs a [camera] table: the camera at shutter open",
            ));
        };
        finite("camera_close.eye", close.eye.to_array())?;
        finite("camera_close.target", close.target.to_array())?;
        let up = close.up.unwrap_or(camera.up);
        finite("camera_close.up", up.to_array())?;
        if let Some(problem) = pose_problem(close.eye, close.target, up) {
            return Err(invalid("camera_close", &problem.reason("camera_close")));
        }
        Ok(())
    }
}

/// Object `i` (`objects[i]`): finite placements, colour, sides, a moving
/// object's non-zero scales, and its displacement table.
fn check_object(i: usize, object: &SceneObject) -> Result<(), SceneError> {
    check_transform(&format!("objects[{i}].transform"), &object.transform)?;
    colour(&format!("objects[{i}].color"), object.color)?;
    if !matches!(object.sides, 1 | 2) {
        return Err(invalid(&format!("objects[{i}].sides"), "must be 1 or 2"));
    }
    if object.subdivision.is_some() && !super::object::is_obj_model(&object.model) {
        return Err(invalid(
            &format!("objects[{i}].subdivision"),
            &format!(
                "applies only to .obj models (meshes); model {:?} is made of patches already",
                crate::input::excerpt(&object.model)
            ),
        ));
    }
    if let Some(t) = &object.transform_close {
        check_transform(&format!("objects[{i}].transform_close"), t)?;
        let degenerate = |t: &Transform| t.scale.to_vec3().cmpeq(Vec3::ZERO).any();
        if degenerate(t) || degenerate(&object.transform) {
            return Err(invalid(
                &format!("objects[{i}].transform_close"),
                "a moving object needs non-zero scales at open and close",
            ));
        }
    }
    if let Some(surface) = &object.surface {
        check_surface(i, surface)?;
    }
    if let Some(rate) = object.shading_rate {
        let field = format!("objects[{i}].shading_rate");
        finite(&field, [rate])?;
        if !(rate > 0.0 && rate <= MAX_SHADING_RATE) {
            return Err(invalid(
                &field,
                &format!("must be in (0, {MAX_SHADING_RATE}] (pixels per micropolygon)"),
            ));
        }
    }
    if let Some(displacement) = &object.displacement {
        displacement.validate().map_err(|problem| {
            let field = format!("objects[{i}].displacement.{}", problem.field);
            match problem.reason {
                None => SceneError::NonFinite { field },
                Some(reason) => SceneError::InvalidValue { field, reason },
            }
        })?;
    }
    Ok(())
}

/// Object `i`'s surface parameters: finite and not negative (RenderMan's
/// terms only add light), and a positive `roughness` (the highlight's
/// exponent is its inverse).
fn check_surface(i: usize, surface: &Surface) -> Result<(), SceneError> {
    for (name, value) in surface.params() {
        let field = format!("objects[{i}].surface.{name}");
        finite(&field, [value])?;
        if value < 0.0 {
            return Err(invalid(&field, "must be >= 0"));
        }
        if name == "roughness" && value == 0.0 {
            return Err(invalid(&field, "must be > 0"));
        }
    }
    Ok(())
}

/// A placement's translation, rotation, scale and matrix are finite; `field` names
/// the placement (`objects[i].transform` or `objects[i].transform_close`).
fn check_transform(field: &str, transform: &Transform) -> Result<(), SceneError> {
    finite(
        &format!("{field}.translate"),
        transform.translate.to_array(),
    )?;
    finite(
        &format!("{field}.rotate_degrees"),
        transform.rotate_degrees.to_array(),
    )?;
    finite(
        &format!("{field}.scale"),
        transform.scale.to_vec3().to_array(),
    )?;
    if let Some(matrix) = transform.matrix {
        finite(&format!("{field}.matrix"), matrix.to_cols_array())?;
    }
    Ok(())
}

/// Light `i` (`lights[i]`): finite colour and intensity, a finite
/// position (point lights and spotlights), a finite, non-zero direction
/// (distant lights and spotlights), and a spotlight's cone: `0 <
/// cone_angle_degrees <= 90`, `0 <= cone_delta_degrees <= cone_angle_degrees`
/// and `beam_distribution >= 0`.
fn check_light(i: usize, light: &Light) -> Result<(), SceneError> {
    colour(&format!("lights[{i}].color"), light.color)?;
    finite(&format!("lights[{i}].intensity"), [light.intensity])?;
    if let Some(position) = light.position {
        finite(&format!("lights[{i}].position"), position.to_array())?;
    }
    if matches!(light.kind, LightKind::Distant | LightKind::Spot) {
        finite(
            &format!("lights[{i}].direction"),
            light.direction.to_array(),
        )?;
        if light.direction.length_squared() == 0.0 {
            return Err(invalid(
                &format!("lights[{i}].direction"),
                "must be non-zero",
            ));
        }
    }
    if light.kind == LightKind::Spot {
        let cone = light.cone_angle_degrees;
        let delta = light.cone_delta_degrees;
        finite(&format!("lights[{i}].cone_angle_degrees"), [cone])?;
        finite(&format!("lights[{i}].cone_delta_degrees"), [delta])?;
        finite(
            &format!("lights[{i}].beam_distribution"),
            [light.beam_distribution],
        )?;
        if !(cone > 0.0 && cone <= 90.0) {
            return Err(invalid(
                &format!("lights[{i}].cone_angle_degrees"),
                "must be in (0, 90]",
            ));
        }
        if !(0.0..=cone).contains(&delta) {
            return Err(invalid(
                &format!("lights[{i}].cone_delta_degrees"),
                "must be in [0, cone_angle_degrees]",
            ));
        }
        if light.beam_distribution < 0.0 {
            return Err(invalid(
                &format!("lights[{i}].beam_distribution"),
                "must be >= 0",
            ));
        }
    }
    if let Some(shadow) = &light.shadow {
        check_shadow(i, light.kind, shadow)?;
    }
    Ok(())
}

/// Light `i`'s shadow: a light that shines from somewhere (not ambient), a
/// usable filter, an automatic map of 1 to [`MAX_SHADOW_MAP_SIZE`] texels,
/// and one map file (six at most for a point light).
fn check_shadow(i: usize, kind: LightKind, shadow: &LightShadow) -> Result<(), SceneError> {
    if kind == LightKind::Ambient {
        return Err(invalid(
            &format!("lights[{i}]"),
            "an ambient light casts no shadow",
        ));
    }
    if let Some(reason) = shadow.filter.problem() {
        return Err(invalid(&format!("lights[{i}]"), &reason));
    }
    match &shadow.maps {
        ShadowMaps::Automatic { map_size } => {
            if !(1..=MAX_SHADOW_MAP_SIZE).contains(map_size) {
                return Err(invalid(
                    &format!("lights[{i}].map_size"),
                    &format!("must be in 1..={MAX_SHADOW_MAP_SIZE}"),
                ));
            }
        }
        ShadowMaps::Files(files) => {
            let most = if kind == LightKind::Point { 6 } else { 1 };
            if files.is_empty() || files.len() > most {
                return Err(invalid(
                    &format!("lights[{i}].shadow_map"),
                    &format!(
                        "names {} files; a {} light takes {}",
                        files.len(),
                        kind.name(),
                        if most == 1 { "one" } else { "one to six" }
                    ),
                ));
            }
        }
    }
    Ok(())
}

impl CameraDesc {
    /// Checks the camera (see [`Scene::validate`]).
    pub fn validate(&self) -> Result<(), SceneError> {
        finite("camera.eye", self.eye.to_array())?;
        finite("camera.target", self.target.to_array())?;
        finite("camera.up", self.up.to_array())?;
        finite("camera.fov_y_degrees", [self.fov_y_degrees])?;
        finite("camera.near", [self.near])?;
        finite("camera.far", [self.far])?;
        if let Some(height) = self.ortho_height {
            finite("camera.ortho_height", [height])?;
        }
        // All values are finite here (checked above), so plain comparisons suffice.
        let reason = if self.near <= 0.0 {
            "near must be > 0".to_string()
        } else if self.far <= self.near {
            "far must be > near".to_string()
        } else if !(self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0) {
            "fov_y_degrees must be in (0, 180)".to_string()
        } else if let Some(problem) = pose_problem(self.eye, self.target, self.up) {
            // Derived: the view direction must be computable in f32.
            problem.reason("camera")
        } else if self.projection == Projection::Orthographic
            && !(self.view_height() > 0.0 && self.view_height().is_finite())
        {
            // Derived when not given: from the distance and the fov.
            format!(
                "the orthographic view height {} must be finite and > 0{}",
                self.view_height(),
                if self.ortho_height.is_some() {
                    ""
                } else {
                    " (from the eye-target distance and fov_y_degrees: set ortho_height)"
                }
            )
        } else {
            return Ok(());
        };
        Err(SceneError::InvalidCamera { reason })
    }
}
