//! The built-in demo recording: a synthetic biped stepping through a short
//! kata, generated in code. It is the app's default recording, and its true
//! motion is known, so it is generated physically consistently:
//! 1. footsteps are planned on the floor (`kata`),
//! 2. feet follow them: a planted foot is held exactly still (it may only pivot
//!    about its ankle), a swinging foot travels on a lifted arc (`plan_frames`),
//! 3. the hips ride over the midpoint of the feet, as high as the legs allow
//!    with bent knees, so lower in wide stances (`hips_cm`),
//! 4. the legs are solved by analytic two-bone IK (`leg_ik`), so forward
//!    kinematics of the channels puts every planted ankle back where it was
//!    planted;
//! 5. the true motion goes through an inertial suit's errors
//!    ([`crate::synth::suit`]): the demo is what a suit would have recorded of
//!    it, the truth kept beside it to measure against.
//!
//! Coordinates: Y up, the floor is y = 0, centimetres and degrees. The figure
//! starts at the origin facing +Z, with its left on +X; a heading of θ turns it
//! left by θ about +Y.

use glam::{DMat3, DVec2, DVec3};

use crate::body::feet::{Foot, PerFoot};
use crate::body::kinematics::{forward_kinematics, zyx_degrees};
use crate::body::skeleton::{Channel, Motion, Skeleton};
use crate::io::bvh::Bvh;
use crate::io::recording::Recording;
use crate::io::table::Accelerations;
use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;
use crate::synth::rng::XorShift64;
use crate::synth::suit;

/// The name the app shows for the demo recording.
pub const DEMO_NAME: &str = "demo (synthetic kata)";
/// Frames per second of the demo.
pub const DEMO_FPS: f64 = 100.0;
/// Height of the ankle (the foot joint) above the floor when the foot is flat:
/// the toe end site sits this far below the ankle, so it touches the floor.
pub const ANKLE_HEIGHT_CM: f64 = 5.07;

/// The rotation channels of every joint, in the karate suit's order.
const ROTATIONS: [Channel; 3] = [Channel::Zrotation, Channel::Yrotation, Channel::Xrotation];
/// Bone lengths and hip joint placement, from the karate suit's skeleton.
const THIGH_CM: f64 = 42.86;
const SHIN_CM: f64 = 39.83;
const HIP_HALF_WIDTH_CM: f64 = 8.51;
const HIP_DROP_CM: f64 = 5.99;
/// The hips stay low enough that each hip-to-ankle distance is at most this
/// fraction of the straight leg: the knees are always bent (a karate posture)
/// and the IK never has to reach further than the leg.
const REACH_FRACTION: f64 = 0.94;
/// A swing lasts `SWING_BASE_S + distance / SWING_CM_PER_S`.
const SWING_BASE_S: f64 = 0.45;
const SWING_CM_PER_S: f64 = 300.0;
/// How high a swinging ankle rises above its flat height, mid-swing.
const LIFT_CM: f64 = 10.0;
/// How long a transition lasts when no foot steps (a pure pivot).
const PIVOT_S: f64 = 0.5;
/// Half-width of the uniform accelerometer noise, per axis.
const NOISE_G: f64 = 0.01;
/// The seed of the demo's suit errors.
pub const DEMO_SUIT_SEED: u64 = 1;

