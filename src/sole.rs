//! The sole of a foot: the points of it that can touch the floor, frame by
//! frame, including the heel, which no skeleton has as a joint.
//!
//! A foot on the floor rolls: it lands on the heel, stands flat, and pushes
//! off over the ball and the toes. The point it rolls over does not move, so
//! that is the point to pin. Skeletons give the ankle and the toes; the ankle
//! never touches the floor, and pinning it while the foot rolls over the heel
//! loses the few centimetres the ankle travels forward in every step (a walk
//! comes out ~3% short). The heel sits at the sole's level below and a little
//! behind the ankle, so we place a virtual heel point there, in the foot's own
//! frame, and let it rock with the foot.

use glam::DVec3;

use crate::feet::foot_points;
use crate::signals::{median, smooth_paths};
use crate::skeleton::Poses;

/// Which part of the foot a sole point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SolePart {
    /// The virtual heel, below and behind the ankle.
    Heel,
    /// The sole straight below the ankle, where a flat foot turning on the
    /// spot pivots.
    UnderAnkle,
    /// A joint of the foot (the ankle when it is the only one, a toe joint, a
    /// toe end site).
    Joint(usize),
}

/// How far the heel reaches behind the ankle, as a fraction of the ankle→toe
/// distance on the floor. In an adult foot the back of the heel is ~6 cm
/// behind the ankle's centre and the ball ~14 cm in front; the result hardly
/// depends on it (2–10 cm behind give the same paths), what matters is that
/// the heel is at the sole's level.
const HEEL_BEHIND_ANKLE: f64 = 0.4;

/// The points of one foot that can touch the floor, relative to the hips.
#[derive(Clone, Debug)]
pub struct Sole {
    pub parts: Vec<SolePart>,
    /// Frame-major, `parts.len()` points per frame: each point's position
    /// minus the hips' position (cm). The hips' own motion is the unknown a
    /// translation method solves for, so it is left out.
    pub points_from_hips_cm: Vec<DVec3>,
    /// Each point's height above the floor when the foot stands flat (cm):
    /// a point is on the floor when its height minus this offset is lowest.
    pub floor_offsets_cm: Vec<f64>,
}

impl Sole {
    pub fn point_count(&self) -> usize {
        self.parts.len()
    }

    /// Point `k` of frame `f`, relative to the hips.
    pub fn at(&self, f: usize, k: usize) -> DVec3 {
        self.points_from_hips_cm[f * self.parts.len() + k]
    }

    /// The height of point `k` in frame `f` above where it would be if it
    /// stood on the floor, relative to the hips: the lowest of these is the
    /// point the foot stands on.
    pub fn height_above_flat_cm(&self, f: usize, k: usize) -> f64 {
        self.at(f, k).y - self.floor_offsets_cm[k]
    }

    /// The sole with every point's path smoothed over `sigma_samples` (see
    /// [`smooth_paths`]).
    pub fn smoothed(self, sigma_samples: f64) -> Sole {
        let points_from_hips_cm = smooth_paths(&self.points_from_hips_cm, self.parts.len(), sigma_samples);
        Sole { points_from_hips_cm, ..self }
    }

    /// The point of frame `f` lowest above its flat-foot level, and that height.
    pub fn lowest(&self, f: usize) -> (usize, f64) {
        (0..self.point_count())
            .map(|k| (k, self.height_above_flat_cm(f, k)))
            .fold((0, f64::INFINITY), |best, c| if c.1 < best.1 { c } else { best })
    }
}

/// Per point, its median height above the lowest point of the same foot over
/// `frames`: its height above the floor in a foot standing flat.
fn floor_offsets(points: &[DVec3], count: usize, frames: &[usize]) -> Vec<f64> {
    (0..count)
        .map(|k| {
            let heights: Vec<f64> = frames
                .iter()
                .map(|&f| {
                    let frame = &points[f * count..(f + 1) * count];
                    frame[k].y - frame.iter().map(|p| p.y).fold(f64::INFINITY, f64::min)
                })
                .collect();
            median(&heights)
        })
        .collect()
}

