//! Accuracy of the translation methods on recordings whose true root motion
//! is known (optical mocap), and on katas, which end where they start.
//!
//! A ground-truth file is evaluated by removing its translation — every
//! position channel from the root down to the hips is frozen at its
//! first-frame value — estimating it again, and comparing the hips with the
//! original recording's. A suit-grade file (the same take through an
//! inertial-suit error model) is evaluated the same way against its truth.
//! May import `translate`, `synth` (the built-in demo is scored against its
//! truth), `io`, `body`, `signal`.

pub mod demo;
pub mod metrics;
pub mod suit;
pub mod suit_errors;
pub mod summary;
pub mod track;

use glam::DVec3;

use crate::body::feet::{Foot, FootJoints, PerFoot, foot_points};
use crate::body::skeleton::Poses;
use crate::error::Error;
use crate::eval::metrics::{final_floor_error_cm, floor_closure_cm, floor_path_cm, mean_floor_error_cm};
use crate::io::bvh::Bvh;
use crate::io::recording::{FeetChoice, Recording, base_name, bvh_stem};
use crate::translate::{Method, Translated};

/// A foot is planted in the truth when its lowest point is within this
/// height of the foot's lowest level in the recording and one of its joints
/// moves no faster than `TRUTH_STILL_CM_PER_S` (horizontally): a few
/// millimetres a frame at 30 fps, an optical marker's jitter, not motion.
/// Frames in which a foot on the floor rolls about a point that is no joint
/// (the heel as it lands, the toe tips as it leaves) have no still joint to
/// measure and are not counted.
const TRUTH_LOW_CM: f64 = 3.0;
const TRUTH_STILL_CM_PER_S: f64 = 5.0;

/// How one method did on one ground-truth recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Accuracy {
    pub true_path_cm: f64,
    /// Mean horizontal hips error (first frame aligned), % of the true path.
    pub mean_error_pct: f64,
    /// The last frame's horizontal hips error, % of the true path.
    pub final_error_pct: f64,
    /// Estimated / true horizontal hips path length.
    pub path_ratio: f64,
    /// Foot skating: over the frames where a foot is planted in the truth
    /// (per foot: a frame with both planted counts twice), the mean
    /// horizontal speed in the estimate of the joint of it that the truth
    /// holds still. NaN when no foot is ever planted (a sprint's 20 frames).
    pub skating_cm_per_s: f64,
    /// The same joints' mean speed in the truth: its tracking jitter, a
    /// reference for `skating_cm_per_s` (an estimate that holds the joint
    /// itself still can come in under it).
    pub truth_skating_cm_per_s: f64,
    /// Mean |estimated − true| hips height.
    pub vertical_error_cm: f64,
}

/// The recording with its translation removed: every position channel from
/// the root down to `hips` holds its first-frame value in every frame.
pub fn freeze_translation(bvh: &Bvh, hips: usize) -> Bvh {
    let mut frozen = bvh.clone();
    let mut joint = Some(hips);
    while let Some(j) = joint {
        frozen.motion.hold_positions_at_first_frame(&bvh.skeleton, j);
        joint = bvh.skeleton.parents[j];
    }
    frozen
}

/// The motion type of a file, from its name: `bandai1_walk-right_normal_001`
/// → `walk-right`; otherwise the name without its extension.
pub fn motion_type(name: &str) -> String {
    let stem = bvh_stem(name).unwrap_or_else(|| base_name(name));
    let parts: Vec<&str> = stem.split('_').collect();
    if parts.len() >= 3 { parts[1].to_string() } else { stem.to_string() }
}

/// Per foot and frame `f` (the motion from `f - 1` to `f`): the joint of the
/// foot that `truth` holds still, if the foot is planted (see
/// [`TRUTH_STILL_CM_PER_S`]).
fn truth_still_joints(
    truth: &Poses,
    parents: &[Option<usize>],
    feet: FootJoints,
    fps: f64,
) -> PerFoot<Vec<Option<usize>>> {
    let n = truth.frame_count();
    PerFoot::from_fn(|foot| {
        let points = foot_points(parents, feet[foot]);
        let lowest = |f: usize| points.iter().map(|&j| truth.at(f, j).y).fold(f64::INFINITY, f64::min);
        let floor = (0..n).map(lowest).fold(f64::INFINITY, f64::min);
        let speed = |f: usize, j: usize| (truth.at(f, j) - truth.at(f - 1, j)).with_y(0.0).length() * fps;
        (0..n)
            .map(|f| {
                if f == 0 || lowest(f) - floor > TRUTH_LOW_CM {
                    return None;
                }
                let still = points.iter().copied().min_by(|&a, &b| speed(f, a).total_cmp(&speed(f, b)))?;
                (speed(f, still) <= TRUTH_STILL_CM_PER_S).then_some(still)
            })
            .collect()
    })
}

