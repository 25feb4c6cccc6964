//! How the fused tracker scores one frame: the energy at a floor position,
//! the search for its least, and what a fit measures; apart from the
//! tracker's filtering over frames, and shared with the path scorer.

use glam::{DMat2, DVec2, DVec3};

use super::params::{ENERGY_NOISE_PX, FusedParams};
use crate::body::shape::{BodyShape, PosedBody};
use crate::camera::Camera;
use crate::image::Shrink;
use crate::image::components::blobs;
use crate::image::pipeline::Features;
use crate::track::energy::{BandedBody, FrameTerms, Scorer, SilhouetteFit};
use crate::track::measurement::measurement_covariance;
use crate::track::path::{PathFrame, PathRecord, PathRequest};
use crate::track::search::coarse_to_fine;
use crate::track::setup::TrackSetup;
use crate::track::smoother::FloorFilter;
use crate::track::smoother::Measurement;
use crate::track::smoother::frames_per_error;

/// Where the fused tracker expects the body in a frame, before reading it.
#[derive(Clone, Copy, Debug)]
pub struct FusedPrediction {
    /// The filter's prediction and how far around it to search (cm); `None`
    /// in the first frame, searched for around a guess from the frame itself.
    pub(super) predicted: Option<(DVec2, f64)>,
    /// Whether the filter has lost the body: the frame is searched for as
    /// the first was, the prediction one guess among the frame's own.
    pub(super) lost: bool,
    /// The filter's position before the prediction.
    pub(super) before_cm: Option<DVec2>,
    /// The suit's step into this frame and its uncertainty (cm, one σ).
    pub(super) step_cm: DVec2,
    pub(super) step_sigma_cm: f64,
    /// How far the frame's distance transforms are needed (px at the
    /// working scale): the energy reads them only up to its truncation, so
    /// they are computed only so far, near the foreground (the same values).
    pub truncate_px: Option<f32>,
    /// How much the frame is shrunk before it is read
    /// ([`working_scale`](crate::track::working_scale::working_scale)): not at
    /// all where nothing says where the body is.
    pub working_scale: Shrink,
}

/// What the search and the filter made of a frame.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Measured {
    /// Where the filter predicted the body (before a first fit: where the
    /// frame's best guess put it).
    pub(super) prediction_cm: DVec2,
    /// Where the frame's terms were made and the search centred: the
    /// prediction, or where a lost filter's best guess put the body.
    pub(super) terms_at_cm: DVec2,
    /// The least energy's position, if any.
    pub(super) fit_cm: Option<DVec2>,
    /// Whether its fit is believable (used here and by the path search).
    pub(super) believable: bool,
    /// What the filter took: the fit's confidence and position where used.
    pub(super) confidence: f64,
    pub(super) measured_cm: Option<DVec2>,
    /// How uncertain the fit was across the line of sight (cm²).
    pub(super) across_variance_cm2: Option<f64>,
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
    pub(super) fn search(&mut self, around_cm: DVec2, radius_cm: f64) -> Option<(DVec2, SilhouetteFit)> {
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
    pub(super) fn measure(
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
    pub(super) fn path_record(
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
pub(super) fn best_guess(
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
pub(super) fn body_depth_cm(camera: &Camera, near_cm: DVec2) -> f64 {
    camera.point_in_camera(DVec3::new(near_cm.x, 100.0, near_cm.y)).z.max(50.0)
}

/// `params.truncation_cm` in `camera`'s pixels (at least 1) at `depth_cm`.
pub(super) fn truncation_px_at(camera: &Camera, params: &FusedParams, depth_cm: f64) -> f32 {
    ((camera.intrinsics.fx_px * params.truncation_cm / depth_cm) as f32).max(1.0)
}

/// The direction on the floor (x, z) of the camera's line of sight through
/// `floor_cm` ([`Camera::line_of_sight_on_floor`]); +x right below the
/// camera's centre, where any direction is as good.
pub(crate) fn line_of_sight(camera: &Camera, floor_cm: DVec2) -> DVec2 {
    let along = camera.line_of_sight_on_floor(floor_cm);
    if along == DVec2::ZERO { DVec2::X } else { along }
}

/// How far either side of a fit (cm) the energy is probed for its curvature.
const CURVATURE_STEP_CM: f64 = 10.0;

/// A measurement is never taken as more uncertain than this (cm, one σ):
/// past it, it might as well not be.
const MAX_MEASUREMENT_SIGMA_CM: f64 = 300.0;
