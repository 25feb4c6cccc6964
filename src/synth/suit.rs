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

use glam::{DMat3, DQuat, DVec3};

use crate::body::feet::{FootJoints, above_hips, hips_joint};
use crate::body::kinematics::{local_rotation, local_translation, rotation_channel_degrees, world_rotations};
use crate::body::skeleton::{Channel, Motion, Skeleton};
use crate::signal::stats::median;
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
/// Relative deviation of the actor's height as the vendor takes it.
pub const BODY_SCALE_DEVIATION: f64 = 0.02;
/// The vendor's translation wanders by this much per √s, per horizontal
/// axis (a random walk): about 50 cm over the demo's 24 s. The real karate
/// suit's vendor translation misses its kata's closure by 3.7 m.
pub const VENDOR_WALK_CM_PER_SQRT_S: f64 = 10.0;
/// Every Gaussian draw is clamped to this many deviations.
pub const MAX_SIGMAS: f64 = 2.5;

/// How large a suit's noise, lag and bone errors are at level 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSizes {
    /// Orientation noise per unit of angular speed, per axis (° per rad/s).
    pub noise_deg_per_rad_per_s: f64,
    /// Orientation noise of a segment at rest, per axis (°).
    pub noise_floor_deg: f64,
    /// The angular speed the noise grows with is the segment's mean over
    /// this long before and after each frame (s); 0: the frame's own.
    pub noise_speed_window_s: f64,
    /// The noise's correlation time `τ` (s): a frame `dt` later keeps
    /// `e^(−dt/τ)` of it; 0: white from frame to frame.
    pub noise_correlation_s: f64,
    /// How late the fusion filter's orientation is (s).
    pub fusion_lag_s: f64,
    /// Relative deviation of each bone of the template from the actor's.
    pub bone_scale_deviation: f64,
}

impl ErrorSizes {
    /// The sizes the README's words give: "about 2° at 2 rad/s" (per axis),
    /// white, "tens of ms", "a few percent". The built-in demo's.
    pub const DESCRIBED: ErrorSizes = ErrorSizes {
        noise_deg_per_rad_per_s: 1.0,
        noise_floor_deg: 0.1,
        noise_speed_window_s: 0.0,
        noise_correlation_s: 0.0,
        fusion_lag_s: 0.03,
        bone_scale_deviation: 0.02,
    };

    /// The sizes the shared suit files measure against their truths
    /// (`examples/suit_stats.rs`, level 1): per axis, the noise left once
    /// the lag and everything slower than ±0.5 s are taken out, binned by
    /// the segment's angular speed, and its correlation one and two frames
    /// apart. Of the seven shared motions (two seeds each), with these
    /// sizes' figures for a third seed in brackets:
    ///
    /// | | below 1 rad/s | 1–2 | 2–4 | 4–8 | over 8 | one / two frames |
    /// | --- | --- | --- | --- | --- | --- | --- |
    /// | walk | 2.05° (2.03) | 3.17 (3.06) | 4.72 (4.43) | 7.16 (6.79) | 9.3 (9.2) | 0.61 / 0.36 (0.58 / 0.30) |
    /// | run | 3.35 (2.65) | 4.79 (4.60) | 7.08 (6.42) | 9.32 (9.04) | 13.2 (12.0) | 0.60 / 0.34 (0.61 / 0.34) |
    /// | bow | 0.78 (0.73) | 2.27 (2.23) | 4.42 (4.44) | 6.2 (7.1) | | 0.60 / 0.33 (0.62 / 0.39) |
    /// | kick | 1.78 (1.69) | 3.74 (3.62) | 6.38 (6.34) | 10.2 (10.1) | 16.4 (15.7) | 0.60 / 0.30 (0.57 / 0.30) |
    /// | dance | 2.12 (1.92) | 4.21 (3.88) | 5.95 (5.54) | 9.86 (9.14) | 17.4 (15.9) | 0.62 / 0.32 (0.59 / 0.32) |
    ///
    /// The noise is a filter's error, so it is not white (0.65 of it
    /// carries to the next frame at 30 fps). A segment at rest is almost
    /// still (the bow's feet 0.07°, as in the shared files), so the floor
    /// is small, and a segment passing slowly through a fast motion is not,
    /// which the speed window and the correlation give. The lag reads 7–27
    /// ms (these sizes 6–21), the bones spread 2.8 % (0.019–0.041). The
    /// README's sizes read half of this noise or less below 4 rad/s.
    pub const MEASURED: ErrorSizes = ErrorSizes {
        noise_deg_per_rad_per_s: 1.8,
        noise_floor_deg: 0.09,
        noise_speed_window_s: 0.13,
        noise_correlation_s: 0.077,
        fusion_lag_s: 0.02,
        bone_scale_deviation: 0.028,
    };

