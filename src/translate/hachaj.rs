//! Hachaj & Ogiela's translation method, as the authors' R code
//! (`RMoCap::calculate.kinematic`) computes it — the code, not the paper's
//! pseudocode, is the reference, and `Smoothing::Faithful` reproduces it to
//! rounding error on their Heian Shodan recording.
//!
//! The idea: the foot whose accelerometer reads less is standing, so it must
//! not move. Three passes, each producing a per-frame shift added to every
//! joint:
//! 1. For each transition `f-1 → f` where the smoothed acceleration magnitude
//!    of one foot is above the other's in both frames, the other (calmer) foot
//!    is pinned: everything from frame `f` on is moved back by that foot's
//!    displacement over the transition.
//! 2. The same on the smoothed foot heights after pass 1 (the lower foot is
//!    pinned), only where the heights differ by more than `dy_eps_cm`.
//! 3. Each frame is moved vertically so that the lower foot (by the smoothed
//!    heights of pass 2, i.e. after pass 1 and before pass 2) sits at the
//!    ground height, which is the right foot's height in the first frame.
//!
//! R's `correctMe3D` subtracts the displacement from all later rows, which is
//! O(frames²); since both rows of a transition already carry the same
//! accumulated shift when it runs, the displacement it sees is the input's
//! (pass 1) or the pass-1-corrected one (pass 2), so a running sum does the
//! same in O(frames).

use glam::DVec3;

use crate::body::feet::{Foot, FootJoints, PerFoot};
use crate::body::skeleton::Poses;
use crate::signal::smoothing::{smooth_gaussian_clean, smooth_r_gaussian};

/// How the foot signals are smoothed. (The wasm build derives its
/// TypeScript type for the page's settings.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
#[serde(rename_all = "lowercase")]
pub enum Smoothing {
    /// R `smoother::smth.gaussian` exactly as RMoCap calls it: the window is a
    /// fraction of the recording, and the first and last half window are set
    /// to 0 — so no foot is pinned there and the left foot is taken as the
    /// grounded one.
    Faithful,
    /// The same Gaussian, centred, renormalised at the ends instead of zeroed
    /// ([`smooth_gaussian_clean`]), so the method also works in the first and
    /// last half window.
    Clean,
}

/// Parameters of [`hachaj_translation`]; the defaults are RMoCap's.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct HachajParams {
    /// Length of the Gaussian smoothing window, in seconds (RMoCap: 100 frames at 100 Hz).
    pub window_s: f64,
    /// Pass 2 pins a foot only where the smoothed foot heights differ by more than this.
    pub dy_eps_cm: f64,
    /// Breadth of the Gaussian: its standard deviation is `window / (2 alpha)`.
    pub alpha: f64,
    pub smoothing: Smoothing,
    /// The floor height the grounded foot is moved to; `None` takes the right
    /// foot's height in the first frame, as RMoCap does.
    pub ground_cm: Option<f64>,
}

impl Default for HachajParams {
    fn default() -> Self {
        HachajParams {
            window_s: 1.0,
            dy_eps_cm: 5.0,
            alpha: 2.5,
            smoothing: Smoothing::Faithful,
            ground_cm: None,
        }
    }
}

/// What [`hachaj_translation`] computed. Per-frame vectors have one entry per
/// frame.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct HachajResult {
    /// The translation to add to every joint of each frame (all three passes).
    pub shift_cm: Vec<DVec3>,
    /// Smoothed accelerometer magnitudes of the feet (pass 1's signal).
    pub accel_smoothed_g: PerFoot<Vec<f64>>,
    /// Smoothed foot heights after pass 1 (the signal of passes 2 and 3).
    pub heights_smoothed_cm: PerFoot<Vec<f64>>,
    /// `pass1_pinned[f]`: the foot held still over the transition from frame
    /// `f - 1` to `f` by pass 1 (`None` for frame 0 and unpinned transitions).
    pub pass1_pinned: Vec<Option<Foot>>,
    /// The same for pass 2.
    pub pass2_pinned: Vec<Option<Foot>>,
    /// The foot put on the ground in each frame by pass 3.
    pub ground_foot: Vec<Foot>,
    /// The ground height used by pass 3.
    pub ground_cm: f64,
    /// Pass 3's vertical shift of each frame (already included in `shift_cm`).
    pub ground_shift_cm: Vec<f64>,
    /// What the method had to adapt (a window longer than the recording).
    pub warnings: Vec<String>,
}

