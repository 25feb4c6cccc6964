//! The contact method: the translation from the feet's contacts with the
//! floor, frame by frame, with flight.
//!
//! The body's joint positions relative to its hips are what an inertial suit
//! measures well; where the hips are is what it guesses. This method throws
//! the guess away and rebuilds it from one physical fact at a time:
//!
//! 1. **A foot on the floor does not slide.** Each frame, the foot point
//!    (ankle, toe, toe tip: the foot joint and everything below it) that is
//!    lowest is the one touching the floor, so heel strike, flat foot and
//!    roll-over onto the toes each pin the right point. Heights are compared
//!    after subtracting each point's own height above the floor in a standing
//!    foot (its *floor offset*, the median over the recording), because an
//!    ankle stands ~8 cm higher than a toe tip when both are down.
//! 2. **The floor pushes but never pulls.** With the lowest foot point on the
//!    floor, the hips' height follows from the pose. When that height would
//!    drop faster than a body falls, the feet have left the floor: the hips
//!    then follow a ballistic arc (gravity only) until a foot reaches the
//!    floor again. Nothing ever sinks below the floor.
//! 3. **A body does not change velocity abruptly.** In flight the hips keep
//!    their take-off horizontal velocity. With both feet low, both are taken
//!    as planted when they agree; when they disagree, one is sliding (a foot
//!    landing, or lifting off), and the one that agrees with the body's
//!    motion so far wins — with an accelerometer, the calmer foot also counts.
//!
//! Everything is in seconds and centimetres, so 30 fps and 100 Hz recordings
//! behave alike, and the cost is O(frames × foot points).

use glam::DVec3;

use crate::feet::{Feet, Foot, foot_points};
use crate::signals::STANDARD_GRAVITY_CM_PER_S2;
use crate::skeleton::Poses;

/// Parameters of the contact method. The defaults are physical quantities,
/// not fitted to any recording.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactParams {
    /// A foot comes down when its lowest point is within this height of the
    /// floor: a sole's thickness plus the centimetre or so that tracking
    /// noise moves a planted foot.
    pub touch_cm: f64,
    /// The stance foot stays down until it is this high (hysteresis, so
    /// noise near `touch_cm` does not flicker the decision).
    pub lift_cm: f64,
    /// Two low feet whose implied hips velocities differ by more than this
    /// are not both planted. Walking speed is ~130 cm/s and a foot in swing
    /// moves at twice that; 25 cm/s is well below both and well above noise.
    pub slip_cm_per_s: f64,
    /// Flight needs the ballistic path to keep the feet at least this far
    /// above the floor, so a fast squat's few millimetres of tracking noise
    /// never look like a jump.
    pub flight_margin_cm: f64,
    /// The take-off velocity is the hips' mean velocity over this long before
    /// take-off (a running stride's push-off lasts about a tenth of a second).
    pub takeoff_window_s: f64,
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            touch_cm: 2.5,
            lift_cm: 5.0,
            slip_cm_per_s: 25.0,
            flight_margin_cm: 1.0,
            takeoff_window_s: 0.1,
        }
    }
}

/// Which feet are on the floor in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Support {
    Single(Foot),
    /// Both feet planted (they agree); the hips follow their mean.
    Double,
    /// Neither foot on the floor: ballistic.
    Flight,
}

/// What the contact method decided, frame by frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactResult {
    /// Added to every joint of frame `f` (cm).
    pub shift_cm: Vec<DVec3>,
    pub support: Vec<Support>,
    /// Per foot `[left, right]`: the joint of that foot nearest the floor.
    pub contact_joint: [Vec<usize>; 2],
    /// Per foot: the height of its lowest point above the floor (cm), as
    /// corrected. Zero for a foot on the floor.
    pub clearance_cm: [Vec<f64>; 2],
    /// The floor's height in the recording's coordinates (cm): where the
    /// corrected recording puts its lowest foot points.
    pub ground_cm: f64,
    pub warnings: Vec<String>,
}

/// Median of a non-empty slice (sorted copy; NaNs last).
fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn horizontal(v: DVec3) -> DVec3 {
    DVec3::new(v.x, 0.0, v.z)
}