    /// The per-axis deviation of the orientation noise of a segment turning
    /// at `angular_speed_rad_per_s`: the floor and the part that grows with
    /// the speed, added in quadrature.
    pub fn noise_deviation_deg(&self, angular_speed_rad_per_s: f64) -> f64 {
        let moving_deg = self.noise_deg_per_rad_per_s * angular_speed_rad_per_s;
        libm::sqrt(self.noise_floor_deg * self.noise_floor_deg + moving_deg * moving_deg)
    }

    /// The share of a frame's noise the next frame keeps at `fps`.
    fn noise_kept(&self, fps: f64) -> f64 {
        if self.noise_correlation_s > 0.0 { libm::exp(-1.0 / (fps * self.noise_correlation_s)) } else { 0.0 }
    }
}

/// A rotation error drawn as a rotation vector with `deviation_deg` per axis.
pub fn random_rotation(rng: &mut XorShift64, deviation_deg: f64) -> DMat3 {
    rotation_deg(random_axis_deg(rng, deviation_deg))
}

/// A rotation vector (°) of `deviation_deg` per axis: three draws of `rng`.
fn random_axis_deg(rng: &mut XorShift64, deviation_deg: f64) -> DVec3 {
    DVec3::new(clamped(rng), clamped(rng), clamped(rng)) * deviation_deg
}

/// The rotation whose rotation vector is `axis_deg` (°).
fn rotation_deg(axis_deg: DVec3) -> DMat3 {
    DMat3::from_quat(DQuat::from_scaled_axis(axis_deg * (std::f64::consts::PI / 180.0)))
}

/// A standard normal draw clamped to ±[`MAX_SIGMAS`].
fn clamped(rng: &mut XorShift64) -> f64 {
    rng.gaussian().clamp(-MAX_SIGMAS, MAX_SIGMAS)
}

/// A slow drift: a sum of `DRIFT_SINES` sines of random periods and
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

/// The level of the real suit's errors: every deviation as the constants
/// above say. Level 0.5 halves every one of them (misalignment, drifts,
/// noise, fusion lag, the bones' scale deviations, the vendor's walk); 0 is
/// a perfect suit.
pub const REAL_SUIT_LEVEL: f64 = 1.0;

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

/// The joints the model must know by their part in the body.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitBody {
    /// Where the legs meet ([`hips_joint`]): the point whose path the
    /// vendor's translation guesses. Joints above it are no body segment.
    pub hips: usize,
    /// The joints whose bones make one leg (the knee's and the ankle's
    /// OFFSET or position channels: thigh and shank), for the leg-length
    /// ratio the vendor's translation is scaled by.
    pub leg_bones: Vec<usize>,
}

impl SuitBody {
    /// The hips and the left leg's bones of a skeleton whose ankle-level
    /// joints are `feet`: the foot's own bone (the shank) and its parent's
    /// (the thigh), the bones `eval::leg_length_cm` measures a leg by.
    pub fn from_feet(skeleton: &Skeleton, feet: FootJoints) -> SuitBody {
        let hips = hips_joint(&skeleton.parents, feet);
        let knee = skeleton.parents.get(feet.left).copied().flatten().filter(|&knee| knee != hips);
        SuitBody { hips, leg_bones: knee.into_iter().chain([feet.left]).collect() }
    }
}

