//! The floor path from two kinds of evidence, weighed by their
//! uncertainties: the inertial steps (the suit's own motion: precise from
//! frame to frame, but its strides a few percent too long or short and its
//! heading drifting) and the camera's measurements (no drift, but blind along
//! its line of sight, lost where the body is hidden, and now and then wrong).
//! A Kalman filter runs forward with the tracker — its prediction is where
//! the camera is searched — and a Rauch–Tung–Striebel pass runs backward once
//! the video has been read, so every frame's position uses the frames after
//! it too.
//!
//! The model, on the floor's (x, z) in cm: the state is the position `p` and
//! a similarity `(a, b)` that maps an inertial step `u` onto the floor, `[[a,
//! −b], [b, a]] · u` (scale `√(a² + b²)`, turn `atan2(b, a)`), so
//! `p[i] = p[i − 1] + S(a, b) · u[i] + w[i]`, `w ~ N(0, σ_step² I)`, and `(a,
//! b)` a slow random walk from (1, 0). It is linear in the state (`S(a, b) ·
//! u = U · (a, b)` with `U = [[u_x, −u_z], [u_z, u_x]]`), so the filter and
//! the smoother are exact. A measurement is `p[i] + v[i]`, `v ~ N(0, R[i])`
//! with `R[i]` a full 2×2 matrix (a camera sees across its line of sight far
//! better than along it). Where the camera sees the body move sideways, the
//! filter learns how the suit's strides and heading are off, and corrects
//! the steps along the line of sight too, where the camera barely sees.

use glam::{DMat2, DMat4, DVec2, DVec4};

/// A measurement farther than this many standard deviations (Mahalanobis)
/// from the prediction is taken for a wrong match and not used: at 4σ a
/// right one is rejected about once in 3000 frames (χ² with 2 degrees of
/// freedom).
pub const GATE_SIGMAS: f64 = 4.0;

/// How far the suit's steps may be off at the start, per component of the
/// similarity: its strides by up to ~15 % (docs/contact.md: 0.78–0.94 of the
/// true stance distance at the real suit's error level), its heading by ~8°.
pub const STEP_MAP_SIGMA: f64 = 0.15;

/// How fast the similarity may change, per √s: the heading drifts over
/// seconds, and the stride error changes with the motion — a walk's strides
/// 8 % short, a run's 22 % (docs/contact.md), within a second or two. (0.03
/// learnt too slowly: walk 8.7, run 29.2 cm against 7.6 and 23.8 at 0.1.)
pub const STEP_MAP_SIGMA_PER_SQRT_S: f64 = 0.1;

/// One frame's filtered state and what it was predicted from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Filtered {
    /// The transition that led here from the frame before.
    transition: DMat4,
    predicted: DVec4,
    predicted_covariance: DMat4,
    state: DVec4,
    covariance: DMat4,
}

/// Frames closer in time than this (s) repeat one error rather than add
/// another: the body model's mismatch with the actor and the suit's step
/// error both belong to a pose, and a pose changes in about this time (a
/// limb swinging at 3 m/s moves its own width, 10 cm). A take filmed
/// faster is worth no more per second than one filmed at this rate.
pub const ERROR_TIME_S: f64 = 1.0 / 30.0;

/// How many frames `dt_s` apart share one independent error (at least
/// one): per frame, the camera's measurements and the path search's
/// energies count as that share of one, and the suit's steps are that
/// many times less certain in variance (a random walk's variance grows
/// with time, not with how finely it is cut). At 30 fps or slower
/// nothing changes.
pub fn frames_per_error(dt_s: f64) -> f64 {
    (ERROR_TIME_S / dt_s).max(1.0)
}

/// What happened to a measurement offered to [`FloorFilter::update`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measurement {
    /// Used.
    Used,
    /// Beyond [`GATE_SIGMAS`] of the prediction: left out.
    Rejected,
    /// Beyond the gate, but after `reacquire_after` frames in a row without
    /// a measurement used (rejected, or none believable to offer): the
    /// filter had lost the body, so it starts again from the camera.
    Reacquired,
}

/// The forward filter over the frames read so far.
#[derive(Clone, Debug)]
pub struct FloorFilter {
    frames: Vec<Filtered>,
    /// Frames in a row, the newest included, without a measurement used.
    unused_in_a_row: usize,
    reacquire_after: usize,
    /// The similarity's random walk per frame (variance).
    map_variance_per_frame: f64,
    /// The sum of the used measurements' squared Mahalanobis distances from
    /// their predictions, and how many: how well the model explains the
    /// camera (2 per measurement on average when it does).
    innovation_sum: f64,
    innovation_count: usize,
}

fn position(state: DVec4) -> DVec2 {
    DVec2::new(state.x, state.y)
}

