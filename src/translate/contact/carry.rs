//! What a coast carries on a noisy pose: the smoothed choice's velocity,
//! scaled by how much faster the stances around it end than that smoothing
//! reads them.
//!
//! The choice of contacts weighs velocities on soles smoothed against the
//! pose's noise (`noise.rs`), and a coast carries the velocity of the
//! smoothed choice at its last pinned step. A runner's stance lasts 4–6
//! frames, and that smoothing reaches across it into the swing: on the
//! suit-grade runs at level 1 the coasts carried 180–200 cm/s where the
//! runner ran at 300, and the runs lost a quarter of their strides.
//!
//! A stance of at least `min_carried_stance_s` tells its own velocity,
//! unsmoothed: the mean of its pinned steps (the noise averages out over
//! the stance), brought from the stance's middle to its end by the floor's
//! push on the inverted pendulum over the pinned point (`pressure.rs`),
//! which speeds a body up once it is past its foot. Carried as it is, that
//! velocity is right on average but off by another share every stance (its
//! noise over 4–6 frames), and a camera tracker, which learns a steady
//! stride error from what it sees (`track::smoother`), cannot follow that
//! (the shared run scene's track 6.4 → 7.8 cm over five runs). So the
//! stances' readings only say by how much the smoothing falls short: per
//! coast, the least-squares factor from the smoothed velocity to the
//! stances' own over the coasts within about two steps either side
//! (`carry_window_s`). The shortfall comes from the smoothing's reach
//! against the stance's length, which a gait keeps stride after stride, and
//! a coast keeps the smoothed velocity's own steadiness.
//!
//! Not where the body is in place (`still::in_place`): there a coast is
//! rare and short, and a stance's mean velocity is the pose's noise (the
//! held-out guides at level 0.5 went 3.3 → 4.9 % with it). Nor on a clean
//! pose, whose smoothing reaches less than a frame.

use glam::DVec3;

use super::footing::{Candidate, Footing};
use super::horizontal;
use super::pressure::{FloorPush, PressureSegment};
use crate::body::feet::Foot;

/// What a coast's velocity is read from, at every frame.
pub(super) struct StanceExit<'a> {
    /// Per frame, the centre of mass relative to the hips (cm).
    pub hips_to_com_cm: &'a [DVec3],
    /// Per frame, whether the body is in place (`still::in_place`).
    pub in_place: &'a [bool],
    /// The shortest stance whose own velocity is carried (frames).
    pub min_stance_frames: usize,
    /// See [`super::ContactParams::min_com_height_cm`].
    pub min_com_height_cm: f64,
    /// How far either side of a coast (frames, a Gaussian's deviation) the
    /// stances' readings count ([`super::ContactParams::carry_window_s`]).
    pub window_frames: f64,
}

/// A stance's end read two ways, at the first frame of the coast after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ExitReading {
    /// The coast's first frame.
    pub frame: usize,
    /// The hips' velocity (cm/s) the stance itself ends with
    /// ([`StanceExit::velocity`]).
    pub read: DVec3,
    /// The smoothed choice's hips velocity (cm/s) in the same frame.
    pub smoothed: DVec3,
}

/// Readings further than this many deviations of the window from a frame
/// are left out of its sum: their Gaussian weight is below 1/2900.
const READING_REACH_SIGMAS: f64 = 4.0;

/// A run of frames pinned on one foot (any of its points: a foot rolls from
/// heel to toes), or on both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Stance {
    /// The first pinned frame.
    pub start: usize,
    /// The foot pinned; `None` for both.
    pub foot: Option<Foot>,
}

impl Stance {
    /// The stance `candidate` (pinned in frame `f`) belongs to: `current`
    /// when it pins the same foot, or both again; a new one from `f`
    /// otherwise.
    pub fn of(candidate: Candidate, f: usize, current: Option<Stance>) -> Option<Stance> {
        let foot = match candidate {
            Candidate::Point { foot, .. } => Some(foot),
            Candidate::Double => None,
            Candidate::Coast => return None,
        };
        match current {
            Some(stance) if stance.foot == foot => Some(stance),
            _ => Some(Stance { start: f, foot }),
        }
    }
}