/// Hachaj & Ogiela's translation (see the module documentation) of `poses`,
/// whose feet are `feet`, from the accelerometer magnitudes of the feet
/// `foot_accel_g` (in g, one per frame) recorded at `fps`.
///
/// In `Faithful` mode the window is `round(window_s · fps)` frames, passed to
/// R's smoother as the fraction `window / frames` as RMoCap does (so the
/// window may come out one frame shorter, as in R).
///
/// Errors when the lengths disagree, a foot index is out of range, a foot
/// position, acceleration or parameter is not finite, or the recording is too
/// short (`Faithful` needs 4 frames, `Clean` 2). A `Faithful` window longer
/// than the recording is shortened to half of it, with a warning.
pub fn hachaj_translation(
    poses: &Poses,
    feet: FootJoints,
    foot_accel_g: PerFoot<&[f64]>,
    fps: f64,
    params: &HachajParams,
) -> Result<HachajResult, String> {
    let n = poses.frame_count();
    check_inputs(poses, feet, foot_accel_g, fps, params)?;
    poses.check_positions()?;
    let paths = feet.map(|joint| poses.trajectory(joint));
    if let Some(f) = (0..n).find(|&f| !(paths.left[f].is_finite() && paths.right[f].is_finite())) {
        return Err(format!("a foot position in frame {f} is not a finite number"));
    }

    let mut warnings = Vec::new();
    let mut window_samples = params.window_s * fps;
    if params.smoothing == Smoothing::Faithful && n as f64 <= window_samples.round() {
        // R would turn `window / frames` (now ≥ 1) into a window of
        // trunc(window / frames) samples, which shrinks as the recording
        // grows shorter. Half the recording is the sensible stand-in: the
        // middle half can still be pinned between the zeroed tails.
        let shortened = (n / 2) as f64;
        warnings.push(format!(
            "the recording ({n} frames) is shorter than the {} s smoothing window ({} frames); using {shortened} frames",
            params.window_s,
            window_samples.round()
        ));
        window_samples = shortened;
    }
    let smooth = |x: &[f64]| -> Result<Vec<f64>, String> {
        match params.smoothing {
            Smoothing::Faithful => {
                // RMoCap's `window_size <- 100 / length(x)`, with 100 = 1 s at 100 Hz.
                smooth_r_gaussian(x, window_samples.round() / n as f64, params.alpha)
            }
            Smoothing::Clean => Ok(smooth_gaussian_clean(x, window_samples, params.alpha)),
        }
    };

    // Pass 1: pin the foot with the smaller smoothed acceleration.
    let accel_smoothed_g = PerFoot::new(smooth(foot_accel_g.left)?, smooth(foot_accel_g.right)?);
    let pass1_pinned = pinned_feet(&accel_smoothed_g, None);
    let zero = vec![DVec3::ZERO; n];
    let shift1 = pin_shifts(&paths, &zero, &pass1_pinned);

    // Pass 2: pin the lower foot, judged on the heights after pass 1.
    let heights =
        paths.as_ref().map(|path| path.iter().zip(&shift1).map(|(p, s)| p.y + s.y).collect::<Vec<f64>>());
    let heights_smoothed_cm = PerFoot::new(smooth(&heights.left)?, smooth(&heights.right)?);
    let pass2_pinned = pinned_feet(&heights_smoothed_cm, Some(params.dy_eps_cm));
    let shift2 = pin_shifts(&paths, &shift1, &pass2_pinned);

    // Pass 3: put the lower foot on the ground. RMoCap reads the ground from
    // the right foot's first frame, which passes 1 and 2 never move.
    let total: Vec<DVec3> = shift1.iter().zip(&shift2).map(|(a, b)| *a + *b).collect();
    let ground_cm = params.ground_cm.unwrap_or(paths.right[0].y + total[0].y);
    let PerFoot { left: left_z, right: right_z } = &heights_smoothed_cm;
    let mut ground_foot = Vec::with_capacity(n);
    let mut ground_shift_cm = Vec::with_capacity(n);
    let mut shift_cm = Vec::with_capacity(n);
    for f in 0..n {
        // `>=`: where both smoothed heights are 0 (R's tails) the left foot is grounded.
        let foot = if right_z[f] >= left_z[f] { Foot::Left } else { Foot::Right };
        let foot_y_cm = paths[foot][f].y + total[f].y;
        let dy_cm = -(foot_y_cm - ground_cm);
        ground_foot.push(foot);
        ground_shift_cm.push(dy_cm);
        shift_cm.push(total[f] + DVec3::new(0.0, dy_cm, 0.0));
    }

    Ok(HachajResult {
        shift_cm,
        accel_smoothed_g,
        heights_smoothed_cm,
        pass1_pinned,
        pass2_pinned,
        ground_foot,
        ground_cm,
        ground_shift_cm,
        warnings,
    })
}

