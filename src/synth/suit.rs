//! An inertial suit's errors, applied to a motion made in code: what a suit
//! would have recorded of it. The model follows the description of the
//! shared suit files' (`../shared/data/README.md`, level 1: the real suit's
//! errors) but for their vendor translation's occasional foot slides,
//! acting on each segment's global orientation as an IMU's fusion would get
//! it wrong:
//!
//! `world_from_suit(j, t) = heading(t) · drift(j, t) · noise(j, t) · world_from_true(j, t − lag) · misalignment(j)`
//!
//! - `misalignment(j)`: the sensor sits a little askew on its segment, a
//!   constant rotation in the segment's frame ([`MISALIGNMENT_DEG`] per axis);
//! - `heading(t)`: the slow heading drift every sensor shares (magnetometer,
//!   gyro bias), about the vertical ([`HEADING_DRIFT_DEG`], periods of
//!   [`HEADING_DRIFT_PERIODS_S`]);
//! - `drift(j, t)`: each sensor's own smaller drift and tilt, about all three
//!   axes ([`SEGMENT_DRIFT_DEG`], periods of [`SEGMENT_DRIFT_PERIODS_S`]);
//! - `noise(j, t)`: orientation noise, white from frame to frame, whose
//!   deviation grows with the segment's angular speed ([`noise_deviation_deg`]:
//!   2° at 2 rad/s): fusion trusts the gyros least when they turn fastest;
//! - `lag`: the fusion filter answers [`FUSION_LAG_S`] late;
//! - bones: the vendor scales a template skeleton from the actor's height, so
//!   every bone is off by the height's error ([`BODY_SCALE_DEVIATION`]) and
//!   its own ([`BONE_SCALE_DEVIATION`]), left and right alike;
//! - translation: the vendor's guess, in the root's position channels: the
//!   true path scaled about its start by the leg-length ratio (strides scale
//!   with the legs) plus a horizontal random walk ([`VENDOR_WALK_CM_PER_SQRT_S`]).
//!
//! Joints without a sensor would keep their rest rotation (a suit's toes);
//! the demo's skeleton, the karate suit's, has none: each foot is one
//! segment, ankle to toe end site, with its own sensor.
//!
//! Random draws are Gaussian, each clamped to ±[`MAX_SIGMAS`] deviations so
//! that no seed gives an absurd suit.

use glam::{DMat3, DQuat, DVec3};

use crate::body::kinematics::{local_rotation, zyx_degrees};
use crate::body::skeleton::{Channel, Motion, Skeleton};
use crate::synth::rng::XorShift64;

/// Deviation of the sensor-to-segment misalignment, per axis.
pub const MISALIGNMENT_DEG: f64 = 2.0;
/// Root mean square of the heading drift shared by the body.
pub const HEADING_DRIFT_DEG: f64 = 3.0;
/// The shared drift's sines have periods drawn in this range.
pub const HEADING_DRIFT_PERIODS_S: (f64, f64) = (8.0, 40.0);
/// Root mean square of each segment's own drift, per axis.
pub const SEGMENT_DRIFT_DEG: f64 = 1.0;
/// A segment's drift's sines have periods drawn in this range.
pub const SEGMENT_DRIFT_PERIODS_S: (f64, f64) = (2.0, 10.0);
/// Sines summed in each drift (each of random period and phase).
const DRIFT_SINES: usize = 4;
/// Orientation noise per unit of angular speed, per axis.
pub const NOISE_DEG_PER_RAD_PER_S: f64 = 1.0;
/// Orientation noise of a segment at rest, per axis.
pub const NOISE_FLOOR_DEG: f64 = 0.1;
/// How late the fusion filter's orientation is.
pub const FUSION_LAG_S: f64 = 0.03;
/// Relative deviation of the actor's height as the vendor takes it.
pub const BODY_SCALE_DEVIATION: f64 = 0.02;
/// Relative deviation of each bone of the template from the actor's.
pub const BONE_SCALE_DEVIATION: f64 = 0.02;
/// The vendor's translation wanders by this much per √s, per horizontal
/// axis (a random walk): about 50 cm over the demo's 24 s. The real karate
/// suit's vendor translation misses its kata's closure by 3.7 m.
pub const VENDOR_WALK_CM_PER_SQRT_S: f64 = 10.0;
/// Every Gaussian draw is clamped to this many deviations.
pub const MAX_SIGMAS: f64 = 2.5;

