//! The sole of a foot: the points of it that can touch the floor, frame by
//! frame, including the heel, which no skeleton has as a joint.
//!
//! A foot on the floor rolls: it lands on the heel, stands flat, and pushes
//! off over the ball and the toes (gait analysis calls these the heel, ankle
//! and forefoot rockers). The point it rolls over does not move, so that is
//! the point to pin. Skeletons give joint centres, and a joint centre is not
//! on the floor: the ankle is ~8 cm above it, the ball of the foot a few cm.
//! Pinning a joint while the foot rolls around a point below it drags the
//! body by that height times the angle rolled, every step.
//!
//! So each sole point is the material point of the sole *below* a joint, in
//! the frame of the foot's bone: the sole around a joint is a rocker centred
//! on the joint, and a rocker rolling without slipping has its lowest
//! material point momentarily still. The heel is such a point too, behind
//! the ankle. How far the sole lies below the foot's lowest joint when it
//! stands flat (`sole_depth_cm`) depends on the skeleton (a toe end site is on
//! the skin, a ball-of-foot joint centre 2–3 cm above it) and on the shoes;
//! [`crate::translate::contact`] estimates it per recording.

use glam::DVec3;

use crate::body::feet::{Foot, FootJoints, PerFoot, foot_points};
use crate::body::skeleton::Poses;
use crate::signal::stats::upper_median;

/// Which part of the foot a sole point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SolePart {
    /// The virtual heel, below and behind the ankle.
    Heel,
    /// The sole straight below the ankle, where a flat foot turning on the
    /// spot pivots.
    UnderAnkle,
    /// The sole below joint `j` of the foot (a toe joint or a toe end site);
    /// in a foot without toes, the ankle joint itself.
    Joint(usize),
}

/// A bone shorter than this (cm) is a point, not a bone: exporters write
/// zero-length toe end sites, which add nothing to the foot's shape.
const MIN_BONE_CM: f64 = 1.0;

/// How far the heel reaches behind the ankle, as a fraction of the ankle→toe
/// distance on the floor. In an adult foot the back of the heel is ~6 cm
/// behind the ankle's centre and the ball ~14 cm in front; what matters is
/// that the heel is at the sole's level, not exactly how far back it is.
const HEEL_BEHIND_ANKLE: f64 = 0.4;

/// The points of one foot that can touch the floor, relative to the hips.
#[derive(Clone, Debug)]
pub struct Sole {
    pub parts: Vec<SolePart>,
    /// Frame-major, `parts.len()` points per frame: each point's position
    /// minus the hips' position (cm). The hips' own motion is the unknown a
    /// translation method solves for, so it is left out.
    pub hips_to_points_cm: Vec<DVec3>,
    /// Each point's height above the floor when the foot stands flat (cm):
    /// a point is on the floor when its height minus this offset is lowest.
    pub floor_offsets_cm: Vec<f64>,
    /// The point under the toe farthest from the ankle: with the heel
    /// (point 0), the ends of the sole. 0 for a foot without toes.
    pub tip: usize,
}

impl Sole {
    pub fn point_count(&self) -> usize {
        self.parts.len()
    }

    /// How many frames the sole has points for.
    pub fn frame_count(&self) -> usize {
        self.hips_to_points_cm.len().checked_div(self.parts.len()).unwrap_or(0)
    }

    /// Whether the sole is more than the ankle: a foot with toes, whose
    /// sole lies below its joints at some depth.
    pub fn has_toes(&self) -> bool {
        self.tip > 0
    }

    /// Point `k` of frame `f`, relative to the hips.
    pub fn at(&self, f: usize, k: usize) -> DVec3 {
        self.hips_to_points_cm[f * self.parts.len() + k]
    }

    /// The height of point `k` in frame `f` above where it would be if it
    /// stood on the floor, relative to the hips: the lowest of these is the
    /// point the foot stands on.
    pub fn height_above_flat_cm(&self, f: usize, k: usize) -> f64 {
        self.at(f, k).y - self.floor_offsets_cm[k]
    }

