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

/// A distant light along `direction` with an automatic shadow of a
/// `map_size` map and the default filter.
fn shadowed_distant(direction: Vec3, map_size: u32) -> Light {
    shadowed(
        Light {
            kind: LightKind::Distant,
            direction,
            ..Light::default()
        },
        map_size,
        ShadowFilter::default(),
    )
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
    let light = shadowed_distant(direction.as_vec3(), 1024);
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
    let light = shadowed_distant(direction.as_vec3(), 512);
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

/// A dense tessellation of patches for casting rays towards a distant
/// light: triangles binned by where they fall on a plane across the
/// light's direction, so that a ray along it (which projects to one point
/// there) tests only the triangles of its cell.
struct Occluders {
    triangles: Vec<[DVec3; 3]>,
    /// The plane's axes, across the direction towards the light.
    axes: [DVec3; 2],
    lo: [f64; 2],
    cell: f64,
    side: usize,
    cells: Vec<Vec<usize>>,
}

impl Occluders {
    /// Each patch of `scene` evaluated on an `n x n` grid of quads, two
    /// triangles each; rays go along `to_light`.
    fn new(scene: &PreparedScene, n: usize, to_light: DVec3) -> Occluders {
        let mut triangles = Vec::new();
        for patch in &scene.patches {
            let at = |i: usize, j: usize| {
                let (s, t) = (i as f32 / n as f32, j as f32 / n as f32);
                reyes::bezier::position(&patch.points, s, t).as_dvec3()
            };
            for j in 0..n {
                for i in 0..n {
                    let [a, b, c, d] = [at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)];
                    triangles.push([a, b, d]);
                    triangles.push([a, d, c]);
                }
            }
        }
        let u = to_light.any_orthonormal_vector();
        let axes = [u, to_light.cross(u)];
        let project = |p: DVec3| [p.dot(axes[0]), p.dot(axes[1])];
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in triangles.iter().flatten() {
            let q = project(*p);
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let side = 256;
        let cell = (hi[0] - lo[0]).max(hi[1] - lo[1]) / side as f64 * 1.001;
        let mut cells = vec![Vec::new(); side * side];
        let index =
            |v: f64, k: usize| (((v - lo[k]) / cell).floor().max(0.0) as usize).min(side - 1);
        for (t, triangle) in triangles.iter().enumerate() {
            let q = triangle.map(project);
            let (x0, x1) = (
                q.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min),
                q.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max),
            );
            let (y0, y1) = (
                q.iter().map(|q| q[1]).fold(f64::INFINITY, f64::min),
                q.iter().map(|q| q[1]).fold(f64::NEG_INFINITY, f64::max),
            );
            for y in index(y0, 1)..=index(y1, 1) {
                for x in index(x0, 0)..=index(x1, 0) {
                    cells[y * side + x].push(t);
                }
            }
        }
        Occluders {
            triangles,
            axes,
            lo,
            cell,
            side,
            cells,
        }
    }

    /// Whether the ray from `origin` along the light's direction meets a
    /// triangle further than `start` from it (Moller-Trumbore).
    fn blocked(&self, origin: DVec3, to_light: DVec3, start: f64) -> bool {
        let q = [origin.dot(self.axes[0]), origin.dot(self.axes[1])];
        let index = |k: usize| ((q[k] - self.lo[k]) / self.cell).floor();
        let (x, y) = (index(0), index(1));
        if x < 0.0 || y < 0.0 || x >= self.side as f64 || y >= self.side as f64 {
            return false;
        }
        self.cells[y as usize * self.side + x as usize]
            .iter()
            .any(|&t| {
                let [a, b, c] = self.triangles[t];
                let (e1, e2) = (b - a, c - a);
                let p = to_light.cross(e2);
                let det = e1.dot(p);
                if det.abs() < 1e-14 {
                    return false;
                }
                let s = origin - a;
                let u = s.dot(p) / det;
                let qv = s.cross(e1);
                let v = to_light.dot(qv) / det;
                let t = e2.dot(qv) / det;
                (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && t > start
            })
    }
}

