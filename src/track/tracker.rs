//! The camera tracker, frame by frame: each video frame is made into edges
//! and a foreground mask (`image::pipeline`), the suit's pose of that
//! instant is posed as a body (`body::shape`) and its silhouette
//! (`silhouette`) is fitted to the frame near where the body should be,
//! either as the paper does (`paper`) or as embusen does (below); once every
//! frame is read, the path is smoothed. Frames come in one at a time, so a
//! long video is never held in memory, and the same code runs in the CLI
//! (frames from ffmpeg) and in the browser (frames from a video element).
//!
//! embusen's tracker (`fused`) removes what the paper lists as its limits:
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
//!   and heading are off from what the camera sees.

use glam::{DMat2, DVec2, DVec3};

use crate::body::shape::{BodyShape, PosedBody};
use crate::camera::Camera;
use crate::error::Error;
use crate::image::GreyImage;
use crate::image::pipeline::{Features, PipelineParams, features};
use crate::track::energy::{Fit, FrameTerms};
use crate::track::paper::{PaperTrackParams, paper_smooth, paper_step};
use crate::track::path::{PathFrame, best_path};
use crate::track::search::coarse_to_fine;
use crate::track::silhouette::{Silhouette, SilhouetteRenderer};
use crate::track::smoother::{FloorFilter, Measurement};
use crate::track::suit_motion::{BvhInstant, SuitMotion, VideoTiming};

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
    /// one nat of cost.
    pub path_temperature_px: f64,
    /// Below this confidence a fit is not used.
    pub min_confidence: f64,
    /// After this long (s) of fits rejected as too far from the prediction,
    /// the prediction is taken for lost and the camera trusted again.
    pub reacquire_after_s: f64,
    /// How far the first frame's search reaches around its starting guess (cm).
    pub start_search_cm: f64,
}

impl Default for FusedParams {
    fn default() -> Self {
        FusedParams {
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
            path_temperature_px: 0.025,
            min_confidence: 0.2,
            reacquire_after_s: 0.5,
            start_search_cm: 80.0,
        }
    }
}

/// Which tracker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrackMethod {
    /// Riečický et al.'s, as published.
    Paper(PaperTrackParams),
    /// embusen's.
    Fused(FusedParams),
}

impl TrackMethod {
    pub fn name(&self) -> &'static str {
        match self {
            TrackMethod::Paper(_) => "paper",
            TrackMethod::Fused(_) => "fused",
        }
    }
}

/// One video frame of a track.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackedFrame {
    /// The video frame's time (s).
    pub time_s: f64,
    /// Where the hips are on the floor (x, z, cm), smoothed.
    pub floor_cm: DVec2,
    /// Their height above the floor (cm), as the contact method stands the
    /// body; NaN where the BVH has no pose.
    pub height_cm: f64,
    /// How well the camera saw the body, 0 to 1 (0 where it was not used).
    pub confidence: f64,
    /// The camera's own measurement before smoothing, where one was used.
    pub measured_cm: Option<DVec2>,
    /// The paper's 25 candidates and their energies (the paper's tracker only).
    pub candidates: Vec<(DVec2, f64)>,
}

/// A whole track.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    pub method: TrackMethod,
    pub frames: Vec<TrackedFrame>,
    pub warnings: Vec<String>,
    /// The fused tracker's mean squared Mahalanobis distance of the camera's
    /// measurements from the predictions (NaN for the paper's).
    pub mean_innovation: f64,
}

/// What the tracker needs besides the frames.
#[derive(Clone, Debug)]
pub struct TrackSetup {
    pub camera: Camera,
    pub suit: SuitMotion,
    pub shape: BodyShape,
    pub timing: VideoTiming,
    pub background: GreyImage,
    pub pipeline: PipelineParams,
    pub method: TrackMethod,
}

impl TrackSetup {
    /// The body model in the suit's pose at video frame `i` (its time
    /// through `timing`), standing at the floor's origin; `None` where the
    /// BVH has no pose.
    pub fn posed_body(&self, i: usize) -> Result<Option<PosedBody>, Error> {
        let instant = self.suit.instant(self.timing.bvh_time_s(i));
        self.suit.body_at(instant).map(|body_cm| self.shape.pose(&body_cm, DVec3::ZERO)).transpose()
    }
}

