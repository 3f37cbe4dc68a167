//! The [`Scene`] made from an interpreted RIB stream.

use std::path::Path;

use glam::{DMat4, EulerRot, Vec3};

use super::interp::{Interp, Prim};
use super::{RibError, RibScene, Warning};
use crate::displacement::DisplacementDesc;
use crate::model::{DEFAULT_ST, Model, Patch};
use crate::params::NEAR_EPS;
use crate::scene::{
    CameraDesc, CameraPose, Lens, Projection, Resolution, Scale, Scene, SceneObject,
    ShadingInterpolation, Surface, Transform,
};

/// Builds the scene of the frame `interp` has read from `file` (at its
/// `FrameEnd`, or at the end of a file without frames), taking the frame's
/// primitives, lights and warnings.
pub(super) fn build(interp: &mut Interp, file: &Path) -> Result<RibScene, RibError> {
    let lights = interp.scene_lights();
    let mut warnings = std::mem::take(&mut interp.warnings);
    let more = std::mem::take(&mut interp.more_warnings);
    if more > 0 {
        warnings.push(Warning {
            file: file.to_path_buf(),
            line: 0,
            message: format!("{more} more warnings not shown"),
        });
    }
    let mut warn = |message: String| {
        warnings.push(Warning {
            file: file.to_path_buf(),
            line: 0,
            message,
        })
    };
    let opts = &interp.opts;
    let mut scene = Scene {
        background: Vec3::ZERO,
        lights: Vec::new(),
        objects: Vec::new(),
        ..Scene::default()
    };
    let (width, height) = opts.image_size();
    scene.resolution = Resolution { width, height };

    // PixelSamples: the renderer takes k x k samples.
    let (xs, ys) = opts.pixel_samples.unwrap_or((2.0, 2.0));
    let k = (xs * ys).max(1.0).sqrt().round().clamp(1.0, 16.0) as u32;
    if f64::from(k * k) != xs * ys {
        warn(format!(
            "PixelSamples {xs} {ys}: the renderer takes a square grid; using {k} x {k} = {} samples",
            k * k
        ));
    }
    scene.spp = k * k;

    if let Some(rate) = opts.shading_rate {
        // Clamped (with a warning) when it was read.
        scene.shading_rate = rate as f32;
    }

    scene.pixel_filter = opts.pixel_filter.unwrap_or_default();
    if opts.depth_output {
        scene.aov = crate::Aov::Z;
    }
    scene.depth_filter = opts.depth_filter.unwrap_or_default();
    scene.exposure = opts.exposure.unwrap_or_default();
    scene.quantize = opts.quantize.unwrap_or_default();
    if let Some(smooth) = opts.smooth {
        scene.shading_interpolation = if smooth {
            ShadingInterpolation::Smooth
        } else {
            ShadingInterpolation::Constant
        };
    }

    // Camera: the origin of camera space looking down +z (RenderMan), which
    // the x mirror makes a right-handed look_at towards +z. The screen
    // window (RenderMan's default: the shorter side spans [-1, 1]) sets the
    // view's height: for a perspective camera in units of tan(fov / 2), for
    // an orthographic one in camera-space units.
    let image_aspect = f64::from(width) / f64::from(height);
    if let Some(aspect) = opts.frame_aspect
        && (aspect - image_aspect).abs() > 1e-6 * image_aspect
    {
        warn(format!(
            "FrameAspectRatio {aspect} differs from the image's {image_aspect} (Format): the renderer's pixels are square; using {image_aspect}"
        ));
    }
    let [l, r, b, t] = opts.screen_window_or_default();
    let window_aspect = (r - l) / (t - b);
    if (window_aspect - image_aspect).abs() > 1e-6 * image_aspect {
        warn(format!(
            "ScreenWindow {l} {r} {b} {t} has the aspect {window_aspect}, the image {image_aspect}: RenderMan would stretch the image; the renderer keeps the window's height"
        ));
    }
    let half_height = (t - b) / 2.0;
    let (projection, fov_y, ortho_height) = if opts.perspective {
        let fov = opts.fov.unwrap_or(90.0);
        if !(fov > 0.0 && fov < 180.0) {
            return Err(scene_error(
                file,
                format!("Projection fov {fov} is not in (0, 180)"),
            ));
        }
        let fov_y = (2.0 * ((fov.to_radians() / 2.0).tan() * half_height).atan()).to_degrees();
        if !(fov_y > 0.0 && fov_y < 180.0) {
            return Err(scene_error(
                file,
                format!(
                    "Projection fov {fov} with ScreenWindow {l} {r} {b} {t} gives a vertical field of view of {fov_y} degrees, not in (0, 180)"
                ),
            ));
        }
        (Projection::Perspective, fov_y, None)
    } else {
        // The fov is unused; the default keeps the description valid.
        (
            Projection::Orthographic,
            40.0,
            Some((2.0 * half_height) as f32),
        )
    };
    // The farthest control point, and the primitive it belongs to.
    let farthest = interp
        .prims
        .iter()
        .flat_map(|p| p.patches.iter().flatten().map(move |q| (q.z, p)))
        .fold(None, |far: Option<(f32, &Prim)>, (z, p)| match far {
            Some((old, _)) if old >= z => far,
            _ => Some((z, p)),
        });
    let (near, far) = match opts.clipping {
        // `Clipping` checked near > 0 (warning below the epsilon) and far >
        // near; RenderMan's RI_INFINITY (1e38) and beyond mean "no far
        // plane", which 1e30 is to the renderer.
        Some((n, f)) => (n.max(f64::from(NEAR_EPS)) as f32, f.min(1e30) as f32),
        None => {
            let z = farthest.map_or(0.0, |(z, _)| z);
            let far = (2.0 * f64::from(z)).max(1000.0);
            if far > f64::from(f32::MAX) {
                let (_, prim) = farthest.expect("a point this far");
                return Err(scene_error(
                    file,
                    format!(
                        "the {} at {}:{} reaches z = {z:e} in camera space: the default far plane, twice the farthest control point, is beyond f32; give Clipping near far, or scale the scene down",
                        prim.request,
                        prim.file.display(),
                        prim.line
                    ),
                ));
            }
            (0.1, far as f32)
        }
    };
    scene.camera = Some(CameraDesc {
        eye: Vec3::ZERO,
        target: Vec3::Z,
        up: Vec3::Y,
        fov_y_degrees: fov_y as f32,
        near,
        far,
        projection,
        ortho_height,
    });

    let mut camera_warning = None;
    // Camera motion: the pose at close, in the renderer's world (camera
    // space at open, x mirrored), if it is rigid.
    if let (Some(open), Some((close, line))) = (interp.camera, interp.camera_close) {
        let f = super::interp::camera_to_world();
        let pose = f * open * close.inverse() * f;
        let basis = glam::DMat3::from_mat4(pose);
        let rigid = (basis.transpose() * basis - glam::DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-6)
            && basis.determinant() > 0.0;
        if rigid {
            scene.camera_close = Some(CameraPose {
                eye: pose.transform_point3(glam::DVec3::ZERO).as_vec3(),
                target: pose.transform_point3(glam::DVec3::Z).as_vec3(),
                up: Some(pose.transform_vector3(glam::DVec3::Y).as_vec3()),
            });
        } else {
            camera_warning = Some(Warning {
                file: file.to_path_buf(),
                line,
                message: "the camera's motion is not rigid (it scales, shears or mirrors): the camera at shutter open is used".into(),
            });
        }
    }

    if opts.dof.is_some() && !opts.perspective {
        warn("DepthOfField needs a perspective camera (the thin lens of an orthographic one is not supported): a pinhole camera is used".into());
    } else if let Some((fstop, focal_length, focal_distance)) = opts.dof {
        if fstop > 0.0 && focal_length > 0.0 && focal_distance > 0.0 && fstop.is_finite() {
            // The request checked that f32 holds them.
            let aperture = focal_length / (2.0 * fstop);
            scene.lens = Lens {
                aperture: aperture as f32,
                focus_distance: Some(focal_distance as f32),
            };
        } else {
            warn(
                "DepthOfField with a non-positive or infinite value: a pinhole camera is used"
                    .into(),
            );
        }
    }

    // Shutter: the fraction of the open-to-close motion the shutter sees.
    let (open, close) = opts.shutter.unwrap_or((0.0, 0.0));
    scene.shutter = match opts.motion_times {
        Some((t0, t1)) if t1 != t0 => {
            if open != t0 {
                warn(format!(
                    "Shutter opens at {open}, the motion starts at {t0}: the renderer's shutter opens at the first motion sample"
                ));
            }
            ((close - t0) / (t1 - t0)).clamp(0.0, 1.0) as f32
        }
        _ => 1.0,
    };

    // Lights: RenderMan's ambient() is the ambient lights alone.
    scene.ambient = 0.0;
    scene.lights.extend(lights.iter().map(|l| l.light.clone()));
    let lit = interp
        .prims
        .iter()
        .any(|p| !p.patches.is_empty() && super::surfaces::is_lit(&p.attrs.surface));
    // A depth frame (a shadow map's) needs no light.
    if lit && lights.is_empty() && !opts.depth_output {
        warn("no light sources: the surfaces that need lights (matte, metal, plastic) are black; add LightSource \"distantlight\", or leave their Surface out for RenderMan's defaultsurface".into());
    }

    // Objects: consecutive primitives with the same look and motion share one.
    let mut models: Vec<Model> = Vec::new();
    let mut keys: Vec<ObjectKey> = Vec::new();
    // Each primitive's patches are dropped once copied into its object's
    // model: the two never both hold the whole scene.
    // Displacement shaders without a bound, by request (one warning each).
    let mut unbounded: Vec<Warning> = Vec::new();
    let mut last_placed = false;
    for prim in std::mem::take(&mut interp.prims) {
        if prim.patches.is_empty() {
            continue;
        }
        let key = object_key(&prim);
        if let Some(desc) = &key.6
            && desc.bound == Some(0.0)
            && prim.attrs.displacement_bound.is_none()
            && !unbounded
                .iter()
                .any(|w| w.file == prim.file && w.line == prim.line)
        {
            unbounded.push(Warning {
                file: prim.file.clone(),
                line: prim.line,
                message: format!(
                    "{}: displacement shader {} without Attribute \"displacementbound\": its bound is 0, so points it moves may be culled near the frame's edges (the render counts them)",
                    prim.request,
                    desc.file.as_deref().unwrap_or(Path::new("")).display()
                ),
            });
        }
        // An instance is an object of its own, placed by its matrix, so
        // that instances of one definition have equal models (which the GPU
        // stores once) and nothing merges into them.
        let placed = prim.placement.is_some() || last_placed;
        last_placed = prim.placement.is_some();
        if keys.last() != Some(&key) || placed {
            let transform_close = match prim.close {
                None => None,
                Some(m) => match decompose(m) {
                    Some(t) => Some(t),
                    None => {
                        warn("a motion that is not scale, rotation and translation (shear) is not supported; that object does not move".into());
                        None
                    }
                },
            };
            // The baked points are in a mirrored frame (see `object_key`);
            // a placement that mirrors turns the front again where the scene
            // is prepared, so the orientation is turned back here.
            let mirrored = prim.placement.is_some_and(|m| m.determinant() < 0.0);
            scene.objects.push(SceneObject {
                model: format!("rib-object-{}", scene.objects.len()),
                subdivision: None,
                transform: Transform {
                    matrix: prim.placement,
                    ..Transform::default()
                },
                color: key.0,
                surface: Some(key.4.clone()),
                shading_rate: key.5.map(|r| r as f32),
                displacement: key.6.clone(),
                transform_close,
                keys: Vec::new(),
                sides: key.1,
                reverse_orientation: key.2 != mirrored,
            });
            models.push(Model::default());
            keys.push(key);
        }
        let model = models.last_mut().expect("pushed");
        // A model keeps `st: None` while all its patches have the default
        // texture coordinates (so plain geometry converts as before).
        if model.st.is_none() && prim.st.iter().any(|&st| st != DEFAULT_ST) {
            model.st = Some(vec![DEFAULT_ST; model.patches.len()]);
        }
        if let Some(st) = &mut model.st {
            st.extend_from_slice(&prim.st);
        }
        model
            .patches
            .extend(prim.patches.iter().map(|&points| Patch { points }));
    }
    warnings.extend(camera_warning);
    warnings.extend(unbounded);
    if scene.objects.is_empty() {
        warnings.push(Warning {
            file: file.to_path_buf(),
            line: 0,
            message: format!(
                "{} (the RIB has no geometry the renderer draws)",
                crate::scene::NO_OBJECTS_WARNING
            ),
        });
    }
    // Shadow maps are kept in the file's world space, which every frame
    // shares; the scene is in this frame's camera space, x mirrored. Only a
    // scene that reads or writes maps keeps that space (a camera beyond
    // f32 is no error for the others).
    if scene.may_use_shadow_map_files() {
        scene.shadow_map_space = Some(
            (super::interp::camera_to_world() * interp.camera.unwrap_or(DMat4::IDENTITY)).as_mat4(),
        );
    }
    scene.validate().map_err(|source| RibError::Scene {
        file: file.to_path_buf(),
        source: Box::new(source),
    })?;
    Ok(RibScene {
        scene,
        models,
        light_origins: lights.iter().map(|l| (l.file.clone(), l.line)).collect(),
        display: interp.opts.display.clone(),
        warnings,
        sources: interp.sources.clone(),
    })
}

