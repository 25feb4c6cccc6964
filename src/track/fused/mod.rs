//! embusen's camera tracker (`fused`): the suit's motion predicts, the
//! camera corrects, a forward–backward smoother weighs both. It removes
//! what Riečický et al. (`riecicky`) list as their tracker's limits:
//! - **the motion is predicted** by the contact method's floor path (the
//!   suit's own steps), not assumed still, and how far the prediction may be
//!   wrong grows with the step ([`FusedParams::stride_error`]: the suit's
//!   strides come out 6–22 % short or long) and with time;
//! - **the search is continuous**, coarse to fine around the prediction to
//!   half a centimetre, over as wide a square as the prediction's
//!   uncertainty asks;
//! - **the energy cannot slide into clutter**: truncated contour distances
//!   plus the silhouette's area off the foreground (`energy`), **nor
//!   shrink away** along the line of sight: the foreground left uncovered
//!   in a band around the body counts too;
//! - **each measurement says how well it sees**: its covariance, along the
//!   camera's line of sight and across it, is the larger of what the
//!   energy's own curvature there allows and of the matching precision in
//!   pixels through the image's sensitivity to a floor shift. Along the line
//!   of sight a silhouette barely changes (a body 20 cm farther is a body 3 %
//!   smaller), so there the suit's steps carry most of the weight, and a
//!   poor fit (low confidence) counts for less; frames where the body is out
//!   of view, or the fit is not believable, are carried by the prediction
//!   alone;
//! - **the smoothing is a forward–backward Kalman smoother**
//!   (`smoother`), not a fixed Gaussian, and it learns how the suit's strides
//!   and heading are off from what the camera sees;
//! - **the depth comes from the floor**: where the planted soles meet the
//!   floor in the image fixes the body's distance whatever its girths
//!   (`soles`); the silhouette's bias along the line of sight that they
//!   show is taken off the smoothed path.
//!
//! A frame is read in two steps: [`FusedTracker::predict`] (which also says
//! how far the frame's distance transforms are needed), then
//! [`FusedTracker::frame`]: search, measure, the path's candidates (`path`).

mod params;
mod scoring;

use glam::{DMat2, DVec2};

pub use params::{ENERGY_NOISE_PX, FusedParams};
pub(crate) use scoring::{FrameScoring, line_of_sight};
pub use scoring::{FusedPrediction, GUESSED_BLOBS, fused_terms};

use crate::body::shape::PosedBody;
use crate::camera::Camera;
use crate::image::Shrink;
use crate::image::pipeline::Features;
use crate::track::depth::{bridge_flights, correct_depth};
use crate::track::energy::Scorer;
use crate::track::measurement::largest_sigma_cm;
use crate::track::path::PathSearch;
use crate::track::setup::{FrameEstimate, TrackSetup};
use crate::track::smoother::FloorFilter;
use crate::track::smoother::frames_per_error;
use crate::track::soles::{Foot, PLANTED_CM, SoleView, feet_of, is_planted, view_soles};
use crate::track::suit_motion::{BvhInstant, SuitMotion};
use crate::track::working_scale::working_scale;
use scoring::{Measured, best_guess, body_depth_cm, truncation_px_at};

/// A frame of the fused tracker's finished path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothedFrame {
    /// Where the hips are on the floor (x, z, cm).
    pub floor_cm: DVec2,
    /// How far they may be from there (cm, one σ): the root of the
    /// covariance's trace.
    pub uncertainty_cm: f64,
    /// How they may be off, per floor axis (x, z; cm²): across the camera's
    /// line of sight a silhouette places the body well, along it the suit's
    /// steps and the soles do; another camera, at an angle, sees that depth
    /// across its own line of sight (`track::views`).
    pub covariance_cm2: DMat2,
}

impl SmoothedFrame {
    /// At `floor_cm`, as uncertain in every direction as `uncertainty_cm` says.
    pub fn round(floor_cm: DVec2, uncertainty_cm: f64) -> SmoothedFrame {
        let covariance_cm2 = DMat2::from_diagonal(DVec2::splat(uncertainty_cm * uncertainty_cm / 2.0));
        SmoothedFrame { floor_cm, uncertainty_cm, covariance_cm2 }
    }
}