/// Compares `estimated` with `truth` (the same skeleton and frames).
pub fn accuracy(estimated: &Translated, truth: &Poses, parents: &[Option<usize>], fps: f64) -> Accuracy {
    let hips = estimated.hips;
    let est = estimated.poses.trajectory(hips);
    let tru = truth.trajectory(hips);
    let n = est.len().min(tru.len());
    let true_path_cm = floor_path_cm(&tru[..n]);
    let mean_error = mean_floor_error_cm(&est[..n], &tru[..n]);
    let pct = |cm: f64| 100.0 * cm / true_path_cm;
    // Skating is a planted foot's motion in the estimate. Which point of it
    // to watch: one the truth holds still. Its lowest joint would not do: a
    // walker's toe joint moves at 10-40 cm/s as the toes peel off, so the
    // truth itself would skate, and a method that wrongly held that joint
    // still would score best.
    let still = truth_still_joints(truth, parents, estimated.feet, fps);
    let speed =
        |poses: &Poses, f: usize, j: usize| (poses.at(f, j) - poses.at(f - 1, j)).with_y(0.0).length() * fps;
    let planted: Vec<(usize, usize)> = still
        .iter()
        .flat_map(|(_, frames)| frames[..n].iter().enumerate().filter_map(|(f, j)| j.map(|j| (f, j))))
        .collect();
    let mean_speed = |poses: &Poses| {
        if planted.is_empty() {
            return f64::NAN;
        }
        planted.iter().map(|&(f, j)| speed(poses, f, j)).sum::<f64>() / planted.len() as f64
    };
    Accuracy {
        true_path_cm,
        mean_error_pct: pct(mean_error),
        final_error_pct: if n > 0 { pct(final_floor_error_cm(&est[..n], &tru[..n])) } else { 0.0 },
        path_ratio: floor_path_cm(&est[..n]) / true_path_cm,
        skating_cm_per_s: mean_speed(&estimated.poses),
        truth_skating_cm_per_s: mean_speed(truth),
        vertical_error_cm: (0..n).map(|f| (est[f].y - tru[f].y).abs()).sum::<f64>() / n.max(1) as f64,
    }
}

/// Evaluates `method` on a ground-truth BVH: freezes its translation,
/// estimates it, and compares.
pub fn evaluate_groundtruth(bvh: &Bvh, name: &str, method: &Method) -> Result<Accuracy, Error> {
    let truth = Recording::from_bvh(bvh.clone(), name);
    let feet = truth.feet(&FeetChoice::default())?;
    let frozen = Recording::from_bvh(freeze_translation(bvh, truth.hips(feet)), name);
    let estimated = frozen.translate(&FeetChoice::default(), method)?;
    Ok(accuracy(&estimated, &truth.poses, &truth.parents, truth.fps))
}

/// How one method did on a suit-grade file, scored against its true motion.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitAccuracy {
    /// The estimate from the suit's pose (its own translation removed)
    /// against the true hips.
    pub accuracy: Accuracy,
    /// The floor no method can go below without the true leg length: the
    /// true hips path scaled about its start by the suit's leg length over
    /// the true one (strides scale with the legs), scored like an estimate.
    pub leg_oracle_mean_error_pct: f64,
    /// Suit leg length / true leg length.
    pub leg_length_ratio: f64,
    /// The mean error of the contacts oracle ([`contacts_oracle_path`]), % of
    /// the true path.
    pub contacts_oracle_mean_error_pct: f64,
    /// The mean error of the grounded oracle ([`grounded_oracle_path`]), %
    /// of the true path.
    pub grounded_oracle_mean_error_pct: f64,
    /// The contacts oracle's path length over the true one: how much path
    /// the pose's noise adds where the truth's own decisions pin it.
    pub contacts_oracle_path_ratio: f64,
    /// The grounded oracle's path length over the true one.
    pub grounded_oracle_path_ratio: f64,
}

/// The fastest (cm/s, horizontally) a foot joint may move in the truth and
/// still be the one the contacts oracle pins: a walker's planted toe joint
/// peels off at 10–40 cm/s; a foot in the air moves at hundreds.
const ORACLE_PINNED_MAX_CM_PER_S: f64 = 50.0;