/// What a primitive's object is made of: colour, sides, reverse
/// orientation, motion, surface, shading rate and displacement.
type ObjectKey = (
    Vec3,
    u8,
    bool,
    Option<DMat4>,
    Surface,
    Option<f64>,
    Option<DisplacementDesc>,
);

/// The [`ObjectKey`] of a primitive.
fn object_key(prim: &Prim) -> ObjectKey {
    // The baked points are in a mirrored (right-handed) frame, which turns
    // RenderMan's front (dP/du x dP/dv with a left-handed orientation) into
    // the renderer's back.
    (
        prim.attrs.color.as_vec3(),
        prim.attrs.sides,
        prim.attrs.orientation_lh,
        prim.close,
        prim.attrs.surface.clone(),
        prim.attrs.shading_rate,
        prim.attrs.displacement.clone().map(|mut desc| {
            // The bound in force at the primitive; a shader that does not
            // bound itself gets 0 without one (and a warning).
            desc.bound = match prim.attrs.displacement_bound {
                Some(bound) => Some(bound as f32),
                None if desc
                    .file
                    .as_deref()
                    .is_some_and(crate::surface_shader::builtin::bounds_itself) =>
                {
                    None
                }
                None => Some(0.0),
            };
            desc
        }),
    )
}

/// `m` as the renderer's scale-rotate-translate [`Transform`], if it is one.
fn decompose(m: DMat4) -> Option<Transform> {
    let (scale, rotation, translation) = m.to_scale_rotation_translation();
    let back = DMat4::from_scale_rotation_translation(scale, rotation, translation);
    let size = m.to_cols_array().iter().fold(1.0f64, |a, b| a.max(b.abs()));
    let error = (back - m)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()));
    if error.is_nan() || error > 1e-6 * size {
        return None;
    }
    let (z, y, x) = rotation.to_euler(EulerRot::ZYX);
    Some(Transform {
        translate: translation.as_vec3(),
        rotate_degrees: Vec3::new(
            x.to_degrees() as f32,
            y.to_degrees() as f32,
            z.to_degrees() as f32,
        ),
        scale: Scale::PerAxis(scale.as_vec3()),
        matrix: None,
    })
}

fn scene_error(file: &Path, reason: String) -> RibError {
    RibError::Scene {
        file: file.to_path_buf(),
        source: Box::new(crate::scene::SceneError::InvalidCamera { reason }),
    }
}
