//! An inertial suit's errors, applied to a recording of the true motion:
//! what a suit would have recorded of it. The model follows the description
//! of the shared suit files' (`../shared/data/README.md`, level 1: the real
//! suit's errors; [`REAL_SUIT_LEVEL`]) but for their vendor translation's
//! occasional foot slides, acting on each segment's global orientation as
//! an IMU's fusion would get it wrong:
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
//! - `noise(j, t)`: orientation noise whose deviation grows with the
//!   segment's angular speed ([`ErrorSizes::noise_deviation_deg`]): fusion
//!   trusts the gyros least when they turn fastest;
//! - `lag`: the fusion filter answers late ([`ErrorSizes::fusion_lag_s`]);
//! - bones: the vendor scales a template skeleton from the actor's height, so
//!   every bone is off by the height's error ([`BODY_SCALE_DEVIATION`]) and
//!   its own ([`ErrorSizes::bone_scale_deviation`]), left and right alike
//!   (`LeftLeg` and `RightLeg`, `UpperLeg_L` and `UpperLeg_R` are one bone),
//!   whether the bone is an OFFSET or position channels (Bandai's);
//! - translation: the vendor's guess of the hips' path
//!   ([`translation_joint`] says in which channels): the true path scaled
//!   about its start by the leg-length ratio (strides scale with the legs)
//!   plus a horizontal random walk ([`VENDOR_WALK_CM_PER_SQRT_S`]).
//!
//! A level scales every one of these deviations, the lag too ([`apply`]).
//! How large the noise, the lag and the bones' spread are at level 1 comes
//! in two sizes ([`ErrorSizes`]): as the README's words put them, and as
//! the shared suit files measure.
//!
//! The suit's rotations are written in each joint's own channel order (any
//! of the six of three axes). Joints without a sensor (toes: the karate
//! suit's 17 sensors have none there) hold their usual bend, and what an
//! exporter puts above the hips (Bandai's `joint_Root`) holds still: see
//! `Part`. The demo's skeleton, the karate suit's, has neither: each foot
//! is one segment, ankle to toe end site, with its own sensor.
//!
//! Random draws are Gaussian, each clamped to ±[`MAX_SIGMAS`] deviations so
//! that no seed gives an absurd suit. A seed's draws come in the same order
//! whatever the skeleton's channels and whichever joints have sensors.

use glam::{DMat3, DVec3};

use crate::body::feet::above_hips;
use crate::body::kinematics::{local_rotation, local_translation, rotation_channel_degrees, world_rotations};
use crate::body::skeleton::{Motion, Skeleton};
use crate::synth::rng::XorShift64;

mod errors;
mod joints;

pub use errors::{
    BODY_SCALE_DEVIATION, Drift, ErrorSizes, HEADING_DRIFT_DEG, HEADING_DRIFT_PERIODS_S, MAX_SIGMAS,
    MISALIGNMENT_DEG, REAL_SUIT_LEVEL, SEGMENT_DRIFT_DEG, SEGMENT_DRIFT_PERIODS_S, VENDOR_WALK_CM_PER_SQRT_S,
    random_rotation,
};
use errors::{CorrelatedNoise, clamped, rotation_deg, windowed_angular_speeds};
use joints::{
    Part, bone_scales, held_channels, parts, rotation_channel_indices, scale_position_bones, scaled_skeleton,
};
pub use joints::{SuitBody, joints_kept_true, sensed_joints, translation_joint};

/// A recording through the suit's errors.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitGrade {
    /// The skeleton with the vendor's bone lengths.
    pub skeleton: Skeleton,
    /// Rotations as the suit measured them; the vendor's translation in the
    /// position channels of the joint that carries it
    /// ([`translation_joint`]); bones given by position channels scaled like
    /// the OFFSETs.
    pub motion: Motion,
    /// Suit leg length / true leg length (the bones `apply` was given).
    pub leg_length_ratio: f64,
}