/// The two soles `[left, right]` of a recording, with Y up. `feet` are the
/// foot (ankle) joints; their descendants in `parents` are the toes.
pub fn soles(poses: &Poses, parents: &[Option<usize>], feet: [usize; 2], hips: usize) -> [Sole; 2] {
    let n = poses.frame_count();
    let joints = feet.map(|foot| foot_points(parents, foot));
    let from_hips = |f: usize, j: usize| poses.at(f, j) - poses.at(f, hips);
    let joint_points: [Vec<DVec3>; 2] =
        [0, 1].map(|side| (0..n).flat_map(|f| joints[side].iter().map(move |&j| from_hips(f, j))).collect());
    // A foot stands flat, mostly, in the frames where it is the lower foot.
    let lowest = |side: usize, f: usize| {
        joint_points[side][f * joints[side].len()..(f + 1) * joints[side].len()]
            .iter()
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min)
    };
    let standing: [Vec<usize>; 2] =
        [0, 1].map(|side| (0..n).filter(|&f| lowest(side, f) <= lowest(1 - side, f)).collect());
    [0, 1].map(|side| {
        let count = joints[side].len();
        let offsets = floor_offsets(&joint_points[side], count, &standing[side]);
        // The toe: the foot point farthest from the ankle.
        let toe = (1..count).max_by(|&a, &b| {
            let d = |k: usize| (joint_points[side][k] - joint_points[side][0]).length();
            d(a).total_cmp(&d(b))
        });
        let Some(toe) =
            toe.filter(|&k| n > 0 && (joint_points[side][k] - joint_points[side][0]).length() > 1.0)
        else {
            // A foot without toes (or whose toes coincide with the ankle):
            // its joints are all there is to pin.
            return Sole {
                parts: joints[side].iter().map(|&j| SolePart::Joint(j)).collect(),
                points_from_hips_cm: joint_points[side].clone(),
                floor_offsets_cm: offsets,
            };
        };
        let ankle_to_toe = |f: usize| joint_points[side][f * count + toe] - joint_points[side][f * count];
        // The ankle→toe line dips toward the toe in a flat foot; its median
        // dip while standing tells where "flat" is for this skeleton.
        // Trigonometry through `libm`, so the CLI and the wasm app compute
        // bit-identical results.
        let dip = |v: DVec3| libm::asin((-v.y / v.length()).clamp(-1.0, 1.0));
        let flat_dip = median(&standing[side].iter().map(|&f| dip(ankle_to_toe(f))).collect::<Vec<_>>());
        let toe_distance =
            median(&standing[side].iter().map(|&f| ankle_to_toe(f).length()).collect::<Vec<_>>());
        let heel_behind_cm = HEEL_BEHIND_ANKLE * toe_distance * libm::cos(flat_dip);
        // The sole's level is the foot's lowest point when flat, so the
        // ankle's floor offset is its height above the sole.
        let ankle_height_cm = offsets[0];
        // Per frame: the heel, in the frame of the sole (forward along the
        // sole, down perpendicular to it), then the toe joints; the ankle
        // itself never touches the floor.
        let mut heading = DVec3::Z;
        let mut points = Vec::with_capacity(n * (count + 1));
        for f in 0..n {
            let v = ankle_to_toe(f);
            let flat = v.with_y(0.0);
            if flat.length() > 1e-6 * v.length() {
                heading = flat.normalize();
            }
            let sole_dip = dip(v) - flat_dip;
            let forward = heading * libm::cos(sole_dip) - DVec3::Y * libm::sin(sole_dip);
            let down = -heading * libm::sin(sole_dip) - DVec3::Y * libm::cos(sole_dip);
            let ankle = joint_points[side][f * count];
            let under_ankle = ankle + down * ankle_height_cm;
            points.push(under_ankle - forward * heel_behind_cm);
            points.push(under_ankle);
            points.extend_from_slice(&joint_points[side][f * count + 1..(f + 1) * count]);
        }
        let mut parts = vec![SolePart::Heel, SolePart::UnderAnkle];
        parts.extend(joints[side][1..].iter().map(|&j| SolePart::Joint(j)));
        let floor_offsets_cm = floor_offsets(&points, parts.len(), &standing[side]);
        Sole { parts, points_from_hips_cm: points, floor_offsets_cm }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hips (0), left ankle (1) and toe (2), right ankle (3) and toe (4).
    const PARENTS: [Option<usize>; 5] = [None, Some(0), Some(1), Some(0), Some(3)];

    /// A body standing on flat feet facing +Z, the left foot tilted toes-up by
    /// `left_toes_up` radians about its heel in frame `f`.
    fn standing(n: usize, left_toes_up: impl Fn(usize) -> f64) -> Poses {
        let mut positions_cm = Vec::new();
        for f in 0..n {
            let (ankle_y, toe_ahead, toe_y) = (8.0, 14.0, 2.0);
            let a = left_toes_up(f);
            // Rotating the left foot about the point on the sole (at the
            // toe's level) 5.6 cm behind the ankle, 0.4 of the ankle→toe
            // distance: the heel.
            let heel = DVec3::new(-10.0, toe_y, -0.4 * toe_ahead);
            let rotate = |p: DVec3| {
                let d = p - heel;
                heel + DVec3::new(d.x, d.y * a.cos() + d.z * a.sin(), -d.y * a.sin() + d.z * a.cos())
            };
            positions_cm.extend([
                DVec3::new(0.0, 90.0, 0.0),
                rotate(DVec3::new(-10.0, ankle_y, 0.0)),
                rotate(DVec3::new(-10.0, toe_y, toe_ahead)),
                DVec3::new(10.0, ankle_y, 0.0),
                DVec3::new(10.0, toe_y, toe_ahead),
            ]);
        }
        Poses { joint_count: 5, positions_cm }
    }

    #[test]
    fn the_heel_is_on_the_sole_behind_the_ankle_and_rocks_with_the_foot() {
        // Flat for most frames (so that is what "flat" is), then heel strike:
        // toes up 20°, rotating about the heel.
        let n = 100;
        let poses = standing(n, |f| if f >= 90 { 20f64.to_radians() } else { 0.0 });
        let [left, right] = soles(&poses, &PARENTS, [1, 3], 0);
        assert_eq!(left.parts, vec![SolePart::Heel, SolePart::UnderAnkle, SolePart::Joint(2)]);
        let hips = DVec3::new(0.0, 90.0, 0.0);
        // Flat: the heel sits at the toe's level, 0.4 of the way back.
        let heel = left.at(0, 0) + hips;
        assert!((heel - DVec3::new(-10.0, 2.0, -5.6)).length() < 1e-9, "{heel}");
        assert!((right.at(0, 1) + hips - DVec3::new(10.0, 2.0, 0.0)).length() < 1e-9);
        for k in 0..3 {
            assert!(left.floor_offsets_cm[k].abs() < 1e-9, "{:?}", left.floor_offsets_cm);
        }
        // Heel strike: the heel is the lowest point and it has not moved.
        assert_eq!(left.lowest(95).0, 0);
        assert!((left.at(95, 0) - left.at(0, 0)).length() < 1e-9);
        assert!(left.height_above_flat_cm(95, 2) - left.height_above_flat_cm(0, 2) > 6.0);
    }

    #[test]
    fn a_foot_without_toes_pins_its_ankle() {
        let poses =
            Poses { joint_count: 3, positions_cm: vec![DVec3::new(0.0, 90.0, 0.0), DVec3::X, -DVec3::X] };
        let [left, _] = soles(&poses, &[None, Some(0), Some(0)], [1, 2], 0);
        assert_eq!(left.parts, vec![SolePart::Joint(1)]);
        assert_eq!(left.at(0, 0), DVec3::new(1.0, -90.0, 0.0));
    }
}
