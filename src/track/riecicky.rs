//! Riečický et al.'s tracker, as published ("Optical-inertial
//! synchronization of mocap suit with single camera setup"): the body starts
//! where the calibration board says (the world origin); in each frame its
//! silhouette, posed as the suit says, is tried at the last position and at
//! `steps` × `step_cm` along each of `directions` floor directions (25
//! positions with the paper's 8 × 3 × 10 cm), each scored by the Chamfer
//! energy `e = Σ DT · S / count(S)` (the distance to the video's nearest
//! edge, averaged over the silhouette's edge pixels), and the cheapest is the
//! new position. The path is then smoothed by a Gaussian over
//! `smoothing_steps` frames. The search never looks farther than
//! `steps × step_cm` from the last position, so a body that gets 30 cm
//! behind stays behind: that is one of the limits the paper states, kept
//! here on purpose.
//!
//! [`RiecickyTracker`] is this tracker's state between frames; `tracker`
//! runs it (or the fused one) over a video.

use glam::DVec2;

use crate::body::shape::PosedBody;
use crate::error::Error;
use crate::image::pipeline::Features;
use crate::signal::smoothing::smooth_gaussian_clean;
use crate::track::energy::{FrameTerms, Scorer};
use crate::track::setup::FrameEstimate;

/// The paper's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RiecickyParams {
    /// Floor directions tried, evenly spread (8).
    pub directions: usize,
    /// Steps tried along each direction (3).
    pub steps: usize,
    /// The length of a step (10 cm).
    pub step_cm: f64,
    /// The Gaussian smoothing's window (20 frames; its standard deviation is
    /// a fifth of it, the kernel reaching 2.5 of them each side).
    pub smoothing_steps: f64,
}

impl Default for RiecickyParams {
    fn default() -> Self {
        RiecickyParams::PUBLISHED
    }
}

impl RiecickyParams {
    /// The paper's own: 8 directions × 3 steps of 10 cm, smoothed over 20 frames.
    pub const PUBLISHED: RiecickyParams =
        RiecickyParams { directions: 8, steps: 3, step_cm: 10.0, smoothing_steps: 20.0 };

    /// An error naming the parameter that makes no search.
    pub fn check(&self) -> Result<(), String> {
        if self.directions == 0 || self.directions > 360 {
            return Err(format!("directions must be 1 to 360, not {}", self.directions));
        }
        if self.steps == 0 || self.steps > 100 {
            return Err(format!("steps must be 1 to 100, not {}", self.steps));
        }
        if !(self.step_cm.is_finite() && self.step_cm > 0.0 && self.step_cm <= 1000.0) {
            return Err(format!("the step must be more than 0 and at most 1000 cm, not {}", self.step_cm));
        }
        if !(self.smoothing_steps.is_finite() && self.smoothing_steps >= 0.0) {
            return Err(format!(
                "the smoothing window must be 0 or more frames, not {}",
                self.smoothing_steps
            ));
        }
        Ok(())
    }

    /// The positions tried around `last`: `last` itself first, then by
    /// direction (from +x towards +z) and step.
    pub fn candidates(&self, last: DVec2) -> Vec<DVec2> {
        let mut out = Vec::with_capacity(1 + self.directions * self.steps);
        out.push(last);
        for d in 0..self.directions {
            let angle = std::f64::consts::TAU * d as f64 / self.directions as f64;
            let direction = DVec2::new(libm::cos(angle), libm::sin(angle));
            for k in 1..=self.steps {
                out.push(last + direction * (k as f64 * self.step_cm));
            }
        }
        out
    }
}

/// One frame's search: every candidate with its energy, and the one chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct RiecickyFrame {
    pub candidates: Vec<(DVec2, f64)>,
    /// Index into `candidates` of the least energy (the first of equals;
    /// the last position when no candidate has a finite energy).
    pub chosen: usize,
}

impl RiecickyFrame {
    pub fn position(&self) -> DVec2 {
        self.candidates[self.chosen].0
    }
}

/// One frame of the paper's search from `last`, `energy` scoring a floor
/// position (NaN or infinite where the silhouette is not in the image).
pub fn riecicky_step(
    last: DVec2,
    params: &RiecickyParams,
    mut energy: impl FnMut(DVec2) -> f64,
) -> RiecickyFrame {
    let candidates: Vec<(DVec2, f64)> = params.candidates(last).into_iter().map(|p| (p, energy(p))).collect();
    let mut chosen = 0;
    for (i, (_, e)) in candidates.iter().enumerate() {
        let best = candidates[chosen].1;
        if e.is_finite() && (!best.is_finite() || *e < best) {
            chosen = i;
        }
    }
    RiecickyFrame { candidates, chosen }
}

