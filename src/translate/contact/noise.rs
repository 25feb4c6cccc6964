//! How much tracking noise a recording's pose carries, measured on the
//! recording itself, and how far to smooth it away before the contacts are
//! chosen.
//!
//! An inertial suit's segment orientations are noisy (more so the faster a
//! segment turns), and a few degrees on a thigh and a shank move the foot a
//! centimetre or more relative to the hips from one frame to the next. A
//! planted foot's velocity relative to the hips is the hips' velocity, so
//! that noise, differenced, is a velocity noise of tens of cm/s at 30 fps:
//! more than the velocity changes the choice of contacts weighs. Smoothing
//! removes it, but also blurs a runner's landings, so the time scale is the
//! least that brings the noise down, and none on a clean recording.

use glam::DVec3;

use crate::body::feet::FootJoints;
use crate::body::skeleton::Poses;
use crate::signal::stats::upper_median;

/// The pose's noise on frames `step` apart, and whether that reading is
/// noise and not motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseNoise {
    /// The standard deviation (cm, per axis) of white noise on the feet's
    /// positions relative to the hips, as seen on frames `step` apart.
    ///
    /// The fourth difference `p[f-2k] − 4 p[f-k] + 6 p[f] − 4 p[f+k] + p[f+2k]`
    /// of a foot's path holds the motion's fourth derivative times `(k dt)⁴`,
    /// which is small wherever the motion is slow beside the frame rate, and,
    /// for white noise of deviation `σ` per axis, a noise of variance `70 σ²` per
    /// axis. The median of its squared length (a χ² of 3 degrees of freedom for
    /// the noise, whose median is 2.366 times the per-axis variance) over both
    /// feet and all frames gives `σ`: the median leaves out the few frames of a
    /// landing, where the real motion is fast. Zero when the recording is too
    /// short.
    pub cm: f64,
    /// Noise reads about the same on frames twice as far apart (white noise
    /// the same, noise correlated over a few frames up to twice as much),
    /// the motion's fourth derivative sixteen times as much. So the reading
    /// is noise when doubling the step raises it less than four times,
    /// halfway (in ratio) between the two: on the shared suit-grade files
    /// it rises 1.0–3.5 times, on clean optical ones 24–54 times.
    pub reads_noise: bool,
    /// The same deviation read on frames twice as far apart (cm): the same
    /// as [`PoseNoise::cm`] for white noise, more for noise correlated over
    /// a few frames, which the nearer fourth difference mostly cancels.
    pub cm_twice_apart: f64,
}

impl PoseNoise {
    /// The noise as it moves the hips of a body that stands (cm, per axis):
    /// the larger reading. A standing body's path wanders with the noise
    /// over tenths of a second, where noise correlated over a few frames is
    /// at its full size (the shared bow at level 1: 0.09 cm near, 0.12–0.13
    /// cm twice as far).
    pub fn wander_cm(&self) -> f64 {
        self.cm.max(self.cm_twice_apart)
    }
}

/// White noise of deviation `σ` per axis gives a fourth difference of
/// variance `70 σ²` per axis (see [`PoseNoise::cm`]).
const FOURTH_DIFFERENCE_GAIN: f64 = 70.0;

/// The median of a χ² of 3 degrees of freedom over its mean: the median
/// squared length of 3-D white noise is this many times its per-axis
/// variance.
const CHI2_3_MEDIAN: f64 = 2.366;

/// The pose's noise (see [`PoseNoise`]): both feet relative to `hips`, on
/// frames `step` apart and twice as far.
pub fn pose_noise(poses: &Poses, feet: FootJoints, hips: usize, step: usize) -> PoseNoise {
    let k = step.max(1);
    let near = fourth_difference_median(poses, feet, hips, k);
    let far = fourth_difference_median(poses, feet, hips, 2 * k);
    PoseNoise {
        cm: deviation_cm(near),
        reads_noise: near > 0.0 && far < 4.0 * near,
        cm_twice_apart: deviation_cm(far),
    }
}

/// Per frame, the pose's noise (cm, per axis, as [`PoseNoise::cm`] reads it)
/// near that frame: per foot the median of the squared fourth differences
/// (frames `step` apart) within `half_window` frames either side, the
/// quieter foot's.
///
/// Why near: a suit's noise grows with its segments' angular speed, so a
/// body that stands while it kicks, slashes or swings its arms carries in
/// those moments several times the recording's median (the shared kicks'
/// 90th percentile reads four times it): enough to make a planted foot
/// look as if it slid. Why the quieter foot: the foot that bears the body
/// is the one to pin, and a kicking or stepping foot's fourth differences
/// hold its motion as well as its noise. Frames within `2 step` of the ends
/// read the nearest frame whose fourth difference is whole; zero where the
/// recording is too short.
pub fn local_noise_cm(
    poses: &Poses,
    feet: FootJoints,
    hips: usize,
    step: usize,
    half_window: usize,
) -> Vec<f64> {
    let n = poses.frame_count();
    let k = step.max(1);
    if n <= 4 * k {
        return vec![0.0; n];
    }
    let per_foot: Vec<Vec<f64>> = feet
        .iter()
        .map(|(_, &joint)| {
            let squared: Vec<f64> = (0..n)
                .map(|f| fourth_difference_squared(poses, joint, hips, k, f.clamp(2 * k, n - 1 - 2 * k)))
                .collect();
            // The upper median of each window, selected in a buffer used
            // again for every frame.
            let mut window = Vec::with_capacity(2 * half_window + 1);
            (0..n)
                .map(|f| {
                    window.clear();
                    window.extend_from_slice(
                        &squared[f.saturating_sub(half_window)..(f + half_window + 1).min(n)],
                    );
                    let middle = window.len() / 2;
                    *window.select_nth_unstable_by(middle, f64::total_cmp).1
                })
                .collect()
        })
        .collect();
    (0..n).map(|f| deviation_cm(per_foot[0][f].min(per_foot[1][f]))).collect()
}