    /// The sole in the given frames only, in their order.
    pub fn at_frames(&self, frames: &[usize]) -> Sole {
        let count = self.parts.len();
        let hips_to_points_cm = frames
            .iter()
            .flat_map(|&f| self.hips_to_points_cm[f * count..(f + 1) * count].iter().copied())
            .collect();
        Sole {
            parts: self.parts.clone(),
            hips_to_points_cm,
            floor_offsets_cm: self.floor_offsets_cm.clone(),
            tip: self.tip,
        }
    }

    /// The point of frame `f` lowest above its flat-foot level (the first
    /// of equally low ones), and that height.
    pub fn lowest(&self, f: usize) -> LowestPoint {
        let start = LowestPoint { point: 0, height_above_flat_cm: f64::INFINITY };
        (0..self.point_count())
            .map(|k| LowestPoint { point: k, height_above_flat_cm: self.height_above_flat_cm(f, k) })
            .fold(start, |best, c| if c.height_above_flat_cm < best.height_above_flat_cm { c } else { best })
    }
}

/// A sole's point nearest the floor in one frame (see [`Sole::lowest`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LowestPoint {
    /// The point's index in [`Sole::parts`].
    pub point: usize,
    /// Its height above its flat-foot level, relative to the hips (cm).
    pub height_above_flat_cm: f64,
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
            upper_median(&heights)
        })
        .collect()
}

/// The two soles of a recording, with Y up, `sole_depth_cm` below the
/// foot's lowest joint when the foot stands flat (see the module
/// documentation). To build soles at several depths, measure the feet once
/// with [`foot_shapes`].
pub fn soles(
    poses: &Poses,
    parents: &[Option<usize>],
    feet: FootJoints,
    hips: usize,
    sole_depth_cm: f64,
) -> PerFoot<Sole> {
    foot_shapes(poses, parents, feet, hips).map(|shape| shape.sole(sole_depth_cm))
}

/// The two feet of a recording, measured: `feet` are the foot (ankle)
/// joints, their descendants in `parents` are the toes.
pub fn foot_shapes(
    poses: &Poses,
    parents: &[Option<usize>],
    feet: FootJoints,
    hips: usize,
) -> PerFoot<FootShape> {
    let n = poses.frame_count();
    let mut joints = feet.map(|foot_joint| foot_points(parents, foot_joint));
    let mut joint_points = PerFoot::from_fn(|foot| {
        let hips_to_joint = |f: usize, j: usize| poses.at(f, j) - poses.at(f, hips);
        (0..n).flat_map(|f| joints[foot].iter().map(move |&j| hips_to_joint(f, j))).collect::<Vec<DVec3>>()
    });
    // A foot stands flat, mostly, in the frames where it is the lower foot.
    let lowest_cm = PerFoot::from_fn(|foot| {
        let count = joints[foot].len();
        (0..n)
            .map(|f| {
                joint_points[foot][f * count..(f + 1) * count]
                    .iter()
                    .map(|p| p.y)
                    .fold(f64::INFINITY, f64::min)
            })
            .collect::<Vec<f64>>()
    });
    PerFoot::from_fn(|foot: Foot| {
        let standing = (0..n).filter(|&f| lowest_cm[foot][f] <= lowest_cm[foot.other()][f]).collect();
        let (joints, joint_points) =
            (std::mem::take(&mut joints[foot]), std::mem::take(&mut joint_points[foot]));
        FootShape::new(joints, parents, joint_points, standing, n)
    })
}

/// One foot, measured once: its joints' paths relative to the hips, how each
/// stands above the floor when the foot is flat, and per frame the axes of
/// its bones' soles. Everything but the depth of the sole, so that soles at
/// several depths cost only their points ([`FootShape::sole`]).
pub struct FootShape {
    /// The foot's joints, the ankle first (as [`foot_points`] lists them).
    joints: Vec<usize>,
    /// Frame-major, `joints.len()` per frame: each joint minus the hips (cm).
    joint_points: Vec<DVec3>,
    /// The frames in which the foot stands (flat, mostly).
    standing: Vec<usize>,
    /// Per joint, its height above the foot's lowest joint when flat (cm).
    offsets_cm: Vec<f64>,
    /// The joints below the ankle that end a real bone, in order.
    toes: Vec<usize>,
    /// The rocker's frames; `None` for a foot without toes.
    rocker: Option<Rocker>,
}