/// What the suit makes of a joint.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Part {
    /// A segment with a sensor: its rotation is the suit's estimate.
    Sensed,
    /// A segment without a sensor (a toe, [`has_no_sensor`]): each of its
    /// rotation channels holds the median of its true values over the take,
    /// the toe's usual bend. (The shared suit files do this; the rest pose
    /// would straighten a toe that is never straight, Bandai's bend 17–25°.)
    Unsensed,
    /// Above the hips: no part of the body but what an exporter puts over
    /// it (Bandai's `joint_Root` on the floor): no sensor and no bone; its
    /// channels hold their first frame's values.
    AboveHips,
}

/// Whether a joint is a segment no suit puts a sensor on: a toe (a name
/// with `toe` in it, in any case: `Toes_L`, `LeftToeBase`). The karate
/// suit's 17 sensors have none on the toes; the demo's skeleton, the karate
/// suit's, has no toe joint (each foot is one segment, ankle to toe end
/// site, with its own sensor).
fn has_no_sensor(name: &str) -> bool {
    name.to_ascii_lowercase().contains("toe")
}

fn parts(skeleton: &Skeleton, hips: usize) -> Vec<Part> {
    let above = above_hips(&skeleton.parents, hips);
    (0..skeleton.joint_count())
        .map(|j| {
            if above.contains(&j) {
                Part::AboveHips
            } else if !skeleton.is_end_site[j] && has_no_sensor(&skeleton.names[j]) {
                Part::Unsensed
            } else {
                Part::Sensed
            }
        })
        .collect()
}

/// The joint whose position channels carry the vendor's translation: the
/// hips if they have any (the demo's and the karate suit's root; Bandai's
/// `Hips` below its `joint_Root`), else the nearest joint above them that
/// has; `None` when no joint from the root down to the hips has a position
/// channel (a recording without translation).
///
/// Why the hips even when the joint above them moves too (Bandai's
/// `dash_normal_001` runs forward in `joint_Root` and bobs in place in
/// `Hips`): a suit's vendor guesses where the pelvis is, one path, not an
/// exporter's split of it. So the joints above the hips hold their first
/// frame, and the hips' channels take the whole guessed path, as in the
/// shared suit files.
pub fn translation_joint(skeleton: &Skeleton, hips: usize) -> Option<usize> {
    std::iter::once(hips)
        .chain(above_hips(&skeleton.parents, hips))
        .find(|&j| skeleton.channels[j].iter().any(|c| c.is_position()))
}

/// A joint's name without its side, so that the two sides name one bone of
/// the template: `LeftLeg` and `RightLeg` are `Leg`, `UpperLeg_L` and
/// `UpperLeg_R` are `UpperLeg`, `thigh.l` and `thigh.r` are `thigh`; an
/// exporter's namespace (`mixamorig:`) is dropped first.
fn sideless(name: &str) -> &str {
    const PREFIXES: [&str; 4] = ["Left", "Right", "left", "right"];
    const SUFFIXES: [&str; 8] = ["_L", "_R", ".L", ".R", "_l", "_r", ".l", ".r"];
    let base = name.rsplit(':').next().unwrap_or(name);
    PREFIXES
        .iter()
        .find_map(|p| base.strip_prefix(p))
        .or_else(|| SUFFIXES.iter().find_map(|s| base.strip_suffix(s)))
        .filter(|rest| !rest.is_empty())
        .unwrap_or(base)
}

/// The bone a joint's offset is, without its side (see [`sideless`]); an
/// end site is its parent's end.
fn bone_key(skeleton: &Skeleton, joint: usize) -> String {
    match (skeleton.is_end_site[joint], skeleton.parents[joint]) {
        (true, Some(parent)) => format!("{} end", bone_key(skeleton, parent)),
        _ => sideless(&skeleton.names[joint]).to_string(),
    }
}