/// The squared length of the fourth difference
/// `p[f-2k] − 4 p[f-k] + 6 p[f] − 4 p[f+k] + p[f+2k]` of `joint`'s path
/// relative to `hips`, `k = step`; `f` at least `2 step` from either end.
fn fourth_difference_squared(poses: &Poses, joint: usize, hips: usize, step: usize, f: usize) -> f64 {
    let k = step;
    let at = |f: usize| -> DVec3 { poses.at(f, joint) - poses.at(f, hips) };
    (at(f - 2 * k) - 4.0 * at(f - k) + 6.0 * at(f) - 4.0 * at(f + k) + at(f + 2 * k)).length_squared()
}

/// The per-axis deviation (cm) of white noise whose squared fourth
/// differences have the median `median_squared` (see [`PoseNoise::cm`]).
fn deviation_cm(median_squared: f64) -> f64 {
    (median_squared / (FOURTH_DIFFERENCE_GAIN * CHI2_3_MEDIAN)).sqrt()
}

/// The median squared length of the fourth difference
/// `p[f-2k] − 4 p[f-k] + 6 p[f] − 4 p[f+k] + p[f+2k]` of both feet's paths
/// relative to the hips, `k = step`; zero when the recording is too short.
fn fourth_difference_median(poses: &Poses, feet: FootJoints, hips: usize, step: usize) -> f64 {
    let n = poses.frame_count();
    let k = step.max(1);
    if n <= 4 * k {
        return 0.0;
    }
    let mut values = Vec::with_capacity(2 * n);
    for (_, &joint) in feet.iter() {
        values.extend((2 * k..n - 2 * k).map(|f| fourth_difference_squared(poses, joint, hips, k, f)));
    }
    upper_median(&values)
}

/// The velocity (cm/s, per axis) that white position noise of `noise_cm`
/// on samples `dt` s apart keeps once smoothed by a Gaussian of
/// `sigma_samples`: the derivative of the smoothed noise has deviation
/// `σ_n / dt · (4 √π s³)^(−1/2)` for a kernel of `s` samples, and the
/// difference of two unsmoothed samples `σ_n √2 / dt` (the formula
/// overshoots that below half a sample). [`smoothing_samples`] is its
/// inverse.
pub fn smoothed_noise_velocity_cm_per_s(noise_cm: f64, dt: f64, sigma_samples: f64) -> f64 {
    let s = sigma_samples;
    if s < 0.5 {
        noise_cm / dt * std::f64::consts::SQRT_2
    } else {
        noise_cm / dt / (4.0 * std::f64::consts::PI.sqrt() * s * s * s).sqrt()
    }
}