fn position_covariance(covariance: DMat4) -> DMat2 {
    DMat2::from_cols(
        DVec2::new(covariance.x_axis.x, covariance.x_axis.y),
        DVec2::new(covariance.y_axis.x, covariance.y_axis.y),
    )
}

fn outer(u: DVec4, v: DVec4) -> DMat4 {
    DMat4::from_cols(u * v.x, u * v.y, u * v.z, u * v.w)
}

fn diagonal(d: DVec4) -> DMat4 {
    DMat4::from_diagonal(d)
}

impl FloorFilter {
    /// A filter whose first frame is at `start` with standard deviation
    /// `start_sigma_cm` per axis, the suit's steps taken as they are (up to
    /// [`STEP_MAP_SIGMA`]), frames `dt_s` apart; after `reacquire_after`
    /// frames in a row without a measurement used it trusts the camera
    /// again.
    pub fn new(start: DVec2, start_sigma_cm: f64, dt_s: f64, reacquire_after: usize) -> FloorFilter {
        let state = DVec4::new(start.x, start.y, 1.0, 0.0);
        let s2 = start_sigma_cm * start_sigma_cm;
        let m2 = STEP_MAP_SIGMA * STEP_MAP_SIGMA;
        let covariance = diagonal(DVec4::new(s2, s2, m2, m2));
        FloorFilter {
            frames: vec![Filtered {
                transition: DMat4::IDENTITY,
                predicted: state,
                predicted_covariance: covariance,
                state,
                covariance,
            }],
            unused_in_a_row: 0,
            reacquire_after,
            map_variance_per_frame: STEP_MAP_SIGMA_PER_SQRT_S * STEP_MAP_SIGMA_PER_SQRT_S * dt_s.max(0.0),
            innovation_sum: 0.0,
            innovation_count: 0,
        }
    }

    /// Whether the filter has gone `reacquire_after` frames, the newest
    /// included, without a measurement used: its prediction may be anywhere
    /// by now, and the next measurement beyond the gate restarts it.
    pub fn is_lost(&self) -> bool {
        self.unused_in_a_row >= self.reacquire_after
    }

    /// The frames filtered so far.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// The newest frame's position and covariance (cm, cm²).
    pub fn current(&self) -> (DVec2, DMat2) {
        let last = self.last();
        (position(last.state), position_covariance(last.covariance))
    }

    /// The mean squared Mahalanobis distance of the used measurements from
    /// their predictions (2 when the model's uncertainties are right; NaN
    /// before any).
    pub fn mean_innovation(&self) -> f64 {
        self.innovation_sum / self.innovation_count as f64
    }

    /// The newest frame's map of the suit's steps: (scale, turn in radians).
    pub fn step_map(&self) -> (f64, f64) {
        let s = self.last().state;
        ((s.z * s.z + s.w * s.w).sqrt(), libm::atan2(s.w, s.z))
    }

    fn last(&self) -> &Filtered {
        // `new` makes the first frame and nothing removes one.
        &self.frames[self.frames.len() - 1]
    }

    fn last_mut(&mut self) -> &mut Filtered {
        let n = self.frames.len();
        &mut self.frames[n - 1]
    }

    /// Moves on to the next frame by the inertial `step_cm` (through the
    /// similarity learnt so far), uncertain by `step_sigma_cm` per axis
    /// besides; returns the predicted position and its covariance.
    pub fn predict(&mut self, step_cm: DVec2, step_sigma_cm: f64) -> (DVec2, DMat2) {
        let last = *self.last();
        // p += U (a, b); (a, b) stays.
        let transition = DMat4::from_cols(
            DVec4::X,
            DVec4::Y,
            DVec4::new(step_cm.x, step_cm.y, 1.0, 0.0),
            DVec4::new(-step_cm.y, step_cm.x, 0.0, 1.0),
        );
        let predicted = transition * last.state;
        let w2 = step_sigma_cm * step_sigma_cm;
        let m2 = self.map_variance_per_frame;
        let predicted_covariance =
            transition * last.covariance * transition.transpose() + diagonal(DVec4::new(w2, w2, m2, m2));
        self.frames.push(Filtered {
            transition,
            predicted,
            predicted_covariance,
            state: predicted,
            covariance: predicted_covariance,
        });
        self.unused_in_a_row += 1;
        (position(predicted), position_covariance(predicted_covariance))
    }

