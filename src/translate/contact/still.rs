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
//! And a body that barely progresses, on a noisy pose, does not coast
//! ([`in_place`]): its coasts carry noise, not momentum.

use glam::DVec3;

use super::noise::smoothed_noise_velocity_cm_per_s;
use super::{ContactParams, horizontal};
use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;
use crate::signal::smoothing::{smooth_gaussian_clean, smoothed_point};

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
/// [`WIDTH_CHANGE_S`]. The ends are extended by point reflection, so the
/// first and last frames stay where they are for a body standing or moving
/// straight.
pub fn hold_still(
    path: &[DVec3],
    noise_cm: f64,
    smoothed_samples: f64,
    dt_s: f64,
    noise_share: f64,
    max_sigma_s: f64,
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
    let chosen: Vec<f64> = (0..n)
        .map(|f| {
            widths
                .iter()
                .zip(&noise_left)
                .find(|&(&s, &v)| v <= noise_share * speed_cm_per_s(path, f, s, dt_s))
                .map_or(widths[widths.len() - 1], |(&s, _)| s)
        })
        .collect();
    let chosen = eased_widths(&chosen, dt_s);
    (0..n).map(|f| smoothed_at(path, f, chosen[f])).collect()
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
    let reach = ((2.0 * sigma).round() as usize).max(1);
    let (first, last) = (f.saturating_sub(reach), (f + reach).min(path.len() - 1));
    (path[last] - path[first]).length() / ((last - first) as f64 * dt_s)
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
        let held = hold_still(&noisy, 0.3, 0.0, DT, 0.2, 0.3);
        let (truth, before, after) = (path_length(&clean), path_length(&noisy), path_length(&held));
        assert!(before > 2.0 * truth, "{before} against {truth}");
        assert!(after < 1.3 * truth && after > 0.85 * truth, "{after} against {truth}");
        // The shift itself stays: still 3 cm each way.
        let reach = held.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
        assert!((reach - 3.0).abs() < 0.5, "{reach}");
    }

    #[test]
    fn a_walk_and_a_clean_pose_are_left_as_they_were() {
        // 130 cm/s under 0.3 cm of noise (18 cm/s of it from frame to
        // frame), or under 1.5 cm already smoothed to about 16 cm/s.
        let (_, walk) = body(130.0, 2.0, 1.0, 0.3);
        assert_eq!(hold_still(&walk, 0.3, 0.0, DT, 0.2, 0.3), walk);
        let (_, walk) = body(130.0, 2.0, 1.0, 1.5);
        assert_eq!(hold_still(&walk, 1.5, 1.3, DT, 0.2, 0.3), walk);
        let (still, _) = body(0.0, 3.0, 0.5, 0.0);
        assert_eq!(hold_still(&still, 0.0, 0.0, DT, 0.2, 0.3), still);
    }
}