/// The template's scale of every joint's bone: one scale per bone (left and
/// right alike) times one for the whole body, deviations `level` times
/// `sizes`'. Drawn for every joint, bone or not, in the joints' order, so
/// that a seed draws the same numbers whatever the skeleton's bones are.
fn bone_scales(skeleton: &Skeleton, rng: &mut XorShift64, sizes: &ErrorSizes, level: f64) -> Vec<f64> {
    let body = 1.0 + BODY_SCALE_DEVIATION * level * clamped(rng);
    let mut scales: Vec<(String, f64)> = Vec::new();
    (0..skeleton.joint_count())
        .map(|joint| {
            let key = bone_key(skeleton, joint);
            match scales.iter().find(|(k, _)| *k == key) {
                Some(&(_, s)) => s,
                None => {
                    let s = body * (1.0 + sizes.bone_scale_deviation * level * clamped(rng));
                    scales.push((key, s));
                    s
                }
            }
        })
        .collect()
}

/// The skeleton with every bone's OFFSET scaled by its joint's `scales`;
/// the hips and the joints above them are no bones and keep theirs.
fn scaled_skeleton(skeleton: &Skeleton, scales: &[f64], is_bone: &[bool]) -> Skeleton {
    let mut scaled = skeleton.clone();
    for (j, offset_cm) in scaled.offsets_cm.iter_mut().enumerate() {
        if is_bone[j] {
            *offset_cm *= scales[j];
        }
    }
    scaled
}

/// The indices, within a joint's channels, of its rotation channels when it
/// has exactly three (whether the model can write them is
/// [`rotation_channel_degrees`]'s to say).
fn rotation_channel_indices(channels: &[Channel]) -> Option<[usize; 3]> {
    let rotations: Vec<usize> = (0..channels.len()).filter(|&i| !channels[i].is_position()).collect();
    rotations.try_into().ok()
}

/// The joints whose rotation is a sensor's (not the end sites, which have
/// none): every one below the hips `hips` but the toes.
pub fn sensed_joints(skeleton: &Skeleton, hips: usize) -> Vec<usize> {
    let parts = parts(skeleton, hips);
    (0..skeleton.joint_count()).filter(|&j| parts[j] == Part::Sensed && !skeleton.is_end_site[j]).collect()
}

/// The joints with a sensor whose rotation channels the model cannot write
/// (one or two of them, or one axis twice): they keep their true rotations
/// (see [`apply`]), so a caller can say so.
pub fn joints_kept_true(skeleton: &Skeleton, body: &SuitBody) -> Vec<usize> {
    let parts = parts(skeleton, body.hips);
    (0..skeleton.joint_count())
        .filter(|&j| parts[j] == Part::Sensed && skeleton.channels[j].iter().any(|c| !c.is_position()))
        .filter(|&j| {
            let channels = &skeleton.channels[j];
            let order = rotation_channel_indices(channels).map(|indices| indices.map(|i| channels[i]));
            order.and_then(|order| rotation_channel_degrees(order, DMat3::IDENTITY)).is_none()
        })
        .collect()
}

/// Frame-major, per frame and joint of `world` (`n` joints a frame, at
/// `fps`), the joint's mean angular speed (rad/s) over the frames within
/// `window_s` of it.
// Not inlined into `apply` (nor `CorrelatedNoise::next`): the player's first
// load is gated (tests/browser/app.test.mjs), and inlined
// they cost it 0.3 KB more. For the same bytes each frame's speed is
// computed again in every window it falls in, not kept: the player's demo
// has no window, and the measured sizes' window is 9 frames at 30 fps.
#[inline(never)]
fn windowed_angular_speeds(world: &[DQuat], n: usize, fps: f64, window_s: f64) -> Vec<f64> {
    let frames = world.len().checked_div(n).unwrap_or(0);
    // The central difference's speed in frame `f`.
    let speed = |f: usize, j: usize| {
        let (prev, next) = (f.saturating_sub(1), (f + 1).min(frames - 1));
        angle_rad(world[prev * n + j].inverse() * world[next * n + j]) * fps / (next - prev).max(1) as f64
    };
    let reach = (window_s * fps).round() as usize;
    (0..frames * n)
        .map(|i| {
            let (f, j) = (i / n, i % n);
            let (first, last) = (f.saturating_sub(reach), (f + reach).min(frames - 1));
            (first..=last).map(|g| speed(g, j)).sum::<f64>() / (last - first + 1) as f64
        })
        .collect()
}

