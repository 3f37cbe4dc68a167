//! [`LoopLimitError`]: what the renderer says when llvmpipe's loop limit
//! still cut loops short after the scheduler's retries, with advice that
//! follows from what the frame was configured with (issue 19, D10).

use std::fmt;

use scheduler::RunError;

use crate::params::{DEFAULT_DICE_THRESHOLD, DEFAULT_SHADING_RATE};
use crate::prepare::PreparedScene;
use crate::scene::{Dicing, Sampling};

/// Micropolygons whose box is at least this many pixels on a side make the
/// bounding-box and INTERVAL rasterization loops long (their box in pixels
/// times the samples per pixel).
const LARGE_MICROPOLYGON_PX: f32 = 4.0;

/// What the frame was configured with and what its last run counted: the
/// inputs of the advice in [`LoopLimitError`].
#[derive(Clone, Debug, PartialEq)]
pub struct LoopLimitContext {
    /// Samples per pixel.
    pub spp: u32,
    /// Sampling mode.
    pub sampling: Sampling,
    /// Whether samples carry time and lens (motion blur or depth of field).
    pub blurred: bool,
    /// How pieces are diced.
    pub dicing: Dicing,
    /// The scene's dice threshold in pixels (fixed dicing).
    pub dice_threshold: f32,
    /// The scene's shading rate in pixels (rate dicing).
    pub shading_rate: f32,
    /// The split-depth guard.
    pub max_split_depth: u32,
    /// Whether a user displacement function (WGSL) is compiled in.
    pub user_displacement: bool,
    /// Pieces the split-depth guard dropped in the last run.
    pub depth_guard_drops: u64,
    /// Largest micropolygon of the last run, in pixels.
    pub largest_micropolygon_px: f32,
}

impl LoopLimitContext {
    /// The configuration of `scene` with the counters of the last run.
    pub fn new(
        scene: &PreparedScene,
        depth_guard_drops: u64,
        largest_micropolygon_px: f32,
    ) -> Self {
        let user_displacement = scene.objects.iter().any(|o| {
            o.displacement
                .as_ref()
                .and_then(|d| d.shader())
                .and_then(|s| scene.shaders.shaders.get(s.reference.shader as usize))
                .is_some_and(|s| !crate::surface_shader::builtin::is_builtin(&s.path))
        });
        Self {
            spp: scene.spp,
            sampling: scene.sampling,
            blurred: scene.samples_time_and_lens(),
            dicing: scene.dicing.mode(),
            dice_threshold: scene.dicing.dice_threshold(),
            shading_rate: scene.dicing.shading_rate(),
            max_split_depth: scene.max_split_depth,
            user_displacement,
            depth_guard_drops,
            largest_micropolygon_px,
        }
    }
}

/// A likely cause of the cut loops and what to change, most likely first.
#[derive(Clone, Debug, PartialEq)]
pub enum LoopLimitHint {
    /// A user's displacement code (a WGSL height function or displacement
    /// shader) is compiled in: it runs for every grid point against the
    /// same per-invocation budget, and an endless or long loop in it is cut
    /// there.
    UserDisplacement,
    /// The split-depth guard dropped pieces: patches kept splitting (a model
    /// far too large or too close for the camera, or a displacement bound
    /// that never fits), each split more work.
    DepthGuard {
        /// The guard.
        max_split_depth: u32,
        /// Pieces dropped.
        drops: u64,
    },
    /// Fixed dicing below the default threshold: many small grids per patch.
    LargerDiceThreshold {
        /// The configured threshold.
        threshold: f32,
        /// The default.
        default: f32,
    },
    /// Rate dicing below the default shading rate: many micropolygons per
    /// patch.
    LargerShadingRate {
        /// The configured rate.
        rate: f32,
        /// The default.
        default: f32,
    },
    /// A micropolygon's rasterization loops are long: its box in pixels
    /// times the samples per pixel (bounding-box and INTERVAL modes).
    LongRasterization {
        /// Samples per pixel.
        spp: u32,
        /// Whether samples carry time and lens.
        blurred: bool,
        /// Whether a smaller dice threshold is worth trying (fixed dicing at
        /// or above the default threshold with large micropolygons).
        smaller_threshold: bool,
    },
    /// Only queue waits were cut: workgroups waiting for work that others
    /// produce spent the budget (contention for the CPU).
    Contention {
        /// Workgroups of the last run.
        workgroups: u32,
    },
}