/// The demo recording, as a suit recorded it, and the ground truth it was
/// generated from.
///
/// 100 Hz, 2406 frames (24.06 s). Every per-frame vector has one entry per
/// frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Demo {
    /// The suit's skeleton: the true hierarchy with the vendor's bone lengths.
    pub skeleton: Skeleton,
    /// The suit's channel values: rotations with the suit's errors, the
    /// vendor's guess of the translation in the Hips position channels.
    pub motion: Motion,
    /// The true skeleton (same joints, true bone lengths).
    pub true_skeleton: Skeleton,
    /// The true channel values, including the true root translation.
    pub true_motion: Motion,
    /// The true Hips position channels of each frame, in cm.
    pub true_root_cm: Vec<DVec3>,
    /// The suit's leg length over the true one (thigh and shank).
    pub leg_length_ratio: f64,
    /// Simulated accelerometers at the foot joints, in g and world axes, of
    /// the true motion (an accelerometer is physical: the suit's orientation
    /// errors are its fusion's, and the methods read only the magnitude,
    /// which no orientation error changes): the second derivative of the
    /// true global foot position (central difference, in cm/s²) plus
    /// gravity's reaction along +Y, divided by [`STANDARD_GRAVITY_CM_PER_S2`],
    /// plus deterministic uniform noise of ±0.01 g per axis. A foot at rest
    /// reads (0, 1, 0).
    pub foot_accel_g: PerFoot<Vec<DVec3>>,
    /// Whether each foot is planted (held still on the floor) in each frame,
    /// in the truth.
    pub stance: Vec<PerFoot<bool>>,
}

impl Demo {
    /// The demo as the tool opens it: the suit's recording with the vendor's
    /// translation stripped (what a translation method starts from), the
    /// simulated foot accelerometers attached as sensors named like the foot
    /// joints.
    pub fn recording(&self) -> Recording {
        let bvh =
            Bvh { skeleton: self.skeleton.clone(), motion: self.without_translation(), warnings: Vec::new() };
        let mut recording = Recording::from_bvh(bvh, DEMO_NAME);
        recording.accel = Some(Accelerations {
            file: DEMO_NAME.to_string(),
            sensor_names: vec!["LeftFoot".to_string(), "RightFoot".to_string()],
            accel_g: vec![self.foot_accel_g.left.clone(), self.foot_accel_g.right.clone()],
        });
        recording
    }

    /// The suit's motion with the Hips position channels of every frame set
    /// to frame 0's values (all three axes): what a translation method gets
    /// as input when it is tested against [`Demo::true_root_cm`].
    pub fn without_translation(&self) -> Motion {
        let mut motion = self.motion.clone();
        motion.hold_positions_at_first_frame(&self.skeleton, 0);
        motion
    }
}

/// Generates the demo recording. Deterministic: every call returns the same.
pub fn demo() -> Demo {
    demo_with_suit_seed(DEMO_SUIT_SEED)
}

/// The demo with the suit's errors drawn from `seed` (the true motion is the
/// same for every seed).
pub fn demo_with_suit_seed(seed: u64) -> Demo {
    let rig = build_rig();
    let frames = plan_frames(&kata());
    let channel_count = rig.skeleton.channel_count();
    let mut motion = Motion {
        channel_count,
        frame_time_s: 1.0 / DEMO_FPS,
        values: vec![0.0; channel_count * frames.len()],
    };
    let mut true_root_cm = Vec::with_capacity(frames.len());
    for (f, targets) in frames.iter().enumerate() {
        true_root_cm.push(pose_frame(&rig, targets, motion.frame_mut(f)));
    }
    // The accelerometers measure the generated motion itself, not the plan.
    let poses = forward_kinematics(&rig.skeleton, &motion);
    let mut rng = XorShift64(0x9E37_79B9_7F4A_7C15);
    let foot_accel_g = rig.legs.map(|[_, _, foot]| accelerometer_g(&poses.trajectory(foot), &mut rng));
    // The hips and the left leg's knee and ankle: thigh and shank.
    let body = suit::SuitBody::from_feet(&rig.skeleton, rig.legs.map(|[_, _, foot]| foot));
    // The README's sizes, not the measured ones: the demo's figures are the
    // ones the project's issues quote, and over suit seeds 1–12 the
    // measured sizes leave both methods where they were (docs/contact.md,
    // "The demo's seed").
    let sizes = suit::ErrorSizes::DESCRIBED;
    let suit = suit::apply(&rig.skeleton, &motion, &body, &sizes, seed, suit::REAL_SUIT_LEVEL);
    Demo {
        skeleton: suit.skeleton,
        motion: suit.motion,
        true_skeleton: rig.skeleton,
        true_motion: motion,
        true_root_cm,
        leg_length_ratio: suit.leg_length_ratio,
        foot_accel_g,
        stance: frames.iter().map(|t| t.planted).collect(),
    }
}