/// Where a foot's sole lies around its joints, frame by frame.
struct Rocker {
    /// Per toe (in [`FootShape::toes`] order), the bone whose sole lies under
    /// it, as an index into the per-frame axes; bone 0 is the foot's long axis.
    under: Vec<usize>,
    /// Frame-major, one per bone: forward along the bone's sole, and down,
    /// perpendicular to it.
    axes: Vec<SoleAxes>,
    bone_count: usize,
    heel_behind_cm: f64,
    /// The sole point under the toe farthest from the ankle.
    tip: usize,
}

/// A bone `from → to` of the foot, as indices into [`FootShape::joints`].
type Bone = (usize, usize);

/// One foot's joint paths relative to the hips: frame-major, `count` joints
/// per frame (in [`FootShape::joints`] order), `n` frames.
struct JointPaths<'a> {
    points: &'a [DVec3],
    count: usize,
    n: usize,
}

impl JointPaths<'_> {
    /// Joint `k` in frame `f`.
    fn at(&self, f: usize, k: usize) -> DVec3 {
        self.points[f * self.count + k]
    }

    /// The median distance between joints `k` and `from` over the frames
    /// `standing` (cm).
    fn length_cm(&self, k: usize, from: usize, standing: &[usize]) -> f64 {
        upper_median(
            &standing.iter().map(|&f| (self.at(f, k) - self.at(f, from)).length()).collect::<Vec<_>>(),
        )
    }
}

/// Forward along a bone's sole, and down, perpendicular to it (unit
/// vectors).
#[derive(Clone, Copy, Debug)]
struct SoleAxes {
    forward: DVec3,
    down: DVec3,
}

/// A bone's dip toward its end (radians, positive down). Trigonometry
/// through `libm`, so the CLI and the wasm app compute bit-identical results.
fn dip(v: DVec3) -> f64 {
    libm::asin((-v.y / v.length()).clamp(-1.0, 1.0))
}

impl Rocker {
    /// The rocker of a foot whose long axis runs from the ankle to `toe`,
    /// `toe_cm` away, with `toes` (and their `parent`s) below the ankle.
    fn new(
        paths: &JointPaths,
        standing: &[usize],
        toes: &[usize],
        parent: &[Option<usize>],
        toe: usize,
        toe_cm: f64,
    ) -> Rocker {
        // The bone whose sole lies under joint `k`: the bone starting at `k`
        // when there is one (a ball-of-foot joint with its toes), else the
        // bone ending at `k` (a toe end site, or a toe joint whose end site
        // has no length); the long axis where neither is.
        let bone_under = |k: usize| -> Bone {
            let starting = toes.iter().find(|&&c| parent[c] == Some(k)).map(|&c| (k, c));
            starting
                .or_else(|| parent[k].filter(|_| toes.contains(&k)).map(|from| (from, k)))
                .unwrap_or((0, toe))
        };
        let mut bones: Vec<Bone> = vec![(0, toe)];
        let under: Vec<usize> = toes
            .iter()
            .map(|&k| {
                let bone = bone_under(k);
                bones.iter().position(|&b| b == bone).unwrap_or_else(|| {
                    bones.push(bone);
                    bones.len() - 1
                })
            })
            .collect();
        // Each bone dips toward its end in a flat foot; its median dip while
        // standing tells where "flat" is for this skeleton.
        let flat_dips: Vec<f64> = bones
            .iter()
            .map(|&(a, b)| {
                upper_median(
                    &standing.iter().map(|&f| dip(paths.at(f, b) - paths.at(f, a))).collect::<Vec<_>>(),
                )
            })
            .collect();
        Rocker {
            under,
            axes: sole_axes(paths, &bones, &flat_dips),
            bone_count: bones.len(),
            heel_behind_cm: HEEL_BEHIND_ANKLE * toe_cm * libm::cos(flat_dips[0]),
            tip: 2 + toes.iter().position(|&k| k == toe).unwrap_or(0),
        }
    }
}