/// Applies the suit's errors (of `sizes`, seeded by `seed`, `level` times
/// the real suit's, see [`REAL_SUIT_LEVEL`]; a negative or NaN level counts
/// as 0) to `motion` of `skeleton`. Rotation channels may come in any order
/// of three axes; a sensed joint with other rotation channels (one, two, or
/// one axis twice) keeps its true ones. Bones may be OFFSETs or position
/// channels: both are scaled, by the same draw. The hips' path is the
/// vendor's guess ([`translation_joint`] says in which channels), the joints
/// above the hips hold still, toes without a sensor hold their usual bend.
pub fn apply(
    skeleton: &Skeleton,
    motion: &Motion,
    body: &SuitBody,
    sizes: &ErrorSizes,
    seed: u64,
    level: f64,
) -> SuitGrade {
    let level = level.max(0.0);
    let n = skeleton.joint_count();
    let parts = parts(skeleton, body.hips);
    let carrier = translation_joint(skeleton, body.hips);
    let is_bone: Vec<bool> = (0..n).map(|j| j != body.hips && parts[j] != Part::AboveHips).collect();
    let mut rng = XorShift64(seed.max(1));
    let scales = bone_scales(skeleton, &mut rng, sizes, level);
    let suit_skeleton = scaled_skeleton(skeleton, &scales, &is_bone);
    let mut out = motion.clone();
    scale_position_bones(skeleton, &mut out, &scales, &is_bone);
    let frames = motion.frame_count();
    if frames == 0 {
        return SuitGrade { skeleton: suit_skeleton, motion: out, leg_length_ratio: 1.0 };
    }
    // A bone's length at the first frame: its OFFSET, or its position channels.
    let leg = |s: &Skeleton, m: &Motion| {
        let bone = |j: usize| {
            let first = s.first_channel[j];
            local_translation(
                s.offsets_cm[j],
                &s.channels[j],
                &m.frame(0)[first..first + s.channels[j].len()],
            )
        };
        body.leg_bones.iter().map(|&j| bone(j).length()).sum::<f64>()
    };
    let leg_length_ratio = Some(leg(&suit_skeleton, &out) / leg(skeleton, motion))
        .filter(|ratio| ratio.is_finite())
        .unwrap_or(1.0);
    let misalignment: Vec<DMat3> =
        (0..n).map(|_| random_rotation(&mut rng, MISALIGNMENT_DEG * level)).collect();
    let heading = Drift::new(&mut rng, HEADING_DRIFT_DEG * level, HEADING_DRIFT_PERIODS_S);
    let drift: Vec<[Drift; 3]> = (0..n)
        .map(|_| {
            std::array::from_fn(|_| Drift::new(&mut rng, SEGMENT_DRIFT_DEG * level, SEGMENT_DRIFT_PERIODS_S))
        })
        .collect();

    let world = world_rotations(skeleton, motion);
    let held = held_channels(skeleton, motion, &parts, carrier);
    let fps = motion.fps();
    let at = |f: usize, j: usize| world[f * n + j];
    let lag_frames = sizes.fusion_lag_s * level * fps;
    let speeds = windowed_angular_speeds(&world, n, fps, sizes.noise_speed_window_s);
    let mut noise = CorrelatedNoise::new(n, sizes.noise_kept(fps));
    let mut suit_world = vec![DMat3::IDENTITY; n];
    // Each joint's global rotation as the file now says it: the suit's for
    // a sensed joint, through the held channels for the others.
    let mut written_world = vec![DMat3::IDENTITY; n];
    for f in 0..frames {
        let t_s = f as f64 / fps;
        let lagged = (f as f64 - lag_frames).max(0.0);
        let (before, fraction) = (lagged.floor() as usize, lagged.fract());
        let after = (before + 1).min(frames - 1);
        let heading_world = DMat3::from_rotation_y(heading.at_deg(t_s).to_radians());
        // Every joint draws its noise, sensor or not: a seed's draws are
        // the same whichever joints have sensors.
        for j in 0..n {
            let true_lagged = DMat3::from_quat(at(before, j).slerp(at(after, j), fraction));
            let noise = noise.next(&mut rng, f, j, sizes.noise_deviation_deg(speeds[f * n + j]) * level);
            let own_deg =
                DVec3::new(drift[j][0].at_deg(t_s), drift[j][1].at_deg(t_s), drift[j][2].at_deg(t_s));
            let own = rotation_deg(own_deg);
            suit_world[j] = heading_world * own * noise * true_lagged * misalignment[j];
        }
        let values = out.frame_mut(f);
        for &(index, value) in &held {
            values[index] = value;
        }
        for j in 0..n {
            let parent = skeleton.parents[j].map_or(DMat3::IDENTITY, |p| written_world[p]);
            let first = skeleton.first_channel[j];
            let channels = &skeleton.channels[j];
            let rotations = rotation_channel_indices(channels).filter(|_| parts[j] == Part::Sensed);
            let angles = rotations.and_then(|indices| {
                rotation_channel_degrees(indices.map(|i| channels[i]), parent.transpose() * suit_world[j])
                    .map(|angles| (indices, angles))
            });
            written_world[j] = match angles {
                Some((indices, angles)) => {
                    for (i, degrees) in indices.into_iter().zip(angles) {
                        values[first + i] = degrees;
                    }
                    suit_world[j]
                }
                None => parent * local_rotation(channels, &values[first..first + channels.len()]),
            };
        }
    }
    if let Some(carrier) = carrier {
        vendor_translation(skeleton, motion, &mut out, carrier, leg_length_ratio, level, &mut rng);
    }
    SuitGrade { skeleton: suit_skeleton, motion: out, leg_length_ratio }
}

