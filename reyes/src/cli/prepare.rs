//! The scene `reyes render` and `reyes view` draw: the scene named on the
//! command line with the command line's overrides, prepared.

use glam::Vec3;

use super::BoxError;
use super::args::RenderArgs;
use super::input::{BaseScene, ReadFile, base_scene, displacement, wgsl_file};
use crate::model::Model;
use crate::modes::ShadingInterpolation;
use crate::output::console::errln;
use crate::prepare::{PreparedScene, far_plane_covering_motion};
use crate::scene::{CameraDesc, Scene, Surface, framed_bounds};

/// The scene a command draws, and every file read to make it.
pub(crate) struct Prepared {
    /// The scene, prepared.
    pub(crate) scene: PreparedScene,
    /// The scene file, RIB archives, models, height maps and user WGSL
    /// read, for the command's [`crate::output::OutputGuard`].
    pub(crate) read: Vec<ReadFile>,
}

/// Loads the scene (of a RIB file, the first frame `--frame` selects),
/// applies the command-line overrides and prepares it.
pub(crate) fn prepare(args: &RenderArgs) -> Result<Prepared, BoxError> {
    let base = base_scene(args.scene.as_deref(), args.lenient, args.frame.as_ref())?;
    prepare_base(args, base)
}

/// Applies the command-line overrides to `base` and prepares it.
pub(crate) fn prepare_base(args: &RenderArgs, base: BaseScene) -> Result<Prepared, BoxError> {
    let BaseScene {
        mut scene,
        models: in_memory,
        mut read,
        light_origins,
        shutter_applied,
    } = base;
    let prepared = |scene: &Scene| match &in_memory {
        Some(models) => PreparedScene::new(scene, models),
        None => PreparedScene::load(scene),
    };
    if let Some(desc) = displacement(args)? {
        for object in &mut scene.objects {
            object.displacement = Some(desc.clone());
        }
    }
    if let Some(wgsl) = wgsl_file(args) {
        read.push(("displacement function", wgsl.to_path_buf()));
    }
    override_frame(&mut scene, args);
    override_objects(&mut scene, args);
    override_lens(&mut scene, args, shutter_applied);
    reframe_model(&mut scene, args, in_memory.as_deref())?;
    if camera_overridden(args) || camera_moves(args) {
        // A camera framed automatically (a bare model, the teapot, a scene
        // without `[camera]`) chose its clipping planes for its own eye.
        let framed = scene.camera.is_none() || is_bare_model(args);
        // Start from the camera the scene would use (framed if absent).
        let camera = match scene.camera {
            Some(desc) => desc,
            None => framed_camera(&prepared(&scene)?),
        };
        override_camera(&mut scene, args, camera);
        if framed && (args.eye.is_some() || args.target.is_some()) {
            // The box the framing fitted.
            let (lo, hi) = framed_bounds(prepared(&scene)?.patches.iter().flat_map(|p| p.points));
            if let Some(camera) = scene.camera.as_mut() {
                clip_around(camera, lo, hi);
            }
        }
        if let Some(camera) = scene.camera.as_mut() {
            clip_planes(camera, args)?;
        }
    }
    let prepared = if args.lenient {
        prepare_without_missing_files(&mut scene, &light_origins, prepared)
    } else {
        prepared(&scene).map_err(BoxError::from)
    }
    .map_err(|e| name_light(e, &light_origins))?;
    // What preparing read: models by path (a RIB's are in memory) and
    // height maps.
    if in_memory.is_none() {
        read.extend(scene.model_files().into_iter().map(|p| ("model", p)));
    }
    read.extend(
        scene
            .height_map_files()
            .into_iter()
            .map(|p| ("height map", p)),
    );
    // The shadow maps of the lights that kept theirs.
    read.extend(
        scene
            .shadow_map_files()
            .into_iter()
            .map(|p| (super::requests::SHADOW_MAP_READ, p)),
    );
    // The surface shaders and the textures their parameters name.
    read.extend(
        prepared
            .shaders
            .shaders
            .iter()
            .map(|s| ("surface shader", s.path.clone())),
    );
    read.extend(
        prepared
            .shaders
            .shadow_files
            .iter()
            .map(|(path, _)| (super::requests::SHADOW_MAP_READ, path.clone())),
    );
    read.extend(
        (0..prepared.textures.len() as u32)
            .filter_map(|i| prepared.textures.path(crate::texture::TextureId(i)))
            .map(|p| ("texture", p.to_path_buf())),
    );
    Ok(Prepared {
        scene: prepared,
        read,
    })
}