/// Frame-major, per frame and bone, the axes of the bone's sole: the bone's
/// heading on the floor, tilted by how far it dips beyond its `flat_dips`.
fn sole_axes(paths: &JointPaths, bones: &[Bone], flat_dips: &[f64]) -> Vec<SoleAxes> {
    let mut headings = vec![DVec3::Z; bones.len()];
    let mut now = vec![SoleAxes { forward: DVec3::Z, down: -DVec3::Y }; bones.len()];
    let mut axes = Vec::with_capacity(paths.n * bones.len());
    for f in 0..paths.n {
        for (i, &(a, b)) in bones.iter().enumerate() {
            let v = paths.at(f, b) - paths.at(f, a);
            // A bone with no length in this frame (a mis-tracked frame) has
            // no direction: its sole keeps the last frame's axes.
            if v.length() <= 1e-9 {
                continue;
            }
            let flat = v.with_y(0.0);
            if flat.length() > 1e-6 * v.length() {
                headings[i] = flat.normalize();
            }
            let tilt = dip(v) - flat_dips[i];
            now[i] = SoleAxes {
                forward: headings[i] * libm::cos(tilt) - DVec3::Y * libm::sin(tilt),
                down: -headings[i] * libm::sin(tilt) - DVec3::Y * libm::cos(tilt),
            };
        }
        axes.extend_from_slice(&now);
    }
    axes
}

