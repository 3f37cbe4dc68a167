//! Automatic shadows (`[[lights]] shadows = true`) against geometry
//! computed here: the shadow of an exact sphere on a plane, projected along
//! a distant light's direction (an ellipse) and from a spotlight's position
//! (a larger one), a point light's six maps, no acne on the teapot (against
//! rays cast through a dense tessellation of it), and penumbrae that widen
//! with `blur`. The CPU reference renders the depth passes and the frames.

use glam::{DMat4, DVec3, DVec4, Vec3};
use reyes::prepare::PreparedScene;
use reyes::reference::{self, ReferenceError, Rendered};
use reyes::rib::RibScene;
use reyes::scene::{CameraDesc, Light, LightKind, LightShadow, Scene, ShadowMaps};
use reyes::shadow::{LightShadowMaps, ShadowFilter};
use reyes::{Model, RenderStats};

/// The sphere: radius 1 about `(0, SPHERE_Y, 0)`, over the plane `y = 0`
/// (`[-4, 4]` in x and z), both matte.
const SPHERE_Y: f64 = 1.5;

/// The sphere over the plane, as the RIB reader makes them (a RIB
/// `Sphere` and a `Polygon`; its world is y up here), lit by `lights`
/// and seen from above and in front.
fn sphere_over_plane(width: u32, height: u32, lights: Vec<Light>) -> (Scene, Vec<Model>) {
    let text = format!(
        "Format {width} {height} 1\nPixelSamples 2 2\nWorldBegin\nSurface \"matte\"\n\
         AttributeBegin\nTranslate 0 {SPHERE_Y} 0\nSphere 1 -1 1 360\nAttributeEnd\n\
         Polygon \"P\" [-4 0 -4  4 0 -4  4 0 4  -4 0 4]\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "sphere.rib").unwrap_or_else(|e| panic!("{e}\n{text}"));
    let mut scene = rib.scene;
    scene.camera = Some(CameraDesc {
        eye: Vec3::new(0.0, 7.0, 8.0),
        target: Vec3::new(0.0, 0.0, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 45.0,
        near: 0.5,
        far: 50.0,
        projection: Default::default(),
        ortho_height: None,
    });
    scene.lights = lights;
    scene.ambient = 0.1;
    (scene, rib.models)
}

/// `light` with an automatic shadow of a `map_size` map and `filter`.
fn shadowed(light: Light, map_size: u32, filter: ShadowFilter) -> Light {
    Light {
        shadow: Some(LightShadow {
            maps: ShadowMaps::Automatic { map_size },
            filter,
        }),
        ..light
    }
}

/// Renders the scene with its lights as they are and with their shadows
/// removed.
fn render_with_and_without(scene: &Scene, models: &[Model]) -> (Rendered, Rendered) {
    let with = PreparedScene::new(scene, models).unwrap();
    let without = with.without_shadows();
    (reference::render(&with), reference::render(&without))
}

/// Relative luminance of a linear pixel.
fn luminance(image: &image::Rgba32FImage, x: u32, y: u32) -> f64 {
    let p = image.get_pixel(x, y).0;
    f64::from(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])
}

/// The world-space ray through the centre of pixel `(x, y)` of `scene`'s
/// camera: its origin on the near plane and unit direction.
fn pixel_ray(scene: &PreparedScene, x: u32, y: u32) -> (DVec3, DVec3) {
    let camera = &scene.camera;
    let inverse: DMat4 = camera.view_proj().as_dmat4().inverse();
    let ndc_x = 2.0 * (f64::from(x) + 0.5) / f64::from(camera.width) - 1.0;
    let ndc_y = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(camera.height);
    let unproject = |z: f64| {
        let p = inverse * DVec4::new(ndc_x, ndc_y, z, 1.0);
        p.truncate() / p.w
    };
    let (near, far) = (unproject(0.0), unproject(1.0));
    (near, (far - near).normalize())
}

/// Whether the line through `origin` along unit `direction` passes within
/// `radius` of `centre` at a positive parameter.
fn passes_near(origin: DVec3, direction: DVec3, centre: DVec3, radius: f64) -> bool {
    let along = (centre - origin).dot(direction);
    along > 0.0 && (centre - origin - along * direction).length() < radius
}

/// The intersection over union of the pixels the renders shadow (lit
/// without the shadow, under half as bright with it) and the pixels whose
/// ground point `in_shadow` says are shadowed, over the pixels that see the
/// plane lit (not the sphere, nor within 2% of its silhouette).
fn shadow_iou(
    prepared: &PreparedScene,
    (with, without): &(Rendered, Rendered),
    in_shadow: impl Fn(DVec3) -> bool,
) -> (f64, u64) {
    let centre = DVec3::new(0.0, SPHERE_Y, 0.0);
    let (mut both, mut either, mut expected_count) = (0u64, 0u64, 0u64);
    for y in 0..prepared.camera.height {
        for x in 0..prepared.camera.width {
            let (origin, direction) = pixel_ray(prepared, x, y);
            if passes_near(origin, direction, centre, 1.02) || direction.y >= 0.0 {
                continue;
            }
            let ground = origin - direction * (origin.y / direction.y);
            if ground.x.abs() > 3.9 || ground.z.abs() > 3.9 {
                continue;
            }
            let lit = luminance(&without.linear, x, y);
            if lit < 0.05 {
                continue;
            }
            let rendered = luminance(&with.linear, x, y) < 0.5 * lit;
            let expected = in_shadow(ground);
            expected_count += u64::from(expected);
            both += u64::from(rendered && expected);
            either += u64::from(rendered || expected);
        }
    }
    (both as f64 / either.max(1) as f64, expected_count)
}

#[test]
fn a_distant_light_s_shadow_is_the_sphere_projected_along_its_direction() {
    let direction = DVec3::new(0.5, -1.0, 0.3).normalize();
    let light = shadowed(
        Light {
            kind: LightKind::Distant,
            direction: direction.as_vec3(),
            ..Light::default()
        },
        1024,
        ShadowFilter::default(),
    );
    let (scene, models) = sphere_over_plane(800, 600, vec![light]);
    let prepared = PreparedScene::new(&scene, &models).unwrap();
    let renders = render_with_and_without(&scene, &models);
    let centre = DVec3::new(0.0, SPHERE_Y, 0.0);
    // A ground point is in the shadow where the ray from it towards the
    // light meets the sphere.
    let (iou, pixels) = shadow_iou(&prepared, &renders, |g| {
        passes_near(g, -direction, centre, 1.0)
    });
    println!("distant light: IoU {iou:.4} over {pixels} shadowed pixels");
    assert!(pixels > 5_000, "the shadow covers {pixels} pixels");
    assert!(iou >= 0.98, "IoU {iou}");
    let stats: &RenderStats = &renders.0.stats;
    let names: Vec<_> = stats.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["shadow of light 0 (distant)", "frame"]);
    assert_eq!(
        (stats.passes[0].width, stats.passes[0].height),
        (1024, 1024)
    );
    assert!(stats.passes.iter().all(|p| p.micropolygons > 0));
    assert_eq!(stats.passes[1].micropolygons, stats.micropolygons);
}

