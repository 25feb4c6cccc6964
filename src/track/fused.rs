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

use glam::{DMat2, DVec2, DVec3};

use crate::body::shape::{BodyShape, PosedBody};
use crate::camera::Camera;
use crate::image::Shrink;
use crate::image::components::blobs;
use crate::image::pipeline::Features;
use crate::track::depth::{bridge_flights, correct_depth};
use crate::track::energy::{BandedBody, FrameTerms, Scorer, SilhouetteFit};
use crate::track::measurement::{largest_sigma_cm, measurement_covariance};
use crate::track::path::{PathFrame, PathRecord, PathRequest, PathSearch};
use crate::track::search::coarse_to_fine;
use crate::track::setup::{FrameEstimate, TrackSetup};
use crate::track::smoother::FloorFilter;
use crate::track::smoother::Measurement;
use crate::track::smoother::frames_per_error;
use crate::track::soles::{Foot, PLANTED_CM, SoleView, feet_of, is_planted, view_soles};
use crate::track::suit_motion::{BvhInstant, SuitMotion};
use crate::track::working_scale::working_scale;

/// embusen's tracker's parameters; each has its physical reason.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FusedParams {
    /// How wrong an inertial step may be, as a share of its length: the
    /// suit's pose moves a planted foot relative to the hips by 0.78–0.94 of
    /// the true distance at the real suit's error level (docs/contact.md).
    pub stride_error: f64,
    /// How fast the inertial path may drift where the body barely moves
    /// (cm/s): a slow slide of the planted feet.
    pub drift_cm_per_s: f64,
    /// How precisely a good fit places the silhouette (px, one σ): the body
    /// model's girths and the suit's limb angles are each off by a pixel or
    /// two at a few metres.
    pub match_sigma_px: f64,
    /// The search reaches this many σ of the prediction's uncertainty ...
    pub search_sigmas: f64,
    /// ... but at least this far (cm) ...
    pub min_search_cm: f64,
    /// ... and at most this far (cm): a step and a half of a run in one frame.
    pub max_search_cm: f64,
    /// The search's last spacing (cm).
    pub resolution_cm: f64,
    /// A contour pixel's distance to an edge counts up to this much (cm at
    /// the body's distance, so the same at any resolution): about a limb's
    /// width, past which the pixel is simply not on its edge.
    pub truncation_cm: f64,
    /// The weight of the silhouette's area off the foreground beside the
    /// contour's distance to the edges.
    pub mask_weight: f64,
    /// The weight of the foreground left uncovered in the band around the
    /// silhouette. Less than the area's: the band also catches the blur and
    /// the penumbra at the outline and the girths the body model misses
    /// (0.5 measured best of 0.3–2 on the shared scenes; 0 turns it off).
    pub uncovered_weight: f64,
    /// The band's width (cm at the body): about a forearm's radius, wide
    /// enough to be many pixels at any distance, narrow enough to stay off
    /// a neighbouring limb or person.
    pub band_cm: f64,
    /// The path search (`path`) tries candidates this far (cm) either side
    /// of each frame's fit along the line of sight (0 turns it off) ...
    pub path_reach_cm: f64,
    /// ... this far apart (cm) ...
    pub path_spacing_cm: f64,
    /// ... and takes an energy this much (px) above the frame's least as
    /// one nat of cost: by default twice [`ENERGY_NOISE_PX`], the scale at
    /// which the filter's measurement reads the same energy (a fit is as
    /// uncertain as moves its energy by the noise: ½ κ σ² = noise, so a
    /// rise ΔE is ΔE / 2·noise nats). One noise model for both.
    pub path_temperature_px: f64,
    /// Below this confidence a fit is not used.
    pub min_confidence: f64,
    /// After this long (s) without a fit used (rejected as too far from the
    /// prediction, or none believable near it), the prediction is taken for
    /// lost: the frame is searched for as the first was, and the camera is
    /// trusted again.
    pub reacquire_after_s: f64,
    /// How far the first frame's search, and a lost filter's, reaches
    /// around each guess (cm).
    pub start_search_cm: f64,
}

impl Default for FusedParams {
    fn default() -> Self {
        FusedParams::DEFAULT
    }
}