/// The skeleton and the joints the generator drives.
struct Rig {
    skeleton: Skeleton,
    /// `[thigh, leg, foot]` per side.
    legs: PerFoot<[usize; 3]>,
    /// `[arm, forearm]` per side.
    arms: PerFoot<[usize; 2]>,
}

/// The karate suit's hierarchy and bone lengths, turned Y-up and facing +Z,
/// with the arms in T-pose and an end site at each toe, hand and the head.
fn build_rig() -> Rig {
    let mut skeleton = Skeleton::default();
    let mut root_channels = vec![Channel::Xposition, Channel::Yposition, Channel::Zposition];
    root_channels.extend(ROTATIONS);
    let hips = skeleton.push_joint("Hips".into(), None, DVec3::ZERO, root_channels, false);
    let s = &mut skeleton;
    let leg_bones = [
        ("Thigh", [HIP_HALF_WIDTH_CM, -HIP_DROP_CM, 0.0]),
        ("Leg", [0.0, -THIGH_CM, 0.0]),
        ("Foot", [0.0, -SHIN_CM, 0.0]),
    ];
    // The toe lies on the floor when the foot is flat.
    let toe = [0.0, -ANKLE_HEIGHT_CM, 13.49];
    // Left first: joint indices follow the order the chains are added in.
    let legs = PerFoot::from_fn(|foot| chain(s, hips, joint_prefix(foot), x_sign(foot), &leg_bones, toe));
    let spine_bones = [
        ("SpineLow", [0.0, 4.78, 0.0]),
        ("SpineMid", [0.0, 13.05, 0.0]),
        ("Chest", [0.0, 13.05, 0.0]),
        ("Neck", [0.0, 15.28, 0.0]),
        ("Head", [0.0, 11.46, 0.0]),
    ];
    let chest = chain(s, hips, "", 1.0, &spine_bones, [0.0, 14.33, 0.0])[2];
    let arm_bones = [
        ("Shoulder", [7.64, 9.55, -1.43]),
        ("Arm", [9.26, 4.30, 0.0]),
        ("Forearm", [26.08, 0.0, 0.0]),
        ("Hand", [25.50, 0.0, 0.0]),
    ];
    let arms = PerFoot::from_fn(|foot| {
        chain(s, chest, joint_prefix(foot), x_sign(foot), &arm_bones, [9.0, 0.0, 0.0])
    });
    Rig { skeleton, legs: legs.map(|j| [j[0], j[1], j[2]]), arms: arms.map(|j| [j[1], j[2]]) }
}

/// How the joints of a side's limbs begin: `Left` (`LeftFoot`) or `Right`.
fn joint_prefix(foot: Foot) -> &'static str {
    match foot {
        Foot::Left => "Left",
        Foot::Right => "Right",
    }
}

/// The sign of a side's X offsets: the figure's left is on +X.
fn x_sign(foot: Foot) -> f64 {
    match foot {
        Foot::Left => 1.0,
        Foot::Right => -1.0,
    }
}

/// Appends `bones` (name suffix, left-side offset in cm) as a chain under
/// `parent`, each with `Zrotation Yrotation Xrotation` channels and named
/// `{side}{name}`, then an end site at `end_cm` under the last. `sign` -1
/// mirrors the offsets to the right side. Returns the bones' indices.
fn chain(
    s: &mut Skeleton,
    parent: usize,
    side: &str,
    sign: f64,
    bones: &[(&str, [f64; 3])],
    end_cm: [f64; 3],
) -> Vec<usize> {
    let mirrored = |[x, y, z]: [f64; 3]| DVec3::new(sign * x, y, z);
    let mut joints = Vec::with_capacity(bones.len());
    let mut last = parent;
    for &(name, offset_cm) in bones {
        let (name, offset_cm) = (format!("{side}{name}"), mirrored(offset_cm));
        last = s.push_joint(name, Some(last), offset_cm, ROTATIONS.to_vec(), false);
        joints.push(last);
    }
    let end_name = format!("EndSite{}", s.joint_count());
    s.push_joint(end_name, Some(last), mirrored(end_cm), vec![], true);
    joints
}