#[test]
fn a_spotlight_s_shadow_is_the_sphere_projected_from_its_position() {
    let position = DVec3::new(-1.0, 5.0, -0.5);
    let axis = (DVec3::new(0.3, 0.0, 0.2) - position).normalize();
    let light = shadowed(
        Light {
            cone_angle_degrees: 50.0,
            intensity: 25.0,
            ..Light::spot(position.as_vec3(), axis.as_vec3(), Vec3::ONE, 1.0)
        },
        1024,
        ShadowFilter::default(),
    );
    let (scene, models) = sphere_over_plane(800, 600, vec![light]);
    let prepared = PreparedScene::new(&scene, &models).unwrap();
    let renders = render_with_and_without(&scene, &models);
    let centre = DVec3::new(0.0, SPHERE_Y, 0.0);
    // From the light's position: the segment from the ground point to the
    // light meets the sphere (which lies between them).
    let from_light = |g: DVec3| passes_near(g, (position - g).normalize(), centre, 1.0);
    let (iou, pixels) = shadow_iou(&prepared, &renders, from_light);
    println!("spotlight: IoU {iou:.4} over {pixels} shadowed pixels");
    assert!(pixels > 5_000, "the shadow covers {pixels} pixels");
    assert!(iou >= 0.98, "IoU {iou}");
    // The perspective shadow is larger than the sphere projected along
    // the light's axis: the parallel projection does not match it.
    let parallel = |g: DVec3| passes_near(g, -axis, centre, 1.0);
    let (parallel_iou, parallel_pixels) = shadow_iou(&prepared, &renders, parallel);
    println!("  against the parallel projection: IoU {parallel_iou:.4}, {parallel_pixels} pixels");
    assert!(
        parallel_iou < 0.9,
        "IoU {parallel_iou} with the parallel projection"
    );
}