impl LoopLimitHint {
    /// The hints for `context` after a run that cut `rasterization`
    /// rasterization loops and `waits` queue waits with `workgroups`
    /// workgroups; never empty.
    pub fn for_context(
        context: &LoopLimitContext,
        rasterization: u32,
        waits: u32,
        workgroups: u32,
    ) -> Vec<Self> {
        let mut hints = Vec::new();
        if context.user_displacement {
            hints.push(Self::UserDisplacement);
        }
        if context.depth_guard_drops > 0 {
            hints.push(Self::DepthGuard {
                max_split_depth: context.max_split_depth,
                drops: context.depth_guard_drops,
            });
        }
        let fine = match context.dicing {
            Dicing::Fixed if context.dice_threshold < DEFAULT_DICE_THRESHOLD => {
                hints.push(Self::LargerDiceThreshold {
                    threshold: context.dice_threshold,
                    default: DEFAULT_DICE_THRESHOLD,
                });
                true
            }
            Dicing::Rate if context.shading_rate < DEFAULT_SHADING_RATE => {
                hints.push(Self::LargerShadingRate {
                    rate: context.shading_rate,
                    default: DEFAULT_SHADING_RATE,
                });
                true
            }
            _ => false,
        };
        let long_boxes = context.largest_micropolygon_px >= LARGE_MICROPOLYGON_PX
            || context.spp > 1
            || context.blurred;
        let rasterizes_boxes = matches!(context.sampling, Sampling::Bbox | Sampling::Interval);
        if rasterization > 0 && long_boxes && (rasterizes_boxes || !fine) {
            hints.push(Self::LongRasterization {
                spp: context.spp,
                blurred: context.blurred,
                smaller_threshold: context.dicing == Dicing::Fixed
                    && !fine
                    && context.largest_micropolygon_px >= LARGE_MICROPOLYGON_PX,
            });
        }
        if rasterization == 0 && waits > 0 && hints.is_empty() {
            hints.push(Self::Contention { workgroups });
        }
        if hints.is_empty() {
            hints.push(Self::LongRasterization {
                spp: context.spp,
                blurred: context.blurred,
                smaller_threshold: false,
            });
        }
        hints
    }
}

impl fmt::Display for LoopLimitHint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UserDisplacement => write!(
                f,
                "the scene's user displacement function or shader runs for every grid point (and its neighbours) within the same budget: an endless or long loop in it is a likely cause; check its loops terminate quickly"
            ),
            Self::DepthGuard {
                max_split_depth,
                drops,
            } => write!(
                f,
                "the split-depth guard (max_split_depth = {max_split_depth}) dropped {drops} piece(s): patches kept splitting (a model scaled far beyond the view, a patch reaching the eye, or a displacement bound that never fits); check the model's scale and transform, or lower max_split_depth so that such pieces are dropped sooner"
            ),
            Self::LargerDiceThreshold { threshold, default } => write!(
                f,
                "dice_threshold = {threshold} px is below the default {default} px, so every patch is split into many small grids: use a LARGER dice threshold"
            ),
            Self::LargerShadingRate { rate, default } => write!(
                f,
                "shading_rate = {rate} px is below the default {default} px, so every patch is diced into many micropolygons: use a LARGER shading rate"
            ),
            Self::LongRasterization {
                spp,
                blurred,
                smaller_threshold,
            } => {
                write!(
                    f,
                    "a micropolygon's sample loops are too long for the driver (in the bounding-box and INTERVAL modes: its box in pixels times the samples per pixel, {spp} here): use fewer samples per pixel"
                )?;
                if *blurred {
                    write!(f, ", less motion blur or depth of field")?;
                }
                write!(f, ", Interleave or Simple UVT sampling")?;
                if *smaller_threshold {
                    write!(f, ", or a smaller dice threshold")?;
                }
                Ok(())
            }
            Self::Contention { workgroups } => write!(
                f,
                "only queue waits were cut: the {workgroups} workgroups waited for work too long, which happens when other processes compete for the CPU; render again with fewer workgroups (GpuOptions::workgroups) or on an idle machine"
            ),
        }
    }
}