/// A karate stance of the kata: where the feet stand relative to the
/// stance's centre.
#[derive(Clone, Copy, Debug)]
enum KataStance {
    /// Shizentai: feet side by side.
    Natural,
    /// Zenkutsu-dachi with the left foot in front.
    FrontLeft,
    /// Zenkutsu-dachi with the right foot in front.
    FrontRight,
    /// Kiba-dachi: feet wide apart sideways.
    Horse,
}

impl KataStance {
    /// Each foot's offset as (to the figure's left, forward), in cm.
    fn feet_cm(self) -> PerFoot<DVec2> {
        let (width, length, horse) = (12.0, 40.0, 40.0);
        let (left, right) = match self {
            KataStance::Natural => (DVec2::new(width, 0.0), DVec2::new(-width, 0.0)),
            KataStance::FrontLeft => (DVec2::new(width, length), DVec2::new(-width, -length)),
            KataStance::FrontRight => (DVec2::new(width, -length), DVec2::new(-width, length)),
            KataStance::Horse => (DVec2::new(horse, 0.0), DVec2::new(-horse, 0.0)),
        };
        PerFoot::new(left, right)
    }
}

/// One posture of the kata, held for `hold_s` once reached.
#[derive(Clone, Copy, Debug)]
struct Key {
    stance: KataStance,
    /// The midpoint of the feet on the floor, as (x, z).
    center_cm: DVec2,
    /// Unwrapped (a full left turn ends at 360), so interpolation turns the
    /// intended way.
    heading_deg: f64,
    /// How far each arm is punched out, 0 (fist at the hip) to 1 (extended),
    /// by the side of the arm.
    punch: PerFoot<f64>,
    hold_s: f64,
    /// The foot that steps first when both feet move to reach this key.
    lead: Foot,
}

impl Key {
    /// Each ankle's position on the floor, as (x, z).
    fn feet_cm(&self) -> PerFoot<DVec2> {
        let yaw = self.heading_deg.to_radians();
        let (sin, cos) = libm::sincos(yaw);
        let (left, forward) = (DVec2::new(cos, -sin), DVec2::new(sin, cos));
        self.stance.feet_cm().map(|o| self.center_cm + o.x * left + o.y * forward)
    }
}

/// The footstep plan, an embusen that ends where it starts: three steps
/// forward in front stance, a 180° turn, two steps forward, two steps back, a
/// 90° turn into horse stance, sidesteps, and a turning step back into the
/// start position. Each key moves one foot unless noted; the other foot stays
/// exactly where it is (the centres are chosen so).
fn kata() -> Vec<Key> {
    use KataStance::*;
    let key = |stance, x, z, heading_deg, punch, hold_s| Key {
        stance,
        center_cm: DVec2::new(x, z),
        heading_deg,
        punch,
        hold_s,
        lead: Foot::Left,
    };
    let (none, left, right) = (PerFoot::new(0.0, 0.0), PerFoot::new(1.0, 0.0), PerFoot::new(0.0, 1.0));
    vec![
        key(Natural, 0.0, 0.0, 0.0, none, 2.0),
        key(FrontLeft, 0.0, 40.0, 0.0, left, 0.6),
        key(FrontRight, 0.0, 120.0, 0.0, right, 0.6),
        key(FrontLeft, 0.0, 200.0, 0.0, left, 0.8),
        // The right foot swings round behind while the left pivots in place.
        key(FrontRight, 24.0, 200.0, 180.0, right, 0.6),
        key(FrontLeft, 24.0, 120.0, 180.0, left, 0.6),
        key(FrontRight, 24.0, 40.0, 180.0, right, 0.8),
        // Steps back: the front foot retreats behind the other.
        key(FrontLeft, 24.0, 120.0, 180.0, left, 0.6),
        key(FrontRight, 24.0, 200.0, 180.0, right, 0.8),
        // Facing -X, so sidesteps to the right lead back towards the start.
        key(Horse, 12.0, 200.0, 270.0, none, 0.6),
        key(Natural, 12.0, 172.0, 270.0, none, 0.3),
        key(Horse, 12.0, 144.0, 270.0, right, 0.6),
        key(Natural, 12.0, 116.0, 270.0, none, 0.3),
        key(Horse, 12.0, 88.0, 270.0, left, 0.8),
        key(Natural, 12.0, 60.0, 270.0, none, 0.3),
        // Both feet move: the right first, so the left's long step back does
        // not cross it.
        Key { lead: Foot::Right, ..key(Natural, 0.0, 0.0, 360.0, none, 1.5) },
    ]
}