/// The tracker in the middle of a video.
pub struct Tracker {
    setup: TrackSetup,
    scorer: Scorer,
    filter: Option<FloorFilter>,
    /// The paper's chosen positions, unsmoothed.
    paper_path: Vec<DVec2>,
    /// The fused tracker's frames for the path search, one per frame.
    path_frames: Vec<Option<PathRecord>>,
    /// Whether the path search's energies are left to the caller
    /// ([`Tracker::defer_path_energies`]), and the last frame's request.
    defer_path: bool,
    path_request: Option<PathRequest>,
    frames: Vec<TrackedFrame>,
}

impl Tracker {
    pub fn new(setup: TrackSetup) -> Result<Tracker, Error> {
        setup.camera.check_image_size(
            setup.background.width_px,
            setup.background.height_px,
            "the background",
        )?;
        if let TrackMethod::Paper(params) = &setup.method {
            params.check().map_err(|m| Error::whole("<paper tracker>", m))?;
        }
        Ok(Tracker {
            scorer: Scorer::new(&setup.camera),
            setup,
            filter: None,
            paper_path: Vec::new(),
            path_frames: Vec::new(),
            defer_path: false,
            path_request: None,
            frames: Vec::new(),
        })
    }

    /// From now on the fused tracker does not score the path search's
    /// candidates itself (half its work): after each frame
    /// [`Tracker::take_path_request`] says what to score, a [`PathScorer`]
    /// scores it from the same frame (in the page, in a second worker, while
    /// this one reads the next frame), and [`Tracker::set_path_energies`]
    /// hands the energies back before [`Tracker::finish`]. The track is the
    /// same to the last bit.
    pub fn defer_path_energies(&mut self) {
        self.defer_path = true;
    }

    /// What the frame just read leaves to score (deferred only; `None`
    /// where it has nothing: no pose, a fit not believable, the paper's).
    pub fn take_path_request(&mut self) -> Option<PathRequest> {
        self.path_request.take()
    }

    /// The energies of a [`PathRequest`]'s candidates, as
    /// [`PathScorer::energies`] gave them. An error when the frame asked for
    /// none or the count differs.
    pub fn set_path_energies(&mut self, frame: usize, energies_px: Vec<f64>) -> Result<(), Error> {
        let record = self.path_frames.get_mut(frame).and_then(|r| r.as_mut());
        match record {
            Some(r) if r.pending && r.frame.candidates_cm.len() == energies_px.len() => {
                r.frame.energies_px = energies_px;
                r.pending = false;
                Ok(())
            }
            _ => Err(Error::whole(
                &format!("video frame {frame}"),
                format!("{} path energies that no request of this frame asked for", energies_px.len()),
            )),
        }
    }

    /// How many frames still wait for their path energies.
    pub fn path_energies_pending(&self) -> usize {
        self.path_frames.iter().flatten().filter(|r| r.pending).count()
    }

    /// The frames read so far.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Reads the next video frame.
    pub fn push_frame(&mut self, frame: &GreyImage) -> Result<&TrackedFrame, Error> {
        let i = self.frames.len();
        let label = format!("video frame {i}");
        self.setup.camera.check_image_size(frame.width_px, frame.height_px, &label)?;
        self.path_request = None;
        let time_s = i as f64 / self.setup.timing.fps;
        let instant = self.setup.suit.instant(self.setup.timing.bvh_time_s(i));
        let Some(body_cm) = self.setup.suit.body_at(instant) else {
            let floor_cm = self.frames.last().map_or(DVec2::ZERO, |f| f.floor_cm);
            self.paper_path.push(floor_cm);
            if let Some(filter) = &mut self.filter {
                filter.predict(DVec2::ZERO, 0.0);
            }
            self.path_frames.push(None);
            self.frames.push(TrackedFrame {
                time_s,
                floor_cm,
                height_cm: f64::NAN,
                confidence: 0.0,
                measured_cm: None,
                candidates: Vec::new(),
            });
            return Ok(&self.frames[i]);
        };
        let height_cm = body_cm[self.setup.suit.hips].y;
        let body = self.setup.shape.pose(&body_cm, DVec3::ZERO)?;
        let tracked = match self.setup.method {
            TrackMethod::Paper(params) => {
                let features = features(frame, &self.setup.background, &self.setup.pipeline, &label)?;
                self.paper_frame(&params, &body, &features)
            }
            TrackMethod::Fused(params) => self.fused_frame(&params, &body, frame, &label, instant, i)?,
        };
        self.frames.push(TrackedFrame { time_s, height_cm, ..tracked });
        Ok(&self.frames[i])
    }