#[test]
fn the_teapot_under_a_low_distant_light_has_no_acne() {
    let mut scene = Scene::default_teapot();
    // The default light's azimuth at 30 degrees above the horizon (z up).
    let default = scene.lights[0].direction.as_dvec3();
    let across = DVec3::new(default.x, default.y, 0.0).normalize();
    let elevation = 30f64.to_radians();
    let direction = across * elevation.cos() - DVec3::Z * elevation.sin();
    scene.lights = vec![shadowed_distant(direction.as_vec3(), 1024)];
    let prepared = PreparedScene::load(&scene).unwrap();
    let with = reference::render(&prepared);
    let without = reference::render(&prepared.without_shadows());
    // Each pixel's surface point: its depth (the nearest sample's) along
    // the ray through its centre.
    let depths = reference::render(&PreparedScene {
        aov: reyes::Aov::Z,
        ..prepared.without_shadows()
    });
    let camera = &prepared.camera;
    let forward = (camera.target - camera.eye).normalize().as_dvec3();
    let to_light = -direction;
    let teapot = Occluders::new(&prepared, 24, to_light);
    let passes = reyes::prepare::depth_passes(&prepared);
    let map_camera = &passes[0].scene.camera;
    let texel = f64::from(map_camera.ortho_height) / f64::from(map_camera.height);
    let (width, height) = (camera.width, camera.height);
    let full = prepared.spp as u16;
    // The pixels whose surface point the teapot itself hides from the
    // light, grown by two pixels (where the pixel's colour mixes its
    // neighbours').
    let mut occluded = vec![false; (width * height) as usize];
    let mut surface = vec![None; (width * height) as usize];
    let mut contact = vec![false; (width * height) as usize];
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            if depths.covered_samples[i] != full {
                continue;
            }
            let depth = f64::from(depths.linear.get_pixel(x, y).0[0]);
            let direction = pixel_ray(&prepared, x, y).1;
            let point = camera.eye.as_dvec3() + direction * (depth / direction.dot(forward));
            surface[i] = Some(point);
            // Where the teapot nearly touches itself (the lid in the body's
            // opening, the spout's tip), an occluder within 0.02 of the
            // point is a contact shadow, not one the offset start can tell
            // from the point's own surface: those points are not checked.
            // Within two of the map's texels (across the light) of a true
            // shadow, the filter's width and the texels' size blur the
            // edge: those points are not checked either.
            occluded[i] = teapot.blocked(point, to_light, 0.02);
            contact[i] = !occluded[i]
                && (teapot.blocked(point, to_light, 0.002)
                    || teapot.axes.iter().any(|&axis| {
                        [-2.0, 2.0]
                            .iter()
                            .any(|&k| teapot.blocked(point + k * texel * axis, to_light, 0.02))
                    }));
        }
    }
    let grown: Vec<bool> = (0..i64::from(height))
        .flat_map(|y| (0..i64::from(width)).map(move |x| (x, y)))
        .map(|(x, y)| {
            (-2..=2).any(|dy| {
                (-2..=2).any(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    (0..i64::from(width)).contains(&nx)
                        && (0..i64::from(height)).contains(&ny)
                        && occluded[(ny * i64::from(width) + nx) as usize]
                })
            })
        })
        .collect();
    // A pixel at a depth discontinuity (a silhouette over another part of
    // the teapot) or at a crease (the spout's lip) mixes two surfaces'
    // colours under one surface point: not checked.
    let normals = reference::render(&PreparedScene {
        aov: reyes::Aov::Normal,
        ..prepared.without_shadows()
    })
    .linear;
    let at_edge = |x: u32, y: u32| {
        let here = surface[(y * width + x) as usize];
        let normal = |x, y| glam::Vec4::from(normals.get_pixel(x, y).0).truncate();
        [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().any(|&(dx, dy)| {
            let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
            if !(0..i64::from(width)).contains(&nx) || !(0..i64::from(height)).contains(&ny) {
                return true;
            }
            let turn = (normal(x, y) - normal(nx as u32, ny as u32))
                .abs()
                .max_element();
            match (here, surface[(ny * i64::from(width) + nx) as usize]) {
                // A normal component changing by more than 0.3 per pixel.
                (Some(a), Some(b)) => a.distance(b) > 0.1 || turn > 0.15,
                _ => true,
            }
        })
    };
    let (mut checked, mut darker, mut shadowed) = (0, Vec::new(), 0);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            if surface[i].is_none() {
                continue;
            }
            shadowed += usize::from(occluded[i]);
            if grown[i] || contact[i] || at_edge(x, y) {
                continue;
            }
            checked += 1;
            let (lit, shaded) = (
                luminance(&without.linear, x, y),
                luminance(&with.linear, x, y),
            );
            if shaded < 0.9 * lit {
                darker.push((x, y, shaded / lit));
            }
        }
    }
    println!(
        "{checked} pixels checked, {shadowed} truly shadowed, {} more than 10% darker: {:?}",
        darker.len(),
        &darker[..darker.len().min(10)]
    );
    assert!(
        checked > 50_000 && shadowed > 1_000,
        "{checked} checked, {shadowed} shadowed"
    );
    // Acne darkens lit surfaces all over; two pixels at the spout's lip
    // (where a micropolygon spans the lip's shadow edge) are darker by up
    // to 20% at this resolution: a few in ten thousand are allowed.
    assert!(
        darker.len() <= checked / 10_000,
        "{} of {checked} pixels darker than the unshadowed render",
        darker.len()
    );
}