/// What the feet, hips heading and arms should do in one frame.
#[derive(Clone, Copy, Debug)]
struct Targets {
    ankle_cm: PerFoot<DVec3>,
    foot_yaw_deg: PerFoot<f64>,
    planted: PerFoot<bool>,
    heading_deg: f64,
    /// By the side of the arm, as [`Key::punch`].
    punch: PerFoot<f64>,
}

/// Samples the plan at [`DEMO_FPS`]: each key is held, then the feet that
/// differ from the next key step one after the other (`lead` first).
fn plan_frames(keys: &[Key]) -> Vec<Targets> {
    let mut frames = Vec::new();
    for (i, key) in keys.iter().enumerate() {
        let held = Targets {
            ankle_cm: key.feet_cm().map(flat),
            foot_yaw_deg: PerFoot::new(key.heading_deg, key.heading_deg),
            planted: PerFoot::new(true, true),
            heading_deg: key.heading_deg,
            punch: key.punch,
        };
        frames.extend(std::iter::repeat_n(held, frame_count(key.hold_s)));
        if let Some(next) = keys.get(i + 1) {
            transition(key, next, &mut frames);
        }
    }
    frames
}

/// The ankle of a flat foot standing at floor point (x, z).
fn flat(floor_cm: DVec2) -> DVec3 {
    DVec3::new(floor_cm.x, ANKLE_HEIGHT_CM, floor_cm.y)
}

fn frame_count(duration_s: f64) -> usize {
    (duration_s * DEMO_FPS).round() as usize
}

/// Appends the frames that take the figure from key `a` to key `b`.
fn transition(a: &Key, b: &Key, frames: &mut Vec<Targets>) {
    let (from, to) = (a.feet_cm(), b.feet_cm());
    // Each moving foot gets its own swing window, in frames from the start.
    let mut swings: PerFoot<Option<(usize, usize)>> = PerFoot::new(None, None);
    let mut end = 0;
    for foot in [b.lead, b.lead.other()] {
        let distance_cm = from[foot].distance(to[foot]);
        // Keys are built so that a staying foot's position is recomputed to
        // within rounding; anything more is a real step.
        if distance_cm > 1e-6 {
            let start = end;
            end += frame_count(SWING_BASE_S + distance_cm / SWING_CM_PER_S);
            swings[foot] = Some((start, end));
        }
    }
    let total = if end == 0 { frame_count(PIVOT_S) } else { end };
    for k in 0..total {
        let s = min_jerk(k as f64 / total as f64);
        // Punches land late in the step, as the stance settles.
        let punch_s = min_jerk((k as f64 / total as f64 - 0.3) / 0.7);
        let mut t = Targets {
            ankle_cm: PerFoot::new(DVec3::ZERO, DVec3::ZERO),
            foot_yaw_deg: PerFoot::new(0.0, 0.0),
            planted: PerFoot::new(true, true),
            heading_deg: lerp(a.heading_deg, b.heading_deg, s),
            punch: PerFoot::from_fn(|side| lerp(a.punch[side], b.punch[side], punch_s)),
        };
        for foot in Foot::BOTH {
            let (yaw0, yaw1) = (a.heading_deg, b.heading_deg);
            (t.ankle_cm[foot], t.foot_yaw_deg[foot], t.planted[foot]) = match swings[foot] {
                Some((start, stop)) if k > start && k < stop => {
                    let u = (k - start) as f64 / (stop - start) as f64;
                    let m = min_jerk(u);
                    // 64 (u (1 - u))³ rises to 1 mid-swing and, like the
                    // min-jerk ease, has no acceleration at either end.
                    let lift = DVec3::Y * LIFT_CM * 64.0 * (u * (1.0 - u)).powi(3);
                    let ankle_cm = flat(from[foot].lerp(to[foot], m)) + lift;
                    (ankle_cm, lerp(yaw0, yaw1, m), false)
                }
                Some((_, stop)) if k >= stop => (flat(to[foot]), yaw1, true),
                Some(_) => (flat(from[foot]), yaw0, true),
                // A foot that does not step pivots about its ankle with the body.
                None => (flat(from[foot]), lerp(yaw0, yaw1, s), true),
            };
        }
        frames.push(t);
    }
}