    /// For evaluations only (a tracker knows no `around_cm`): the least of
    /// the fused energy (the fused parameters of the setup, or the defaults)
    /// in video frame `i`, tried every 2 cm along the camera's line of sight
    /// through `around_cm` within `reach_cm` of it, and every 1 cm across
    /// within 8 cm — how close the camera alone can place the body in that
    /// frame when the truth is known. `None` where the BVH has no pose or
    /// the body is nowhere in the image. Does not advance the tracker.
    pub fn camera_oracle(
        &mut self,
        frame: &GreyImage,
        i: usize,
        around_cm: DVec2,
        reach_cm: f64,
    ) -> Result<Option<DVec2>, Error> {
        let params = match self.setup.method {
            TrackMethod::Fused(params) => params,
            TrackMethod::Paper(_) => FusedParams::default(),
        };
        let label = format!("video frame {i}");
        let camera = self.setup.camera;
        camera.check_image_size(frame.width_px, frame.height_px, &label)?;
        let Some(body) = self.setup.posed_body(i)? else { return Ok(None) };
        let features = features(frame, &self.setup.background, &self.setup.pipeline, &label)?;
        let (terms, depth_cm) = fused_terms(&camera, &params, &features, around_cm);
        let banded = BandedBody::new(&self.setup.shape, &body, &camera, &params, depth_cm);
        let along = line_of_sight(&camera, around_cm);
        let steps = (reach_cm / 2.0).ceil() as i32;
        let mut best: Option<(DVec2, f64)> = None;
        for a in -steps..=steps {
            for b in -8..=8 {
                let p = around_cm + along * (2.0 * a as f64) + along.perp() * b as f64;
                let e = self.scorer.energy(&terms, &banded, p, &params);
                if e.is_finite() && best.is_none_or(|(_, least)| e < least) {
                    best = Some((p, e));
                }
            }
        }
        Ok(best.map(|(p, _)| p))
    }

    fn paper_frame(
        &mut self,
        params: &PaperTrackParams,
        body: &PosedBody,
        features: &Features,
    ) -> TrackedFrame {
        // The paper's energy is untruncated; the terms' truncation is unused.
        let terms = FrameTerms::new(
            &features.edge_distance,
            &features.outside_distance,
            &features.foreground,
            f32::INFINITY,
        );
        // The board's origin is the actor's start.
        let last = self.paper_path.last().copied().unwrap_or(DVec2::ZERO);
        let mut fits = Vec::new();
        let frame = paper_step(last, params, |p| {
            let fit = self.scorer.plain_fit(&terms, body, p);
            fits.push(fit);
            fit.map_or(f64::NAN, |f| f.chamfer_px)
        });
        let position = frame.position();
        self.paper_path.push(position);
        let confidence = fits[frame.chosen].map_or(0.0, |f| f.confidence());
        TrackedFrame {
            time_s: 0.0,
            floor_cm: position,
            height_cm: 0.0,
            confidence,
            measured_cm: Some(position),
            candidates: frame.candidates,
        }
    }