/// The per-axis deviation of the orientation noise of a segment turning at
/// `angular_speed_rad_per_s`: the floor and the part that grows with the
/// speed, added in quadrature.
pub fn noise_deviation_deg(angular_speed_rad_per_s: f64) -> f64 {
    let moving_deg = NOISE_DEG_PER_RAD_PER_S * angular_speed_rad_per_s;
    libm::sqrt(NOISE_FLOOR_DEG * NOISE_FLOOR_DEG + moving_deg * moving_deg)
}

/// A rotation error drawn as a rotation vector with `deviation_deg` per axis.
pub fn random_rotation(rng: &mut XorShift64, deviation_deg: f64) -> DMat3 {
    let axis_deg = DVec3::new(clamped(rng), clamped(rng), clamped(rng)) * deviation_deg;
    DMat3::from_quat(DQuat::from_scaled_axis(axis_deg * (std::f64::consts::PI / 180.0)))
}

/// A standard normal draw clamped to ±[`MAX_SIGMAS`].
fn clamped(rng: &mut XorShift64) -> f64 {
    rng.gaussian().clamp(-MAX_SIGMAS, MAX_SIGMAS)
}

/// A slow drift: a sum of [`DRIFT_SINES`] sines of random periods and
/// phases whose root mean square, over times long against the periods, is
/// the one asked for.
#[derive(Clone, Debug)]
pub struct Drift {
    amplitude_deg: f64,
    /// (angular frequency in rad/s, phase in rad) of each sine.
    sines: Vec<(f64, f64)>,
}

impl Drift {
    pub fn new(rng: &mut XorShift64, rms_deg: f64, periods_s: (f64, f64)) -> Drift {
        let sines = (0..DRIFT_SINES)
            .map(|_| {
                let u = 0.5 * (rng.symmetric() + 1.0);
                let period_s = periods_s.0 + u * (periods_s.1 - periods_s.0);
                (std::f64::consts::TAU / period_s, std::f64::consts::PI * rng.symmetric())
            })
            .collect();
        Drift { amplitude_deg: rms_deg * libm::sqrt(2.0 / DRIFT_SINES as f64), sines }
    }

    /// The drift at time `t_s`, in degrees.
    pub fn at_deg(&self, t_s: f64) -> f64 {
        self.sines.iter().map(|&(w, phase)| self.amplitude_deg * libm::sin(w * t_s + phase)).sum()
    }
}

/// A recording through the suit's errors.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitGrade {
    /// The skeleton with the vendor's bone lengths.
    pub skeleton: Skeleton,
    /// Rotations as the suit measured them; the vendor's translation in the
    /// root's position channels.
    pub motion: Motion,
    /// Suit leg length / true leg length (the bones `apply` was given).
    pub leg_length_ratio: f64,
}

/// The bone a joint's offset is, without its side: `LeftLeg` and `RightLeg`
/// are the same bone of the template; an end site is its parent's end.
fn bone_key(skeleton: &Skeleton, joint: usize) -> String {
    let name = &skeleton.names[joint];
    match (skeleton.is_end_site[joint], skeleton.parents[joint]) {
        (true, Some(parent)) => format!("{} end", bone_key(skeleton, parent)),
        _ => name.strip_prefix("Left").or_else(|| name.strip_prefix("Right")).unwrap_or(name).to_string(),
    }
}

/// The template's bone lengths: one scale per bone (left and right alike)
/// times one for the whole body.
fn scaled_skeleton(skeleton: &Skeleton, rng: &mut XorShift64) -> Skeleton {
    let body = 1.0 + BODY_SCALE_DEVIATION * clamped(rng);
    let mut scales: Vec<(String, f64)> = Vec::new();
    let mut scaled = skeleton.clone();
    for joint in 0..skeleton.joint_count() {
        let key = bone_key(skeleton, joint);
        let scale = match scales.iter().find(|(k, _)| *k == key) {
            Some(&(_, s)) => s,
            None => {
                let s = body * (1.0 + BONE_SCALE_DEVIATION * clamped(rng));
                scales.push((key, s));
                s
            }
        };
        scaled.offsets_cm[joint] *= scale;
    }
    scaled
}

/// Where a joint's rotation channels start, if they are
/// `Zrotation Yrotation Xrotation` (the only order the model writes).
fn zyx_start(channels: &[Channel]) -> Option<usize> {
    let zyx = [Channel::Zrotation, Channel::Yrotation, Channel::Xrotation];
    channels.windows(3).position(|w| w == zyx)
}

