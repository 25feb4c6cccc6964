//! The floor path from two kinds of evidence, weighed by their
//! uncertainties: the inertial steps (the suit's own motion: precise from
//! frame to frame, drifting over seconds) and the camera's measurements
//! (no drift, but blind along its line of sight, lost where the body is
//! hidden, and now and then wrong). A Kalman filter runs forward with the
//! tracker — its prediction is where the camera is searched — and a
//! Rauch–Tung–Striebel pass runs backward once the video has been read, so
//! every frame's position uses the frames after it too.
//!
//! The model, on the floor's (x, z) in cm: `position[i] = position[i − 1] +
//! step[i] + w[i]`, `w[i] ~ N(0, step_sigma[i]² · I)`; a measurement is
//! `position[i] + v[i]`, `v[i] ~ N(0, R[i])` with `R[i]` a full 2×2 matrix (a
//! camera sees across its line of sight far better than along it).

use glam::{DMat2, DVec2};

/// A measurement farther than this many standard deviations (Mahalanobis)
/// from the prediction is taken for a wrong match and not used: at 4σ a
/// right one is rejected about once in 3000 frames (χ² with 2 degrees of
/// freedom).
pub const GATE_SIGMAS: f64 = 4.0;

/// One frame's filtered state and what it was predicted from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Filtered {
    predicted: DVec2,
    predicted_covariance: DMat2,
    position: DVec2,
    covariance: DMat2,
}

/// What happened to a measurement offered to [`FloorFilter::update`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measurement {
    /// Used.
    Used,
    /// Beyond [`GATE_SIGMAS`] of the prediction: left out.
    Rejected,
    /// Beyond the gate, but after `reacquire_after` frames in a row of
    /// rejections: the filter had lost the body, so it starts again from the
    /// camera.
    Reacquired,
}

/// The forward filter over the frames read so far.
#[derive(Clone, Debug)]
pub struct FloorFilter {
    frames: Vec<Filtered>,
    rejected_in_a_row: usize,
    reacquire_after: usize,
}

impl FloorFilter {
    /// A filter whose first frame is at `start` with standard deviation
    /// `start_sigma_cm` per axis; after `reacquire_after` rejected
    /// measurements in a row it trusts the camera again.
    pub fn new(start: DVec2, start_sigma_cm: f64, reacquire_after: usize) -> FloorFilter {
        let covariance = DMat2::from_diagonal(DVec2::splat(start_sigma_cm * start_sigma_cm));
        FloorFilter {
            frames: vec![Filtered {
                predicted: start,
                predicted_covariance: covariance,
                position: start,
                covariance,
            }],
            rejected_in_a_row: 0,
            reacquire_after,
        }
    }

    /// The frames filtered so far.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// The newest frame's position and covariance (cm, cm²).
    pub fn current(&self) -> (DVec2, DMat2) {
        let last = self.last();
        (last.position, last.covariance)
    }

    fn last(&self) -> &Filtered {
        // `new` makes the first frame and nothing removes one.
        &self.frames[self.frames.len() - 1]
    }

    fn last_mut(&mut self) -> &mut Filtered {
        let n = self.frames.len();
        &mut self.frames[n - 1]
    }

    /// Moves on to the next frame by the inertial `step_cm`, uncertain by
    /// `step_sigma_cm` per axis; returns the prediction and its covariance.
    pub fn predict(&mut self, step_cm: DVec2, step_sigma_cm: f64) -> (DVec2, DMat2) {
        let last = *self.last();
        let predicted = last.position + step_cm;
        let predicted_covariance =
            last.covariance + DMat2::from_diagonal(DVec2::splat(step_sigma_cm * step_sigma_cm));
        self.frames.push(Filtered {
            predicted,
            predicted_covariance,
            position: predicted,
            covariance: predicted_covariance,
        });
        (predicted, predicted_covariance)
    }