/// The hips' floor path that every contact decision made right gives on the
/// suit's pose, from its [`oracle_pinned_steps`]: in each frame, the foot
/// joint the truth holds stillest (among the feet's joints and their
/// children) is pinned in `suit` (a frame's hips move by minus that joint's
/// move relative to them), and where the truth holds none slower than
/// 50 cm/s (in the air) the hips move as the truth's do. It starts at the
/// truth's start.
///
/// What it measures: how much of the error the suit's pose itself carries
/// when the decisions are the truth's. It is no strict floor: it pins the
/// joints, not the rolling sole below them, which costs about 1.5 % on the
/// clean walks, and a method that smooths the pose's noise out of the path
/// can land below it. Nor is it a ceiling where the body is often in the
/// air: there it is given the true motion, which nothing in the pose
/// measures (see [`grounded_oracle_path`]).
pub fn contacts_oracle_path(pinned: &[Option<DVec3>], truth: &Poses, hips: usize) -> Vec<DVec3> {
    let air = |f: usize| (truth.at(f, hips) - truth.at(f - 1, hips)).with_y(0.0);
    path_from_steps(truth.at(0, hips).with_y(0.0), pinned, air)
}

/// How far (s, a Gaussian's deviation) the grounded oracle reaches for the
/// stances that tell a flight's velocity: a runner's stances come every
/// 0.3–0.4 s, so the take-off's and the landing's weigh most. (Measured on
/// the shared run and dash: 0.1–0.5 s move its figure by about a tenth.)
pub const GROUNDED_ORACLE_REACH_S: f64 = 0.2;

/// The contacts oracle ([`contacts_oracle_path`]) with only what the suit
/// measures in the air: nothing. No joint's motion relative to the hips
/// tells how fast the body flies; it keeps the horizontal velocity it took
/// off with, and lands with it, and those the pose tells only on the floor.
/// So in the air the hips step by the mean of the pinned steps around,
/// weighed by a Gaussian of [`GROUNDED_ORACLE_REACH_S`]. On the floor it is
/// the contacts oracle. Where a body is rarely in the air (walks, kicks)
/// the two agree; on a run or a dash, in the air two thirds of the time,
/// this is what the truth's decisions can do with the pose alone.
pub fn grounded_oracle_path(pinned: &[Option<DVec3>], truth: &Poses, hips: usize, fps: f64) -> Vec<DVec3> {
    let reach_frames = GROUNDED_ORACLE_REACH_S * fps;
    let air = |f: usize| {
        let (mut sum, mut weight) = (DVec3::ZERO, 0.0);
        for (g, step) in pinned.iter().enumerate() {
            if let Some(step) = step {
                let d = (g as f64 - f as f64) / reach_frames;
                let w = libm::exp(-0.5 * d * d);
                sum += *step * w;
                weight += w;
            }
        }
        if weight > 0.0 { sum / weight } else { DVec3::ZERO }
    };
    path_from_steps(truth.at(0, hips).with_y(0.0), pinned, air)
}

/// Per frame, the hips' floor step into it that the truth's contact decision
/// gives on `suit` (see [`contacts_oracle_path`]); `None` in frame 0 and
/// where the truth holds no foot joint slower than
/// `ORACLE_PINNED_MAX_CM_PER_S`. Both oracles are built on these steps.
pub fn oracle_pinned_steps(
    suit: &Poses,
    truth: &Poses,
    parents: &[Option<usize>],
    feet: FootJoints,
    hips: usize,
    fps: f64,
) -> Vec<Option<DVec3>> {
    let n = suit.frame_count().min(truth.frame_count());
    let joints: Vec<usize> =
        Foot::BOTH.into_iter().flat_map(|foot| foot_points(parents, feet[foot])).collect();
    (0..n)
        .map(|f| {
            if f == 0 {
                return None;
            }
            let speed = |j: usize| (truth.at(f, j) - truth.at(f - 1, j)).with_y(0.0).length() * fps;
            let still = joints.iter().copied().min_by(|&a, &b| speed(a).total_cmp(&speed(b)))?;
            (speed(still) <= ORACLE_PINNED_MAX_CM_PER_S).then(|| {
                let hips_to_joint = |g: usize| (suit.at(g, still) - suit.at(g, hips)).with_y(0.0);
                hips_to_joint(f - 1) - hips_to_joint(f)
            })
        })
        .collect()
}