/// What the fused tracker gives at the end of a video.
#[derive(Clone, Debug, PartialEq)]
pub struct FusedTrack {
    /// Per frame read, where the hips are with how uncertain (cm, one σ:
    /// the smoother's, and that of the depth the soles corrected); `None`
    /// when no frame had a pose (the frames stay as they were).
    pub path: Option<Vec<SmoothedFrame>>,
    /// The forward filter's mean squared innovation (NaN when the camera
    /// placed no frame).
    pub mean_innovation: f64,
    /// What the user should know.
    pub warnings: Vec<String>,
}

/// The fused tracker in the middle of a video.
pub struct FusedTracker {
    params: FusedParams,
    /// The forward filter, from the first frame with a pose on.
    filter: Option<FloorFilter>,
    path: PathSearch,
    /// The body model's feet, found in the first frame with a pose.
    feet: Option<Vec<Foot>>,
    /// Frames read, and the first with a pose (where the filter starts).
    frames_read: usize,
    first_filtered: Option<usize>,
    /// The planted soles in view, by frame read.
    soles: Vec<(usize, SoleView)>,
    /// Per frame read, whether the suit's pose has a foot on the floor, and
    /// its step into the frame (cm).
    planted: Vec<bool>,
    steps_cm: Vec<DVec2>,
    /// Frames whose fit the filter took.
    frames_measured: usize,
}

impl FusedTracker {
    pub fn new(params: FusedParams) -> FusedTracker {
        FusedTracker {
            params,
            filter: None,
            path: PathSearch::default(),
            feet: None,
            frames_read: 0,
            first_filtered: None,
            frames_measured: 0,
            soles: Vec::new(),
            planted: Vec::new(),
            steps_cm: Vec::new(),
        }
    }

    pub fn params(&self) -> FusedParams {
        self.params
    }

    /// The path search's frames, its energies perhaps deferred.
    pub fn path(&mut self) -> &mut PathSearch {
        &mut self.path
    }

    /// How many frames still wait for their path energies.
    pub fn path_energies_pending(&self) -> usize {
        self.path.pending()
    }

    /// A frame without a pose: the suit says nothing, the filter carries on.
    pub fn skip_frame(&mut self) {
        self.frames_read += 1;
        self.planted.push(false);
        self.steps_cm.push(DVec2::ZERO);
        self.path.next_frame();
        if let Some(filter) = &mut self.filter {
            filter.predict(DVec2::ZERO, 0.0);
        }
        self.path.push(None, None);
    }

    /// A frame's first step: the filter's prediction from the suit's step
    /// into video frame `i` (at `instant` of the BVH), and how far the
    /// frame's features are needed.
    pub fn predict(&mut self, setup: &TrackSetup, instant: BvhInstant, i: usize) -> FusedPrediction {
        self.path.next_frame();
        let params = &self.params;
        let pipeline_truncate_px = setup.pipeline.truncate_px;
        let before = setup.suit.instant(setup.timing.bvh_time_s(i.saturating_sub(1)));
        let path = &setup.suit.inertial_floor_cm;
        let step_cm = match (SuitMotion::floor_at(path, before), SuitMotion::floor_at(path, instant)) {
            (Some(a), Some(b)) => b - a,
            _ => DVec2::ZERO,
        };
        let Some(filter) = &mut self.filter else {
            // Until a first fit, each frame is searched for over the whole
            // image.
            return FusedPrediction {
                predicted: None,
                lost: false,
                before_cm: None,
                step_cm,
                step_sigma_cm: f64::INFINITY,
                truncate_px: pipeline_truncate_px,
                working_scale: Shrink::NONE,
            };
        };
        let before_cm = Some(filter.current().0);
        let dt = 1.0 / setup.timing.fps;
        let step_sigma_cm = step_sigma_cm(params, step_cm, dt);
        let (predicted, covariance) = filter.predict(step_cm, step_sigma_cm);
        let lost = filter.is_lost();
        let spread = largest_sigma_cm(covariance);
        let radius_cm = (params.search_sigmas * spread).clamp(params.min_search_cm, params.max_search_cm);
        // Lost, the body may be anywhere: the frame read whole, its
        // features as the first frame's.
        let depth_cm = body_depth_cm(&setup.camera, predicted);
        let scale = if lost { Shrink::NONE } else { working_scale(&setup.camera, depth_cm) };
        let truncation_px = truncation_px_at(&setup.camera.shrunk(scale), params, depth_cm);
        FusedPrediction {
            predicted: Some((predicted, radius_cm)),
            lost,
            before_cm,
            step_cm,
            step_sigma_cm,
            truncate_px: if lost {
                pipeline_truncate_px
            } else {
                Some(pipeline_truncate_px.map_or(truncation_px, |t| t.min(truncation_px)))
            },
            working_scale: scale,
        }
    }