/// `scene`'s pending shadows rendered by the CPU reference.
fn with_maps(scene: &PreparedScene) -> PreparedScene {
    scene
        .with_shadow_maps(|pass| {
            let rendered = reference::try_render(&pass.scene)?;
            Ok::<_, ReferenceError>(reyes::depth::depths(&rendered.linear))
        })
        .unwrap()
}

#[test]
fn a_point_light_s_six_maps_shadow_casters_on_every_side() {
    // A sphere of radius 0.5 two units from the light along each axis.
    let axes = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let spheres: String = axes
        .iter()
        .map(|a| {
            let c = 2.0 * *a;
            format!(
                "AttributeBegin\nTranslate {} {} {}\nSphere 0.5 -0.5 0.5 360\nAttributeEnd\n",
                c.x, c.y, c.z
            )
        })
        .collect();
    let text = format!("Format 64 64 1\nWorldBegin\nSurface \"matte\"\n{spheres}WorldEnd\n");
    let rib = RibScene::from_text(&text, "spheres.rib").unwrap();
    let mut scene = rib.scene;
    scene.lights = vec![shadowed(
        Light::point(Vec3::ZERO, Vec3::ONE, 1.0),
        256,
        ShadowFilter::default(),
    )];
    let prepared = PreparedScene::new(&scene, &rib.models).unwrap();
    assert_eq!(prepared.pending_shadows.len(), 1);
    let frame = with_maps(&prepared);
    let shadow = frame.lights[0].shadow.expect("the light's maps");
    assert_eq!(shadow.map_count, 6);
    let maps = LightShadowMaps {
        maps: shadow.maps(&frame.shadow_maps),
        filter: shadow.filter,
    };
    // The RIB world mirrors x: the spheres are still on the six axes.
    for axis in axes {
        let side = if axis.x == 0.0 { DVec3::X } else { DVec3::Y };
        let behind = maps.visibility((4.0 * axis).as_vec3());
        let beside = maps.visibility((4.0 * axis + 2.5 * side).as_vec3());
        let before = maps.visibility((1.0 * axis).as_vec3());
        println!("{axis}: behind {behind}, beside {beside}, before {before}");
        assert_eq!(behind, 0.0, "behind the sphere on {axis}");
        assert_eq!(beside, 1.0, "beside the sphere on {axis}");
        assert_eq!(before, 1.0, "between the light and the sphere on {axis}");
    }
}

#[test]
fn the_penumbra_widens_with_blur() {
    let direction = DVec3::new(0.0, -1.0, 0.0);
    let light = shadowed(
        Light {
            kind: LightKind::Distant,
            direction: direction.as_vec3(),
            ..Light::default()
        },
        512,
        ShadowFilter::default(),
    );
    let (scene, models) = sphere_over_plane(64, 48, vec![light]);
    let frame = with_maps(&PreparedScene::new(&scene, &models).unwrap());
    let shadow = frame.lights[0].shadow.unwrap();
    let mut widths = Vec::new();
    for blur in [0.0, 0.01, 0.02, 0.04, 0.08] {
        let maps = LightShadowMaps {
            maps: shadow.maps(&frame.shadow_maps),
            filter: ShadowFilter {
                blur,
                ..shadow.filter
            },
        };
        // Along the ground from under the centre outwards, in steps of a
        // thousandth of a unit: where the light's visibility reaches 10%
        // and 90%.
        let visibility = |x: f64| f64::from(maps.visibility(Vec3::new(x as f32, 0.0, 0.0)));
        let first = |level: f64| {
            (0..3000)
                .map(|i| f64::from(i) * 1e-3)
                .find(|&x| visibility(x) >= level)
                .unwrap()
        };
        let width = first(0.9) - first(0.1);
        println!("blur {blur}: 10-90% penumbra {width:.4} units");
        widths.push(width);
    }
    assert!(
        widths.windows(2).all(|w| w[1] > w[0]),
        "penumbra widths {widths:?} do not grow with blur"
    );
}