/// The path from `start` by `pinned` steps, and `air(f)` where there is none.
fn path_from_steps(start: DVec3, pinned: &[Option<DVec3>], air: impl Fn(usize) -> DVec3) -> Vec<DVec3> {
    let mut path: Vec<DVec3> = Vec::with_capacity(pinned.len());
    for (f, step) in pinned.iter().enumerate() {
        match path.last() {
            None => path.push(start),
            Some(&last) => path.push(last + step.unwrap_or_else(|| air(f))),
        }
    }
    path
}

/// The legs' length (cm): per foot, the bones from the foot joint up to the
/// joint whose parent is `hips` (thigh, shank; not the pelvis's offset to the
/// hip joint), each the median over the frames of its length in `poses`,
/// averaged over the two legs.
pub fn leg_length_cm(poses: &Poses, parents: &[Option<usize>], feet: FootJoints, hips: usize) -> f64 {
    let leg = |foot_joint: usize| {
        let mut length_cm = 0.0;
        let mut joint = foot_joint;
        while let Some(parent) = parents.get(joint).copied().flatten() {
            if parent == hips || joint == hips {
                break;
            }
            let bone: Vec<f64> = (0..poses.frame_count())
                .map(|f| (poses.at(f, joint) - poses.at(f, parent)).length())
                .collect();
            length_cm += crate::signal::stats::median(&bone);
            joint = parent;
        }
        length_cm
    };
    0.5 * (leg(feet.left) + leg(feet.right))
}

/// Evaluates `method` on a suit-grade BVH whose true motion is `truth` (the
/// same skeleton hierarchy and frames): freezes the suit's translation,
/// estimates it, and compares the hips with the truth's.
pub fn evaluate_suit(suit: &Bvh, truth: &Bvh, name: &str, method: &Method) -> Result<SuitAccuracy, Error> {
    let truth = Recording::from_bvh(truth.clone(), name);
    // The suit's pose is read once, with its translation frozen: the legs'
    // length and the checks do not depend on where the body is.
    if suit.skeleton.names != truth.joint_names {
        return Err(Error::whole(
            name,
            "the suit file and its truth have different joints; they must be one skeleton",
        ));
    }
    if suit.motion.frame_count() != truth.frame_count() {
        return Err(Error::whole(
            name,
            format!(
                "has {} frames but its truth has {}; they must be the same take",
                suit.motion.frame_count(),
                truth.frame_count()
            ),
        ));
    }
    if (suit.motion.fps() - truth.fps).abs() > 1e-6 * truth.fps {
        return Err(Error::whole(
            name,
            format!(
                "is at {} Hz but its truth at {} Hz; they must be the same take",
                suit.motion.fps(),
                truth.fps
            ),
        ));
    }
    let feet = truth.feet(&FeetChoice::default())?;
    let hips = truth.hips(feet);
    let true_leg_cm = leg_length_cm(&truth.poses, &truth.parents, feet, hips);
    if true_leg_cm.is_nan() || true_leg_cm <= 0.0 {
        return Err(Error::whole(
            name,
            "its truth has no bones between the feet and the hips to measure the legs by",
        ));
    }
    let frozen = Recording::from_bvh(freeze_translation(suit, hips), name);
    let estimated = frozen.translate(&FeetChoice::default(), method)?;
    let accuracy = accuracy(&estimated, &truth.poses, &truth.parents, truth.fps);
    let leg_length_ratio = leg_length_cm(&frozen.poses, &frozen.parents, feet, hips) / true_leg_cm;
    let true_hips = truth.poses.trajectory(hips);
    let start = true_hips.first().copied().unwrap_or(DVec3::ZERO);
    let oracle: Vec<DVec3> = true_hips.iter().map(|&p| start + (p - start) * leg_length_ratio).collect();
    let oracle_error_cm = mean_floor_error_cm(&oracle, &true_hips);
    let pinned = oracle_pinned_steps(&frozen.poses, &truth.poses, &truth.parents, feet, hips, truth.fps);
    let contacts_oracle = contacts_oracle_path(&pinned, &truth.poses, hips);
    let grounded_oracle = grounded_oracle_path(&pinned, &truth.poses, hips, truth.fps);
    let true_path_cm = floor_path_cm(&true_hips);
    Ok(SuitAccuracy {
        accuracy,
        leg_oracle_mean_error_pct: 100.0 * oracle_error_cm / true_path_cm,
        leg_length_ratio,
        contacts_oracle_mean_error_pct: 100.0 * mean_floor_error_cm(&contacts_oracle, &true_hips)
            / true_path_cm,
        grounded_oracle_mean_error_pct: 100.0 * mean_floor_error_cm(&grounded_oracle, &true_hips)
            / true_path_cm,
        contacts_oracle_path_ratio: floor_path_cm(&contacts_oracle) / true_path_cm,
        grounded_oracle_path_ratio: floor_path_cm(&grounded_oracle) / true_path_cm,
    })
}