/// The image and how it is sampled, diced and shaded.
fn override_frame(scene: &mut Scene, args: &RenderArgs) {
    if let Some(width) = args.width {
        scene.resolution.width = width;
    }
    if let Some(height) = args.height {
        scene.resolution.height = height;
    }
    if let Some(spp) = args.spp {
        scene.spp = spp;
    }
    if let Some(sampling) = args.sampling {
        scene.sampling = sampling;
    }
    if let Some(dicing) = args.dicing {
        scene.dicing = dicing;
    }
    if let Some(rate) = args.shading_rate {
        scene.shading_rate = rate;
    }
    if let Some(interpolation) = args.shading_interpolation {
        scene.shading_interpolation = interpolation;
    }
    if args.flat_shading {
        scene.shading_interpolation = ShadingInterpolation::Constant;
    }
    if let Some(tile) = args.interleave_tile {
        scene.interleave_tile = tile;
    }
    if let Some(permutations) = args.interleave_permutations {
        scene.interleave_permutations = permutations;
    }
    if let Some(aov) = args.aov {
        scene.aov = aov;
    }
    if let Some(filter) = args.depth_filter {
        scene.depth_filter = filter;
    }
}

/// Every object's sides and orientation, and the motion `--spin` and
/// `--move` add at shutter close.
fn override_objects(scene: &mut Scene, args: &RenderArgs) {
    for object in &mut scene.objects {
        if let Some(sides) = args.sides {
            object.sides = sides;
        }
        object.reverse_orientation |= args.reverse_orientation;
    }
    if objects_move(args) {
        for object in &mut scene.objects {
            let mut close = object.transform_close.unwrap_or(object.transform);
            close.rotate_degrees.z += args.spin.unwrap_or(0.0);
            close.translate += args.move_by.unwrap_or(Vec3::ZERO);
            object.transform_close = Some(close);
        }
    }
}

/// The shutter (unless `shutter_applied`: an animated frame made with it)
/// and the thin lens.
fn override_lens(scene: &mut Scene, args: &RenderArgs, shutter_applied: bool) {
    if let Some(shutter) = args.shutter.filter(|_| !shutter_applied) {
        scene.shutter = shutter;
    }
    if let Some(aperture) = args.aperture {
        scene.lens.aperture = aperture;
    }
    if let Some(focus) = args.focus {
        scene.lens.focus_distance = Some(focus);
    }
}

/// A bare model or the teapot was framed for 800x600: frames it again for
/// the requested aspect ratio (through the same helper), unless the user
/// places the camera. Scene files (TOML, RIB) keep their own camera.
fn reframe_model(
    scene: &mut Scene,
    args: &RenderArgs,
    in_memory: Option<&[Model]>,
) -> Result<(), BoxError> {
    let is_model = is_bare_model(args);
    let resized = args.width.is_some() || args.height.is_some();
    let moved = objects_move(args);
    if !(is_model && (resized || moved) && scene.camera.is_some()) {
        return Ok(());
    }
    // A bare model is in memory; the teapot is loaded by name.
    let loaded;
    let models = match in_memory {
        Some(models) => models,
        None => {
            loaded = scene.load_models()?;
            &loaded
        }
    };
    if resized {
        let (lo, hi) = models[0].bounds();
        let aspect = scene.resolution.width as f32 / scene.resolution.height.max(1) as f32;
        scene.camera = Some(CameraDesc::framing(lo, hi, aspect));
    }
    // The framing sees the model at open: its far plane must also cover
    // where `--move` and `--spin` take it.
    if let Some(mut camera) = scene.camera.filter(|_| moved && !camera_overridden(args)) {
        camera.far = far_plane_covering_motion(&camera, scene, models);
        scene.camera = Some(camera);
    }
    Ok(())
}

/// Whether the command draws a bare model (or the embedded teapot), whose
/// camera is framed automatically, rather than a scene file.
fn is_bare_model(args: &RenderArgs) -> bool {
    args.scene
        .as_deref()
        .and_then(|p| p.extension())
        .is_none_or(|e| !(e.eq_ignore_ascii_case("toml") || e.eq_ignore_ascii_case("rib")))
}

/// Sets `camera`'s clipping planes around the box `lo..hi` as seen from
/// its eye: `far` beyond the box's bounding sphere, `near` before it (or,
/// with the eye inside the sphere, at `far / 10^4`), so that a camera moved
/// by `--eye` or `--target` still sees what the framing saw.
fn clip_around(camera: &mut CameraDesc, lo: Vec3, hi: Vec3) {
    let centre = lo * 0.5 + hi * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let distance = (camera.eye - centre).length();
    let far = (distance + radius) * 1.05 + 1e-3;
    let near = if distance > radius {
        ((distance - radius) * 0.5).max(far * 1e-4)
    } else {
        far * 1e-4
    };
    if near.is_finite() && far.is_finite() && near < far {
        camera.near = near;
        camera.far = far;
    }
}

/// The description of the camera `prepared` framed automatically.
fn framed_camera(prepared: &PreparedScene) -> CameraDesc {
    let framed = prepared.camera;
    CameraDesc {
        eye: framed.eye,
        target: framed.target,
        up: framed.up,
        fov_y_degrees: framed.fov_y_radians.to_degrees(),
        near: framed.near,
        far: framed.far,
        projection: framed.projection,
        ortho_height: (!framed.projection.is_perspective()).then_some(framed.ortho_height),
    }
}