    /// A frame's second step, video frame `i` read: `body` (posed as the
    /// suit says) searched for around the prediction (lost: around the
    /// frame's best guess) in `features`
    /// (computed as `prediction` asked), the fit measured into the filter,
    /// the path search's candidates recorded.
    pub fn frame(
        &mut self,
        setup: &TrackSetup,
        scorer: &mut Scorer,
        body: &PosedBody,
        features: &Features,
        prediction: &FusedPrediction,
        i: usize,
    ) -> FrameEstimate {
        let params = self.params;
        let start_cm = params.start_search_cm;
        // Where the body is expected, and where and how far it is searched for.
        let (prediction_cm, (around_cm, radius_cm)) = match prediction.predicted {
            Some((p, _)) if prediction.lost => {
                (p, (best_guess(setup, &params, scorer, features, body, p), start_cm))
            }
            Some((p, r)) => (p, (p, r)),
            None => {
                let guess = best_guess(setup, &params, scorer, features, body, DVec2::ZERO);
                (guess, (guess, start_cm))
            }
        };
        let mut scoring = FrameScoring::new(setup, &params, scorer, body, features, around_cm);
        let fit = scoring.search(around_cm, radius_cm);
        let dt = 1.0 / setup.timing.fps;
        let reacquire_after = reacquire_after_frames(&params, dt);
        let read = self.frames_read;
        self.frames_read += 1;
        let believable = fit.is_some_and(|(_, fit)| fit.confidence() >= params.min_confidence);
        if self.filter.is_none() && !believable {
            // No one seen yet (the actor not yet in view): nothing to start
            // the path from. The frame is placed back from the first fit
            // by the suit's steps once there is one.
            self.planted.push(false);
            self.steps_cm.push(prediction.step_cm);
            self.path.push(None, None);
            return FrameEstimate { floor_cm: prediction_cm, confidence: 0.0, measured_cm: None };
        }
        self.first_filtered.get_or_insert(read);
        let filter = self
            .filter
            .get_or_insert_with(|| FloorFilter::new(prediction_cm, radius_cm, dt, reacquire_after));
        let mut measured = Measured {
            prediction_cm,
            terms_at_cm: around_cm,
            fit_cm: fit.map(|(p, _)| p),
            ..Measured::default()
        };
        // A fit not believable is not used, here nor by the path search.
        if let Some((p, fit)) = fit
            && fit.confidence() >= params.min_confidence
        {
            measured.believable = true;
            scoring.measure(filter, body, p, &fit, &mut measured, dt);
        }
        if params.path_reach_cm > 0.0 && params.path_spacing_cm > 0.0 {
            let (record, request) = scoring.path_record(prediction, &measured, self.path.is_deferred(), i);
            self.path.push(Some(record), request);
        }
        let feet = self.feet.get_or_insert_with(|| feet_of(&setup.shape));
        let near_cm = filter.current().0;
        self.planted.push(feet.iter().any(|f| is_planted(f, body)));
        self.steps_cm.push(prediction.step_cm);
        let views = view_soles(&setup.camera, feet, body, &features.foreground, near_cm);
        self.soles.extend(views.into_iter().map(|v| (read, v)));
        self.frames_measured += usize::from(measured.measured_cm.is_some());
        FrameEstimate {
            floor_cm: near_cm,
            confidence: measured.confidence,
            measured_cm: measured.measured_cm,
        }
    }