/// Every joint's true global rotation, frame after frame (`frame * joints + joint`).
fn world_rotations(skeleton: &Skeleton, motion: &Motion) -> Vec<DQuat> {
    let n = skeleton.joint_count();
    let mut world = Vec::with_capacity(n * motion.frame_count());
    for f in 0..motion.frame_count() {
        let values = motion.frame(f);
        let start = world.len();
        for j in 0..n {
            let first = skeleton.first_channel[j];
            let channels = &skeleton.channels[j];
            let local = local_rotation(channels, &values[first..first + channels.len()]);
            let parent = skeleton.parents[j].map_or(DMat3::IDENTITY, |p| DMat3::from_quat(world[start + p]));
            world.push(DQuat::from_mat3(&(parent * local)).normalize());
        }
    }
    world
}

/// The angle of a rotation, in radians.
fn angle_rad(q: DQuat) -> f64 {
    2.0 * libm::atan2(q.xyz().length(), q.w.abs())
}

/// Applies the suit's errors (seeded by `seed`) to `motion` of `skeleton`,
/// whose root carries the translation in its position channels. `leg_bones`
/// are the joints whose offsets make one leg (thigh and shank), for the
/// leg-length ratio the vendor's translation is scaled by. Joints whose
/// rotation channels are not `Zrotation Yrotation Xrotation` keep their
/// true rotations.
pub fn apply(skeleton: &Skeleton, motion: &Motion, leg_bones: &[usize], seed: u64) -> SuitGrade {
    let mut rng = XorShift64(seed.max(1));
    let suit_skeleton = scaled_skeleton(skeleton, &mut rng);
    let leg = |s: &Skeleton| leg_bones.iter().map(|&j| s.offsets_cm[j].length()).sum::<f64>();
    let leg_length_ratio = leg(&suit_skeleton) / leg(skeleton);
    let n = skeleton.joint_count();
    let misalignment: Vec<DMat3> = (0..n).map(|_| random_rotation(&mut rng, MISALIGNMENT_DEG)).collect();
    let heading = Drift::new(&mut rng, HEADING_DRIFT_DEG, HEADING_DRIFT_PERIODS_S);
    let drift: Vec<[Drift; 3]> = (0..n)
        .map(|_| std::array::from_fn(|_| Drift::new(&mut rng, SEGMENT_DRIFT_DEG, SEGMENT_DRIFT_PERIODS_S)))
        .collect();

    let world = world_rotations(skeleton, motion);
    let frames = motion.frame_count();
    let fps = motion.fps();
    let at = |f: usize, j: usize| world[f * n + j];
    let lag_frames = FUSION_LAG_S * fps;
    let mut out = motion.clone();
    let mut suit_world = vec![DMat3::IDENTITY; n];
    for f in 0..frames {
        let t_s = f as f64 / fps;
        let lagged = (f as f64 - lag_frames).max(0.0);
        let (before, fraction) = (lagged.floor() as usize, lagged.fract());
        let after = (before + 1).min(frames - 1);
        let (prev, next) = (f.saturating_sub(1), (f + 1).min(frames - 1));
        let heading_world = DMat3::from_rotation_y(heading.at_deg(t_s).to_radians());
        for j in 0..n {
            let true_lagged = DMat3::from_quat(at(before, j).slerp(at(after, j), fraction));
            let turned_rad = angle_rad(at(prev, j).inverse() * at(next, j));
            let speed_rad_per_s = turned_rad * fps / (next - prev).max(1) as f64;
            let noise = random_rotation(&mut rng, noise_deviation_deg(speed_rad_per_s));
            let own_deg =
                DVec3::new(drift[j][0].at_deg(t_s), drift[j][1].at_deg(t_s), drift[j][2].at_deg(t_s));
            let own = DMat3::from_quat(DQuat::from_scaled_axis(own_deg * (std::f64::consts::PI / 180.0)));
            suit_world[j] = heading_world * own * noise * true_lagged * misalignment[j];
        }
        let values = out.frame_mut(f);
        for j in 0..n {
            let Some(start) = zyx_start(&skeleton.channels[j]) else { continue };
            let parent = skeleton.parents[j].map_or(DMat3::IDENTITY, |p| suit_world[p]);
            let first = skeleton.first_channel[j] + start;
            values[first..first + 3].copy_from_slice(&zyx_degrees(parent.transpose() * suit_world[j]));
        }
    }
    vendor_translation(skeleton, &mut out, leg_length_ratio, &mut rng);
    SuitGrade { skeleton: suit_skeleton, motion: out, leg_length_ratio }
}