/// Runs the contact method on global joint positions `poses` (Y up, cm).
/// `parents` gives the foot points below each foot joint; `hips` is the joint
/// whose path is rebuilt; `foot_accel_g` are accelerometer magnitudes
/// `[left, right]` in g when the suit recorded them.
pub fn contact_translation(
    poses: &Poses,
    parents: &[Option<usize>],
    feet: Feet,
    hips: usize,
    foot_accel_g: Option<[&[f64]; 2]>,
    fps: f64,
    params: &ContactParams,
) -> Result<ContactResult, String> {
    let n = poses.frame_count();
    if n == 0 {
        return Err("the recording has no frames".into());
    }
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("the frame rate must be positive, not {fps}"));
    }
    let dt = 1.0 / fps;
    let points: [Vec<usize>; 2] = [foot_points(parents, feet.left), foot_points(parents, feet.right)];
    let relative = |f: usize, j: usize| poses.at(f, j) - poses.at(f, hips);

    // Floor offsets: each foot point's height above the lowest point of its
    // foot, in the frames where that foot is the lower one; the median is its
    // height in a foot standing flat.
    let lowest: [Vec<f64>; 2] = [0, 1].map(|side| {
        (0..n).map(|f| points[side].iter().map(|&j| relative(f, j).y).fold(f64::INFINITY, f64::min)).collect()
    });
    let offsets: [Vec<f64>; 2] = [0, 1].map(|side| {
        points[side]
            .iter()
            .map(|&j| {
                let heights: Vec<f64> = (0..n)
                    .filter(|&f| lowest[side][f] <= lowest[1 - side][f])
                    .map(|f| relative(f, j).y - lowest[side][f])
                    .collect();
                median(&heights)
            })
            .collect()
    });
    // Per frame and foot: the lowest point after offsets, relative to the hips.
    let mut low = [vec![0.0; n], vec![0.0; n]];
    let mut contact_joint = [vec![feet.left; n], vec![feet.right; n]];
    for f in 0..n {
        for side in 0..2 {
            let (joint, height) = points[side]
                .iter()
                .zip(&offsets[side])
                .map(|(&j, &o)| (j, relative(f, j).y - o))
                .fold((points[side][0], f64::INFINITY), |best, c| if c.1 < best.1 { c } else { best });
            low[side][f] = height;
            contact_joint[side][f] = joint;
        }
    }

    // Vertical: the hips' height above the floor with the lowest point down
    // (`pinned`), unless that would fall faster than gravity allows: flight.
    let g = STANDARD_GRAVITY_CM_PER_S2;
    let pinned: Vec<f64> = (0..n).map(|f| -low[0][f].min(low[1][f])).collect();
    // Vertical velocity over 30 ms: one frame at 30 fps, three at 100 Hz.
    let velocity_frames = ((0.03 * fps).round() as usize).max(1);
    let mut height = vec![pinned[0]; n];
    let mut flight = vec![false; n];
    let mut vertical_velocity = 0.0;
    for f in 1..n {
        let ballistic = height[f - 1] + vertical_velocity * dt - 0.5 * g * dt * dt;
        if ballistic > pinned[f] + params.flight_margin_cm {
            flight[f] = true;
            height[f] = ballistic;
            vertical_velocity -= g * dt;
        } else {
            height[f] = pinned[f];
            let back = f.saturating_sub(velocity_frames);
            vertical_velocity = (height[f] - height[back]) / ((f - back) as f64 * dt);
        }
    }
    let clearance_cm: [Vec<f64>; 2] = [0, 1].map(|side| (0..n).map(|f| height[f] + low[side][f]).collect());

    // Horizontal: integrate the hips' displacement from the planted feet.
    let calm_g = |side: usize, f: usize| -> f64 {
        foot_accel_g.and_then(|a| a[side].get(f).copied()).map_or(0.0, |a| (a - 1.0).abs())
    };
    let takeoff_frames = ((params.takeoff_window_s * fps).round() as usize).max(1);
    let mut support = vec![Support::Flight; n];
    let mut path = vec![horizontal(poses.at(0, hips)); n];
    let mut step = vec![DVec3::ZERO; n]; // hips displacement from f - 1 to f
    // Which feet were planted in the previous frame: they stay down up to
    // `lift_cm`, the others come down at `touch_cm`.
    let mut was_down = [false; 2];
    let mut takeoff_velocity = DVec3::ZERO;
    for f in 0..n {
        let down: Vec<usize> = (0..2)
            .filter(|&side| {
                let limit = if was_down[side] { params.lift_cm } else { params.touch_cm };
                !flight[f] && clearance_cm[side][f] <= limit
            })
            .collect();
        // The displacement from f - 1 to f implied by keeping a foot's contact
        // point (as chosen at f - 1) where it was.
        let implied = |side: usize| -> DVec3 {
            let j = contact_joint[side][f - 1];
            -horizontal(relative(f, j) - relative(f - 1, j))
        };
        let previous = if f >= 2 { step[f - 1] } else { DVec3::ZERO };
        let (chosen, displacement) = match down.as_slice() {
            [] => {
                if was_down != [false; 2] || f == 0 {
                    // Take-off: the mean velocity of the last strides on the floor.
                    let back = f.saturating_sub(takeoff_frames);
                    takeoff_velocity = if f > back {
                        (path[f - 1] - path[back]) / ((f - 1 - back).max(1) as f64)
                    } else {
                        DVec3::ZERO
                    };
                }
                (Support::Flight, takeoff_velocity)
            }
            _ if f == 0 => {
                let side = if low[0][0] <= low[1][0] { 0 } else { 1 };
                (Support::Single(foot(side)), DVec3::ZERO)
            }
            [side] => (Support::Single(foot(*side)), implied(*side)),
            _ => {
                let (left, right) = (implied(0), implied(1));
                if (left - right).length() <= params.slip_cm_per_s * dt {
                    (Support::Double, (left + right) * 0.5)
                } else {
                    // One foot slides: follow the one that agrees with the
                    // body's motion so far (and, with accelerometers, reads
                    // nearer 1 g, as a still foot does). 50 cm/s per g of
                    // disagreement weighs a clearly shaking foot like a
                    // clearly sliding one.
                    let score = |side: usize, d: DVec3| (d - previous).length() / dt + 50.0 * calm_g(side, f);
                    if score(0, left) <= score(1, right) {
                        (Support::Single(Foot::Left), left)
                    } else {
                        (Support::Single(Foot::Right), right)
                    }
                }
            }
        };
        support[f] = chosen;
        was_down = match chosen {
            Support::Single(Foot::Left) => [true, false],
            Support::Single(Foot::Right) => [false, true],
            Support::Double => [true, true],
            Support::Flight => [false, false],
        };
        if f > 0 {
            step[f] = displacement;
            path[f] = path[f - 1] + displacement;
        }
    }

    // The floor in the recording's coordinates: where its lowest foot points
    // sit in most frames, so a vendor's roughly right vertical is kept and a
    // frozen one gets a sensible level. Frame 0 alone would let one
    // mis-tracked frame shift the whole recording.
    let ground_cm = median(&(0..n).map(|f| poses.at(f, hips).y - pinned[f]).collect::<Vec<_>>());
    let shift_cm = (0..n)
        .map(|f| {
            let hips_now = poses.at(f, hips);
            DVec3::new(path[f].x - hips_now.x, ground_cm + height[f] - hips_now.y, path[f].z - hips_now.z)
        })
        .collect();
    let mut warnings = Vec::new();
    let flight_frames = flight.iter().filter(|&&x| x).count();
    if flight_frames * 5 > n {
        warnings.push(format!(
            "{:.0}% of the frames are in flight; check that the feet are right and Y is up",
            100.0 * flight_frames as f64 / n as f64
        ));
    }
    Ok(ContactResult { shift_cm, support, contact_joint, clearance_cm, ground_cm, warnings })
}

fn foot(side: usize) -> Foot {
    if side == 0 { Foot::Left } else { Foot::Right }
}
