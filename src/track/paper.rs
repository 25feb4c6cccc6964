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

use glam::DVec2;

use crate::signal::smoothing::smooth_gaussian_clean;

/// The paper's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperTrackParams {
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

impl Default for PaperTrackParams {
    fn default() -> Self {
        PaperTrackParams { directions: 8, steps: 3, step_cm: 10.0, smoothing_steps: 20.0 }
    }
}

impl PaperTrackParams {
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
pub struct PaperFrame {
    pub candidates: Vec<(DVec2, f64)>,
    /// Index into `candidates` of the least energy (the first of equals;
    /// the last position when no candidate has a finite energy).
    pub chosen: usize,
}

impl PaperFrame {
    pub fn position(&self) -> DVec2 {
        self.candidates[self.chosen].0
    }
}

/// One frame of the paper's search from `last`, `energy` scoring a floor
/// position (NaN or infinite where the silhouette is not in the image).
pub fn paper_step(
    last: DVec2,
    params: &PaperTrackParams,
    mut energy: impl FnMut(DVec2) -> f64,
) -> PaperFrame {
    let candidates: Vec<(DVec2, f64)> = params.candidates(last).into_iter().map(|p| (p, energy(p))).collect();
    let mut chosen = 0;
    for (i, (_, e)) in candidates.iter().enumerate() {
        let best = candidates[chosen].1;
        if e.is_finite() && (!best.is_finite() || *e < best) {
            chosen = i;
        }
    }
    PaperFrame { candidates, chosen }
}

/// The paper's smoothing of the chosen positions.
pub fn paper_smooth(path: &[DVec2], params: &PaperTrackParams) -> Vec<DVec2> {
    let axis = |get: fn(&DVec2) -> f64| {
        smooth_gaussian_clean(&path.iter().map(get).collect::<Vec<_>>(), params.smoothing_steps, 2.5)
    };
    let (x, y) = (axis(|p| p.x), axis(|p| p.y));
    x.into_iter().zip(y).map(|(x, y)| DVec2::new(x, y)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twenty_five_positions_around_the_last_one() {
        let params = PaperTrackParams::default();
        let candidates = params.candidates(DVec2::new(5.0, -5.0));
        assert_eq!(candidates.len(), 25);
        assert_eq!(candidates[0], DVec2::new(5.0, -5.0));
        assert!((candidates[3] - DVec2::new(35.0, -5.0)).length() < 1e-12);
        let farthest = candidates.iter().map(|c| (*c - candidates[0]).length()).fold(0.0, f64::max);
        assert!((farthest - 30.0).abs() < 1e-9);
    }

    #[test]
    fn the_search_takes_the_least_energy_and_cannot_catch_up_past_its_reach() {
        let params = PaperTrackParams::default();
        let target = DVec2::new(100.0, 0.0);
        let mut position = DVec2::ZERO;
        for _ in 0..2 {
            position = paper_step(position, &params, |p| (p - target).length()).position();
        }
        // Two frames of 30 cm reach 60 cm, not the 100 cm away.
        assert!((position - DVec2::new(60.0, 0.0)).length() < 1e-9);
        // A frame whose every energy is unknown keeps the last position.
        let frame = paper_step(position, &params, |_| f64::NAN);
        assert_eq!(frame.position(), position);
        assert!(PaperTrackParams { steps: 0, ..params }.check().is_err());
    }
}