/// `camera` with the command line's placement, and its pose at shutter
/// close when the command line moves it.
fn override_camera(scene: &mut Scene, args: &RenderArgs, camera: CameraDesc) {
    let camera = CameraDesc {
        eye: args.eye.unwrap_or(camera.eye),
        target: args.target.unwrap_or(camera.target),
        up: args.up.unwrap_or(camera.up),
        fov_y_degrees: args.fov.unwrap_or(camera.fov_y_degrees),
        ..camera
    };
    scene.camera = Some(camera);
    if camera_moves(args) {
        let by = args.camera_move.unwrap_or(Vec3::ZERO);
        scene.camera_close = Some(camera.moved(by, args.camera_pan.unwrap_or(0.0)));
    }
}

/// Whether the command line places the camera or its clipping planes.
fn camera_overridden(args: &RenderArgs) -> bool {
    args.eye.is_some()
        || args.target.is_some()
        || args.up.is_some()
        || args.fov.is_some()
        || args.near.is_some()
        || args.far.is_some()
}

/// `--near` and `--far` on `camera`, checked against each other and
/// against the plane the command line leaves as it is.
fn clip_planes(camera: &mut CameraDesc, args: &RenderArgs) -> Result<(), BoxError> {
    let near = args.near.unwrap_or(camera.near);
    let far = args.far.unwrap_or(camera.far);
    if let Some(near) = args.near.filter(|n| !(n.is_finite() && *n > 0.0)) {
        return Err(format!("--near {near}: must be a finite distance > 0").into());
    }
    if !(far.is_finite() && far > near) {
        let which = match (args.near, args.far) {
            (_, Some(_)) => format!("--far {far}"),
            _ => format!("--near {near}"),
        };
        return Err(format!(
            "{which}: the far plane ({far}) must be finite and beyond the near plane ({near})"
        )
        .into());
    }
    camera.near = near;
    camera.far = far;
    Ok(())
}

/// Whether the command line moves the camera during the shutter.
fn camera_moves(args: &RenderArgs) -> bool {
    args.camera_move.is_some() || args.camera_pan.is_some()
}

/// Whether the command line moves the objects during the shutter.
fn objects_move(args: &RenderArgs) -> bool {
    args.spin.is_some() || args.move_by.is_some()
}

/// Prepares `scene` under `--lenient`: an object whose shader reads a
/// texture file that is missing loses that shader (a surface falls back to
/// RenderMan's `defaultsurface`, which shows the object's colour without
/// lights; a displacement is dropped), and a light whose shadow map file is missing loses its shadow
/// (it lights unshadowed), each with a warning naming the object or light
/// and the file, instead of failing the run. Any other error still fails
/// it.
fn prepare_without_missing_files(
    scene: &mut Scene,
    light_origins: &[String],
    prepared: impl Fn(&Scene) -> Result<PreparedScene, crate::scene::SceneError>,
) -> Result<PreparedScene, BoxError> {
    use crate::displacement::DisplacementError;
    use crate::scene::SceneError;
    use crate::surface_shader::SurfaceShaderError;
    use crate::texture::TextureError;
    let missing = |error: &SurfaceShaderError| {
        matches!(
            error,
            SurfaceShaderError::Texture {
                source: TextureError::Missing { .. },
                ..
            }
        )
    };
    // Each round drops one shader of one object or one light's shadow:
    // bounded by their number.
    for _ in 0..=2 * scene.objects.len() + scene.lights.len() {
        match prepared(scene) {
            Err(SceneError::ShadowMap {
                light,
                kind,
                path,
                source,
            }) if !path.exists() && scene.lights[light].shadow.is_some() => {
                let at = light_origins
                    .get(light)
                    .map_or_else(String::new, |origin| format!("{origin}: "));
                errln!(
                    "warning: {at}lights[{light}] ({kind} light): shadow map {} is missing ({source}); --lenient renders the light unshadowed",
                    path.display()
                )?;
                scene.lights[light].shadow = None;
            }
            Err(SceneError::SurfaceShader {
                index,
                file,
                source,
            }) if missing(&source) => {
                errln!(
                    "warning: object {index}: surface shader {}: {source}; --lenient renders the object in its colour with RenderMan's defaultsurface",
                    file.display()
                )?;
                // The headlight shading needs no light, so the object shows
                // in its colour whatever the scene's lights and ambient
                // term (a RIB scene's is 0).
                scene.objects[index].surface = Some(Surface::DEFAULT_SURFACE);
            }
            Err(SceneError::Displacement {
                index,
                source: DisplacementError::Shader { file, source },
                ..
            }) if missing(&source) => {
                errln!(
                    "warning: object {index}: displacement shader {}: {source}; --lenient renders the object undisplaced",
                    file.display()
                )?;
                scene.objects[index].displacement = None;
            }
            other => return Ok(other?),
        }
    }
    Ok(prepared(scene)?)
}

/// `error`, headed by where its light was declared when it is about a
/// light's shadow map and the scene says where its lights come from (a
/// RIB's `LightSource` line).
fn name_light(error: BoxError, light_origins: &[String]) -> BoxError {
    let origin = match error.downcast_ref::<crate::scene::SceneError>() {
        Some(crate::scene::SceneError::ShadowMap { light, .. }) => light_origins.get(*light),
        _ => None,
    };
    match origin {
        Some(origin) => format!("{origin}: {error}").into(),
        None => error,
    }
}