impl StanceExit<'_> {
    /// The centre of mass's horizontal velocity (cm/s) at the end of
    /// `stance`, whose frames run up to `end` (the first coasting frame),
    /// `dt` s apart: `None` where it is too short, where the body is in
    /// place at `end`, or where the stance starts the take. `hips_velocity`
    /// holds, per frame, the hips' velocity its pinned point gives
    /// (unsmoothed), `pressed` where it presses in a frame (relative to the
    /// hips; [`pressed_at`]).
    pub fn velocity(
        &self,
        stance: Stance,
        end: usize,
        hips_velocity: &[DVec3],
        pressed: impl Fn(usize) -> Option<DVec3>,
        standing_cm: &[f64],
        dt: f64,
    ) -> Option<DVec3> {
        let start = stance.start;
        let frames = end.checked_sub(start)?;
        if frames < self.min_stance_frames.max(1) || start == 0 || self.in_place[end] {
            return None;
        }
        let h2c = self.hips_to_com_cm;
        let mean_hips = hips_velocity[start..end].iter().sum::<DVec3>() / frames as f64;
        let mean_com = mean_hips + horizontal(h2c[end - 1] - h2c[start - 1]) / (frames as f64 * dt);
        // The push's velocity change since the stance's first move, at each
        // of its moves; the mean velocity is that of the stance's middle.
        let mut pushed = DVec3::ZERO;
        let mut pushed_sum = DVec3::ZERO;
        for j in start..end - 1 {
            let at = pressed(j)?;
            let point = Some(PressureSegment { from: at, to: at });
            pushed +=
                FloorPush::new(h2c[j], standing_cm[j], dt, self.min_com_height_cm).range_from(point).start;
            pushed_sum += pushed;
        }
        Some(mean_com + pushed - pushed_sum / frames as f64)
    }

    /// By how much the smoothed velocity falls short of the stances' own
    /// around frame `f`: the least-squares factor `k` in `read ≈ k ·
    /// smoothed` over `readings` (in frame order), each weighed by a
    /// Gaussian of [`StanceExit::window_frames`] in time; 1 where none is
    /// near. Fast readings weigh most, so a slow coast's noisy direction
    /// does not tip it.
    pub fn shortfall_at(&self, f: usize, readings: &[ExitReading]) -> f64 {
        let (f, reach) = (f as f64, READING_REACH_SIGMAS * self.window_frames);
        let from = readings.partition_point(|r| (r.frame as f64) < f - reach);
        let (mut along, mut smoothed_sq) = (0.0, 0.0);
        for reading in readings[from..].iter().take_while(|r| r.frame as f64 <= f + reach) {
            let d = (reading.frame as f64 - f) / self.window_frames;
            let weight = libm::exp(-0.5 * d * d);
            along += weight * reading.read.dot(reading.smoothed);
            smoothed_sq += weight * reading.smoothed.length_squared();
        }
        if smoothed_sq > 0.0 { along / smoothed_sq } else { 1.0 }
    }

    /// The hips' horizontal velocity (cm/s) for the move into frame `f`
    /// (`dt` s after the one before) of a centre of mass moving at `com`.
    pub fn hips_velocity(&self, com: DVec3, f: usize, dt: f64) -> DVec3 {
        com - horizontal(self.hips_to_com_cm[f] - self.hips_to_com_cm[f - 1]) / dt
    }
}