/// llvmpipe's loop limit still cut loops short after the scheduler's
/// retries with smaller iteration budgets
/// ([`Executor::run_with_retry`](scheduler::Executor::run_with_retry)), so
/// samples would be missing.
///
/// Rasterization loops count their own completion (`STAT_LOOPS_CUT`, which
/// the renderer reports to the scheduler through
/// [`Retry::check_loops`](scheduler::Retry::check_loops)); the scheduler
/// finds cut queue waits, which an item's long loops starve of the budget
/// they share.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct LoopLimitError {
    /// Rasterization loops cut in the last run.
    pub rasterization: u32,
    /// Queue waits cut in the last run.
    pub waits: u32,
    /// Attempts at the frame (or tile), the retries included.
    pub runs: u32,
    /// Persistent workgroups of the last run.
    pub workgroups: u32,
    /// Batches per dispatch of the last run (`None`: the scheduler's default).
    pub iteration_budget: Option<u32>,
    /// The input batch the last run failed in (1-based) and the batches of
    /// the frame.
    pub batch: (u32, u32),
    /// What the frame was configured with.
    pub context: LoopLimitContext,
    /// Likely causes, most likely first (never empty).
    pub hints: Vec<LoopLimitHint>,
}

impl LoopLimitError {
    /// The error for the scheduler's final [`RunError::LoopLimit`] (its
    /// cut waits, the rasterization loops reported cut, its attempts and
    /// workgroups), with the iteration budget the scheduler ended with, the
    /// input batch it failed in and the frame's `context`. `Err`: `error`
    /// back when it is not a loop limit.
    pub fn from_run(
        error: RunError,
        iteration_budget: Option<u32>,
        batch: (u32, u32),
        context: LoopLimitContext,
    ) -> Result<Self, RunError> {
        match error {
            RunError::LoopLimit {
                waits,
                body_loops,
                report,
                ..
            } => Ok(Self::new(
                body_loops,
                waits,
                report.attempts.max(1),
                report.workgroups,
                iteration_budget,
                batch,
                context,
            )),
            other => Err(other),
        }
    }

    /// The error for a run with these counts; the hints follow from
    /// `context` ([`LoopLimitHint::for_context`]).
    pub fn new(
        rasterization: u32,
        waits: u32,
        runs: u32,
        workgroups: u32,
        iteration_budget: Option<u32>,
        batch: (u32, u32),
        context: LoopLimitContext,
    ) -> Self {
        let hints = LoopLimitHint::for_context(&context, rasterization, waits, workgroups);
        Self {
            rasterization,
            waits,
            runs,
            workgroups,
            iteration_budget,
            batch,
            context,
            hints,
        }
    }
}

impl fmt::Display for LoopLimitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "llvmpipe's loop limit (65,535 iterations per invocation) cut {} rasterization loop(s) and {} queue wait(s) short in the last of {} attempt(s) ({} workgroups, ",
            self.rasterization, self.waits, self.runs, self.workgroups
        )?;
        match self.iteration_budget {
            Some(budget) => write!(f, "an iteration budget of {budget} batch(es) per dispatch")?,
            None => write!(f, "the scheduler's default iteration budget")?,
        }
        if self.batch.1 > 1 {
            write!(f, ", input batch {} of {}", self.batch.0, self.batch.1)?;
        }
        write!(f, "); the image would be incomplete. Likely cause")?;
        if self.hints.len() > 1 {
            write!(f, "s, most likely first")?;
        }
        for (i, hint) in self.hints.iter().enumerate() {
            write!(f, "{} ({}) {hint}", if i == 0 { ":" } else { ";" }, i + 1)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