impl FusedParams {
    /// embusen's settings, measured on the shared scenes.
    pub const DEFAULT: FusedParams = FusedParams {
        stride_error: 0.15,
        drift_cm_per_s: 10.0,
        match_sigma_px: 1.5,
        search_sigmas: 3.0,
        min_search_cm: 10.0,
        max_search_cm: 60.0,
        resolution_cm: 0.5,
        truncation_cm: 10.0,
        mask_weight: 1.0,
        uncovered_weight: 0.5,
        band_cm: 5.0,
        path_reach_cm: 100.0,
        path_spacing_cm: 4.0,
        path_temperature_px: 2.0 * ENERGY_NOISE_PX,
        min_confidence: 0.2,
        reacquire_after_s: 0.5,
        start_search_cm: 80.0,
    };
}

/// Where the fused tracker expects the body in a frame, before reading it.
#[derive(Clone, Copy, Debug)]
pub struct FusedPrediction {
    /// The filter's prediction and how far around it to search (cm); `None`
    /// in the first frame, searched for around a guess from the frame itself.
    predicted: Option<(DVec2, f64)>,
    /// Whether the filter has lost the body: the frame is searched for as
    /// the first was, the prediction one guess among the frame's own.
    lost: bool,
    /// The filter's position before the prediction.
    before_cm: Option<DVec2>,
    /// The suit's step into this frame and its uncertainty (cm, one σ).
    step_cm: DVec2,
    step_sigma_cm: f64,
    /// How far the frame's distance transforms are needed (px at the
    /// working scale): the energy reads them only up to its truncation, so
    /// they are computed only so far, near the foreground (the same values).
    pub truncate_px: Option<f32>,
    /// How much the frame is shrunk before it is read
    /// ([`working_scale`]): not at all where nothing says where the body is.
    pub working_scale: Shrink,
}