/// Replaces the root's position channels in `motion` with the vendor's
/// guess: the true path scaled about its start by `ratio` (the height
/// too, from the floor), plus the horizontal random walk.
fn vendor_translation(skeleton: &Skeleton, motion: &mut Motion, ratio: f64, rng: &mut XorShift64) {
    let root = skeleton.first_channel[0];
    let axes: Vec<(usize, usize)> = skeleton.channels[0]
        .iter()
        .enumerate()
        .filter(|(_, c)| c.is_position())
        .map(|(i, c)| (root + i, c.axis()))
        .collect();
    let start: Vec<f64> = axes.iter().map(|&(i, _)| motion.frame(0)[i]).collect();
    let step_cm = VENDOR_WALK_CM_PER_SQRT_S * libm::sqrt(motion.frame_time_s);
    let mut walk_cm = [0.0; 3];
    for f in 0..motion.frame_count() {
        if f > 0 {
            walk_cm[0] += step_cm * clamped(rng);
            walk_cm[2] += step_cm * clamped(rng);
        }
        let values = motion.frame_mut(f);
        for (&(i, axis), &start_cm) in axes.iter().zip(&start) {
            values[i] = match axis {
                1 => values[i] * ratio,
                _ => start_cm + (values[i] - start_cm) * ratio + walk_cm[axis],
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_has_the_deviation_it_says() {
        assert!((noise_deviation_deg(2.0) - 2.0).abs() < 0.01, "about 2° at 2 rad/s");
        assert_eq!(noise_deviation_deg(0.0), NOISE_FLOOR_DEG);
        let mut rng = XorShift64(7);
        let n = 40_000;
        let deviation_deg = noise_deviation_deg(2.0);
        let mut sum_sq = DVec3::ZERO;
        for _ in 0..n {
            let q = DQuat::from_mat3(&random_rotation(&mut rng, deviation_deg));
            let v = q.to_scaled_axis() * (180.0 / std::f64::consts::PI);
            sum_sq += v * v;
        }
        let measured = (sum_sq / n as f64).to_array().map(f64::sqrt);
        // Clamping at 2.5 deviations takes ~3% of the variance away.
        for axis_deg in measured {
            assert!((axis_deg / deviation_deg - 0.985).abs() < 0.02, "{measured:?} for {deviation_deg}");
        }
    }

    #[test]
    fn a_drift_has_its_root_mean_square() {
        let mut rng = XorShift64(11);
        let drift = Drift::new(&mut rng, HEADING_DRIFT_DEG, HEADING_DRIFT_PERIODS_S);
        let samples: Vec<f64> = (0..200_000).map(|k| drift.at_deg(k as f64 * 0.05)).collect();
        let rms = (samples.iter().map(|x| x * x).sum::<f64>() / samples.len() as f64).sqrt();
        assert!((rms / HEADING_DRIFT_DEG - 1.0).abs() < 0.05, "{rms}");
        let peak = samples.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(peak <= HEADING_DRIFT_DEG * (2.0 * DRIFT_SINES as f64).sqrt() + 1e-9, "{peak}");
    }

    #[test]
    fn left_and_right_are_one_bone() {
        let mut s = Skeleton::default();
        let root = s.push_joint("Hips".into(), None, DVec3::ZERO, vec![], false);
        let left = s.push_joint("LeftLeg".into(), Some(root), DVec3::new(0.0, -40.0, 0.0), vec![], false);
        let right = s.push_joint("RightLeg".into(), Some(root), DVec3::new(0.0, -40.0, 0.0), vec![], false);
        let end_l = s.push_joint("EndSite3".into(), Some(left), DVec3::new(0.0, -10.0, 0.0), vec![], true);
        let end_r = s.push_joint("EndSite4".into(), Some(right), DVec3::new(0.0, -10.0, 0.0), vec![], true);
        let scaled = scaled_skeleton(&s, &mut XorShift64(3));
        assert_eq!(scaled.offsets_cm[left], scaled.offsets_cm[right]);
        assert_eq!(scaled.offsets_cm[end_l], scaled.offsets_cm[end_r]);
        assert_ne!(scaled.offsets_cm[left], s.offsets_cm[left]);
    }
}