    fn fused_frame(
        &mut self,
        params: &FusedParams,
        body: &PosedBody,
        frame: &GreyImage,
        label: &str,
        instant: BvhInstant,
        i: usize,
    ) -> Result<TrackedFrame, Error> {
        let camera = self.setup.camera;
        let dt = 1.0 / self.setup.timing.fps;
        let before_cm = self.filter.as_ref().map(|f| f.current().0);
        let mut step_cm = DVec2::ZERO;
        let mut step_sigma_cm = f64::INFINITY;
        let mut first_features = None;
        let (prediction, radius_cm) = match &mut self.filter {
            None => {
                // The first frame is searched for over the whole image.
                let f = features(frame, &self.setup.background, &self.setup.pipeline, label)?;
                let guess = self.first_guess(&f, body);
                first_features = Some(f);
                (guess, params.start_search_cm)
            }
            Some(filter) => {
                let before = self.setup.timing.bvh_time_s(i.saturating_sub(1));
                let path = &self.setup.suit.inertial_floor_cm;
                let step = match (
                    SuitMotion::floor_at(path, self.setup.suit.instant(before)),
                    SuitMotion::floor_at(path, instant),
                ) {
                    (Some(a), Some(b)) => b - a,
                    _ => DVec2::ZERO,
                };
                let sigma = params.stride_error * step.length() + params.drift_cm_per_s * dt;
                (step_cm, step_sigma_cm) = (step, sigma);
                let (predicted, covariance) = filter.predict(step, sigma);
                let spread = largest_sigma_cm(covariance);
                (predicted, (params.search_sigmas * spread).clamp(params.min_search_cm, params.max_search_cm))
            }
        };
        // The energy reads the distances only up to the truncation, so they
        // are computed only so far, near the foreground (the same values).
        let pipeline = &self.setup.pipeline;
        let (features, truncate_px) = match first_features {
            Some(f) => (f, pipeline.truncate_px),
            None => {
                let (truncation_px, _) = fused_truncation_px(&camera, params, prediction);
                let truncate_px = Some(pipeline.truncate_px.map_or(truncation_px, |t| t.min(truncation_px)));
                let params = PipelineParams { truncate_px, ..*pipeline };
                (features(frame, &self.setup.background, &params, label)?, truncate_px)
            }
        };
        let (terms, depth_cm) = fused_terms(&camera, params, &features, prediction);
        let banded = BandedBody::new(&self.setup.shape, body, &camera, params, depth_cm);
        let found = coarse_to_fine(prediction, radius_cm, params.resolution_cm, |p| {
            self.scorer.energy(&terms, &banded, p, params)
        });
        let fit = found.and_then(|(p, _)| self.scorer.fit(&terms, &banded, p).map(|fit| (p, fit)));
        let reacquire_after = reacquire_after_frames(params, dt);
        self.filter.get_or_insert_with(|| FloorFilter::new(prediction, radius_cm, dt, reacquire_after));
        let mut confidence = 0.0;
        let mut measured_cm = None;
        let mut across_variance_cm2 = None;
        // A fit not believable is not used, here nor by the path search.
        let believable = fit.is_some_and(|(_, f)| f.confidence() >= params.min_confidence);
        if let Some((p, fit)) = fit
            && believable
        {
            let sigma_px = params.match_sigma_px / fit.confidence();
            let geometric = measurement_covariance(&camera, body, p, sigma_px);
            let along = line_of_sight(&camera, p);
            let across = along.perp();
            let e0 = fit.fused_energy(params.mask_weight, params.uncovered_weight);
            let h = CURVATURE_STEP_CM;
            let mut sigma2 = [0.0; 2];
            for (k, u) in [along, across].into_iter().enumerate() {
                let (plus, minus) = (
                    self.scorer.energy(&terms, &banded, p + u * h, params),
                    self.scorer.energy(&terms, &banded, p - u * h, params),
                );
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
            let filter = self
                .filter
                .get_or_insert_with(|| FloorFilter::new(prediction, radius_cm, dt, reacquire_after));
            if let Some(covariance) = covariance {
                across_variance_cm2 = Some(across.dot(covariance * across));
                match filter.update(p, covariance) {
                    Measurement::Used | Measurement::Reacquired => {
                        confidence = fit.confidence();
                        measured_cm = Some(p);
                    }
                    Measurement::Rejected => {}
                }
            }
        }
        if params.path_reach_cm > 0.0 && params.path_spacing_cm > 0.0 {
            let base = measured_cm.or(fit.map(|(p, _)| p)).unwrap_or(prediction);
            let along = line_of_sight(&camera, base);
            let steps = (params.path_reach_cm / params.path_spacing_cm).round() as i32;
            let candidates_cm: Vec<DVec2> =
                (-steps..=steps).map(|k| base + along * (k as f64 * params.path_spacing_cm)).collect();
            // Where the fit is not believable the suit's steps carry the
            // frame (all candidates alike).
            let pending = believable && self.defer_path;
            let energies_px = if !believable {
                vec![f64::NAN; candidates_cm.len()]
            } else if pending {
                self.path_request = Some(PathRequest {
                    frame: i,
                    prediction_cm: prediction,
                    truncate_px,
                    candidates_cm: candidates_cm.clone(),
                });
                Vec::new()
            } else {
                candidates_cm.iter().map(|&p| self.scorer.energy(&terms, &banded, p, params)).collect()
            };
            self.path_frames.push(Some(PathRecord {
                pending,
                frame: PathFrame {
                    candidates_cm,
                    energies_px,
                    expected_step_cm: before_cm.map_or(DVec2::ZERO, |b| prediction - b),
                    step_sigma_cm,
                },
                inertial_step_cm: step_cm,
                across_variance_cm2: across_variance_cm2
                    .unwrap_or(MAX_MEASUREMENT_SIGMA_CM * MAX_MEASUREMENT_SIGMA_CM),
                along,
            }));
        }
        Ok(TrackedFrame {
            time_s: 0.0,
            floor_cm: self.filter.as_ref().map_or(prediction, |f| f.current().0),
            height_cm: 0.0,
            confidence,
            measured_cm,
            candidates: Vec::new(),
        })
    }

    /// Where to look for the body in the first frame: the floor below the
    /// foreground's lowest pixels (the feet stand on the floor), or the
    /// world's origin (where the board is, and where the paper has the actor
    /// start) when there is no foreground, whichever fits better.
    fn first_guess(&mut self, features: &Features, body: &PosedBody) -> DVec2 {
        let mask = &features.foreground;
        let (w, h) = (mask.width_px as usize, mask.height_px as usize);
        let mut guesses = vec![DVec2::ZERO];
        if let Some(bottom) =
            (0..h).rev().find(|&y| mask.on[y * w..(y + 1) * w].iter().filter(|&&o| o).count() >= 3)
        {
            let row = &mask.on[bottom * w..(bottom + 1) * w];
            let xs: Vec<usize> = (0..w).filter(|&x| row[x]).collect();
            let x = xs[xs.len() / 2] as f64;
            if let Some(floor) = self.setup.camera.floor_point(glam::DVec2::new(x, bottom as f64)) {
                guesses.push(DVec2::new(floor.x, floor.z));
            }
        }
        let terms = FrameTerms::new(&features.edge_distance, &features.outside_distance, mask, 8.0);
        guesses
            .into_iter()
            .map(|g| {
                (
                    g,
                    self.scorer
                        .plain_fit(&terms, body, g)
                        .map_or(f64::INFINITY, |f| f.fused_energy(1.0, 0.0)),
                )
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(DVec2::ZERO, |(g, _)| g)
    }

    /// The forward filter run again with the path search's choices as its
    /// measurements (along the line of sight as uncertain as the candidates'
    /// spacing, across as the fits were), ready for smoothing; `None` when
    /// the search is off or had no frames.
    fn path_search(&self, params: &FusedParams, first_pass: &FloorFilter) -> Option<FloorFilter> {
        let start = self.path_frames.iter().position(|f| f.is_some())?;
        let records = &self.path_frames[start..];
        // `first_pass` starts at the first frame with a pose, as `records` do.
        if records.len() != first_pass.frame_count() {
            return None;
        }
        let frames: Vec<PathFrame> = records
            .iter()
            .map(|r| {
                r.as_ref().map_or(
                    PathFrame {
                        candidates_cm: Vec::new(),
                        energies_px: Vec::new(),
                        expected_step_cm: DVec2::ZERO,
                        step_sigma_cm: f64::INFINITY,
                    },
                    |r| r.frame.clone(),
                )
            })
            .collect();
        let chosen = best_path(&frames, params.path_temperature_px);
        let dt = 1.0 / self.setup.timing.fps;
        let reacquire_after = reacquire_after_frames(params, dt);
        let along_variance = params.path_spacing_cm * params.path_spacing_cm;
        let measurement = |r: &PathRecord, k: usize| {
            let across = r.along.perp();
            let basis = DMat2::from_cols(r.along, across);
            let covariance = basis
                * DMat2::from_diagonal(DVec2::new(along_variance, r.across_variance_cm2))
                * basis.transpose();
            (r.frame.candidates_cm[k], covariance)
        };
        let first = records[0].as_ref()?;
        let (start_cm, _) = measurement(first, chosen[0]);
        let mut filter = FloorFilter::new(start_cm, params.path_spacing_cm, dt, reacquire_after);
        for (record, &k) in records.iter().zip(&chosen).skip(1) {
            match record {
                None => {
                    filter.predict(DVec2::ZERO, 0.0);
                }
                Some(r) => {
                    filter.predict(r.inertial_step_cm, r.frame.step_sigma_cm);
                    if r.frame.energies_px.iter().any(|e| e.is_finite()) {
                        let (p, covariance) = measurement(r, k);
                        filter.update(p, covariance);
                    }
                }
            }
        }
        Some(filter)
    }

    /// The track, smoothed. Deferred path energies that never came count
    /// as a fit not believed (and are said in the warnings).
    pub fn finish(mut self) -> Track {
        let mut warnings = Vec::new();
        let never_came = self.path_energies_pending();
        if never_came > 0 {
            warnings
                .push(format!("{never_came} frames' path energies never came: the suit's steps carry them"));
            for r in self.path_frames.iter_mut().flatten().filter(|r| r.pending) {
                r.frame.energies_px = vec![f64::NAN; r.frame.candidates_cm.len()];
                r.pending = false;
            }
        }
        let mut frames = std::mem::take(&mut self.frames);
        let smoothed: Vec<DVec2> = match (&self.setup.method, &self.filter) {
            (TrackMethod::Paper(params), _) => paper_smooth(&self.paper_path, params),
            (TrackMethod::Fused(params), Some(filter)) => match self.path_search(params, filter) {
                Some(searched) => searched.smooth().into_iter().map(|(p, _)| p).collect(),
                None => filter.smooth().into_iter().map(|(p, _)| p).collect(),
            },
            (TrackMethod::Fused(_), None) => frames.iter().map(|f| f.floor_cm).collect(),
        };
        // The filter starts at the first frame with a pose: align the ends.
        let offset = frames.len().saturating_sub(smoothed.len());
        for (frame, p) in frames.iter_mut().skip(offset).zip(smoothed) {
            frame.floor_cm = p;
        }
        // A frame without a pose has no height; one the camera did not see
        // has no confidence.
        let without_pose = frames.iter().filter(|f| f.height_cm.is_nan()).count();
        if without_pose > 0 {
            warnings
                .push(format!("{without_pose} video frames have no pose in the BVH (outside its time span)"));
        }
        let unseen: Vec<bool> =
            frames.iter().map(|f| f.confidence == 0.0 && f.height_cm.is_finite()).collect();
        let unseen_count = unseen.iter().filter(|&&u| u).count();
        if unseen_count > 0 {
            warnings.push(format!(
                "the camera did not see the body well enough in video frames {} ({unseen_count} of {}): the suit's motion carries them",
                frame_ranges(&unseen),
                frames.len()
            ));
        }
        let mean_innovation = self.filter.as_ref().map_or(f64::NAN, |f| f.mean_innovation());
        Track { method: self.setup.method, frames, warnings, mean_innovation }
    }
}

/// What the path search asks of one frame when its energies are deferred
/// ([`Tracker::defer_path_energies`]): the fused energy at each candidate,
/// in the frame's terms as the tracker made them.
#[derive(Clone, Debug, PartialEq)]
pub struct PathRequest {
    /// The video frame.
    pub frame: usize,
    /// Where the frame's terms were made: the prediction (x, z, cm).
    pub prediction_cm: DVec2,
    /// The cap of the distance transforms the frame's features had.
    pub truncate_px: Option<f32>,
    /// Where to score (x, z, cm).
    pub candidates_cm: Vec<DVec2>,
}

/// Scores [`PathRequest`]s apart from the tracker, from the same frames:
/// what the tracker would have computed, to the last bit.
pub struct PathScorer {
    setup: TrackSetup,
    params: FusedParams,
    scorer: Scorer,
}

impl PathScorer {
    /// An error when the setup's tracker is not the fused one (the paper's
    /// has no path search).
    pub fn new(setup: TrackSetup) -> Result<PathScorer, Error> {
        let TrackMethod::Fused(params) = setup.method else {
            return Err(Error::whole("<path scorer>", "only the fused tracker searches a path"));
        };
        Ok(PathScorer { scorer: Scorer::new(&setup.camera), params, setup })
    }

    /// The fused energy (px) at each of `request`'s candidates in `frame`,
    /// video frame `request.frame`; NaN where the body is not in the image.
    pub fn energies(&mut self, request: &PathRequest, frame: &GreyImage) -> Result<Vec<f64>, Error> {
        let label = format!("video frame {}", request.frame);
        let setup = &self.setup;
        setup.camera.check_image_size(frame.width_px, frame.height_px, &label)?;
        let Some(body) = setup.posed_body(request.frame)? else {
            return Err(Error::whole(&label, "no pose in the BVH here: no path to score"));
        };
        let pipeline = PipelineParams { truncate_px: request.truncate_px, ..setup.pipeline };
        let features = features(frame, &setup.background, &pipeline, &label)?;
        let (terms, depth_cm) = fused_terms(&setup.camera, &self.params, &features, request.prediction_cm);
        let banded = BandedBody::new(&setup.shape, &body, &setup.camera, &self.params, depth_cm);
        let params = self.params;
        Ok(request.candidates_cm.iter().map(|&p| self.scorer.energy(&terms, &banded, p, &params)).collect())
    }
}

/// Scores a body's silhouette at floor positions in one frame's terms: a
/// renderer and its two silhouettes, kept from one position to the next.
struct Scorer {
    renderer: SilhouetteRenderer,
    silhouette: Silhouette,
    /// The widened body's silhouette, for the band.
    band_silhouette: Silhouette,
}

impl Scorer {
    fn new(camera: &Camera) -> Scorer {
        Scorer {
            renderer: SilhouetteRenderer::new(camera),
            silhouette: Silhouette::empty(camera.image_size),
            band_silhouette: Silhouette::empty(camera.image_size),
        }
    }

    /// The fused energy of `body` at `floor_cm`; NaN where it is not in the image.
    fn energy(
        &mut self,
        terms: &FrameTerms,
        body: &BandedBody,
        floor_cm: DVec2,
        params: &FusedParams,
    ) -> f64 {
        self.fit(terms, body, floor_cm)
            .map_or(f64::NAN, |f| f.fused_energy(params.mask_weight, params.uncovered_weight))
    }

    /// The fit of `body` at `floor_cm` with its band (none when the band is
    /// 0 px wide: then the widened body is not drawn at all).
    fn fit(&mut self, terms: &FrameTerms, body: &BandedBody, floor_cm: DVec2) -> Option<Fit> {
        let shift = DVec3::new(floor_cm.x, 0.0, floor_cm.y);
        self.renderer.render_into(&body.body, shift, &mut self.silhouette);
        if body.band_px <= 0.0 {
            return terms.fit(&self.silhouette);
        }
        self.renderer.render_into(&body.widened, shift, &mut self.band_silhouette);
        terms.fit_in_band(&self.silhouette, &self.band_silhouette, body.band_px)
    }

    /// The fit of `body` alone at `floor_cm` (no band).
    fn plain_fit(&mut self, terms: &FrameTerms, body: &PosedBody, floor_cm: DVec2) -> Option<Fit> {
        self.renderer.render_into(body, DVec3::new(floor_cm.x, 0.0, floor_cm.y), &mut self.silhouette);
        terms.fit(&self.silhouette)
    }
}

/// What the path search keeps of one frame.
#[derive(Clone, Debug)]
struct PathRecord {
    frame: PathFrame,
    /// Its energies are deferred and have not come yet.
    pending: bool,
    /// The suit's own step into this frame, as the forward filter took it.
    inertial_step_cm: DVec2,
    /// How uncertain the frame's fit was across the line of sight (cm²).
    across_variance_cm2: f64,
    /// The line of sight's direction on the floor.
    along: DVec2,
}

/// One frame's body as the fused energy scores it: posed, widened by the
/// band ([`BodyShape::widened`]), and the band's width in pixels at the
/// body's distance.
struct BandedBody {
    body: PosedBody,
    widened: PosedBody,
    band_px: f64,
}

impl BandedBody {
    /// `body` of `shape` with its band, `depth_cm` from `camera`; no band
    /// (0 px) when the band term is off.
    fn new(
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
}

/// The fused energy's image terms of a frame for a body standing near
/// `near_cm`, the contour's distances truncated at `params.truncation_cm`
/// at the body's distance; and that distance (cm, the camera's depth of
/// the point 1 m above `near_cm`, at least 50 cm).
pub(crate) fn fused_terms<'a>(
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
    let depth_cm = camera.point_in_camera(DVec3::new(near_cm.x, 100.0, near_cm.y)).z.max(50.0);
    let truncation_px = (camera.intrinsics.fx_px * params.truncation_cm / depth_cm) as f32;
    (truncation_px.max(1.0), depth_cm)
}

/// The direction on the floor (x, z) of the camera's line of sight through
/// `floor_cm`: from below the camera's centre towards it.
fn line_of_sight(camera: &Camera, floor_cm: DVec2) -> DVec2 {
    let centre = camera.center_in_world();
    (floor_cm - DVec2::new(centre.x, centre.z)).normalize_or(DVec2::X)
}

/// After this many frames of rejected fits the filter trusts the camera
/// again ([`FusedParams::reacquire_after_s`] at `dt_s` a frame, at least 1).
fn reacquire_after_frames(params: &FusedParams, dt_s: f64) -> usize {
    ((params.reacquire_after_s / dt_s).round() as usize).max(1)
}

/// The frames where `flags` holds, as ranges: `3–7, 12, 40–41`.
fn frame_ranges(flags: &[bool]) -> String {
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    for (i, _) in flags.iter().enumerate().filter(|(_, f)| **f) {
        match ranges.last_mut() {
            Some((_, last)) if *last + 1 == i => *last = i,
            _ => ranges.push((i, i)),
        }
    }
    let text: Vec<String> =
        ranges.iter().map(|&(a, b)| if a == b { a.to_string() } else { format!("{a}–{b}") }).collect();
    text.join(", ")
}

/// How far either side of a fit (cm) the energy is probed for its curvature.
const CURVATURE_STEP_CM: f64 = 10.0;

/// How uncertain a fit's energy is (px): the mean truncated distance over a
/// few hundred contour pixels, each good to a pixel or so, but neighbours
/// err together.
const ENERGY_NOISE_PX: f64 = 0.1;

/// A measurement is never taken as more uncertain than this (cm, one σ):
/// past it, it might as well not be.
const MAX_MEASUREMENT_SIGMA_CM: f64 = 300.0;

/// The square root of the covariance's larger eigenvalue (cm).
fn largest_sigma_cm(covariance: DMat2) -> f64 {
    let (a, b, d) = (covariance.x_axis.x, covariance.y_axis.x, covariance.y_axis.y);
    let mean = 0.5 * (a + d);
    let spread = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    (mean + spread).max(0.0).sqrt()
}

/// The covariance (cm²) of a floor position measured to `sigma_px` in the
/// image: `σ² (Jᵀ J)⁻¹`, with `Jᵀ J` the mean over the body's spheres of
/// how their pixels move per cm of floor shift (finite differences through
/// the lens). Along the camera's line of sight the pixels barely move, so
/// that direction comes out uncertain, as it is. `None` when the body is
/// not in front of the camera.
fn measurement_covariance(
    camera: &Camera,
    body: &PosedBody,
    floor_cm: DVec2,
    sigma_px: f64,
) -> Option<DMat2> {
    let shift = DVec3::new(floor_cm.x, 0.0, floor_cm.y);
    let mut normal = DMat2::ZERO;
    let mut count = 0usize;
    for sphere in &body.spheres {
        let at = sphere.centre_cm + shift;
        let (Some(p), Some(px), Some(pz)) = (
            camera.point_in_image(at),
            camera.point_in_image(at + DVec3::X),
            camera.point_in_image(at + DVec3::Z),
        ) else {
            continue;
        };
        let j = DMat2::from_cols(px - p, pz - p);
        normal += j.transpose() * j;
        count += 1;
    }
    if count == 0 {
        return None;
    }
    let normal = normal * (1.0 / count as f64);
    if normal.determinant().abs() < 1e-12 {
        return None;
    }
    Some(normal.inverse() * (sigma_px * sigma_px))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_name_runs_and_single_frames() {
        let flags = [false, true, true, true, false, true, false, false, true, true];
        assert_eq!(frame_ranges(&flags), "1–3, 5, 8–9");
        assert_eq!(frame_ranges(&[false; 3]), "");
    }

    #[test]
    fn the_covariance_of_a_camera_s_measurement_is_long_along_its_line_of_sight() {
        // A camera on the -Z side looking along +Z at a body 5 m away: a
        // floor shift across the view (x) moves the pixels far more than one
        // along it (z).
        let camera = Camera {
            image_size: crate::camera::ImageSize { width_px: 640, height_px: 480 },
            intrinsics: crate::camera::Intrinsics { fx_px: 500.0, fy_px: 500.0, cx_px: 319.5, cy_px: 239.5 },
            distortion: crate::camera::Distortion::default(),
            camera_from_world: glam::DAffine3::from_mat3_translation(
                glam::DMat3::from_cols(DVec3::X, DVec3::NEG_Y, DVec3::Z),
                DVec3::new(0.0, 150.0, -500.0),
            )
            .inverse(),
        };
        let body = PosedBody {
            spheres: [0.0, 50.0, 100.0, 150.0]
                .map(|y| crate::body::shape::Sphere { centre_cm: DVec3::new(0.0, y, 0.0), radius_cm: 10.0 })
                .to_vec(),
            cones: vec![(0, 1), (1, 2), (2, 3)],
        };
        let covariance = measurement_covariance(&camera, &body, DVec2::ZERO, 1.0).unwrap();
        let (across, along) = (covariance.x_axis.x, covariance.y_axis.y);
        assert!(along > 10.0 * across, "across {across} cm², along {along} cm²");
        assert!((largest_sigma_cm(covariance) - along.sqrt()).abs() < 1e-6 * along.sqrt());
    }
}