/// Where `candidate` presses in frame `f` (relative to the hips, cm): the
/// pinned point, or midway between the two feet's lowest points; `None`
/// for a coast.
pub(super) fn pressed_at(footing: &Footing, candidate: Candidate, f: usize) -> Option<DVec3> {
    match candidate {
        Candidate::Point { foot, point } => Some(footing.soles[foot].at(f, point)),
        Candidate::Double => {
            let pins = footing.lowest.double_support(f.saturating_sub(1));
            Some((footing.soles.left.at(f, pins.left) + footing.soles.right.at(f, pins.right)) * 0.5)
        }
        Candidate::Coast => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;

    const DT: f64 = 1.0 / 30.0;

    /// A stance from frame 10 to 15 (5 frames) on a body whose hips move at
    /// `hips_velocity` and whose centre of mass stands `lean` ahead of the
    /// pressed point, hips 90 cm up, the centre of mass 10 cm above the hips.
    fn exit_of(frames: usize, lean: DVec3, in_place_at_end: bool) -> Option<DVec3> {
        let n = 30;
        let hips_to_com_cm = vec![DVec3::new(0.0, 10.0, 0.0); n];
        let mut in_place = vec![false; n];
        in_place[10 + frames] = in_place_at_end;
        let exit = StanceExit {
            hips_to_com_cm: &hips_to_com_cm,
            in_place: &in_place,
            min_stance_frames: 3,
            min_com_height_cm: 30.0,
            window_frames: 30.0,
        };
        let hips_velocity = vec![DVec3::new(0.0, 0.0, 300.0); n];
        let pressed = vec![DVec3::new(0.0, -90.0, 0.0) - lean; n];
        let stance = Stance { start: 10, foot: Some(Foot::Left) };
        exit.velocity(stance, 10 + frames, &hips_velocity, |j| Some(pressed[j]), &vec![90.0; n], DT)
    }

    #[test]
    fn a_stance_under_the_body_ends_at_its_mean_velocity() {
        let exit = exit_of(5, DVec3::ZERO, false).expect("a stance of 5 frames is read");
        assert!((exit - DVec3::new(0.0, 0.0, 300.0)).length() < 1e-9, "{exit}");
    }

    /// Past its foot the body speeds up at `g d / h`; the mean velocity is
    /// the stance's middle's, and from there to its last move the push adds
    /// `(k − 1) / 2` frames of it (`k` moves).
    #[test]
    fn a_body_past_its_foot_leaves_faster_than_its_mean() {
        let lean = DVec3::new(0.0, 0.0, 10.0);
        let exit = exit_of(5, lean, false).expect("a stance of 5 frames is read");
        let per_frame = STANDARD_GRAVITY_CM_PER_S2 / 100.0 * 10.0 * DT;
        let expected = 300.0 + 2.0 * per_frame;
        assert!((exit.z - expected).abs() < 1e-9 && exit.x.abs() < 1e-12, "{exit} against {expected}");
    }

    fn reading(frame: usize, smoothed_z: f64, factor: f64) -> ExitReading {
        let smoothed = DVec3::new(0.0, 0.0, smoothed_z);
        ExitReading { frame, read: smoothed * factor, smoothed }
    }

    fn exit_with_window(window_frames: f64) -> StanceExit<'static> {
        StanceExit {
            hips_to_com_cm: &[],
            in_place: &[],
            min_stance_frames: 3,
            min_com_height_cm: 30.0,
            window_frames,
        }
    }

    #[test]
    fn a_steady_shortfall_is_read_whatever_the_speed() {
        let readings: Vec<ExitReading> =
            (0..10).map(|k| reading(10 * k, 150.0 + 20.0 * k as f64, 1.25)).collect();
        let exit = exit_with_window(30.0);
        for f in [0, 37, 95, 200] {
            assert!((exit.shortfall_at(f, &readings) - 1.25).abs() < 1e-12, "frame {f}");
        }
    }

    #[test]
    fn without_readings_near_the_smoothed_velocity_is_kept() {
        let exit = exit_with_window(30.0);
        assert_eq!(exit.shortfall_at(50, &[]), 1.0);
        assert_eq!(exit.shortfall_at(1000, &[reading(10, 200.0, 1.5)]), 1.0);
    }

    /// A walk's stances read 1.1, a run's two seconds later 1.4: each
    /// coast takes its own gait's, not the take's mean.
    #[test]
    fn the_shortfall_follows_a_change_of_gait() {
        let mut readings: Vec<ExitReading> = (0..6).map(|k| reading(15 * k, 120.0, 1.1)).collect();
        readings.extend((0..6).map(|k| reading(150 + 10 * k, 300.0, 1.4)));
        let exit = exit_with_window(30.0);
        assert!((exit.shortfall_at(30, &readings) - 1.1).abs() < 0.01);
        assert!((exit.shortfall_at(180, &readings) - 1.4).abs() < 0.01);
    }

    #[test]
    fn short_stances_and_bodies_in_place_are_not_read() {
        assert_eq!(exit_of(2, DVec3::ZERO, false), None);
        assert_eq!(exit_of(5, DVec3::ZERO, true), None);
    }

    #[test]
    fn a_stance_is_one_foot_whatever_point_of_it_rolls() {
        let heel = Candidate::Point { foot: Foot::Left, point: 0 };
        let toes = Candidate::Point { foot: Foot::Left, point: 2 };
        let other = Candidate::Point { foot: Foot::Right, point: 0 };
        let stance = Stance::of(heel, 4, None);
        assert_eq!(Stance::of(toes, 5, stance), stance);
        assert_eq!(Stance::of(other, 6, stance), Some(Stance { start: 6, foot: Some(Foot::Right) }));
        assert_eq!(Stance::of(Candidate::Double, 7, stance), Some(Stance { start: 7, foot: None }));
        assert_eq!(Stance::of(Candidate::Coast, 8, stance), None);
    }
}