    /// The finished track (see [`FusedTrack`]): deferred path energies
    /// that never came count as a fit not believed. The frames are `dt_s`
    /// apart and were filmed by `camera`.
    pub fn finish(mut self, camera: &Camera, dt_s: f64) -> FusedTrack {
        let mut warnings = Vec::new();
        let never_came = self.path.give_up_pending();
        if never_came > 0 {
            warnings
                .push(format!("{never_came} frames' path energies never came: the suit's steps carry them"));
        }
        let filter = self.filter.as_ref().filter(|_| self.frames_measured > 0);
        let Some(filter) = filter else {
            if self.steps_cm.is_empty() {
                return FusedTrack { path: None, mean_innovation: f64::NAN, warnings };
            }
            // Never worse than the inertial path: with no fit to place it,
            // the take is where the suit's own steps put it, from where
            // takes start (the board's origin), as uncertain as the first
            // frame's search is wide.
            warnings.push(
                "the camera never saw the body well enough to place it: the track is the suit's own steps (the contact method) from the floor's origin".to_string(),
            );
            let start = SmoothedFrame::round(DVec2::ZERO, self.params.start_search_cm);
            let path = Some(self.suit_steps_from(start, dt_s));
            return FusedTrack { path, mean_innovation: f64::NAN, warnings };
        };
        let params = &self.params;
        let searched = self.path.refilter(
            filter,
            params.path_temperature_px,
            params.path_spacing_cm,
            dt_s,
            reacquire_after_frames(params, dt_s),
        );
        let (mut smoothed, mut covariances): (Vec<DVec2>, Vec<DMat2>) =
            searched.as_ref().unwrap_or(filter).smooth().into_iter().unzip();
        let mut variances: Vec<f64> = covariances.iter().map(|c| c.x_axis.x + c.y_axis.y).collect();
        let first = self.first_filtered.unwrap_or(0);
        let soles: Vec<(usize, SoleView)> =
            self.soles.drain(..).filter_map(|(i, v)| i.checked_sub(first).map(|k| (k, v))).collect();
        let corrections = correct_depth(&mut smoothed, &soles, camera, dt_s);
        warnings.extend(self.soles_warning(corrections.frames_sighted));
        // The soles' depth is uncertain along the line of sight only.
        for (k, (variance, (_, sigma_cm))) in variances.iter_mut().zip(corrections.per_frame).enumerate() {
            *variance += sigma_cm * sigma_cm;
            if let (Some(covariance), Some(&floor_cm)) = (covariances.get_mut(k), smoothed.get(k)) {
                let along = line_of_sight(camera, floor_cm);
                *covariance += sigma_cm * sigma_cm * DMat2::from_cols(along * along.x, along * along.y);
            }
        }
        let (planted, steps_cm) = (self.planted.get(first..), self.steps_cm.get(first..));
        if let (Some(planted), Some(steps_cm)) = (planted, steps_cm) {
            bridge_flights(&mut smoothed, planted, steps_cm, dt_s, camera);
        }
        let mut path: Vec<SmoothedFrame> = smoothed
            .into_iter()
            .zip(variances)
            .zip(covariances)
            .map(|((floor_cm, v), covariance_cm2)| SmoothedFrame {
                floor_cm,
                uncertainty_cm: v.sqrt(),
                covariance_cm2,
            })
            .collect();
        let before_first = self.back_from_first_fit(path.first().copied(), first, dt_s);
        path.splice(0..0, before_first);
        FusedTrack { path: Some(path), mean_innovation: filter.mean_innovation(), warnings }
    }

    /// What the user should know when the planted feet were seldom seen:
    /// in under [`MIN_SOLES_SEEN_SHARE`] of the frames where the suit has a
    /// foot down, the depth along the line of sight rests on the
    /// silhouette.
    fn soles_warning(&self, frames_sighted: usize) -> Option<String> {
        let down = self.planted.iter().filter(|&&p| p).count();
        if down == 0 {
            return Some(format!(
                "the suit's pose has no foot within {PLANTED_CM} cm of the floor in any frame: no depth from the soles, the depth along the camera's line of sight rests on the silhouette"
            ));
        }
        ((frames_sighted as f64) < MIN_SOLES_SEEN_SHARE * down as f64).then(|| {
            format!(
                "the feet on the floor were seen in {frames_sighted} of the {down} frames where the suit has one down: the depth along the camera's line of sight rests on the silhouette (the body small in the image, or its feet hidden or out of view)"
            )
        })
    }

    /// Every frame read, from `start` at the first by the suit's steps, as
    /// uncertain as those steps are.
    fn suit_steps_from(&self, start: SmoothedFrame, dt_s: f64) -> Vec<SmoothedFrame> {
        let mut at = start;
        let mut path = Vec::with_capacity(self.steps_cm.len());
        for (k, &step) in self.steps_cm.iter().enumerate() {
            if k > 0 {
                at = self.stepped(at, step, dt_s);
            }
            path.push(at);
        }
        path
    }

    /// The frames read before the first fit (`first` of them), placed back
    /// from it (`first_fit`) by the suit's steps, as uncertain as those
    /// steps are.
    fn back_from_first_fit(
        &self,
        first_fit: Option<SmoothedFrame>,
        first: usize,
        dt_s: f64,
    ) -> Vec<SmoothedFrame> {
        let Some(mut at) = first_fit else { return Vec::new() };
        let mut before = vec![at; first];
        for k in (0..first).rev() {
            let step = self.steps_cm.get(k + 1).copied().unwrap_or(DVec2::ZERO);
            at = self.stepped(at, -step, dt_s);
            before[k] = at;
        }
        before
    }