/// A distant light from above and to the side, shadowed by a `map_size` map.
fn distant_from_above(map_size: u32) -> Light {
    shadowed_distant(Vec3::new(0.5, -1.0, 0.3), map_size)
}

#[test]
fn a_map_too_large_for_the_cpu_names_its_pass_and_the_map_size() {
    let (scene, models) = sphere_over_plane(64, 48, vec![distant_from_above(8192)]);
    let prepared = PreparedScene::new(&scene, &models).unwrap();
    let Err(error) = reference::try_render(&prepared) else {
        panic!("a map of 8192^2 renders on the CPU")
    };
    let message = error.to_string();
    println!("{message}");
    assert!(
        matches!(&error, ReferenceError::DepthPassTooLarge { pass, width: 8192, .. }
            if pass == "shadow of light 0 (distant)"),
        "{error:?}"
    );
    assert!(
        message.contains("map_size") && !message.contains("--width"),
        "{message}"
    );
}

#[test]
fn the_samples_of_a_frame_with_pending_shadows_are_shadowed() {
    let (scene, models) = sphere_over_plane(80, 60, vec![distant_from_above(256)]);
    let prepared = PreparedScene::new(&scene, &models).unwrap();
    let options = reyes::ReferenceOptions::default();
    let (with, _) = reference::try_render_samples(&prepared, &options).unwrap();
    let (without, _) =
        reference::try_render_samples(&prepared.without_shadows(), &options).unwrap();
    let changed = with
        .keys
        .iter()
        .zip(&without.keys)
        .filter(|(a, b)| a != b)
        .count();
    println!("{changed} of {} samples differ", with.keys.len());
    assert!(changed > with.keys.len() / 100, "{changed} samples differ");
}