/// Each joint's orientation noise, frame after frame: a first-order
/// autoregression that keeps `keep` of the last frame's rotation vector
/// (`e^(−dt/τ)`, [`ErrorSizes::noise_correlation_s`]) and adds a fresh
/// draw, sized so that a steady deviation asked for is the deviation the
/// noise has; the first frame draws it whole.
struct CorrelatedNoise {
    /// Per joint, the last rotation vector (degrees).
    last_deg: Vec<DVec3>,
    keep: f64,
}

impl CorrelatedNoise {
    fn new(n: usize, keep: f64) -> CorrelatedNoise {
        CorrelatedNoise { last_deg: vec![DVec3::ZERO; n], keep }
    }

    /// Joint `j`'s noise in frame `f`, of `deviation_deg` per axis; three
    /// draws of `rng`, as [`random_rotation`] takes.
    #[inline(never)]
    fn next(&mut self, rng: &mut XorShift64, f: usize, j: usize, deviation_deg: f64) -> DMat3 {
        let keep = if f == 0 { 0.0 } else { self.keep };
        let draw_deg = random_axis_deg(rng, deviation_deg);
        let now_deg = self.last_deg[j] * keep + draw_deg * libm::sqrt(1.0 - keep * keep);
        self.last_deg[j] = now_deg;
        rotation_deg(now_deg)
    }
}

/// The angle of a rotation, in radians.
fn angle_rad(q: DQuat) -> f64 {
    2.0 * libm::atan2(q.xyz().length(), q.w.abs())
}

