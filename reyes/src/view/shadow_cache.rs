//! The viewer's shadow maps: a frame with automatic shadows
//! (`shadows = true`) renders its depth passes once, and later frames
//! reuse the maps while nothing they depend on changes. Only the camera
//! moves in the viewer; the maps depend on the scene, its lights and the
//! settings that change how the passes dice and sample (dicing, sampling,
//! motion blur), which are their key.

use std::time::Instant;

use crate::prepare::PreparedScene;
use crate::scene::{Dicing, Sampling};
use crate::shading::PreparedLight;
use crate::shadow::ShadowMap;

use super::controls::Settings;

/// What the depth passes depend on besides the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ShadowKey {
    sampling: Sampling,
    dicing: Dicing,
    shading_rate: f32,
    dice_threshold: f32,
    motion_blur: bool,
}

impl ShadowKey {
    fn of(settings: &Settings) -> ShadowKey {
        ShadowKey {
            sampling: settings.sampling,
            dicing: settings.dicing,
            shading_rate: settings.shading_rate,
            dice_threshold: settings.dice_threshold,
            motion_blur: settings.motion_blur,
        }
    }
}

/// The maps of the last passes and what they were rendered for.
#[derive(Debug, Clone)]
struct Cached {
    key: ShadowKey,
    lights: Vec<PreparedLight>,
    maps: Vec<ShadowMap>,
    passes_ms: f64,
}

/// The time the maps of a frame took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowTime {
    /// Wall time of the depth passes, in milliseconds.
    pub passes_ms: f64,
    /// Whether the frame reused maps rendered for an earlier one (the
    /// time is theirs).
    pub reused: bool,
}

/// The viewer's shadow maps, kept between frames.
#[derive(Debug, Clone, Default)]
pub struct ShadowCache {
    cached: Option<Cached>,
}

impl ShadowCache {
    /// Gives `frame` (the view's scene, [`super::worker::scene_for`]) its
    /// shadow maps: those kept when they were rendered with the same
    /// `settings`, else the depth passes rendered now by `render` (a
    /// depth frame to its depths, as [`PreparedScene::with_shadow_maps`]
    /// takes it). `None` for a frame without pending shadows.
    pub fn apply<E>(
        &mut self,
        frame: &mut PreparedScene,
        settings: &Settings,
        mut render: impl FnMut(&PreparedScene) -> Result<Vec<f32>, E>,
    ) -> Result<Option<ShadowTime>, E> {
        if frame.pending_shadows.is_empty() {
            return Ok(None);
        }
        let key = ShadowKey::of(settings);
        let reused = self.cached.as_ref().is_some_and(|c| c.key == key);
        if !reused {
            let start = Instant::now();
            let shadowed = frame.with_shadow_maps(|pass| render(&pass.scene))?;
            self.cached = Some(Cached {
                key,
                lights: shadowed.lights,
                maps: shadowed.shadow_maps,
                passes_ms: start.elapsed().as_secs_f64() * 1e3,
            });
        }
        let cached = self.cached.as_ref().expect("kept above");
        frame.lights.clone_from(&cached.lights);
        frame.shadow_maps.clone_from(&cached.maps);
        frame.pending_shadows.clear();
        Ok(Some(ShadowTime {
            passes_ms: cached.passes_ms,
            reused,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LightShadow, Scene, ShadowMaps};
    use crate::view::worker::settings_of;

    #[test]
    fn maps_are_rendered_once_and_again_only_when_the_passes_change() {
        let mut scene = Scene::default_teapot();
        scene.resolution.width = 64;
        scene.resolution.height = 48;
        scene.lights[0].shadow = Some(LightShadow {
            maps: ShadowMaps::Automatic { map_size: 32 },
            filter: Default::default(),
        });
        let base = PreparedScene::load(&scene).unwrap();
        let mut settings = settings_of(&base);
        let mut cache = ShadowCache::default();
        let mut passes = 0;
        let mut frame_with = |cache: &mut ShadowCache, settings: &Settings| {
            let mut frame = base.clone();
            let time = cache
                .apply(&mut frame, settings, |pass| {
                    passes += 1;
                    crate::reference::try_render(pass)
                        .map(|r| crate::depth::depths(&r.linear))
                })
                .unwrap()
                .unwrap();
            assert!(frame.pending_shadows.is_empty());
            assert_eq!(frame.shadow_maps.len(), 1);
            assert!(frame.lights[0].shadow.is_some());
            time.reused
        };
        assert!(!frame_with(&mut cache, &settings));
        // Another camera, spp or AOV: the same maps.
        settings.spp = 16;
        assert!(frame_with(&mut cache, &settings));
        settings.motion_blur = false;
        assert!(!frame_with(&mut cache, &settings));
        settings.shading_rate *= 2.0;
        assert!(!frame_with(&mut cache, &settings));
        assert!(frame_with(&mut cache, &settings));
        assert_eq!(passes, 3);
    }
}