/// The Gaussian's standard deviation (samples) that brings white position
/// noise of `noise_cm` on samples `dt` s apart down to a velocity noise of
/// `velocity_noise_cm_per_s` (the inverse of
/// [`smoothed_noise_velocity_cm_per_s`] above half a sample).
pub fn smoothing_samples(noise_cm: f64, dt: f64, velocity_noise_cm_per_s: f64) -> f64 {
    if !(noise_cm > 0.0 && dt > 0.0 && velocity_noise_cm_per_s > 0.0) {
        return 0.0;
    }
    let ratio = noise_cm / dt / velocity_noise_cm_per_s;
    libm::cbrt(ratio * ratio / (4.0 * std::f64::consts::PI.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A foot circling the hips at `omega` rad/s, sampled at 30 fps, with
    /// white Gaussian noise of deviation `noise` cm per axis.
    fn circling(noise: f64, omega: f64) -> (Poses, FootJoints) {
        let mut rng = crate::synth::rng::XorShift64(12345);
        let mut jitter = || DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * noise;
        let mut positions = Vec::new();
        for f in 0..600 {
            let t = f as f64 / 30.0;
            let foot = DVec3::new(20.0 * (omega * t).cos(), -80.0, 20.0 * (omega * t).sin());
            positions.extend([DVec3::ZERO, foot + jitter(), foot + jitter()]);
        }
        (Poses { joint_count: 3, positions_cm: positions }, FootJoints { left: 1, right: 2 })
    }

    #[test]
    fn the_noise_is_measured_apart_from_the_motion() {
        let (clean, feet) = circling(0.0, 6.0);
        let clean_cm = pose_noise(&clean, feet, 0, 1).cm;
        assert!(clean_cm < 0.05, "{clean_cm}");
        for noise in [0.5, 2.0] {
            let (noisy, feet) = circling(noise, 6.0);
            let measured = pose_noise(&noisy, feet, 0, 1).cm;
            assert!((measured / noise - 1.0).abs() < 0.25, "{noise} cm measured as {measured}");
        }
    }

    #[test]
    fn a_burst_of_noise_is_read_where_it_is() {
        // 0.5 cm of noise, and 3 cm on the right foot from frame 200 to 260
        // and on both from 400 to 460.
        let (mut poses, feet) = circling(0.5, 2.0);
        let mut rng = crate::synth::rng::XorShift64(99);
        let mut jitter = || DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * 3.0;
        for f in (200..260).chain(400..460) {
            poses.positions_cm[f * 3 + 2] += jitter();
        }
        for f in 400..460 {
            poses.positions_cm[f * 3 + 1] += jitter();
        }
        let local = local_noise_cm(&poses, feet, 0, 1, 6);
        // What the method acts on is a reading over twice the recording's
        // noise. Not there, nor where one foot alone is noisy (the quieter
        // foot is read); throughout where both are.
        for (f, &cm) in local.iter().enumerate().take(390) {
            assert!(cm < 1.0, "frame {f}: {cm}");
        }
        for (f, &cm) in local.iter().enumerate().take(457).skip(403) {
            assert!(cm > 1.0 && cm < 4.5, "frame {f}: {cm}");
        }
        let median = crate::signal::stats::upper_median(&local[410..450]);
        assert!((median / 3.0 - 1.0).abs() < 0.25, "{median}");
    }

    #[test]
    fn noise_correlated_over_frames_reads_larger_twice_as_far_apart() {
        // White noise reads alike near and twice as far apart.
        let (white, feet) = circling(1.0, 2.0);
        let noise = pose_noise(&white, feet, 0, 1);
        assert!((noise.cm_twice_apart / noise.cm - 1.0).abs() < 0.15, "{noise:?}");
        assert_eq!(noise.wander_cm(), noise.cm.max(noise.cm_twice_apart));
        // The same noise averaged over three frames: the near fourth
        // difference cancels most of it, the far one less.
        let (clean, _) = circling(0.0, 2.0);
        let jitter = |g: usize, joint: usize| white.at(g, joint) - clean.at(g, joint);
        let mut correlated = clean.clone();
        for f in 1..white.frame_count() - 1 {
            for joint in 1..3 {
                correlated.positions_cm[f * 3 + joint] +=
                    (jitter(f - 1, joint) + jitter(f, joint) + jitter(f + 1, joint)) / 3.0;
            }
        }
        let noise = pose_noise(&correlated, feet, 0, 1);
        assert!(noise.reads_noise, "{noise:?}");
        assert!(noise.cm_twice_apart > 1.3 * noise.cm, "{noise:?}");
    }

    #[test]
    fn noise_reads_alike_at_twice_the_step_and_motion_does_not() {
        let (noisy, feet) = circling(1.0, 6.0);
        assert!(pose_noise(&noisy, feet, 0, 1).reads_noise);
        // A clean foot circling at 6 rad/s: its fourth differences are the
        // motion's, sixteen times larger two frames apart.
        let (clean, feet) = circling(0.0, 6.0);
        assert!(!pose_noise(&clean, feet, 0, 1).reads_noise);
    }

    #[test]
    fn the_smoothing_brings_white_noise_down_to_the_velocity_asked_for() {
        assert_eq!(smoothing_samples(0.0, 1.0 / 30.0, 12.5), 0.0);
        let dt = 1.0 / 30.0;
        for (noise_cm, target_cm_per_s) in [(1.0, 12.5), (2.0, 12.5), (1.0, 5.0)] {
            let (poses, _) = circling(noise_cm, 0.0);
            // The left foot's path: a still point plus white noise.
            let path: Vec<DVec3> = (0..poses.frame_count()).map(|f| poses.at(f, 1)).collect();
            let s = smoothing_samples(noise_cm, dt, target_cm_per_s);
            let smoothed = crate::signal::smoothing::smooth_paths(&path, 1, s);
            let velocities: Vec<f64> = smoothed.windows(2).map(|w| (w[1].x - w[0].x) / dt).collect();
            let mean = velocities.iter().sum::<f64>() / velocities.len() as f64;
            let deviation =
                (velocities.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / velocities.len() as f64).sqrt();
            assert!(
                (deviation / target_cm_per_s - 1.0).abs() < 0.2,
                "{noise_cm} cm smoothed over {s:.2} samples moves at {deviation:.2} cm/s, not {target_cm_per_s}"
            );
        }
    }
}