fn check_inputs(
    poses: &Poses,
    feet: FootJoints,
    foot_accel_g: PerFoot<&[f64]>,
    fps: f64,
    params: &HachajParams,
) -> Result<(), String> {
    let n = poses.frame_count();
    for (foot, &joint) in feet.iter() {
        let side = foot.name();
        if joint >= poses.joint_count {
            return Err(format!(
                "the {side} foot is joint {joint}, but there are only {} joints",
                poses.joint_count
            ));
        }
    }
    for (foot, accel) in foot_accel_g.iter() {
        let side = foot.name();
        if accel.len() != n {
            return Err(format!(
                "expected one {side}-foot acceleration per frame ({n}), found {}",
                accel.len()
            ));
        }
        if let Some(f) = accel.iter().position(|a| !a.is_finite()) {
            return Err(format!("the {side}-foot acceleration in frame {f} is not a finite number"));
        }
    }
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("expected a positive frame rate, found {fps} fps"));
    }
    if !(params.window_s.is_finite() && params.window_s > 0.0) {
        return Err(format!("expected a positive smoothing window, found {} s", params.window_s));
    }
    if !(params.alpha.is_finite() && params.alpha > 0.0) {
        return Err(format!("expected a positive Gaussian alpha, found {}", params.alpha));
    }
    if !params.dy_eps_cm.is_finite() {
        return Err(format!("expected a finite height threshold, found {} cm", params.dy_eps_cm));
    }
    if let Some(g) = params.ground_cm.filter(|g| !g.is_finite()) {
        return Err(format!("expected a finite ground height, found {g} cm"));
    }
    match params.smoothing {
        Smoothing::Faithful => {
            let window = (params.window_s * fps).round();
            if window < 1.0 {
                return Err(format!(
                    "a smoothing window of {} s at {fps} fps is less than one frame",
                    params.window_s
                ));
            }
            if n < 4 {
                return Err(format!("expected at least 4 frames, found {n}"));
            }
        }
        Smoothing::Clean => {
            if n < 2 {
                return Err(format!("expected at least 2 frames, found {n}"));
            }
        }
    }
    Ok(())
}

/// Which foot RMoCap pins over each transition `f-1 → f` given smoothed
/// signals: the one whose signal is lower in both frames
/// (strictly; ties pin nothing). With `min_gap`, only transitions where the
/// signals differ by more than it in frame `f-1` count (pass 2's `dyEps`).
fn pinned_feet(signals: &PerFoot<Vec<f64>>, min_gap: Option<f64>) -> Vec<Option<Foot>> {
    let PerFoot { left, right } = signals;
    let n = left.len();
    let mut pinned = vec![None; n];
    for f in 1..n {
        let a = f - 1;
        if let Some(gap) = min_gap
            && (right[a] - left[a]).abs() <= gap
        {
            continue;
        }
        pinned[f] = if right[a] > left[a] && right[f] > left[f] {
            Some(Foot::Left)
        } else if right[a] < left[a] && right[f] < left[f] {
            Some(Foot::Right)
        } else {
            None
        };
    }
    pinned
}

