//! Stillness: a body that barely moves keeps the hips where they are.
//!
//! A pinned sole holds still, so the hips' path is the pinned point minus
//! the pose's foot relative to the hips, and the pose's noise is in it.
//! `noise.rs` smooths that noise to what the choice of contacts weighs, a
//! velocity; but the length of a path is the sum of its steps, and a body
//! standing, bowing or waving moves its hips a few centimetres a second,
//! less than the noise's own velocity: its path came out 1.5 to 2.7 times
//! the truth's. So, frame by frame, the path is smoothed further wherever
//! the body moves slowly beside its noise: over the least time at which the
//! noise left moves the hips at most `still_noise_share` of the body's own
//! speed over that time. A walk or a run, fast beside its noise, keeps its
//! path as it was; a small weight shift, slow but beyond the noise, moves
//! the hips as the pose says; a clean recording, whose fourth differences
//! are motion and not noise (`noise::PoseNoise`), is left as it is.
//!
//! The fourth differences read the noise from frame to frame; a suit's legs
//! also drift, over seconds, and a standing body's hips wander with them
//! (on waves at level 1, a path 1.3 to 1.6 times the truth's, all of the
//! excess at periods of 2 to 6 s). Where both feet stand, their distance
//! apart reads that drift ([`FeetApart`]), and there the hold takes it
//! as the noise left where it is more.
//!
//! And a body that barely progresses, on a noisy pose, does not coast
//! ([`in_place`]): its coasts carry noise, not momentum.

use glam::DVec3;

use super::footing::Footing;
use super::noise::smoothed_noise_velocity_cm_per_s;
use super::{ContactParams, horizontal};
use crate::body::feet::{Foot, PerFoot};
use crate::body::sole::Sole;
use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;
use crate::signal::smoothing::{smooth_gaussian_clean, smoothed_point};
use crate::signal::stats::median;

/// How fast the smoothing's width may change (s, the Gaussian over which
/// the chosen widths are averaged): a body goes from standing to a step in
/// about a tenth of a second, and a width that jumped from one frame to the
/// next would put a jump in the path.
const WIDTH_CHANGE_S: f64 = 0.1;

/// The candidate widths are tried this far apart (samples).
const WIDTH_STEP_SAMPLES: f64 = 0.25;

/// A Gaussian narrower than this (samples) leaves a frame as it is.
const NARROWEST_SAMPLES: f64 = 0.05;

/// The hips' `path` (one point per frame, `dt_s` apart, on the floor) with
/// the pose's noise — white, `noise_cm` per axis, as `noise.rs` measures
/// it, already smoothed by a Gaussian of `smoothed_samples` — smoothed out
/// further where the body moves slowly beside it. For each frame the
/// further width is the least (up to `max_sigma_s`) whose noise left moves
/// the hips by at most `noise_share` of the body's speed over the kernel's
/// reach (two widths either side); the widths are then averaged over
/// [`WIDTH_CHANGE_S`]. Where `feet` stand in place, the noise left is the
/// legs' drift they read where that is more. The ends are extended by
/// point reflection, so the first and last frames stay where they are for
/// a body standing or moving straight.
pub fn hold_still(
    path: &[DVec3],
    noise_cm: f64,
    smoothed_samples: f64,
    dt_s: f64,
    noise_share: f64,
    max_sigma_s: f64,
    feet: Option<&FeetApart>,
) -> Vec<DVec3> {
    let n = path.len();
    if n < 3 || !(noise_cm > 0.0 && dt_s > 0.0 && noise_share > 0.0 && max_sigma_s > 0.0) {
        return path.to_vec();
    }
    let widths: Vec<f64> = (0..)
        .map(|k| k as f64 * WIDTH_STEP_SAMPLES)
        .take_while(|&s| s <= max_sigma_s / dt_s + 1e-9)
        .collect();
    let noise_left = noise_velocities(noise_cm, smoothed_samples, dt_s, &widths);
    // Where both feet stand in place: the legs' drift, where it is more.
    let standing_noise_left: Option<(Vec<f64>, &[bool])> = feet.map(|feet| {
        let drift = feet.drift_velocities(smoothed_samples, &widths, dt_s);
        (noise_left.iter().zip(drift).map(|(v, d)| v.max(d)).collect(), &feet.both_down[..])
    });
    let chosen: Vec<f64> = (0..n)
        .map(|f| {
            let noise_left_here = match &standing_noise_left {
                Some((standing, both_down)) if both_down[f] => standing,
                _ => &noise_left,
            };
            widths
                .iter()
                .zip(noise_left_here)
                .find(|&(&s, &v)| v <= noise_share * speed_cm_per_s(path, f, s, dt_s))
                .map_or(widths[widths.len() - 1], |(&s, _)| s)
        })
        .collect();
    let chosen = eased_widths(&chosen, dt_s);
    (0..n).map(|f| smoothed_at(path, f, chosen[f])).collect()
}