/// Minimum-jerk ease from 0 to 1 (`u` clamped to [0, 1]): zero velocity and
/// acceleration at both ends, so feet leave and reach the floor smoothly.
fn min_jerk(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

fn lerp(a: f64, b: f64, s: f64) -> f64 {
    a + (b - a) * s
}

fn yaw(degrees: f64) -> DMat3 {
    DMat3::from_rotation_y(degrees.to_radians())
}

/// The hips position: horizontally the midpoint of the ankles; vertically the
/// highest point from which both hip joints are within `REACH_FRACTION` of a
/// straight leg from their ankles.
fn hips_cm(t: &Targets) -> DVec3 {
    let mid = (t.ankle_cm.left + t.ankle_cm.right) / 2.0;
    let reach_cm = REACH_FRACTION * (THIGH_CM + SHIN_CM);
    let height_cm = Foot::BOTH
        .map(|foot| {
            let hip = mid + yaw(t.heading_deg) * hip_offset_cm(foot);
            let horizontal_cm = (hip - t.ankle_cm[foot]).with_y(0.0).length().min(0.99 * reach_cm);
            t.ankle_cm[foot].y + HIP_DROP_CM + (reach_cm * reach_cm - horizontal_cm * horizontal_cm).sqrt()
        })
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    mid.with_y(height_cm)
}

/// The thigh joint's offset from the hips (the skeleton's OFFSET).
fn hip_offset_cm(foot: Foot) -> DVec3 {
    DVec3::new(x_sign(foot) * HIP_HALF_WIDTH_CM, -HIP_DROP_CM, 0.0)
}

/// Two-bone IK: the world rotations of thigh and shin that put the ankle at
/// `ankle_cm` from a hip joint at `hip_cm`, with the knee bending towards
/// `forward` (the foot's facing). Exact when the ankle is within reach.
fn leg_ik(hip_cm: DVec3, ankle_cm: DVec3, forward: DVec3) -> [DMat3; 2] {
    let to_ankle = ankle_cm - hip_cm;
    let distance_cm = to_ankle.length().min(THIGH_CM + SHIN_CM);
    let along = to_ankle / to_ankle.length();
    let toward_knee = (forward - forward.dot(along) * along).normalize();
    // Law of cosines for the angle at the hip between thigh and hip–ankle line.
    let cos_hip = ((THIGH_CM * THIGH_CM + distance_cm * distance_cm - SHIN_CM * SHIN_CM)
        / (2.0 * THIGH_CM * distance_cm))
        .clamp(-1.0, 1.0);
    let sin_hip = (1.0 - cos_hip * cos_hip).sqrt();
    let knee_cm = hip_cm + THIGH_CM * (cos_hip * along + sin_hip * toward_knee);
    [bone_frame(knee_cm - hip_cm, toward_knee), bone_frame(ankle_cm - knee_cm, toward_knee)]
}

/// The rotation taking a rest bone (along -Y, front +Z) to point along `bone`
/// with its front towards `front` (made perpendicular to the bone). Both leg
/// bones share the knee's hinge axis as their X axis.
fn bone_frame(bone: DVec3, front: DVec3) -> DMat3 {
    let y = -bone.normalize();
    let z = (front - front.dot(y) * y).normalize();
    DMat3::from_cols(y.cross(z), y, z)
}

/// Left arm `[upper arm, forearm]` channel angles for a punch amount: from
/// the fist chambered at the waist (arm down, elbow bent forward) to the arm
/// straight out in front at shoulder height.
fn left_arm_zyx_degrees(punch: f64) -> [[f64; 3]; 2] {
    [[lerp(-75.0, 0.0, punch), lerp(-15.0, -90.0, punch), 0.0], [0.0, lerp(-80.0, 0.0, punch), 0.0]]
}

/// Writes one frame's channel values and returns the hips position.
fn pose_frame(rig: &Rig, t: &Targets, values: &mut [f64]) -> DVec3 {
    let sk = &rig.skeleton;
    let mut set = |joint: usize, zyx: [f64; 3]| {
        let first = sk.first_channel[joint];
        values[first..first + 3].copy_from_slice(&zyx);
    };
    let hips = hips_cm(t);
    let pelvis = yaw(t.heading_deg);
    for foot in Foot::BOTH {
        let [thigh, leg, ankle] = rig.legs[foot];
        let foot_world = yaw(t.foot_yaw_deg[foot]);
        let hip = hips + pelvis * hip_offset_cm(foot);
        let [thigh_world, shin_world] = leg_ik(hip, t.ankle_cm[foot], foot_world * DVec3::Z);
        set(thigh, zyx_degrees(pelvis.transpose() * thigh_world));
        set(leg, zyx_degrees(thigh_world.transpose() * shin_world));
        // FootJoints stay flat (only yawed), so the toe rests on the floor.
        set(ankle, zyx_degrees(shin_world.transpose() * foot_world));
        let [arm, forearm] = rig.arms[foot];
        let [upper_zyx, fore_zyx] = left_arm_zyx_degrees(t.punch[foot]);
        // The right arm mirrors the left across the X = 0 plane, which
        // negates rotations about Z and Y.
        let mirror = |[z, y, x]: [f64; 3]| if foot == Foot::Left { [z, y, x] } else { [-z, -y, x] };
        set(arm, mirror(upper_zyx));
        set(forearm, mirror(fore_zyx));
    }
    let root = sk.first_channel[0];
    values[root..root + 6].copy_from_slice(&[hips.x, hips.y, hips.z, 0.0, t.heading_deg, 0.0]);
    hips
}

/// Accelerometer readings in g for a trajectory sampled at [`DEMO_FPS`]: the
/// central second difference (end frames repeat their neighbour, the figure
/// stands still there), plus gravity's reaction, plus noise.
fn accelerometer_g(positions_cm: &[DVec3], rng: &mut XorShift64) -> Vec<DVec3> {
    let n = positions_cm.len();
    (0..n)
        .map(|f| {
            let (prev, next) = (positions_cm[f.saturating_sub(1)], positions_cm[(f + 1).min(n - 1)]);
            let accel_cm_s2 = (prev - 2.0 * positions_cm[f] + next) * (DEMO_FPS * DEMO_FPS);
            let noise = DVec3::new(rng.symmetric(), rng.symmetric(), rng.symmetric()) * NOISE_G;
            (accel_cm_s2 + DVec3::Y * STANDARD_GRAVITY_CM_PER_S2) / STANDARD_GRAVITY_CM_PER_S2 + noise
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_key_but_the_last_moves_one_foot() {
        let keys = kata();
        for (i, pair) in keys.windows(2).enumerate() {
            let (a, b) = (pair[0].feet_cm(), pair[1].feet_cm());
            let moved = Foot::BOTH.iter().filter(|&&f| a[f].distance(b[f]) > 1e-6).count();
            let expected = if i + 2 == keys.len() { 2 } else { 1 };
            assert_eq!(moved, expected, "key {} -> {}", i, i + 1);
        }
    }
}