    /// `at` moved by a suit's step of `step_cm` (either way along it), as
    /// much more uncertain as that step is (`dt_s` long).
    fn stepped(&self, at: SmoothedFrame, step_cm: DVec2, dt_s: f64) -> SmoothedFrame {
        let sigma = step_sigma_cm(&self.params, step_cm, dt_s);
        SmoothedFrame {
            floor_cm: at.floor_cm + step_cm,
            uncertainty_cm: (at.uncertainty_cm * at.uncertainty_cm + sigma * sigma).sqrt(),
            covariance_cm2: at.covariance_cm2 + DMat2::from_diagonal(DVec2::splat(sigma * sigma / 2.0)),
        }
    }
}

/// After this many frames of rejected fits the filter trusts the camera
/// again ([`FusedParams::reacquire_after_s`] at `dt_s` a frame, at least 1).
fn reacquire_after_frames(params: &FusedParams, dt_s: f64) -> usize {
    ((params.reacquire_after_s / dt_s).round() as usize).max(1)
}

/// The suit's step `step_cm` into a frame `dt_s` after the last, and how
/// uncertain it is (cm, one σ): its stride error, and the drift where the
/// body barely moves, as [`frames_per_error`] shares them out.
fn step_sigma_cm(params: &FusedParams, step_cm: DVec2, dt_s: f64) -> f64 {
    (params.stride_error * step_cm.length() + params.drift_cm_per_s * dt_s) * frames_per_error(dt_s).sqrt()
}

/// Planted feet seen in fewer of the frames that have one than this leave
/// the path's depth to the silhouette: one stance in four seen is about
/// one sighting a second, where the bias is weighed over half a second.
pub const MIN_SOLES_SEEN_SHARE: f64 = 0.25;

#[cfg(test)]
mod tests {
    use super::*;
    fn camera() -> Camera {
        Camera::at_origin(640, 480, 500.0)
    }

    #[test]
    fn a_tracker_that_read_nothing_finishes_with_no_path() {
        let track = FusedTracker::new(FusedParams::default()).finish(&camera(), 1.0 / 30.0);
        assert_eq!(track.path, None);
        assert!(track.mean_innovation.is_nan());
        assert!(track.warnings.is_empty(), "{:?}", track.warnings);
    }

    /// Never placed by the camera, the take is where the suit's own steps
    /// put it from the floor's origin, and says so; each frame is as
    /// uncertain as the first search was wide, and more with every step.
    #[test]
    fn frames_the_camera_never_placed_follow_the_suits_steps_from_the_origin() {
        let params = FusedParams::default();
        let mut tracker = FusedTracker::new(params);
        for _ in 0..4 {
            tracker.skip_frame();
        }
        let dt_s = 1.0 / 30.0;
        let track = tracker.finish(&camera(), dt_s);
        let path = track.path.expect("a path");
        assert_eq!(path.len(), 4);
        assert!(path.iter().all(|f| f.floor_cm == DVec2::ZERO));
        assert_eq!(path[0].uncertainty_cm, params.start_search_cm);
        let sigma = step_sigma_cm(&params, DVec2::ZERO, dt_s);
        for pair in path.windows(2) {
            let grown = (pair[0].uncertainty_cm.powi(2) + sigma * sigma).sqrt();
            assert!((pair[1].uncertainty_cm - grown).abs() < 1e-12, "{pair:?}");
        }
        assert!(track.mean_innovation.is_nan());
        assert_eq!(track.warnings.len(), 1, "{:?}", track.warnings);
        assert!(track.warnings[0].contains("never saw the body"), "{:?}", track.warnings);
    }

    /// A step's uncertainty is the suit's stride error on its length plus
    /// the drift over its time: a longer step is less certain.
    #[test]
    fn a_longer_step_is_less_certain() {
        let params = FusedParams::default();
        let dt_s = 1.0 / 30.0;
        let still = step_sigma_cm(&params, DVec2::ZERO, dt_s);
        let step = step_sigma_cm(&params, DVec2::new(3.0, 4.0), dt_s);
        let per_frame = frames_per_error(dt_s).sqrt();
        assert!((still - params.drift_cm_per_s * dt_s * per_frame).abs() < 1e-12);
        assert!((step - still - params.stride_error * 5.0 * per_frame).abs() < 1e-12);
    }
}