/// A caster moving during the shutter leaves a partial shadow along its
/// path: the depth pass samples the shutter one time per texel, and the
/// filtered lookup turns the dithered trail into the fraction of the
/// shutter each ground point spends in the shadow. Here a sphere of radius
/// 1 slides from x = -1 to x = 1 (1.5 above the plane) under a distant
/// light at 45 degrees: a ground point is shadowed while the ray from it
/// towards the light passes within 1 of the sphere's centre, for a
/// fraction of the shutter computed here by sampling the path. With no
/// ambient light, the shadowed frame over the unshadowed one is the rest.
/// A depth pass at shutter open alone would put a hard ellipse about
/// x = -1 instead.
#[test]
fn a_moving_caster_leaves_a_partial_shadow_along_its_path() {
    let text = "Format 400 300 1\nPixelSamples 4 4\nShutter 0 1\nWorldBegin\nSurface \"matte\"\n\
                AttributeBegin\nColor [0.9 0.9 0.9]\n\
                MotionBegin [0 1]\nTranslate -1 1.5 0\nTranslate 1 1.5 0\nMotionEnd\n\
                Sphere 1 -1 1 360\nAttributeEnd\n\
                Polygon \"P\" [-4 0 -4  4 0 -4  4 0 4  -4 0 4]\nWorldEnd\n";
    let rib = RibScene::from_text(text, "moving.rib").unwrap_or_else(|e| panic!("{e}"));
    let mut scene = rib.scene;
    assert_eq!(scene.objects.len(), 2, "the sphere and the plane");
    scene.camera = Some(CameraDesc {
        eye: Vec3::new(0.0, 8.0, 8.0),
        target: Vec3::new(0.0, 0.0, 1.0),
        up: Vec3::Y,
        fov_y_degrees: 40.0,
        near: 0.5,
        far: 50.0,
        projection: Default::default(),
        ortho_height: None,
    });
    scene.ambient = 0.0;
    let direction = DVec3::new(0.0, -1.0, 1.0).normalize();
    scene.lights = vec![shadowed_distant(direction.as_vec3(), 1024)];
    let prepared = PreparedScene::new(&scene, &rib.models).unwrap();
    let (with, without) = render_with_and_without(&scene, &rib.models);
    let centre_at = |t: f64| DVec3::new(-1.0 + 2.0 * t, SPHERE_Y, 0.0);
    const STEPS: u32 = 200;
    // Per tenth of the expected visibility: pixels and their rendered sum.
    let mut bins = [(0u64, 0.0f64); 10];
    let (mut partial, mut error_sum, mut clear, mut clear_dark) = (0u64, 0.0f64, 0u64, 0u64);
    for y in 0..prepared.camera.height {
        for x in 0..prepared.camera.width {
            let (origin, direction_to_pixel) = pixel_ray(&prepared, x, y);
            if direction_to_pixel.y >= 0.0 {
                continue;
            }
            let ground = origin - direction_to_pixel * (origin.y / direction_to_pixel.y);
            if ground.x.abs() > 3.8 || ground.z.abs() > 3.8 {
                continue;
            }
            // Leave out the pixels that see the moving sphere at any time.
            let seen = (0..=STEPS / 10).any(|k| {
                passes_near(
                    origin,
                    direction_to_pixel,
                    centre_at(f64::from(k) * 10.0 / f64::from(STEPS)),
                    1.1,
                )
            });
            let lit = luminance(&without.linear, x, y);
            if seen || lit < 0.05 {
                continue;
            }
            let visible = luminance(&with.linear, x, y) / lit;
            let shadowed_steps = (0..STEPS)
                .filter(|&k| {
                    let t = (f64::from(k) + 0.5) / f64::from(STEPS);
                    passes_near(ground, -direction, centre_at(t), 1.0)
                })
                .count();
            let expected = 1.0 - shadowed_steps as f64 / f64::from(STEPS);
            let bin = &mut bins[((expected * 10.0) as usize).min(9)];
            bin.0 += 1;
            bin.1 += visible;
            if expected == 1.0 {
                // Clear of the path, with a margin for the filter.
                let near_path = (0..=STEPS / 10).any(|k| {
                    passes_near(
                        ground,
                        -direction,
                        centre_at(f64::from(k) * 10.0 / f64::from(STEPS)),
                        1.15,
                    )
                });
                if !near_path {
                    clear += 1;
                    clear_dark += u64::from(visible < 0.9);
                }
            } else if expected > 0.02 && expected < 0.98 {
                partial += 1;
                error_sum += (visible - expected).abs();
            }
        }
    }
    let mean_error = error_sum / partial.max(1) as f64;
    for (i, (count, sum)) in bins.iter().enumerate() {
        if *count > 0 {
            println!(
                "expected visibility {:.1}-{:.1}: {count} pixels, rendered mean {:.3}",
                i as f64 / 10.0,
                (i + 1) as f64 / 10.0,
                sum / *count as f64
            );
        }
    }
    println!(
        "moving caster: {partial} partly shadowed pixels, mean |visible - expected| {mean_error:.4}; \
         {clear_dark} of {clear} clear pixels darker than 0.9"
    );
    assert!(partial > 3_000, "{partial} partly shadowed pixels");
    assert!(mean_error < 0.12, "mean error {mean_error}");
    // The rendered visibility follows the expected one, bin by bin.
    for (i, (count, sum)) in bins.iter().enumerate() {
        if *count > 200 {
            let mean = sum / *count as f64;
            let centre = (i as f64 + 0.5) / 10.0;
            assert!((mean - centre).abs() < 0.05, "bin {i}: mean {mean}");
        }
    }
    assert!(clear > 10_000 && clear_dark == 0, "{clear_dark} of {clear}");
}