    /// Offers the newest frame a camera measurement at `measured_cm` with
    /// covariance `covariance_cm2` (symmetric, positive definite).
    pub fn update(&mut self, measured_cm: DVec2, covariance_cm2: DMat2) -> Measurement {
        let last = *self.last();
        let innovation = measured_cm - position(last.state);
        let innovation_covariance = position_covariance(last.covariance) + covariance_cm2;
        if innovation_covariance.determinant().abs() < 1e-300 || !innovation.is_finite() {
            return Measurement::Rejected;
        }
        let inverse = innovation_covariance.inverse();
        let distance2 = innovation.dot(inverse * innovation);
        let outcome = if distance2 <= GATE_SIGMAS * GATE_SIGMAS {
            self.innovation_sum += distance2;
            self.innovation_count += 1;
            Measurement::Used
        } else if self.is_lost() {
            Measurement::Reacquired
        } else {
            return Measurement::Rejected;
        };
        self.unused_in_a_row = 0;
        let frame = self.last_mut();
        if outcome == Measurement::Reacquired {
            // Lost: the past says nothing of where the body is now; what was
            // learnt of the suit's steps stands.
            frame.state.x = measured_cm.x;
            frame.state.y = measured_cm.y;
            let (r, map) = (covariance_cm2, frame.covariance);
            frame.covariance = DMat4::from_cols(
                DVec4::new(r.x_axis.x, r.x_axis.y, 0.0, 0.0),
                DVec4::new(r.y_axis.x, r.y_axis.y, 0.0, 0.0),
                DVec4::new(0.0, 0.0, map.z_axis.z, map.z_axis.w),
                DVec4::new(0.0, 0.0, map.w_axis.z, map.w_axis.w),
            );
            return outcome;
        }
        // K = P Hᵀ S⁻¹, H taking the position: P Hᵀ is P's first two columns.
        let (c0, c1) = (last.covariance.x_axis, last.covariance.y_axis);
        let k0 = c0 * inverse.x_axis.x + c1 * inverse.x_axis.y;
        let k1 = c0 * inverse.y_axis.x + c1 * inverse.y_axis.y;
        frame.state = last.state + k0 * innovation.x + k1 * innovation.y;
        // Joseph's form keeps the covariance symmetric and positive.
        let keep = DMat4::IDENTITY - DMat4::from_cols(k0, k1, DVec4::ZERO, DVec4::ZERO);
        let r = covariance_cm2;
        let noise = outer(k0, k0) * r.x_axis.x
            + outer(k0, k1) * r.y_axis.x
            + outer(k1, k0) * r.x_axis.y
            + outer(k1, k1) * r.y_axis.y;
        frame.covariance = keep * last.covariance * keep.transpose() + noise;
        outcome
    }

    /// The Rauch–Tung–Striebel pass: per frame, the position and covariance
    /// given every frame, before and after.
    pub fn smooth(&self) -> Vec<(DVec2, DMat2)> {
        let n = self.frames.len();
        let mut smoothed: Vec<(DVec4, DMat4)> = self.frames.iter().map(|f| (f.state, f.covariance)).collect();
        for i in (0..n.saturating_sub(1)).rev() {
            let (now, next) = (&self.frames[i], &self.frames[i + 1]);
            if next.predicted_covariance.determinant().abs() < 1e-300 {
                continue;
            }
            let gain = now.covariance * next.transition.transpose() * next.predicted_covariance.inverse();
            let (after, after_covariance) = smoothed[i + 1];
            let state = now.state + gain * (after - next.predicted);
            let covariance =
                now.covariance + gain * (after_covariance - next.predicted_covariance) * gain.transpose();
            smoothed[i] = (state, covariance);
        }
        smoothed.into_iter().map(|(s, c)| (position(s), position_covariance(c))).collect()
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
        let mut filter = FloorFilter::new(DVec2::new(1.0, 2.0), 1.0, 1.0 / 30.0, 10);
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
        let mut filter = FloorFilter::new(DVec2::ZERO, 1.0, 1.0 / 30.0, 10);
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
        // It learnt that the steps are 10 % long.
        let (scale, turn) = filter.step_map();
        assert!((scale - 2.0 / 2.2).abs() < 0.02 && turn.abs() < 0.02, "{scale} {turn}");
    }

    #[test]
    fn a_wrong_match_is_left_out_and_a_lost_body_is_found_again() {
        let mut filter = FloorFilter::new(DVec2::ZERO, 1.0, 1.0 / 30.0, 5);
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

    #[test]
    fn frames_with_no_believable_fit_count_towards_being_lost() {
        // Used once, then four frames with nothing offered (the body not
        // seen well enough): the first measurement beyond the gate restarts.
        let mut filter = FloorFilter::new(DVec2::ZERO, 1.0, 1.0 / 30.0, 5);
        filter.predict(DVec2::ZERO, 1.0);
        assert_eq!(filter.update(DVec2::ZERO, isotropic(2.0)), Measurement::Used);
        for _ in 0..4 {
            filter.predict(DVec2::ZERO, 1.0);
            assert!(!filter.is_lost());
        }
        filter.predict(DVec2::ZERO, 1.0);
        assert!(filter.is_lost());
        assert_eq!(filter.update(DVec2::new(100.0, 0.0), isotropic(2.0)), Measurement::Reacquired);
        assert!(!filter.is_lost());
        assert_eq!(filter.current().0, DVec2::new(100.0, 0.0));
    }
}