/// The cumulative shift one pinning pass adds: at each pinned transition
/// `f-1 → f`, every frame from `f` on moves back by the pinned foot's
/// displacement over it, measured on the foot `paths` already moved by
/// `before` and by this pass so far (as R's `correctMe3D` sees them).
fn pin_shifts(paths: &PerFoot<Vec<DVec3>>, before: &[DVec3], pinned: &[Option<Foot>]) -> Vec<DVec3> {
    let mut shift = DVec3::ZERO;
    let mut out = Vec::with_capacity(pinned.len());
    for (f, pin) in pinned.iter().enumerate() {
        if let Some(foot) = pin {
            let path = &paths[*foot];
            let from = path[f - 1] + before[f - 1] + shift;
            let to = path[f] + before[f] + shift;
            shift -= to - from;
        }
        out.push(shift);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two feet (joints 0 and 1) and the hips (joint 2) over `n` frames.
    fn walk(n: usize, left: impl Fn(usize) -> DVec3, right: impl Fn(usize) -> DVec3) -> Poses {
        let mut positions_cm = Vec::new();
        for f in 0..n {
            let (l, r) = (left(f), right(f));
            positions_cm.extend([l, r, (l + r) / 2.0 + DVec3::new(0.0, 90.0, 0.0)]);
        }
        Poses { joint_count: 3, positions_cm }
    }

    const FEET: FootJoints = FootJoints { left: 0, right: 1 };

    #[test]
    fn a_sliding_body_with_a_calm_left_foot_is_held_still() {
        // The whole body drifts along X; the right foot shakes (high accel),
        // so the left foot is pinned and the drift is cancelled.
        let n = 400;
        let drift = |f: usize| DVec3::new(f as f64 * 0.5, 0.0, 0.0);
        let poses = walk(n, drift, |f| drift(f) + DVec3::new(20.0, 10.0, 0.0));
        let left = vec![1.0; n];
        let right = vec![1.5; n];
        let params = HachajParams { smoothing: Smoothing::Clean, ..Default::default() };
        let result =
            hachaj_translation(&poses, FEET, PerFoot::new(&left[..], &right[..]), 100.0, &params).unwrap();
        assert!(result.pass1_pinned[1..].iter().all(|&p| p == Some(Foot::Left)));
        let moved = poses.shifted(&result.shift_cm);
        for f in 0..n {
            assert!((moved.at(f, 0) - moved.at(0, 0)).length() < 1e-9);
        }
        // Pass 3 grounds the lower (left) foot at the right foot's first height.
        assert_eq!(result.ground_cm, 10.0);
        assert!(result.ground_foot.iter().all(|&g| g == Foot::Left));
        assert!((moved.at(n - 1, 0).y - 10.0).abs() < 1e-9);
    }

    #[test]
    fn faithful_mode_leaves_the_tails_unpinned() {
        let n = 300;
        let poses = walk(n, |f| DVec3::new(f as f64, 0.0, 0.0), |_| DVec3::new(0.0, 10.0, 0.0));
        let left = vec![1.0; n];
        let right = vec![1.5; n];
        let result = hachaj_translation(
            &poses,
            FEET,
            PerFoot::new(&left[..], &right[..]),
            100.0,
            &HachajParams::default(),
        )
        .unwrap();
        assert!(result.pass1_pinned[..51].iter().all(Option::is_none));
        assert!(result.pass1_pinned[51..250].iter().all(|&p| p == Some(Foot::Left)));
        assert!(result.pass1_pinned[250..].iter().all(Option::is_none));
        assert_eq!(result.accel_smoothed_g.left[0], 0.0);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let n = 300;
        let poses = walk(n, |_| DVec3::ZERO, |_| DVec3::ZERO);
        let ok = vec![1.0; n];
        let p = HachajParams::default();
        assert!(hachaj_translation(&poses, FEET, PerFoot::new(&ok[..], &ok[1..]), 100.0, &p).is_err());
        assert!(
            hachaj_translation(
                &poses,
                FootJoints { left: 0, right: 7 },
                PerFoot::new(&ok[..], &ok[..]),
                100.0,
                &p
            )
            .is_err()
        );
        let mut nan = ok.clone();
        nan[5] = f64::NAN;
        assert!(hachaj_translation(&poses, FEET, PerFoot::new(&ok[..], &nan[..]), 100.0, &p).is_err());
        assert!(hachaj_translation(&poses, FEET, PerFoot::new(&ok[..], &ok[..]), 0.0, &p).is_err());
        // 300 frames at 400 fps is shorter than the 400-frame window: the
        // window is halved to fit, and the result says so.
        let short = hachaj_translation(&poses, FEET, PerFoot::new(&ok[..], &ok[..]), 400.0, &p).unwrap();
        assert!(short.warnings[0].contains("using 150 frames"), "{:?}", short.warnings);
        let three = walk(3, |_| DVec3::ZERO, |_| DVec3::ZERO);
        assert!(hachaj_translation(&three, FEET, PerFoot::new(&ok[..3], &ok[..3]), 100.0, &p).is_err());
        let clean = HachajParams { smoothing: Smoothing::Clean, ..p };
        assert!(hachaj_translation(&poses, FEET, PerFoot::new(&ok[..], &ok[..]), 400.0, &clean).is_ok());
        let mut bad_pose = poses.clone();
        bad_pose.positions_cm[3] = DVec3::new(f64::INFINITY, 0.0, 0.0);
        assert!(hachaj_translation(&bad_pose, FEET, PerFoot::new(&ok[..], &ok[..]), 100.0, &p).is_err());
    }
}