/// The values that stay the same in every frame, as (index in a frame,
/// value): an unsensed joint's rotation channels at their medians over the
/// take, and every channel of the joints above the hips at its first frame,
/// but for the translation carrier's positions (the vendor's to write).
fn held_channels(
    skeleton: &Skeleton,
    motion: &Motion,
    parts: &[Part],
    carrier: Option<usize>,
) -> Vec<(usize, f64)> {
    let mut held = Vec::new();
    for (j, part) in parts.iter().enumerate() {
        let first = skeleton.first_channel[j];
        for (i, channel) in skeleton.channels[j].iter().enumerate() {
            let index = first + i;
            let over_take =
                || (0..motion.frame_count()).map(|f| motion.frame(f)[index]).collect::<Vec<f64>>();
            match part {
                Part::Unsensed if !channel.is_position() => held.push((index, median(&over_take()))),
                Part::AboveHips if !(channel.is_position() && Some(j) == carrier) => {
                    held.push((index, motion.frame(0)[index]))
                }
                _ => {}
            }
        }
    }
    held
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

/// Scales every bone's position channels (in every frame) by its joint's
/// `scales`, as its OFFSET is: a skeleton whose bones are position channels
/// (Bandai's) gets the template's bone lengths too.
fn scale_position_bones(skeleton: &Skeleton, motion: &mut Motion, scales: &[f64], is_bone: &[bool]) {
    let indices: Vec<(usize, f64)> = (0..skeleton.joint_count())
        .filter(|&j| is_bone[j])
        .flat_map(|j| {
            let first = skeleton.first_channel[j];
            let channels = &skeleton.channels[j];
            (0..channels.len()).filter(|&i| channels[i].is_position()).map(move |i| (first + i, scales[j]))
        })
        .collect();
    if indices.is_empty() {
        return;
    }
    for f in 0..motion.frame_count() {
        let values = motion.frame_mut(f);
        for &(index, scale) in &indices {
            values[index] *= scale;
        }
    }
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
    use std::f64::consts::PI;

    #[test]
    fn the_noise_has_the_deviation_it_says() {
        let described = ErrorSizes::DESCRIBED;
        assert!((described.noise_deviation_deg(2.0) - 2.0).abs() < 0.01, "about 2° at 2 rad/s");
        assert_eq!(described.noise_deviation_deg(0.0), described.noise_floor_deg);
        assert!((ErrorSizes::MEASURED.noise_deviation_deg(2.0) - 3.6).abs() < 0.01);
        let mut rng = XorShift64(7);
        let n = 40_000;
        let deviation_deg = described.noise_deviation_deg(2.0);
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
    fn the_noise_keeps_its_deviation_and_its_correlation_at_any_rate() {
        let sizes = ErrorSizes::MEASURED;
        for fps in [30.0, 100.0] {
            let mut noise = CorrelatedNoise::new(1, sizes.noise_kept(fps));
            let mut rng = XorShift64(5);
            let n = 40_000;
            let deg: Vec<DVec3> = (0..n)
                .map(|f| DQuat::from_mat3(&noise.next(&mut rng, f, 0, 2.0)).to_scaled_axis() * (180.0 / PI))
                .collect();
            let variance = deg.iter().map(|v| v.length_squared()).sum::<f64>() / (3 * n) as f64;
            // Clamping at 2.5 deviations takes ~3% of the variance away.
            assert!((variance.sqrt() / 2.0 - 0.985).abs() < 0.03, "{} at {fps} fps", variance.sqrt());
            // A frame keeps e^(−dt/τ) of the last one, whatever dt is.
            let lag_one =
                deg.windows(2).map(|w| w[0].dot(w[1])).sum::<f64>() / (3.0 * variance * (n - 1) as f64);
            let expected = (-1.0 / (fps * sizes.noise_correlation_s)).exp();
            assert!((lag_one - expected).abs() < 0.02, "{lag_one} against {expected} at {fps} fps");
        }
        assert!((sizes.noise_kept(30.0) - 0.65).abs() < 0.01);
        // The README's noise is white.
        assert_eq!(ErrorSizes::DESCRIBED.noise_kept(30.0), 0.0);
    }

    #[test]
    fn the_speed_the_noise_grows_with_is_a_window_mean() {
        // One joint turning about Y at 2 rad/s for 30 frames of 30, then still.
        let fps = 30.0;
        let world: Vec<DQuat> =
            (0..60).map(|f| DQuat::from_rotation_y(2.0 * (f.min(30) as f64) / fps)).collect();
        let window_s = ErrorSizes::MEASURED.noise_speed_window_s;
        let speeds = windowed_angular_speeds(&world, 1, fps, window_s);
        assert!((speeds[15] - 2.0).abs() < 1e-9);
        assert!(speeds[55].abs() < 1e-9);
        // Within the window of the stop, the mean of both.
        let reach = (window_s * fps).round() as usize;
        assert!(speeds[31] > 0.2 && speeds[31] < 1.8, "{}", speeds[31]);
        assert!(speeds[30 + reach + 1].abs() < 1e-9);
        // With no window, each frame's own.
        assert_eq!(windowed_angular_speeds(&world, 1, fps, 0.0)[31], 0.0);
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
        let scales = bone_scales(&s, &mut XorShift64(3), &ErrorSizes::MEASURED, REAL_SUIT_LEVEL);
        let scaled = scaled_skeleton(&s, &scales, &[false, true, true, true, true]);
        assert_eq!(scaled.offsets_cm[left], scaled.offsets_cm[right]);
        assert_eq!(scaled.offsets_cm[end_l], scaled.offsets_cm[end_r]);
        assert_ne!(scaled.offsets_cm[left], s.offsets_cm[left]);
    }

    #[test]
    fn side_marks_name_one_bone() {
        for (left, right, bone) in [
            ("LeftUpLeg", "RightUpLeg", "UpLeg"),
            ("UpperLeg_L", "UpperLeg_R", "UpperLeg"),
            ("thigh.l", "thigh.r", "thigh"),
            ("mixamorig:LeftFoot", "mixamorig:RightFoot", "Foot"),
        ] {
            assert_eq!((sideless(left), sideless(right)), (bone, bone));
        }
        for unsided in ["Hips", "Spine", "Left", "_L", "Chest"] {
            assert_eq!(sideless(unsided), unsided);
        }
    }

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