/// Where `joint` is and how it is turned in the world, in a frame whose
/// channel values are `values`: the joints from the root down to it, one
/// after the other.
fn world_frame(skeleton: &Skeleton, values: &[f64], joint: usize) -> (DVec3, DMat3) {
    let mut chain = vec![joint];
    chain.extend(above_hips(&skeleton.parents, joint));
    let (mut position_cm, mut rotation) = (DVec3::ZERO, DMat3::IDENTITY);
    for &j in chain.iter().rev() {
        let first = skeleton.first_channel[j];
        let own = &values[first..first + skeleton.channels[j].len()];
        position_cm += rotation * local_translation(skeleton.offsets_cm[j], &skeleton.channels[j], own);
        rotation *= local_rotation(&skeleton.channels[j], own);
    }
    (position_cm, rotation)
}

/// Replaces the position channels of `carrier` ([`translation_joint`]) in
/// `motion` with the vendor's guess of its path in `truth`: the true path
/// scaled about its start by `ratio` (the height too, from the floor), plus
/// the horizontal random walk (`level` times the real suit's). A carrier
/// below the root has its whole path guessed in the world (its parents'
/// motion too) and written in its parent's frame, which in `motion` holds
/// its first frame.
fn vendor_translation(
    skeleton: &Skeleton,
    truth: &Motion,
    motion: &mut Motion,
    carrier: usize,
    ratio: f64,
    level: f64,
    rng: &mut XorShift64,
) {
    let first = skeleton.first_channel[carrier];
    let axes: Vec<(usize, usize)> = skeleton.channels[carrier]
        .iter()
        .enumerate()
        .filter(|(_, c)| c.is_position())
        .map(|(i, c)| (first + i, c.axis()))
        .collect();
    let parent_frame = skeleton.parents[carrier].map(|p| world_frame(skeleton, motion.frame(0), p));
    let true_start_cm = world_frame(skeleton, truth.frame(0), carrier).0;
    let start: Vec<f64> = axes.iter().map(|&(i, _)| motion.frame(0)[i]).collect();
    let step_cm = VENDOR_WALK_CM_PER_SQRT_S * level * libm::sqrt(motion.frame_time_s);
    let mut walk_cm = [0.0; 3];
    for f in 0..motion.frame_count() {
        if f > 0 {
            walk_cm[0] += step_cm * clamped(rng);
            walk_cm[2] += step_cm * clamped(rng);
        }
        let values = motion.frame_mut(f);
        match parent_frame {
            Some((parent_cm, parent_rotation)) => {
                let true_cm = world_frame(skeleton, truth.frame(f), carrier).0;
                let guess_cm = DVec3::new(
                    true_start_cm.x + (true_cm.x - true_start_cm.x) * ratio + walk_cm[0],
                    true_cm.y * ratio,
                    true_start_cm.z + (true_cm.z - true_start_cm.z) * ratio + walk_cm[2],
                );
                let local_cm = parent_rotation.transpose() * (guess_cm - parent_cm);
                for &(i, axis) in &axes {
                    values[i] = local_cm[axis];
                }
            }
            // The root: its channels are its path.
            None => {
                for (&(i, axis), &start_cm) in axes.iter().zip(&start) {
                    values[i] = match axis {
                        1 => values[i] * ratio,
                        _ => start_cm + (values[i] - start_cm) * ratio + walk_cm[axis],
                    };
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::skeleton::Channel;
    use crate::signal::stats::median;
    use glam::DQuat;

    use crate::body::feet::detect_feet;
    use crate::body::kinematics::forward_kinematics;

    /// A Bandai-like skeleton: every joint has `Xposition Yposition
    /// Zposition` and then `rotations`; position channels are the bones.
    /// `joint_Root` on the floor, `Hips` above it, one leg a side (thigh,
    /// shank, foot, toes) and a spine. Ten frames of a made-up motion: the
    /// hips travel along +Z (in `joint_Root` too when `root_moves`), every
    /// joint turns.
    fn bandai_like(rotations: [Channel; 3], root_moves: bool) -> (Skeleton, Motion) {
        let mut s = Skeleton::default();
        let mut channels = vec![Channel::Xposition, Channel::Yposition, Channel::Zposition];
        channels.extend(rotations);
        let mut add = |name: &str, parent: Option<usize>, bone_cm: [f64; 3]| {
            s.push_joint(name.into(), parent, DVec3::from_array(bone_cm), channels.clone(), false)
        };
        let root = add("joint_Root", None, [0.0; 3]);
        let hips = add("Hips", Some(root), [0.0, 92.0, 0.0]);
        for (side, x) in [("L", 9.0), ("R", -9.0)] {
            let thigh = add(&format!("UpperLeg_{side}"), Some(hips), [x, -6.0, 0.0]);
            let shank = add(&format!("LowerLeg_{side}"), Some(thigh), [0.0, -40.0, 0.0]);
            let foot = add(&format!("Foot_{side}"), Some(shank), [0.0, -41.0, 0.0]);
            add(&format!("Toes_{side}"), Some(foot), [0.0, -5.0, 11.0]);
        }
        let spine = add("Spine", Some(hips), [0.0, 15.0, 0.0]);
        s.push_joint("EndSite".into(), Some(spine), DVec3::new(0.0, 30.0, 0.0), vec![], true);
        let frames = 10;
        let mut motion =
            Motion { channel_count: s.channel_count(), frame_time_s: 1.0 / 30.0, values: Vec::new() };
        for f in 0..frames {
            let t = f as f64;
            for j in 0..s.joint_count() {
                let bone_cm = s.offsets_cm[j];
                for (i, channel) in s.channels[j].iter().enumerate() {
                    motion.values.push(match (j, channel.is_position()) {
                        (0, true) if root_moves && i == 2 => 12.0 * t,
                        (1, true) if i == 2 => 3.0 * t,
                        (1, true) if i == 1 => 92.0 + 0.5 * t,
                        (_, true) => bone_cm[i],
                        (0, false) => 0.0,
                        // Every joint turns, by its own amount about each axis.
                        (_, false) => (j as f64 + 1.0) * (i as f64) * (0.7 + 0.3 * t),
                    });
                }
            }
        }
        (s, motion)
    }

    fn suit_body(s: &Skeleton) -> SuitBody {
        SuitBody::from_feet(s, detect_feet(&s.names).unwrap())
    }

    fn channel(s: &Skeleton, joint: &str, channel: Channel) -> usize {
        let j = s.joint(joint).unwrap();
        s.first_channel[j] + s.channels[j].iter().position(|&c| c == channel).unwrap()
    }

    #[test]
    fn bones_given_by_position_channels_are_scaled_like_offsets() {
        use Channel::{Xposition, Xrotation, Yposition, Yrotation, Zposition, Zrotation};
        let (s, motion) = bandai_like([Zrotation, Xrotation, Yrotation], false);
        let body = suit_body(&s);
        assert_eq!((s.names[body.hips].as_str(), body.leg_bones.len()), ("Hips", 2));
        let suit = apply(&s, &motion, &body, &ErrorSizes::MEASURED, 5, REAL_SUIT_LEVEL);
        let frame = suit.motion.frame(7);
        let scale = |joint: &str, axis: Channel| {
            frame[channel(&s, joint, axis)] / motion.frame(7)[channel(&s, joint, axis)]
        };
        let shank = scale("LowerLeg_L", Yposition);
        assert!((shank - 1.0).abs() > 1e-4 && (shank - 1.0).abs() < 0.1, "{shank}");
        // One bone, one scale: in every frame, both sides, the OFFSET too.
        assert_eq!(scale("LowerLeg_R", Yposition), shank);
        assert_eq!(suit.motion.frame(2)[channel(&s, "LowerLeg_L", Yposition)], -40.0 * shank);
        let shank_joint = s.joint("LowerLeg_L").unwrap();
        assert_eq!(suit.skeleton.offsets_cm[shank_joint], s.offsets_cm[shank_joint] * shank);
        assert_eq!(scale("UpperLeg_L", Xposition), scale("UpperLeg_L", Yposition));
        assert_ne!(scale("Spine", Yposition), shank);
        let thigh = scale("LowerLeg_L", Yposition);
        let foot = scale("Foot_L", Yposition);
        let expected_ratio = (40.0 * thigh + 41.0 * foot) / 81.0;
        assert!((suit.leg_length_ratio - expected_ratio).abs() < 1e-12);
        // The hips are no bone: their channels are the vendor's path, from
        // the same start, the true 3 cm a frame scaled by the leg-length
        // ratio, plus the walk (about 1.8 cm a frame at 30 fps).
        let hips_z = channel(&s, "Hips", Zposition);
        assert_eq!(suit.motion.frame(0)[hips_z], 0.0);
        assert!((suit.motion.frame(9)[hips_z] - 27.0 * suit.leg_length_ratio).abs() < 10.0);
        let hips_y = channel(&s, "Hips", Yposition);
        assert_eq!(suit.motion.frame(0)[hips_y], 92.0 * suit.leg_length_ratio);
    }

    /// The global rotations of `motion` of `s`, frame after frame.
    fn rotations(s: &Skeleton, motion: &Motion) -> Vec<DQuat> {
        world_rotations(s, motion)
    }

    #[test]
    fn a_perfect_suit_gives_back_the_truth_in_any_channel_order() {
        use Channel::{Xrotation as X, Yrotation as Y, Zrotation as Z};
        for order in [[Z, X, Y], [Y, X, Z], [X, Y, Z]] {
            let (s, motion) = bandai_like(order, true);
            let body = suit_body(&s);
            let suit = apply(&s, &motion, &body, &ErrorSizes::MEASURED, 9, 0.0);
            assert_eq!(suit.leg_length_ratio, 1.0);
            let (truth, graded) = (rotations(&s, &motion), rotations(&s, &suit.motion));
            let toes: Vec<usize> = ["Toes_L", "Toes_R"].map(|t| s.joint(t).unwrap()).to_vec();
            let n = s.joint_count();
            for (k, (a, b)) in truth.iter().zip(&graded).enumerate() {
                if !toes.contains(&(k % n)) {
                    let e = a.angle_between(*b);
                    // acos near 1 is good to ~1e-8 only.
                    assert!(e < 1e-6, "{order:?}: joint {} frame {}: {e}", k % n, k / n);
                }
            }
            // Where the body is: the whole path in the hips, none in the root.
            let (true_poses, suit_poses) =
                (forward_kinematics(&s, &motion), forward_kinematics(&suit.skeleton, &suit.motion));
            for f in 0..motion.frame_count() {
                assert_eq!(suit_poses.at(f, 0), DVec3::ZERO);
                let (suit_cm, true_cm) = (suit_poses.at(f, body.hips), true_poses.at(f, body.hips));
                assert!(suit_cm.distance(true_cm) < 1e-9, "{order:?} frame {f}: {suit_cm} {true_cm}");
            }
        }
    }

    #[test]
    fn toes_without_a_sensor_hold_their_usual_bend() {
        use Channel::{Xrotation, Yrotation, Zrotation};
        let (s, motion) = bandai_like([Zrotation, Xrotation, Yrotation], false);
        let suit = apply(&s, &motion, &suit_body(&s), &ErrorSizes::MEASURED, 3, REAL_SUIT_LEVEL);
        for rotation in [Zrotation, Xrotation, Yrotation] {
            let index = channel(&s, "Toes_L", rotation);
            let truth: Vec<f64> = (0..motion.frame_count()).map(|f| motion.frame(f)[index]).collect();
            for f in 0..motion.frame_count() {
                assert_eq!(suit.motion.frame(f)[index], median(&truth), "{rotation:?} frame {f}");
            }
        }
        // The foot above them has a sensor.
        let foot = channel(&s, "Foot_L", Zrotation);
        assert_ne!(suit.motion.frame(4)[foot], motion.frame(4)[foot]);
    }

    #[test]
    fn half_the_level_is_half_of_each_error() {
        use Channel::{Xrotation, Yrotation, Zrotation};
        let (s, motion) = bandai_like([Zrotation, Xrotation, Yrotation], false);
        let body = suit_body(&s);
        let [full, half] =
            [REAL_SUIT_LEVEL, 0.5].map(|level| apply(&s, &motion, &body, &ErrorSizes::MEASURED, 11, level));
        let shank = s.joint("LowerLeg_L").unwrap();
        let deviation = |g: &SuitGrade| g.skeleton.offsets_cm[shank].y / s.offsets_cm[shank].y - 1.0;
        // One draw for both levels: the body's and the bone's deviations
        // halve, their product's square goes by a quarter.
        let (a, b) = (deviation(&full), deviation(&half));
        assert!(b.abs() < a.abs() && (a - 2.0 * b).abs() < a.abs() * 0.05 + 1e-3, "{a} {b}");
        let truth = rotations(&s, &motion);
        let error_rad = |g: &SuitGrade| {
            let graded = rotations(&s, &g.motion);
            truth.iter().zip(&graded).map(|(a, b)| a.angle_between(*b)).sum::<f64>()
        };
        let ratio = error_rad(&half) / error_rad(&full);
        assert!((ratio - 0.5).abs() < 0.1, "{ratio}");
    }
}