impl FootShape {
    fn new(
        joints: Vec<usize>,
        parents: &[Option<usize>],
        joint_points: Vec<DVec3>,
        standing: Vec<usize>,
        n: usize,
    ) -> Self {
        let count = joints.len();
        let paths = JointPaths { points: &joint_points, count, n };
        let parent: Vec<Option<usize>> = joints
            .iter()
            .map(|&j| parents.get(j).copied().flatten().and_then(|p| joints.iter().position(|&x| x == p)))
            .collect();
        let toes: Vec<usize> = (1..count)
            .filter(|&k| parent[k].is_some_and(|from| paths.length_cm(k, from, &standing) >= MIN_BONE_CM))
            .collect();
        let offsets_cm = floor_offsets(&joint_points, count, &standing);
        // The foot's long axis: from the ankle to the toe joint farthest from it.
        let far: Vec<(usize, f64)> = toes.iter().map(|&k| (k, paths.length_cm(k, 0, &standing))).collect();
        let rocker = far
            .iter()
            .copied()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(toe, toe_cm)| Rocker::new(&paths, &standing, &toes, &parent, toe, toe_cm));
        FootShape { joints, joint_points, standing, offsets_cm, toes, rocker }
    }

    /// Whether the foot has toes, so that its sole lies below its joints at
    /// some depth (see [`Sole::has_toes`]).
    pub fn has_toes(&self) -> bool {
        self.rocker.is_some()
    }

    /// The foot's sole, `sole_depth_cm` below its lowest joint when flat.
    pub fn sole(&self, sole_depth_cm: f64) -> Sole {
        let count = self.joints.len();
        let n = self.joint_points.len().checked_div(count).unwrap_or(0);
        let p = |f: usize, k: usize| self.joint_points[f * count + k];
        let Some(rocker) = &self.rocker else {
            // A foot without toes: its ankle is all there is to pin.
            return Sole {
                parts: vec![SolePart::Joint(self.joints[0])],
                hips_to_points_cm: (0..n).map(|f| p(f, 0)).collect(),
                floor_offsets_cm: vec![0.0],
                tip: 0,
            };
        };
        let mut sole_points = Vec::with_capacity(n * (self.toes.len() + 2));
        for f in 0..n {
            let axes = &rocker.axes[f * rocker.bone_count..(f + 1) * rocker.bone_count];
            let below = |k: usize, down: DVec3| p(f, k) + down * (self.offsets_cm[k] + sole_depth_cm);
            let SoleAxes { forward, down } = axes[0];
            let under_ankle = below(0, down);
            sole_points.push(under_ankle - forward * rocker.heel_behind_cm);
            sole_points.push(under_ankle);
            sole_points
                .extend(self.toes.iter().zip(&rocker.under).map(|(&k, &bone)| below(k, axes[bone].down)));
        }
        let mut parts = vec![SolePart::Heel, SolePart::UnderAnkle];
        parts.extend(self.toes.iter().map(|&k| SolePart::Joint(self.joints[k])));
        let floor_offsets_cm = floor_offsets(&sole_points, parts.len(), &self.standing);
        Sole { parts, hips_to_points_cm: sole_points, floor_offsets_cm, tip: rocker.tip }
    }
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
                let (sin, cos) = libm::sincos(a);
                heel + DVec3::new(d.x, d.y * cos + d.z * sin, -d.y * sin + d.z * cos)
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
        let PerFoot { left, right } = soles(&poses, &PARENTS, FootJoints { left: 1, right: 3 }, 0, 0.0);
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
        assert_eq!(left.lowest(95).point, 0);
        assert!((left.at(95, 0) - left.at(0, 0)).length() < 1e-9);
        assert!(left.height_above_flat_cm(95, 2) - left.height_above_flat_cm(0, 2) > 6.0);
    }

    /// A left foot standing on the ball of a rocker: its toe joint is
    /// `depth` cm above the floor, and in frame `f` the foot has rolled
    /// forward by `roll(f)` radians (heel rising) on a circle of that radius
    /// about the toe joint, without slipping, as a forefoot rolls. A zero-length
    /// end site hangs under the toe joint (exporters write them). The hips
    /// stay put.
    fn rolling_on_the_ball(depth: f64, roll: impl Fn(usize) -> f64, n: usize) -> Poses {
        let mut positions_cm = Vec::new();
        for f in 0..n {
            let a = roll(f);
            // The toe joint rolls forward by depth · a; the foot pitches
            // heel-up about it.
            let toe = DVec3::new(-10.0, depth, 14.0 + depth * a);
            let ankle_from_toe = DVec3::new(0.0, 6.0, -14.0);
            let (sin, cos) = libm::sincos(a);
            let pitched = DVec3::new(
                0.0,
                ankle_from_toe.y * cos - ankle_from_toe.z * sin,
                ankle_from_toe.y * sin + ankle_from_toe.z * cos,
            );
            positions_cm.extend([
                DVec3::new(0.0, 90.0, 0.0),
                toe + pitched,
                toe,
                toe,
                DVec3::new(10.0, 40.0, 0.0),
                DVec3::new(10.0, 34.0, 14.0),
            ]);
        }
        Poses { joint_count: 6, positions_cm }
    }

    #[test]
    fn the_sole_under_a_rolling_joint_stays_put_at_the_right_depth() {
        // Hips (0); left ankle (1), toe (2), zero-length end site (3); right
        // ankle (4) and toe (5), lifted.
        let parents = [None, Some(0), Some(1), Some(2), Some(0), Some(4)];
        let n = 100;
        let roll = |f: usize| if f < 70 { 0.0 } else { (f - 70) as f64 * 0.01 };
        let poses = rolling_on_the_ball(4.0, roll, n);
        let under_toe = |depth: f64| {
            let left = soles(&poses, &parents, FootJoints { left: 1, right: 4 }, 0, depth).left;
            // The zero-length end site adds no point of its own.
            assert_eq!(left.parts, vec![SolePart::Heel, SolePart::UnderAnkle, SolePart::Joint(2)]);
            // How far the point moves over each frame of the roll, summed.
            (71..n).map(|f| (left.at(f, 2) - left.at(f - 1, 2)).with_y(0.0).length()).sum::<f64>()
        };
        // Rolled 0.29 rad: the toe joint itself travels 4 · 0.29 = 1.16 cm;
        // the sole under it, a material point of the rocker, only along the
        // cycloid, 4 (0.29 - sin 0.29) = 0.016 cm.
        assert!((under_toe(0.0) - 4.0 * 0.29).abs() < 1e-9, "{}", under_toe(0.0));
        assert!((under_toe(4.0) - 4.0 * (0.29 - 0.29f64.sin())).abs() < 1e-6, "{}", under_toe(4.0));
    }

    #[test]
    fn a_foot_without_toes_pins_its_ankle() {
        let poses =
            Poses { joint_count: 3, positions_cm: vec![DVec3::new(0.0, 90.0, 0.0), DVec3::X, -DVec3::X] };
        let left = soles(&poses, &[None, Some(0), Some(0)], FootJoints { left: 1, right: 2 }, 0, 0.0).left;
        assert_eq!(left.parts, vec![SolePart::Joint(1)]);
        assert_eq!(left.at(0, 0), DVec3::new(1.0, -90.0, 0.0));
    }
}