/// Two feet standing in place, as the pose has them. Each foot on the
/// floor holds a point of its sole still (its heel, its ball, or all of
/// it), so in the truth the floor distance between those two points holds
/// still; in a suit's pose it wanders by both legs' errors. That reading is
/// the legs' drift over seconds, which the fourth differences of
/// `noise.rs` do not see: on a wave at level 1, 10 to 16 cm of the
/// separation's path smoothed over 0.3 s, against the truth's 0 to 2.
pub(super) struct FeetApart<'a> {
    soles: &'a PerFoot<Sole>,
    /// Per frame: the body is in place and both feet stand flat.
    both_down: Vec<bool>,
}

/// The fewest frames a drift is read over: a median of fewer says little.
const MIN_DRIFT_FRAMES: usize = 10;

impl<'a> FeetApart<'a> {
    /// The feet of `footing`, down where the body is `in_place` and each
    /// foot stands flat: its heel and its tip within `touch_cm` of the
    /// floor. A foot turning on its heel or ball, or sliding in on its toes,
    /// moves with the body's motion, not its drift.
    pub fn of(footing: &'a Footing, in_place: &[bool], touch_cm: f64) -> FeetApart<'a> {
        let flat = |foot: Foot, f: usize| {
            [0, footing.soles[foot].tip].into_iter().all(|k| footing.clearance_cm(foot, k, f) <= touch_cm)
        };
        let both_down = (0..footing.frame_count())
            .map(|f| in_place[f] && Foot::BOTH.into_iter().all(|foot| flat(foot, f)))
            .collect();
        FeetApart { soles: &footing.soles, both_down }
    }

    /// Per width of `widths` (samples, on top of `smoothed_samples`, as in
    /// [`hold_still`]), one leg's drift (cm/s): over the frames whose reach
    /// ([`reach_frames`] of the whole smoothing's width) has both feet
    /// down throughout, the median of the slowest that
    /// any point of one sole and any of the other move apart over it, over
    /// √2 (two legs drift, each its own way). Never rising with the width;
    /// zero where fewer than [`MIN_DRIFT_FRAMES`] frames tell.
    fn drift_velocities(&self, smoothed_samples: f64, widths: &[f64], dt_s: f64) -> Vec<f64> {
        let n = self.both_down.len();
        // Per frame, for how many frames up to it both feet have been down.
        let down_for: Vec<usize> = self
            .both_down
            .iter()
            .scan(0, |run, &down| {
                *run = if down { *run + 1 } else { 0 };
                Some(*run)
            })
            .collect();
        let PerFoot { left, right } = self.soles;
        let mut least = f64::INFINITY;
        widths
            .iter()
            .map(|&extra| {
                let sigma = (extra * extra + smoothed_samples * smoothed_samples).sqrt();
                let reach = reach_frames(sigma);
                let moved = |sole: &Sole, f: usize, k: usize| {
                    horizontal(sole.at(f + reach, k) - sole.at(f - reach, k))
                };
                let speeds: Vec<f64> = (reach..n.saturating_sub(reach))
                    .filter(|&f| down_for[f + reach] > 2 * reach)
                    .map(|f| {
                        let mut slowest = f64::INFINITY;
                        for i in 0..left.point_count() {
                            let moved_left = moved(left, f, i);
                            for j in 0..right.point_count() {
                                slowest = slowest.min((moved_left - moved(right, f, j)).length());
                            }
                        }
                        slowest / ((2 * reach) as f64 * dt_s)
                    })
                    .collect();
                let drift = if speeds.len() < MIN_DRIFT_FRAMES {
                    0.0
                } else {
                    median(&speeds) / std::f64::consts::SQRT_2
                };
                least = least.min(drift);
                least
            })
            .collect()
    }
}

/// `widths` (samples, one per frame, frames `dt_s` apart) averaged over
/// [`WIDTH_CHANGE_S`]: a width chosen frame by frame, changed that smoothly.
pub(super) fn eased_widths(widths: &[f64], dt_s: f64) -> Vec<f64> {
    smooth_gaussian_clean(widths, 2.0 * 2.5 * WIDTH_CHANGE_S / dt_s, 2.5)
}

/// The speed of the noise left after a further Gaussian of each of
/// `widths` (samples) on top of one of `smoothed_samples` (together one of
/// their root sum of squares), white noise of `noise_cm` per axis on
/// samples `dt_s` apart, as the length of its velocity on the floor (two
/// axes; see [`smoothed_noise_velocity_cm_per_s`]); never rising with the
/// width.
fn noise_velocities(noise_cm: f64, smoothed_samples: f64, dt_s: f64, widths: &[f64]) -> Vec<f64> {
    let mut least = f64::INFINITY;
    widths
        .iter()
        .map(|&extra| {
            let s = (extra * extra + smoothed_samples * smoothed_samples).sqrt();
            let per_axis = smoothed_noise_velocity_cm_per_s(noise_cm, dt_s, s);
            least = least.min(per_axis * std::f64::consts::SQRT_2);
            least
        })
        .collect()
}

/// How fast `path` moves at frame `f` over the reach of a Gaussian of
/// `sigma` samples (two widths either side, at least one frame; cut at the
/// ends): the distance between the reach's ends over its time.
fn speed_cm_per_s(path: &[DVec3], f: usize, sigma: f64, dt_s: f64) -> f64 {
    let reach = reach_frames(sigma);
    let (first, last) = (f.saturating_sub(reach), (f + reach).min(path.len() - 1));
    (path[last] - path[first]).length() / ((last - first) as f64 * dt_s)
}

/// How far (frames) a Gaussian of `sigma` samples reaches either side, as
/// the hold reads speeds over it: two widths, at least one frame.
fn reach_frames(sigma: f64) -> usize {
    ((2.0 * sigma).round() as usize).max(1)
}

/// Frame `f` of `path` smoothed by a Gaussian of `sigma` samples (see
/// [`smoothed_point`]); a width under [`NARROWEST_SAMPLES`] leaves it as it
/// is.
fn smoothed_at(path: &[DVec3], f: usize, sigma: f64) -> DVec3 {
    if sigma < NARROWEST_SAMPLES { path[f] } else { smoothed_point(path, 1, 0, f, sigma) }
}

/// Per frame of the hips' `path` (on the floor, `dt_s` apart), whether the
/// body is in place: its hips progress, from `in_place_window_s` before to
/// as long after (cut at the ends), slower than `√(Fr g L)` with `Fr` the
/// `in_place_froude` and `L` the standing hips height `hips_cm`.
///
/// Why: on a noisy pose, a coast carries the velocity that the pose's noise
/// gave the last pin, and where the body barely progresses that velocity is
/// mostly noise. The suit-grade dances coasted through a quarter of their
/// frames while the truth stood on one foot, carrying up to 1.5 m/s of
/// error, and ended further from the truth than pinning the lower foot
/// throughout does. A walk or a run, faster than its noise, keeps its
/// coasts.
pub fn in_place(path: &[DVec3], hips_cm: f64, dt_s: f64, params: &ContactParams) -> Vec<bool> {
    let n = path.len();
    let slowest_cm_per_s = (params.in_place_froude * STANDARD_GRAVITY_CM_PER_S2 * hips_cm.max(0.0)).sqrt();
    let reach = (params.in_place_window_s / dt_s).round().max(1.0) as usize;
    (0..n)
        .map(|f| {
            let (a, b) = (f.saturating_sub(reach), (f + reach).min(n - 1));
            let speed = horizontal(path[b] - path[a]).length() / ((b - a).max(1) as f64 * dt_s);
            speed < slowest_cm_per_s
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::sole::SolePart;
    use crate::synth::rng::XorShift64;

    const DT: f64 = 1.0 / 30.0;

    /// Hips 90 cm high are in place below `√(g · 90 cm / 16)`, 74 cm/s: a
    /// body stepping on the spot or drifting at 60 cm/s is, a walk at
    /// 90 cm/s is not; where it stops after walking, the frames a second
    /// from its last step are.
    #[test]
    fn in_place_is_slower_than_half_the_easiest_walk() {
        let params = ContactParams::default();
        let moving = |speed: f64, f: usize| DVec3::new(speed * f as f64 * DT, 0.0, 0.0);
        let sway = |f: usize| DVec3::new(0.0, 0.0, 8.0 * (f as f64 * DT * std::f64::consts::TAU).sin());
        let stepping: Vec<DVec3> = (0..150).map(sway).collect();
        assert!(in_place(&stepping, 90.0, DT, &params).iter().all(|&here| here));
        let drifting: Vec<DVec3> = (0..150).map(|f| moving(60.0, f) + sway(f)).collect();
        assert!(in_place(&drifting, 90.0, DT, &params).iter().all(|&here| here));
        let walking: Vec<DVec3> = (0..150).map(|f| moving(90.0, f) + sway(f)).collect();
        assert!(in_place(&walking, 90.0, DT, &params).iter().all(|&here| !here));
        let stopping: Vec<DVec3> = (0..150).map(|f| moving(130.0, f.min(60))).collect();
        let here = in_place(&stopping, 90.0, DT, &params);
        assert!(!here[30] && here[100], "{here:?}");
    }

    fn path_length(path: &[DVec3]) -> f64 {
        path.windows(2).map(|w| (w[1] - w[0]).length()).sum()
    }

    /// A body swaying `amplitude_cm` at `hz` along x on top of walking at
    /// `speed_cm_per_s`, 300 frames at 30 fps, and the same with white noise
    /// of `noise_cm` per floor axis.
    fn body(speed_cm_per_s: f64, amplitude_cm: f64, hz: f64, noise_cm: f64) -> (Vec<DVec3>, Vec<DVec3>) {
        let mut rng = XorShift64(777);
        let clean: Vec<DVec3> = (0..300)
            .map(|f| {
                let t = f as f64 * DT;
                DVec3::new(
                    speed_cm_per_s * t + amplitude_cm * (std::f64::consts::TAU * hz * t).sin(),
                    0.0,
                    0.0,
                )
            })
            .collect();
        let noisy =
            clean.iter().map(|p| *p + DVec3::new(rng.gaussian(), 0.0, rng.gaussian()) * noise_cm).collect();
        (clean, noisy)
    }

    #[test]
    fn a_body_standing_keeps_its_hips_and_its_slow_weight_shifts() {
        // A weight shift of 3 cm each way over 2 s under 0.3 cm of noise:
        // the noisy path is twice the true one.
        let (clean, noisy) = body(0.0, 3.0, 0.5, 0.3);
        let held = hold_still(&noisy, 0.3, 0.0, DT, 0.2, 0.3, None);
        let (truth, before, after) = (path_length(&clean), path_length(&noisy), path_length(&held));
        assert!(before > 2.0 * truth, "{before} against {truth}");
        assert!(after < 1.3 * truth && after > 0.85 * truth, "{after} against {truth}");
        // The shift itself stays: still 3 cm each way.
        let reach = held.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
        assert!((reach - 3.0).abs() < 0.5, "{reach}");
    }

    /// Two soles of three points (heel, under the ankle, toe) over `n`
    /// frames: `left(f)` and `right(f)` give each frame's points.
    fn soles(
        n: usize,
        left: impl Fn(usize) -> [DVec3; 3],
        right: impl Fn(usize) -> [DVec3; 3],
    ) -> PerFoot<Sole> {
        let sole = |points: &dyn Fn(usize) -> [DVec3; 3]| Sole {
            parts: vec![SolePart::Heel, SolePart::UnderAnkle, SolePart::Joint(2)],
            hips_to_points_cm: (0..n).flat_map(points).collect(),
            floor_offsets_cm: vec![0.0; 3],
            tip: 2,
        };
        PerFoot::new(sole(&left), sole(&right))
    }

    /// A foot at `x` cm beside the hips, its toe `toe_z` cm ahead, turned
    /// by `turn` radians about its toe.
    fn foot(x: f64, toe_z: f64, turn: f64) -> [DVec3; 3] {
        let toe = DVec3::new(x, -90.0, toe_z);
        let (sin, cos) = libm::sincos(turn);
        let behind = |cm: f64| toe + DVec3::new(-sin * cm, 0.0, -cos * cm);
        [behind(20.0), behind(14.0), toe]
    }

    #[test]
    fn the_feet_apart_read_one_legs_drift_not_a_turn_on_the_ball_or_a_step() {
        // The left leg drifts forward at 3 cm/s; the right foot turns on
        // its ball, ±0.3 rad once a second, and each second steps 30 cm to
        // the side in its first third (up, not down). Two legs' drift would
        // read 3 cm/s apart: one leg's is 3 / √2.
        let n = 150;
        let turn = |f: usize| 0.3 * (std::f64::consts::TAU * f as f64 * DT).sin();
        let step = |f: usize| 30.0 * ((f / 30) as f64 + ((f % 30) as f64 / 10.0).min(1.0));
        let soles = soles(
            n,
            |f| foot(-10.0, 14.0 + 3.0 * f as f64 * DT, 0.0),
            |f| foot(10.0 + step(f), 14.0, turn(f)),
        );
        let down = |f: usize| f % 30 > 10;
        let feet = FeetApart { soles: &soles, both_down: (0..n).map(down).collect() };
        let widths = [0.0, 1.0, 2.0, 4.0];
        let one_leg = 3.0 / std::f64::consts::SQRT_2;
        for drift in feet.drift_velocities(0.0, &widths, DT) {
            assert!((drift - one_leg).abs() < 0.05 * one_leg, "{drift} against {one_leg}");
        }
        // Read across the steps, they would be taken for drift.
        let careless = FeetApart { soles: &soles, both_down: vec![true; n] };
        assert!(careless.drift_velocities(0.0, &[4.0], DT)[0] > 2.0 * one_leg);
        // Too few frames down tell nothing.
        let brief = FeetApart { soles: &soles, both_down: (0..n).map(|f| (11..22).contains(&f)).collect() };
        assert_eq!(brief.drift_velocities(0.0, &widths, DT), vec![0.0; 4]);
    }

    #[test]
    fn a_body_standing_is_held_against_its_legs_drift_where_both_feet_stand() {
        // The hips wander 1.5 cm once a second with the left leg's error,
        // which the fourth differences do not read (0.01 cm of noise): the
        // feet read it, and the hold takes it out.
        let n = 300;
        let wander = |f: usize| 1.5 * (std::f64::consts::TAU * f as f64 * DT).sin();
        let path: Vec<DVec3> = (0..n).map(|f| DVec3::new(wander(f), 0.0, 0.0)).collect();
        let soles = soles(
            n,
            |f| foot(-10.0 - std::f64::consts::SQRT_2 * wander(f), 14.0, 0.0),
            |_| foot(10.0, 14.0, 0.0),
        );
        let feet = FeetApart { soles: &soles, both_down: vec![true; n] };
        let unread = hold_still(&path, 0.01, 0.0, DT, 0.2, 0.3, None);
        let held = hold_still(&path, 0.01, 0.0, DT, 0.2, 0.3, Some(&feet));
        let (before, ignored, after) = (path_length(&path), path_length(&unread), path_length(&held));
        assert!(ignored > 0.95 * before, "{ignored} against {before}");
        assert!(after < 0.5 * before, "{after} against {before}");
        // Where the feet are not both down, the path is left to the noise.
        let walking = FeetApart { soles: &soles, both_down: (0..n).map(|f| f < 150).collect() };
        let half = hold_still(&path, 0.01, 0.0, DT, 0.2, 0.3, Some(&walking));
        assert_eq!(half[200..260], unread[200..260]);
        assert!(path_length(&half[..140]) < 0.5 * path_length(&path[..140]));
    }

    #[test]
    fn a_walk_and_a_clean_pose_are_left_as_they_were() {
        // 130 cm/s under 0.3 cm of noise (18 cm/s of it from frame to
        // frame), or under 1.5 cm already smoothed to about 16 cm/s.
        let (_, walk) = body(130.0, 2.0, 1.0, 0.3);
        assert_eq!(hold_still(&walk, 0.3, 0.0, DT, 0.2, 0.3, None), walk);
        let (_, walk) = body(130.0, 2.0, 1.0, 1.5);
        assert_eq!(hold_still(&walk, 1.5, 1.3, DT, 0.2, 0.3, None), walk);
        let (still, _) = body(0.0, 3.0, 0.5, 0.0);
        assert_eq!(hold_still(&still, 0.0, 0.0, DT, 0.2, 0.3, None), still);
    }
}