    /// Offers the newest frame a camera measurement at `measured_cm` with
    /// covariance `covariance_cm2` (symmetric, positive definite).
    pub fn update(&mut self, measured_cm: DVec2, covariance_cm2: DMat2) -> Measurement {
        let last = *self.last();
        let innovation = measured_cm - last.position;
        let innovation_covariance = last.covariance + covariance_cm2;
        if innovation_covariance.determinant().abs() < 1e-300 || !innovation.is_finite() {
            return Measurement::Rejected;
        }
        let inverse = innovation_covariance.inverse();
        let distance2 = innovation.dot(inverse * innovation);
        let outcome = if distance2 <= GATE_SIGMAS * GATE_SIGMAS {
            Measurement::Used
        } else if self.rejected_in_a_row + 1 >= self.reacquire_after {
            Measurement::Reacquired
        } else {
            self.rejected_in_a_row += 1;
            return Measurement::Rejected;
        };
        self.rejected_in_a_row = 0;
        let frame = self.last_mut();
        if outcome == Measurement::Reacquired {
            // Lost: the past says nothing of where the body is now.
            frame.position = measured_cm;
            frame.covariance = covariance_cm2;
            return outcome;
        }
        let gain = last.covariance * inverse;
        frame.position = last.position + gain * innovation;
        // Joseph's form keeps the covariance symmetric and positive.
        let keep = DMat2::IDENTITY - gain;
        frame.covariance =
            keep * last.covariance * keep.transpose() + gain * covariance_cm2 * gain.transpose();
        outcome
    }

    /// The Rauch–Tung–Striebel pass: per frame, the position and covariance
    /// given every frame, before and after.
    pub fn smooth(&self) -> Vec<(DVec2, DMat2)> {
        let n = self.frames.len();
        let mut smoothed: Vec<(DVec2, DMat2)> =
            self.frames.iter().map(|f| (f.position, f.covariance)).collect();
        for i in (0..n.saturating_sub(1)).rev() {
            let (now, next) = (&self.frames[i], &self.frames[i + 1]);
            if next.predicted_covariance.determinant().abs() < 1e-300 {
                continue;
            }
            // The model's transition is the identity: the gain is P_i|i P_i+1|i⁻¹.
            let gain = now.covariance * next.predicted_covariance.inverse();
            let (after, after_covariance) = smoothed[i + 1];
            let position = now.position + gain * (after - next.predicted);
            let covariance =
                now.covariance + gain * (after_covariance - next.predicted_covariance) * gain.transpose();
            smoothed[i] = (position, covariance);
        }
        smoothed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::rng::XorShift64;

    fn isotropic(sigma: f64) -> DMat2 {
        DMat2::from_diagonal(DVec2::splat(sigma * sigma))
    }

    #[test]
    fn exact_steps_and_no_camera_follow_the_steps() {
        let mut filter = FloorFilter::new(DVec2::new(1.0, 2.0), 1.0, 10);
        for _ in 0..10 {
            filter.predict(DVec2::new(3.0, 0.0), 0.5);
        }
        let path = filter.smooth();
        assert!((path[10].0 - DVec2::new(31.0, 2.0)).length() < 1e-12);
        // Uncertainty grows along the way.
        assert!(path[10].1.x_axis.x > path[1].1.x_axis.x);
    }

    #[test]
    fn drifting_steps_are_pulled_back_by_the_camera_and_the_blind_axis_trusts_the_steps() {
        // The truth moves 2 cm a frame along x; the steps say 2.2 (10 % long).
        // The camera sees x to 1 cm but z only to 30 cm, and its z is biased.
        let mut rng = XorShift64(7);
        let mut filter = FloorFilter::new(DVec2::ZERO, 1.0, 10);
        let camera = DMat2::from_diagonal(DVec2::new(1.0, 900.0));
        for i in 1..=300 {
            filter.predict(DVec2::new(2.2, 0.0), 0.5);
            let truth = DVec2::new(2.0 * i as f64, 0.0);
            let noise = DVec2::new(rng.gaussian(), 30.0 * rng.gaussian());
            filter.update(truth + noise, camera);
        }
        let path = filter.smooth();
        for (i, (position, _)) in path.iter().enumerate().skip(10) {
            let truth = DVec2::new(2.0 * i as f64, 0.0);
            assert!((position.x - truth.x).abs() < 3.0, "frame {i}: {position}");
            assert!(position.y.abs() < 15.0, "frame {i}: {position}");
        }
    }

    #[test]
    fn a_wrong_match_is_left_out_and_a_lost_body_is_found_again() {
        let mut filter = FloorFilter::new(DVec2::ZERO, 1.0, 5);
        filter.predict(DVec2::ZERO, 1.0);
        assert_eq!(filter.update(DVec2::new(100.0, 0.0), isotropic(2.0)), Measurement::Rejected);
        let mut outcomes = Vec::new();
        for _ in 0..4 {
            filter.predict(DVec2::ZERO, 1.0);
            outcomes.push(filter.update(DVec2::new(100.0, 0.0), isotropic(2.0)));
        }
        assert_eq!(
            outcomes,
            [Measurement::Rejected, Measurement::Rejected, Measurement::Rejected, Measurement::Reacquired]
        );
        assert_eq!(filter.current().0, DVec2::new(100.0, 0.0));
    }
}