/// What the search and the filter made of a frame.
#[derive(Clone, Copy, Debug, Default)]
struct Measured {
    /// Where the filter predicted the body (before a first fit: where the
    /// frame's best guess put it).
    prediction_cm: DVec2,
    /// Where the frame's terms were made and the search centred: the
    /// prediction, or where a lost filter's best guess put the body.
    terms_at_cm: DVec2,
    /// The least energy's position, if any.
    fit_cm: Option<DVec2>,
    /// Whether its fit is believable (used here and by the path search).
    believable: bool,
    /// What the filter took: the fit's confidence and position where used.
    confidence: f64,
    measured_cm: Option<DVec2>,
    /// How uncertain the fit was across the line of sight (cm²).
    across_variance_cm2: Option<f64>,
}

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

    /// The smoothed path with each frame's uncertainty (cm, one σ: the
    /// smoother's, and that of the depth the soles corrected) (`None` when
    /// no frame had a pose: the frames stay as they were), the filter's
    /// mean squared innovation, and what the user should know: deferred
    /// path energies that never came count as a fit not believed. The
    /// frames are `dt_s` apart and were filmed by `camera`.
    pub fn finish(mut self, camera: &Camera, dt_s: f64) -> (Option<Vec<SmoothedFrame>>, f64, Vec<String>) {
        let mut warnings = Vec::new();
        let never_came = self.path.give_up_pending();
        if never_came > 0 {
            warnings
                .push(format!("{never_came} frames' path energies never came: the suit's steps carry them"));
        }
        let filter = self.filter.as_ref().filter(|_| self.frames_measured > 0);
        let Some(filter) = filter else {
            if self.steps_cm.is_empty() {
                return (None, f64::NAN, warnings);
            }
            // Never worse than the inertial path: with no fit to place it,
            // the take is where the suit's own steps put it, from where
            // takes start (the board's origin), as uncertain as the first
            // frame's search is wide.
            warnings.push(
                "the camera never saw the body well enough to place it: the track is the suit's own steps (the contact method) from the floor's origin".to_string(),
            );
            let start = SmoothedFrame::round(DVec2::ZERO, self.params.start_search_cm);
            return (Some(self.suit_steps_from(start, dt_s)), f64::NAN, warnings);
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
        (Some(path), filter.mean_innovation(), warnings)
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

/// One frame as the fused energy scores it: its terms near the
/// prediction, the body with its band, and the scorer that renders it.
pub(crate) struct FrameScoring<'a> {
    camera: Camera,
    params: FusedParams,
    scorer: &'a mut Scorer,
    terms: FrameTerms<'a>,
    banded: BandedBody,
}

impl<'a> FrameScoring<'a> {
    pub(crate) fn new(
        setup: &TrackSetup,
        params: &FusedParams,
        scorer: &'a mut Scorer,
        body: &PosedBody,
        features: &'a Features,
        near_cm: DVec2,
    ) -> FrameScoring<'a> {
        let (terms, depth_cm) = fused_terms(&setup.camera, params, features, near_cm);
        let banded = banded_body(&setup.shape, body, &setup.camera, params, depth_cm);
        FrameScoring { camera: setup.camera, params: *params, scorer, terms, banded }
    }

    /// The fused energy at `floor_cm`; NaN where the body is not in the image.
    pub(crate) fn energy(&mut self, floor_cm: DVec2) -> f64 {
        fused_energy(self.scorer, &self.terms, &self.banded, floor_cm, &self.params)
    }

    /// The least energy within `radius_cm` of `around_cm`, and its fit.
    fn search(&mut self, around_cm: DVec2, radius_cm: f64) -> Option<(DVec2, SilhouetteFit)> {
        // The search keeps the first of the least energies; so does this,
        // with its fit, rather than render the winner again.
        let mut best: Option<(f64, SilhouetteFit)> = None;
        let (params, scorer, terms, banded) = (&self.params, &mut *self.scorer, &self.terms, &self.banded);
        let found = coarse_to_fine(around_cm, radius_cm, params.resolution_cm, |p| {
            let fit = scorer.banded_fit(terms, banded, p);
            let energy = energy_of(fit.as_ref(), params);
            if let Some(fit) = fit.filter(|_| energy.is_finite() && best.is_none_or(|(b, _)| energy < b)) {
                best = Some((energy, fit));
            }
            energy
        });
        found.zip(best).map(|((p, _), (_, fit))| (p, fit))
    }

    /// The believable `fit` at `p` as a measurement: its covariance, along
    /// the camera's line of sight and across it, the larger of what the
    /// energy's curvature there allows and of the matching precision
    /// through the image's sensitivity; handed to `filter`, and what it
    /// took written into `measured`.
    fn measure(
        &mut self,
        filter: &mut FloorFilter,
        body: &PosedBody,
        p: DVec2,
        fit: &SilhouetteFit,
        measured: &mut Measured,
        dt_s: f64,
    ) {
        let params = self.params;
        let sigma_px = params.match_sigma_px / fit.confidence();
        let geometric = measurement_covariance(&self.camera, body, p, sigma_px);
        let along = line_of_sight(&self.camera, p);
        let across = along.perp();
        let e0 = fit.fused_energy(params.mask_weight, params.uncovered_weight);
        let h = CURVATURE_STEP_CM;
        let mut sigma2 = [0.0; 2];
        for (k, u) in [along, across].into_iter().enumerate() {
            let (plus, minus) = (self.energy(p + u * h), self.energy(p - u * h));
            let curvature = (plus + minus - 2.0 * e0) / (h * h);
            // The energy is a mean over the contour; it is as uncertain
            // as `ENERGY_NOISE_PX`, which moves the minimum by σ with
            // ½ κ σ² = noise. A flat (or concave) valley says nothing.
            sigma2[k] = if curvature > 0.0 { 2.0 * ENERGY_NOISE_PX / curvature } else { f64::INFINITY };
        }
        let covariance = geometric.and_then(|g| {
            let project = |u: DVec2| u.dot(g * u);
            let (r, a) = (sigma2[0].max(project(along)), sigma2[1].max(project(across)));
            let limit = MAX_MEASUREMENT_SIGMA_CM * MAX_MEASUREMENT_SIGMA_CM;
            (r.is_finite() && a.is_finite()).then(|| {
                let basis = DMat2::from_cols(along, across);
                basis * DMat2::from_diagonal(DVec2::new(r.min(limit), a.min(limit))) * basis.transpose()
            })
        });
        // Within one error's time the frames repeat it: each counts as that
        // share of one.
        let covariance = covariance.map(|c| c * frames_per_error(dt_s));
        if let Some(covariance) = covariance {
            measured.across_variance_cm2 = Some(across.dot(covariance * across));
            match filter.update(p, covariance) {
                Measurement::Used | Measurement::Reacquired => {
                    measured.confidence = fit.confidence();
                    measured.measured_cm = Some(p);
                }
                Measurement::Rejected => {}
            }
        }
    }

    /// The path search's line of candidates along the line of sight
    /// through the frame's best position, scored here or, when `deferred`,
    /// asked for in a [`PathRequest`].
    fn path_record(
        &mut self,
        prediction: &FusedPrediction,
        measured: &Measured,
        deferred: bool,
        i: usize,
    ) -> (PathRecord, Option<PathRequest>) {
        let params = self.params;
        // A fit not believed (no one in view) is anywhere: the line goes
        // through the prediction, or the path would be tied to it.
        let believed_fit = measured.fit_cm.filter(|_| measured.believable);
        let base = measured.measured_cm.or(believed_fit).unwrap_or(measured.prediction_cm);
        let along = line_of_sight(&self.camera, base);
        let steps = (params.path_reach_cm / params.path_spacing_cm).round() as i32;
        let candidates_cm: Vec<DVec2> =
            (-steps..=steps).map(|k| base + along * (k as f64 * params.path_spacing_cm)).collect();
        // Where the fit is not believable the suit's steps carry the frame
        // (all candidates alike).
        let pending = measured.believable && deferred;
        let mut request = None;
        let energies_px = if !measured.believable {
            vec![f64::NAN; candidates_cm.len()]
        } else if pending {
            request = Some(PathRequest {
                frame: i,
                terms_at_cm: measured.terms_at_cm,
                truncate_px: prediction.truncate_px,
                working_scale: prediction.working_scale,
                candidates_cm: candidates_cm.clone(),
            });
            Vec::new()
        } else {
            candidates_cm.iter().map(|&p| self.energy(p)).collect()
        };
        let record = PathRecord {
            pending,
            frame: PathFrame {
                candidates_cm,
                energies_px,
                expected_step_cm: prediction.before_cm.map_or(DVec2::ZERO, |b| measured.prediction_cm - b),
                step_sigma_cm: prediction.step_sigma_cm,
            },
            inertial_step_cm: prediction.step_cm,
            across_variance_cm2: measured
                .across_variance_cm2
                .unwrap_or(MAX_MEASUREMENT_SIGMA_CM * MAX_MEASUREMENT_SIGMA_CM),
            along,
        };
        (record, request)
    }
}

