//! One view of a model made ready for crack counting: the model's visible
//! patches and the reference coverage where cracks are counted, built from
//! the pieces of [`crate::watertight`] (see `tests/tests/reyes_watertight.rs`
//! for why each is needed).

use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::Scene;

use crate::shapes::unmatched_edges;
use crate::watertight::{
    coverage_iou, cracks, dense_coverage, exclude_edges, smooth_front, visible_patches,
};

/// How a [`CrackScene`]'s reference is made.
#[derive(Debug, Clone, Copy)]
pub struct CrackSettings {
    /// Points per patch side of the dense tessellation ([`dense_coverage`]).
    pub density: u32,
    /// How far behind the front (a fraction of the view depth) a patch must
    /// be everywhere to be left out as hidden ([`visible_patches`]).
    pub hidden_margin: f64,
    /// The largest relative depth step where the front counts as smooth
    /// ([`smooth_front`]).
    pub max_depth_step: f64,
    /// Pixels left out around the model's own open seams ([`exclude_edges`]).
    pub seam_margin_px: f32,
}

/// A view of a model whose render can be checked for cracks.
#[derive(Debug)]
pub struct CrackScene {
    /// What the view is, for messages.
    pub name: String,
    /// The model's patches that are not clearly hidden in this view
    /// ([`visible_patches`]): a crack in front shows the background.
    pub model: Model,
    /// The view, with everything but the dicing as the render uses it.
    pub scene: Scene,
    /// The reference coverage of `model` in this view.
    pub coverage: Vec<bool>,
    /// `coverage` where the front is smooth and away from the model's own
    /// open seams: where cracks are counted.
    pub crack_reference: Vec<bool>,
}

/// The crack count of one render against a [`CrackScene`].
#[derive(Debug, Clone)]
pub struct CrackCount {
    /// The crack pixels ([`cracks`]).
    pub cracks: Vec<(u32, u32)>,
    /// The render's coverage IoU against the reference ([`coverage_iou`]).
    pub iou: f64,
}

impl CrackCount {
    /// `N cracks (first: ...), IoU x`.
    pub fn describe(&self) -> String {
        let first: Vec<_> = self.cracks.iter().take(6).collect();
        format!(
            "{} cracks (first: {first:?}), IoU {:.4}",
            self.cracks.len(),
            self.iou
        )
    }
}

impl CrackScene {
    /// `whole` seen as in `scene` (whose single object is the model), at
    /// `spp` samples per pixel (a square).
    pub fn new(
        name: impl Into<String>,
        whole: &Model,
        scene: Scene,
        spp: u32,
        settings: CrackSettings,
    ) -> CrackScene {
        let density = settings.density;
        let prepared = PreparedScene::new(&scene, std::slice::from_ref(whole))
            .expect("the test scene prepares");
        let visible = visible_patches(&prepared, density, spp.isqrt(), settings.hidden_margin);
        // The kept patches' indices in the whole model, and the whole
        // model's open seams renumbered to the kept patches.
        let kept: Vec<usize> = (0..whole.patches.len()).filter(|&p| visible[p]).collect();
        let model = Model::new(kept.iter().map(|&p| whole.patches[p]).collect());
        let seams: Vec<(usize, usize)> = unmatched_edges(whole)
            .into_iter()
            .filter_map(|(patch, edge)| Some((kept.binary_search(&patch).ok()?, edge)))
            .collect();
        let prepared = PreparedScene::new(&scene, std::slice::from_ref(&model))
            .expect("the test scene prepares");
        let coverage = dense_coverage(&prepared, density);
        let smooth = smooth_front(&prepared, density, spp.isqrt(), settings.max_depth_step);
        let mut crack_reference: Vec<bool> = coverage
            .iter()
            .zip(&smooth)
            .map(|(&c, &s)| c && s)
            .collect();
        exclude_edges(
            &mut crack_reference,
            &prepared,
            &seams,
            settings.seam_margin_px,
        );
        CrackScene {
            name: name.into(),
            model,
            scene,
            coverage,
            crack_reference,
        }
    }

    /// The view prepared with the scene's dicing at `shading_rate`.
    pub fn prepared(&self, shading_rate: f32) -> PreparedScene {
        let mut scene = self.scene.clone();
        scene.shading_rate = shading_rate;
        PreparedScene::new(&scene, std::slice::from_ref(&self.model))
            .expect("the test scene prepares")
    }

    /// Pixels where cracks are counted.
    pub fn counted_pixels(&self) -> usize {
        self.crack_reference.iter().filter(|&&c| c).count()
    }

    /// The cracks and coverage IoU of a render's per-pixel covered sample
    /// counts at `spp` samples per pixel, counting cracks only
    /// `silhouette_margin_px` pixels or more inside the crack reference
    /// (besides the 2 of [`cracks`]' 5 x 5 rule).
    ///
    /// Why a margin: a render's chords cut across a convex silhouette by
    /// their sagitta, up to half their length where a chord spans a tight
    /// curve (a knob seen from above), and chords are up to `sqrt 2`
    /// micropolygon sides long: 11 pixels at shading rate 64. That is
    /// coverage the surface lacks by design, not a gap between pieces.
    pub fn count(
        &self,
        covered_samples: &[u16],
        spp: u32,
        silhouette_margin_px: u32,
    ) -> CrackCount {
        let resolution = &self.scene.resolution;
        let reference = erode(
            &self.crack_reference,
            resolution.width as usize,
            resolution.height as usize,
            silhouette_margin_px as usize,
        );
        CrackCount {
            cracks: cracks(
                covered_samples,
                spp,
                &reference,
                resolution.width,
                resolution.height,
            ),
            iou: coverage_iou(covered_samples, spp, &self.coverage),
        }
    }
}

/// `mask` (row-major, `width x height`) where every pixel within
/// `radius` pixels across and down (a square) is set too; pixels outside
/// the image count as set.
fn erode(mask: &[bool], width: usize, height: usize, radius: usize) -> Vec<bool> {
    if radius == 0 {
        return mask.to_vec();
    }
    let rows: Vec<bool> = (0..width * height)
        .map(|k| {
            let (x, y) = (k % width, k / width);
            (x.saturating_sub(radius)..=(x + radius).min(width - 1)).all(|nx| mask[y * width + nx])
        })
        .collect();
    (0..width * height)
        .map(|k| {
            let (x, y) = (k % width, k / width);
            (y.saturating_sub(radius)..=(y + radius).min(height - 1)).all(|ny| rows[ny * width + x])
        })
        .collect()
}