/// How far a kata's hips end from where they started (cm), after removing the
/// vendor's translation and estimating it with `method`.
pub fn kata_closure_cm(recording: &Recording, method: &Method) -> Result<f64, Error> {
    let feet = recording.feet(&FeetChoice::default())?;
    let hips = recording.hips(feet);
    let stripped = match &recording.source {
        crate::io::recording::Source::Bvh(bvh) => {
            let mut r = Recording::from_bvh(freeze_translation(bvh, hips), &recording.name);
            r.accel = recording.accel.clone();
            r
        }
        // A table stores global positions: strip the hips' motion from every joint.
        crate::io::recording::Source::Table(_) => {
            let start = recording.poses.at(0, hips);
            let shift: Vec<DVec3> =
                (0..recording.frame_count()).map(|f| start - recording.poses.at(f, hips)).collect();
            let mut r = recording.clone();
            r.poses = recording.poses.shifted(&shift);
            r
        }
    };
    let translated = stripped.translate(&FeetChoice::default(), method)?;
    Ok(floor_closure_cm(&translated.poses.trajectory(hips)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_types_come_from_the_name() {
        assert_eq!(motion_type("bandai1_walk-right_normal_001.bvh"), "walk-right");
        assert_eq!(motion_type("dir/bandai1_dash_normal_001.bvh"), "dash");
        assert_eq!(motion_type("heian_nidan.bvh"), "heian_nidan");
        // Whichever system the path came from, whatever the ending's case.
        assert_eq!(motion_type("dir\\x_walk_y_001.BVH"), "walk");
    }

    /// A runner along +Z at 300 cm/s, 30 fps: 6 frames on one foot (planted
    /// under the hips' mid-stance place), 6 in the air with both feet
    /// carried along, then the other foot. Hips (0), left foot (1), right
    /// foot (2). `stride` scales every foot's place relative to the hips, as
    /// a suit that reads the legs' swing short would.
    fn runner(frames: usize, stride: f64) -> Poses {
        let (speed, dt) = (300.0, 1.0 / 30.0);
        let mut positions_cm = Vec::new();
        for f in 0..frames {
            let (step, in_step) = (f / 12, f % 12);
            let hips = DVec3::new(0.0, 90.0, speed * f as f64 * dt);
            let planted_z = speed * (12 * step) as f64 * dt + speed * 2.5 * dt;
            let foot = |side: usize| {
                let x = if side == 0 { -10.0 } else { 10.0 };
                let carried = hips + DVec3::new(x, -80.0, 0.0);
                let truth = if in_step < 6 && side == step % 2 { carried.with_z(planted_z) } else { carried };
                hips + (truth - hips) * stride
            };
            positions_cm.extend([hips, foot(0), foot(1)]);
        }
        Poses { joint_count: 3, positions_cm }
    }

    #[test]
    fn the_grounded_oracle_flies_at_the_stances_velocity_and_the_contacts_oracle_at_the_truth_s() {
        let parents = [None, Some(0), Some(0)];
        let feet = FootJoints { left: 1, right: 2 };
        let truth = runner(60, 1.0);
        let true_hips = truth.trajectory(0);
        let end = |path: &[DVec3]| (path[path.len() - 1] - path[0]).z;
        let true_end = end(&true_hips);
        // On the truth's own pose both are exact.
        let exact = oracle_pinned_steps(&truth, &truth, &parents, feet, 0, 30.0);
        for path in [contacts_oracle_path(&exact, &truth, 0), grounded_oracle_path(&exact, &truth, 0, 30.0)] {
            assert!((end(&path) - true_end).abs() < 1e-9, "{} vs {true_end}", end(&path));
        }
        // A pose whose stances read 0.8 of the stride: the grounded oracle
        // flies at that velocity too, the contacts oracle at the truth's.
        let short = oracle_pinned_steps(&runner(60, 0.8), &truth, &parents, feet, 0, 30.0);
        let grounded = grounded_oracle_path(&short, &truth, 0, 30.0);
        assert!((end(&grounded) / true_end - 0.8).abs() < 1e-9, "{}", end(&grounded) / true_end);
        let contacts = contacts_oracle_path(&short, &truth, 0);
        assert!(end(&contacts) / true_end > 0.85, "{}", end(&contacts) / true_end);
    }
}