/// Where to look for the body when nothing says where it is (before any
/// fit, or with the filter lost): `guess_cm` (the floor's origin, where a
/// take usually starts, on the board; or the lost prediction) and the feet
/// of each of the [`GUESSED_BLOBS`] largest parts of the foreground — the
/// actor, and anyone else in the room. Each is searched within
/// [`FusedParams::start_search_cm`] and the least energy wins: the body
/// whose outline is the suit's pose, not merely the nearest or the lowest
/// in the image.
fn best_guess(
    setup: &TrackSetup,
    params: &FusedParams,
    scorer: &mut Scorer,
    features: &Features,
    body: &PosedBody,
    guess_cm: DVec2,
) -> DVec2 {
    let radius_cm = params.start_search_cm;
    let found = blobs(&features.foreground);
    let largest = found.first().map_or(0, |b| b.area_px);
    let mut guesses = vec![guess_cm];
    for blob in found.iter().take(GUESSED_BLOBS).filter(|b| b.area_px * 8 >= largest) {
        let feet_px = DVec2::new(blob.bottom_column, f64::from(blob.bottom_row));
        if let Some(floor) = setup.camera.floor_point(feet_px) {
            guesses.push(DVec2::new(floor.x, floor.z));
        }
    }
    let mut best = (guess_cm, f64::INFINITY);
    for guess in guesses {
        let mut scoring = FrameScoring::new(setup, params, scorer, body, features, guess);
        let Some((_, fit)) = scoring.search(guess, radius_cm) else { continue };
        let energy = fit.fused_energy(params.mask_weight, params.uncovered_weight);
        if energy < best.1 {
            best = (guess, energy);
        }
    }
    best.0
}