/// The paper's smoothing of the chosen positions.
pub fn riecicky_smooth(path: &[DVec2], params: &RiecickyParams) -> Vec<DVec2> {
    let axis = |get: fn(&DVec2) -> f64| {
        smooth_gaussian_clean(&path.iter().map(get).collect::<Vec<_>>(), params.smoothing_steps, 2.5)
    };
    let (x, y) = (axis(|p| p.x), axis(|p| p.y));
    x.into_iter().zip(y).map(|(x, y)| DVec2::new(x, y)).collect()
}

/// The paper's tracker in the middle of a video.
pub struct RiecickyTracker {
    params: RiecickyParams,
    /// The positions chosen so far, unsmoothed, one per frame.
    path: Vec<DVec2>,
    /// Each frame's candidates with their energies (none without a pose).
    candidates: Vec<Vec<(DVec2, f64)>>,
}

impl RiecickyTracker {
    /// An error naming the parameter that makes no search.
    pub fn new(params: RiecickyParams) -> Result<RiecickyTracker, Error> {
        params.check().map_err(|m| Error::whole("<paper tracker>", m))?;
        Ok(RiecickyTracker { params, path: Vec::new(), candidates: Vec::new() })
    }

    pub fn params(&self) -> RiecickyParams {
        self.params
    }

    /// A frame without a pose: the body stays at `floor_cm`.
    pub fn skip_frame(&mut self, floor_cm: DVec2) {
        self.path.push(floor_cm);
        self.candidates.push(Vec::new());
    }

    /// The search in one frame, `body` scored against its `features`.
    pub fn frame(&mut self, scorer: &mut Scorer, body: &PosedBody, features: &Features) -> FrameEstimate {
        // The paper's energy is untruncated; the terms' truncation is unused.
        let terms = FrameTerms::new(
            &features.edge_distance,
            &features.outside_distance,
            &features.foreground,
            f32::INFINITY,
        );
        // The board's origin is the actor's start.
        let last = self.path.last().copied().unwrap_or(DVec2::ZERO);
        let mut fits = Vec::new();
        let frame = riecicky_step(last, &self.params, |p| {
            let fit = scorer.plain_fit(&terms, body, p);
            fits.push(fit);
            fit.map_or(f64::NAN, |f| f.chamfer_px)
        });
        let position = frame.position();
        self.path.push(position);
        self.candidates.push(frame.candidates);
        let confidence = fits[frame.chosen].map_or(0.0, |f| f.confidence());
        FrameEstimate { floor_cm: position, confidence, measured_cm: Some(position) }
    }

    /// The smoothed path, and each frame's candidates.
    pub fn finish(self) -> (Vec<DVec2>, Vec<Vec<(DVec2, f64)>>) {
        (riecicky_smooth(&self.path, &self.params), self.candidates)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twenty_five_positions_around_the_last_one() {
        let params = RiecickyParams::default();
        let candidates = params.candidates(DVec2::new(5.0, -5.0));
        assert_eq!(candidates.len(), 25);
        assert_eq!(candidates[0], DVec2::new(5.0, -5.0));
        assert!((candidates[3] - DVec2::new(35.0, -5.0)).length() < 1e-12);
        let farthest = candidates.iter().map(|c| (*c - candidates[0]).length()).fold(0.0, f64::max);
        assert!((farthest - 30.0).abs() < 1e-9);
    }

    #[test]
    fn the_search_takes_the_least_energy_and_cannot_catch_up_past_its_reach() {
        let params = RiecickyParams::default();
        let target = DVec2::new(100.0, 0.0);
        let mut position = DVec2::ZERO;
        for _ in 0..2 {
            position = riecicky_step(position, &params, |p| (p - target).length()).position();
        }
        // Two frames of 30 cm reach 60 cm, not the 100 cm away.
        assert!((position - DVec2::new(60.0, 0.0)).length() < 1e-9);
        // A frame whose every energy is unknown keeps the last position.
        let frame = riecicky_step(position, &params, |_| f64::NAN);
        assert_eq!(frame.position(), position);
        assert!(RiecickyParams { steps: 0, ..params }.check().is_err());
    }
}