/// How many of the foreground's largest parts the first frame looks at
/// (those at least an eighth of the largest): the actor and a few others
/// in the room; the rest are specks.
pub const GUESSED_BLOBS: usize = 4;

/// The fused energy of `body` at `floor_cm`; NaN where it is not in the image.
fn fused_energy(
    scorer: &mut Scorer,
    terms: &FrameTerms,
    body: &BandedBody,
    floor_cm: DVec2,
    params: &FusedParams,
) -> f64 {
    energy_of(scorer.banded_fit(terms, body, floor_cm).as_ref(), params)
}

/// The fused energy of a fit; NaN for none (the body not in the image).
fn energy_of(fit: Option<&SilhouetteFit>, params: &FusedParams) -> f64 {
    fit.map_or(f64::NAN, |f| f.fused_energy(params.mask_weight, params.uncovered_weight))
}

/// `body` of `shape` with its band, `depth_cm` from `camera`; no band
/// (0 px) when the band term is off.
fn banded_body(
    shape: &BodyShape,
    body: &PosedBody,
    camera: &Camera,
    params: &FusedParams,
    depth_cm: f64,
) -> BandedBody {
    BandedBody {
        body: body.clone(),
        widened: shape.widened(body, params.band_cm),
        band_px: if params.uncovered_weight > 0.0 {
            camera.intrinsics.fx_px * params.band_cm / depth_cm
        } else {
            0.0
        },
    }
}

/// The fused energy's image terms of a frame for a body standing near
/// `near_cm`, the contour's distances truncated at `params.truncation_cm`
/// at the body's distance; and that distance (cm, the camera's depth of
/// the point 1 m above `near_cm`, at least 50 cm).
pub fn fused_terms<'a>(
    camera: &Camera,
    params: &FusedParams,
    features: &'a Features,
    near_cm: DVec2,
) -> (FrameTerms<'a>, f64) {
    let (truncation_px, depth_cm) = fused_truncation_px(camera, params, near_cm);
    let terms = FrameTerms::new(
        &features.edge_distance,
        &features.outside_distance,
        &features.foreground,
        truncation_px,
    );
    (terms, depth_cm)
}

/// The truncation (px, at least 1) of the fused energy's distances for a
/// body standing near `near_cm`: `params.truncation_cm` at the body's
/// distance; and that distance (cm, the camera's depth of the point 1 m
/// above `near_cm`, at least 50 cm).
fn fused_truncation_px(camera: &Camera, params: &FusedParams, near_cm: DVec2) -> (f32, f64) {
    let depth_cm = body_depth_cm(camera, near_cm);
    (truncation_px_at(camera, params, depth_cm), depth_cm)
}

/// The camera's depth (cm, at least 50) of the point 1 m above `near_cm`:
/// how far a body standing there is.
fn body_depth_cm(camera: &Camera, near_cm: DVec2) -> f64 {
    camera.point_in_camera(DVec3::new(near_cm.x, 100.0, near_cm.y)).z.max(50.0)
}

/// `params.truncation_cm` in `camera`'s pixels (at least 1) at `depth_cm`.
fn truncation_px_at(camera: &Camera, params: &FusedParams, depth_cm: f64) -> f32 {
    ((camera.intrinsics.fx_px * params.truncation_cm / depth_cm) as f32).max(1.0)
}

/// The direction on the floor (x, z) of the camera's line of sight through
/// `floor_cm` ([`Camera::line_of_sight_on_floor`]); +x right below the
/// camera's centre, where any direction is as good.
pub(crate) fn line_of_sight(camera: &Camera, floor_cm: DVec2) -> DVec2 {
    let along = camera.line_of_sight_on_floor(floor_cm);
    if along == DVec2::ZERO { DVec2::X } else { along }
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

/// How far either side of a fit (cm) the energy is probed for its curvature.
const CURVATURE_STEP_CM: f64 = 10.0;

/// How uncertain a fit's energy is (px): the mean truncated distance over a
/// few hundred contour pixels, each good to a pixel or so, but neighbours
/// err together.
pub const ENERGY_NOISE_PX: f64 = 0.1;

/// A measurement is never taken as more uncertain than this (cm, one σ):
/// past it, it might as well not be.
const MAX_MEASUREMENT_SIGMA_CM: f64 = 300.0;
