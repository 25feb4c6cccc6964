//! The contact method: the translation from the feet's contacts with the
//! floor, with flight.
//!
//! The body's joint positions relative to its hips are what an inertial suit
//! measures well; where the hips are is what it guesses. This method throws
//! the guess away and rebuilds it from physical facts:
//!
//! 1. **A foot on the floor does not slide.** The foot rolls — lands on the
//!    heel, stands flat, pushes off over the toes — and the point it rolls
//!    over stays put. The candidates are the points of the sole
//!    ([`crate::body::sole`]): a virtual heel, the sole under the ankle, the sole
//!    under the toes, at a depth below the joints that is estimated per
//!    recording.
//! 2. **The floor pushes the centre of mass.** Of all the ways to pin one
//!    sole point (or both feet) in each frame, the method takes the one
//!    sequence over the whole recording along which the centre of mass's
//!    changes of velocity are best explained by the floor pushing it from the
//!    pinned foot (the inverted pendulum, `pressure.rs`), solved exactly by
//!    dynamic programming (`solve.rs`). Where no foot explains the motion — in
//!    the air, or while one foot slides in as the other slides out — the
//!    centre of mass *coasts*: it keeps its horizontal velocity, as in flight
//!    it must.
//! 3. **The floor pushes but never pulls.** The hips' height puts the lowest
//!    sole point on the floor. Over a coasting stretch the centre of mass
//!    follows the parabola that gravity gives between take-off and landing;
//!    where that lifts both feet off the floor, and the body was thrown up
//!    into it, it is a flight (`flight.rs`), and no foot ever goes below the
//!    floor.
//!
//! An inertial suit's pose is noisy: a centimetre of noise on a foot
//! relative to the hips is tens of cm/s of velocity at 30 fps. The noise is
//! measured on the recording (`noise.rs`) and smoothed away before the
//! contacts are chosen, over the least time that brings it below what the
//! choice weighs, and wider where a kick or a swing makes it burst; a clean
//! optical pose is not smoothed. Where a noisy pose's body barely
//! progresses, a coast would carry that noise, not a momentum: coasting
//! costs more there and the contacts are chosen a second time; and where
//! it barely moves, its hips are held still against the noise and, where
//! both feet stand, against the legs' drift their distance apart reads
//! (`still.rs`).
//! Elsewhere a noisy pose's coast carries its smoothed velocity scaled by
//! how much faster the stances around it end, read unsmoothed (`carry.rs`),
//! and a double support, whose mean of two feet carries less of the noise,
//! pays for its feet moving apart beyond it: one of them slides
//! (`solve.rs`).
//!
//! Everything is in seconds and centimetres ([`ContactParams`]), and the
//! costs are integrals over time. The contacts are chosen on frames about
//! 1/30 s apart, once for each way of taking them, and the paths averaged
//! (`grid.rs`), so that a jump of velocity, where the pinned point changes,
//! weighs about what it weighs at 30 fps at any rate. The cost is
//! O(frames × sole points²) per sole depth tried (twice on a noisy pose
//! that stays in place somewhere), plus O(frames × step) to bring the grids
//! back to every frame. Measured figures and the method's
//! history are in `docs/contact.md`.

mod carry;
mod flight;
mod footing;
mod grid;
mod noise;
mod params;
mod pressure;
mod solve;
mod still;

use glam::DVec3;

pub use params::{ContactParams, MAX_SOLE_DEPTH_CM, SOLE_DEPTHS_CM};

use crate::body::com::hips_to_com_cm;
use crate::body::feet::{Foot, FootJoints, PerFoot};
use crate::body::skeleton::Poses;
use crate::body::sole::{FootShape, Sole, SolePart, foot_shapes};
use crate::signal::smoothing::smooth_paths;
use crate::signal::stats::upper_median;
use carry::StanceExit;
use footing::{Candidate, Footing};
use grid::{Grid, Motion, PhaseChoice, Vertical};

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
    /// Per foot: the part of the sole pinned while that foot is down, else
    /// the part nearest the floor.
    pub contact_part: PerFoot<Vec<SolePart>>,
    /// Per foot: the height of its lowest sole point above the floor (cm),
    /// as corrected. Zero for the lower foot on the floor; the other foot's
    /// lowest point may stand a little above it even while pinned.
    pub clearance_cm: PerFoot<Vec<f64>>,
    /// The floor's height in the recording's coordinates (cm): where the
    /// corrected recording puts its lowest foot points.
    pub ground_cm: f64,
    /// The tracking noise measured on the pose (cm, per axis, of the feet
    /// relative to the hips; see `noise`): what the choice of contacts was
    /// smoothed for.
    pub pose_noise_cm: f64,
    /// The sole depth used (cm), as given or as estimated; `None` where it
    /// does not apply (feet without toes: their ankles are pinned).
    pub sole_depth_cm: Option<f64>,
    pub warnings: Vec<String>,
}

fn horizontal(v: DVec3) -> DVec3 {
    DVec3::new(v.x, 0.0, v.z)
}

/// Runs the contact method on global joint positions `poses` (Y up, cm).
/// `parents` gives the foot points below each foot joint; `hips` is the joint
/// whose path is rebuilt; `foot_accel_g` are the feet's accelerometer
/// magnitudes in g when the suit recorded them.
pub fn contact_translation(
    poses: &Poses,
    parents: &[Option<usize>],
    feet: FootJoints,
    hips: usize,
    foot_accel_g: Option<PerFoot<&[f64]>>,
    fps: f64,
    params: &ContactParams,
) -> Result<ContactResult, String> {
    let n = poses.frame_count();
    check_input(poses, fps, params)?;
    let dt = 1.0 / fps;
    let step = grid::grid_step(fps, params.cost_time_s);
    let pose_noise = noise::pose_noise(poses, feet, hips, step);
    let noise_cm = pose_noise.cm;
    let mut grid = Grid::new(n, fps, noise_cm, params);
    // Where a kick or a swing makes the noise burst (only where the fourth
    // differences read noise: on a clean pose they are motion).
    if pose_noise.reads_noise {
        let half_window = (params.noise_window_s * fps).round() as usize;
        let local_noise_cm = noise::local_noise_cm(poses, feet, hips, step, half_window);
        grid.widen_where_noise_bursts(&local_noise_cm, noise_cm, fps, params);
    }
    let mut motion = Motion {
        hips_to_com_cm: grid.smooth_for_choice(&hips_to_com_cm(poses, parents, feet, hips), 1),
        accel_off_g: accel_off_g(foot_accel_g, n),
        dt,
        open_start: grid.moves_measured_apart(),
        in_place: vec![false; n],
    };
    let shapes = foot_shapes(poses, parents, feet, hips);
    let has_toes = shapes.left.has_toes() || shapes.right.has_toes();
    let (mut sole_depth_cm, mut soles, mut choices) =
        choose_sole_depth(&shapes, has_toes, &grid, &motion, params)?;
    grid.start_from_what_follows(&mut choices, &soles, &motion, params);
    // Where a noisy pose's body stays in place, it does not coast (see
    // `still::in_place`), read from the path these contacts give; chosen
    // again if it is anywhere. A clean pose's coasts carry the body's own
    // velocity.
    if pose_noise.reads_noise {
        let footing = Footing::new(shapes.as_ref().map(|shape| shape.sole(sole_depth_cm)));
        let path = grid.hips_path(&footing, &choices, horizontal(poses.at(0, hips)), dt, None);
        let hips_cm = upper_median(&footing.lowest.standing_cm);
        motion.in_place = still::in_place(&path, hips_cm, dt, params);
        if motion.in_place.contains(&true) {
            (sole_depth_cm, soles, choices) = choose_sole_depth(&shapes, has_toes, &grid, &motion, params)?;
            grid.start_from_what_follows(&mut choices, &soles, &motion, params);
        }
    }

    // Back to every frame, on the unsmoothed soles.
    let footing = Footing::new(shapes.as_ref().map(|shape| shape.sole(sole_depth_cm)));
    // A pinned point holds still, so the pose's noise relative to the hips
    // lands in the hips' path; a body's hips do not shake at that scale. On
    // a noisy pose, nor below the grid's spacing, where no contact was
    // chosen: above 30 fps the path is built from every frame's pinned
    // velocity, and its frame-to-frame jitter made the 100 Hz demo's path
    // 1.8 times the truth's; smoothed as the contacts were chosen, 1.1. (A
    // clean pose's pinned points are exact: smoothed, its feet would slide.)
    let noisy = pose_noise.reads_noise;
    let sigma_samples = if noisy { grid.sigma_samples } else { grid.noise_sigma_samples };
    // A noisy pose's coasts carry the smoothed velocity by as much as the
    // stances around end faster than it (`carry.rs`).
    let exit = noisy.then(|| StanceExit {
        hips_to_com_cm: &motion.hips_to_com_cm,
        in_place: &motion.in_place,
        min_stance_frames: (params.min_carried_stance_s * fps).round() as usize,
        min_com_height_cm: params.min_com_height_cm,
        window_frames: params.carry_window_s * fps,
    });
    let path = smooth_paths(
        &grid.hips_path(&footing, &choices, horizontal(poses.at(0, hips)), dt, exit.as_ref()),
        1,
        sigma_samples,
    );
    // And where the body barely moves beside that noise, further: its steps
    // would otherwise lengthen a standing body's path several times. A
    // standing body's path wanders with the noise over tenths of a second,
    // where noise correlated over a few frames is at its full size: the
    // reading on frames twice as far apart.
    // Where both feet stand in place, their distance apart reads the legs'
    // drift, which the fourth differences do not see.
    let path = if noisy {
        still::hold_still(
            &path,
            pose_noise.wander_cm(),
            sigma_samples,
            dt,
            params.still_noise_share,
            params.max_still_smoothing_s,
            Some(&still::FeetApart::of(&footing, &motion.in_place, params.touch_cm)),
        )
    } else {
        path
    };
    let vertical = grid.vertical(&footing.lowest.standing_cm, &choices, params);
    let decisions = grid.decisions(&choices, n);
    let support = (0..n).map(|f| support(decisions[f], vertical.flight[f], &footing, f)).collect();
    let contact_part =
        PerFoot::from_fn(|foot| (0..n).map(|f| footing.contact_part(decisions[f], foot, f)).collect());
    let clearance_cm = PerFoot::from_fn(|foot| {
        (0..n).map(|f| vertical.height_cm[f] + footing.lowest.height_cm[foot][f]).collect()
    });
    let ground_cm = ground_cm(poses, hips, &footing);
    let shift_cm = shift_cm(poses, hips, &path, &vertical, ground_cm);
    let warnings = flight_warnings(&vertical);
    let sole_depth_cm = has_toes.then_some(sole_depth_cm);
    Ok(ContactResult {
        shift_cm,
        support,
        contact_part,
        clearance_cm,
        ground_cm,
        pose_noise_cm: noise_cm,
        sole_depth_cm,
        warnings,
    })
}

/// An error when there is nothing to translate, the rate is no rate, a
/// parameter is out of its range, or a joint is no position.
fn check_input(poses: &Poses, fps: f64, params: &ContactParams) -> Result<(), String> {
    if poses.frame_count() == 0 {
        return Err("the recording has no frames".into());
    }
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("the frame rate must be positive, not {fps}"));
    }
    params.check()?;
    poses.check_positions()
}

/// Per foot and frame of `n`, how far its accelerometer reads from 1 g;
/// `None` without a reading.
fn accel_off_g(foot_accel_g: Option<PerFoot<&[f64]>>, n: usize) -> PerFoot<Vec<Option<f64>>> {
    PerFoot::from_fn(|foot| {
        (0..n).map(|f| foot_accel_g.and_then(|a| a[foot].get(f).copied()).map(|a| (a - 1.0).abs())).collect()
    })
}

/// The sole depth whose phases' best contacts cost least in all, its soles
/// (smoothed for the choice) and those contacts: the given depth, else each of [`SOLE_DEPTHS_CM`]. Ties keep the
/// shallower sole: where depth makes no difference (no foot rolls), the
/// joints themselves are the plainest answer. Feet without toes
/// (`has_toes` false) have no sole below their joints to place, so one depth
/// is tried.
fn choose_sole_depth(
    shapes: &PerFoot<FootShape>,
    has_toes: bool,
    grid: &Grid,
    motion: &Motion,
    params: &ContactParams,
) -> Result<(f64, PerFoot<Sole>, Vec<PhaseChoice>), String> {
    let depths = params.sole_depth_cm.map_or(SOLE_DEPTHS_CM.to_vec(), |depth| vec![depth]);
    let tried = if has_toes { depths.len() } else { 1 };
    let mut best: Option<(f64, f64, PerFoot<Sole>, Vec<PhaseChoice>)> = None;
    for sole_depth_cm in depths.into_iter().take(tried) {
        let soles = shapes.as_ref().map(|shape| {
            let sole = shape.sole(sole_depth_cm);
            Sole {
                hips_to_points_cm: grid.smooth_for_choice(&sole.hips_to_points_cm, sole.point_count()),
                ..sole
            }
        });
        let choices = grid.choose(&soles, motion, params);
        let cost = choices.iter().map(|c| c.solution.cost).sum::<f64>();
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, sole_depth_cm, soles, choices));
        }
    }
    best.map(|(_, sole_depth_cm, soles, choices)| (sole_depth_cm, soles, choices))
        .ok_or_else(|| "no sole depth to try".into())
}

/// Which feet are on the floor in frame `f` when `decision` holds there.
/// Coasting with a foot on the floor is sliding on it: the lower one.
fn support(decision: Candidate, flight: bool, footing: &Footing, f: usize) -> Support {
    match decision {
        Candidate::Point { foot, .. } => Support::Single(foot),
        Candidate::Double => Support::Double,
        Candidate::Coast if flight => Support::Flight,
        Candidate::Coast => Support::Single(footing.lowest.lower_foot(f)),
    }
}

/// The floor in the recording's coordinates: where its lowest foot points
/// sit in most frames, so a vendor's roughly right vertical is kept and a
/// frozen one gets a sensible level. Frame 0 alone would let one
/// mis-tracked frame shift the whole recording.
fn ground_cm(poses: &Poses, hips: usize, footing: &Footing) -> f64 {
    let standing_cm = &footing.lowest.standing_cm;
    upper_median(&(0..standing_cm.len()).map(|f| poses.at(f, hips).y - standing_cm[f]).collect::<Vec<_>>())
}

/// Per frame, what moves the hips from where the recording has them to the
/// horizontal `path` and `vertical.height_cm` above the floor at `ground_cm`.
fn shift_cm(poses: &Poses, hips: usize, path: &[DVec3], vertical: &Vertical, ground_cm: f64) -> Vec<DVec3> {
    (0..path.len())
        .map(|f| {
            let hips_now = poses.at(f, hips);
            DVec3::new(
                path[f].x - hips_now.x,
                ground_cm + vertical.height_cm[f] - hips_now.y,
                path[f].z - hips_now.z,
            )
        })
        .collect()
}

/// A warning when too many frames are in flight for a body on its feet: a
/// fast run is in the air up to about two thirds of the time, so more than
/// three quarters is not a body on its feet.
fn flight_warnings(vertical: &Vertical) -> Vec<String> {
    let n = vertical.flight.len();
    let flight_frames = vertical.flight.iter().filter(|&&x| x).count();
    if flight_frames * 4 > n * 3 {
        vec![format!(
            "{:.0}% of the frames are in flight; check that the feet are right and Y is up",
            100.0 * flight_frames as f64 / n as f64
        )]
    } else {
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;

    /// Hips (0), left ankle (1) and toe (2), right ankle (3) and toe (4).
    const PARENTS: [Option<usize>; 5] = [None, Some(0), Some(1), Some(0), Some(3)];
    const FEET: FootJoints = FootJoints { left: 1, right: 3 };
    /// 30 fps, where no jitter smoothing applies: these tests are about the
    /// choice of contacts, coasting and flight.
    const FPS: f64 = 30.0;

    /// A run along +Z at `speed` cm/s: 0.2 s on one foot (planted flat, the
    /// ankle 8 cm up and the toe 2 cm up, the hips dipping on the bent leg
    /// and thrown up again), then 0.15 s in the air with both feet 30 cm up
    /// and the hips on gravity's arc, then the other foot.
    /// Returns the poses and, per frame, whether the body is in the air.
    /// Without `pushed`, the hips glide level through the stance instead:
    /// no floor threw them up.
    fn run(frames: usize, speed: f64, pushed: bool) -> (Poses, Vec<bool>) {
        let (stance, flight) = (0.2, 0.15);
        let period = stance + flight;
        let g = STANDARD_GRAVITY_CM_PER_S2;
        let mut positions_cm = Vec::new();
        let mut airborne = Vec::new();
        for f in 0..frames {
            let t = f as f64 / FPS;
            let step = (t / period).floor();
            let in_step = t - step * period;
            let in_air = in_step >= stance;
            // The stance's dip, half a sine, lands and takes off at the
            // flight's vertical speed g · flight / 2.
            let dip = if pushed { g * flight / 2.0 * stance / std::f64::consts::PI } else { 0.0 };
            let hips_y = if in_air {
                90.0 + 0.5 * g * (in_step - stance) * (period - in_step)
            } else {
                90.0 - dip * (std::f64::consts::PI * in_step / stance).sin()
            };
            let hips = DVec3::new(0.0, hips_y, speed * t);
            let stance_foot = if (step as usize).is_multiple_of(2) { Foot::Left } else { Foot::Right };
            let plant_z = speed * (step * period + stance / 2.0);
            let foot = |foot: Foot| -> [DVec3; 2] {
                let x = if foot == Foot::Left { -10.0 } else { 10.0 };
                if foot == stance_foot && !in_air {
                    [DVec3::new(x, 8.0, plant_z), DVec3::new(x, 2.0, plant_z + 14.0)]
                } else {
                    let ankle = hips + DVec3::new(x, -60.0, 0.0);
                    [ankle, ankle + DVec3::new(0.0, -6.0, 14.0)]
                }
            };
            let ([la, lt], [ra, rt]) = (foot(Foot::Left), foot(Foot::Right));
            positions_cm.extend([hips, la, lt, ra, rt]);
            airborne.push(in_air);
        }
        (Poses { joint_count: 5, positions_cm }, airborne)
    }

    #[test]
    fn a_runner_keeps_its_speed_through_the_air() {
        // Within 2%: this synthetic body does not conserve momentum (a foot
        // leaving the floor jumps to its place in the air, which changes the
        // centre of mass's velocity by ~1.5% at every take-off).
        let (poses, airborne) = run(53, 300.0, true);
        let result =
            contact_translation(&poses, &PARENTS, FEET, 0, None, FPS, &ContactParams::default()).unwrap();
        let moved = poses.shifted(&result.shift_cm);
        let path = 300.0 * (poses.frame_count() - 1) as f64 / FPS;
        for f in 0..poses.frame_count() {
            let error = (moved.at(f, 0) - poses.at(f, 0)).with_y(0.0).length();
            assert!(error < 0.02 * path, "frame {f}: {error} cm off");
        }
        // The flights are flights (give or take the frame either side), and
        // the stances are not.
        let labelled = |f: usize| result.support[f] == Support::Flight;
        let flights = (1..airborne.len() - 1).filter(|&f| airborne[f - 1] && airborne[f] && airborne[f + 1]);
        assert!(flights.clone().all(labelled), "{:?}", result.support);
        let stances =
            (1..airborne.len() - 1).filter(|&f| !airborne[f - 1] && !airborne[f] && !airborne[f + 1]);
        assert!(!stances.clone().any(labelled), "{:?}", result.support);
        // In the air the body rises on gravity's arc, and nothing is below the floor.
        let floor = result.ground_cm;
        for f in 0..poses.frame_count() {
            let lowest = [1, 2, 3, 4].map(|j| moved.at(f, j).y).into_iter().fold(f64::INFINITY, f64::min);
            assert!(lowest > floor - 1e-6, "frame {f}: a foot at {lowest} below the floor {floor}");
        }
        assert!(flights.map(|f| moved.at(f, 0).y).fold(0.0, f64::max) > 90.0 + (floor - 2.0) + 2.0);
        // The hips' height is the true one, up to where the floor is put,
        // in the air and out of it, within the 3 mm that a take-off between
        // two frames costs the arc (it starts at the last frame on the
        // floor); the flight that runs off the recording's end is left out
        // (its arc is a guess, taken level).
        let off = |f: usize| moved.at(f, 0).y - poses.at(f, 0).y;
        let last_on_floor = airborne.iter().rposition(|&a| !a).unwrap_or(0);
        for f in 0..=last_on_floor {
            let wrong = off(f) - off(0);
            assert!(wrong.abs() < 0.35, "frame {f} ({:?}): hips {wrong} cm off", result.support[f]);
        }
    }

    #[test]
    fn a_body_that_nothing_threw_up_is_not_in_flight() {
        // The same strides with the hips level: the body coasts between the
        // feet (as in a kata's turn, where no foot holds still), but it was
        // not rising when it left the floor nor falling into the landing.
        let (poses, airborne) = run(53, 300.0, false);
        assert!(airborne.iter().any(|&a| a));
        let result =
            contact_translation(&poses, &PARENTS, FEET, 0, None, FPS, &ContactParams::default()).unwrap();
        assert!(result.support.iter().all(|s| *s != Support::Flight), "{:?}", result.support);
    }

    #[test]
    fn a_body_standing_still_stays_where_it_is() {
        let (mut poses, _) = run(1, 0.0, true);
        let frame = poses.positions_cm.clone();
        for _ in 0..99 {
            poses.positions_cm.extend_from_slice(&frame);
        }
        let result =
            contact_translation(&poses, &PARENTS, FEET, 0, None, FPS, &ContactParams::default()).unwrap();
        assert!(result.shift_cm.iter().all(|s| (*s - result.shift_cm[0]).length() < 1e-9));
        assert!(result.support.iter().all(|s| *s != Support::Flight));
        assert!(result.warnings.is_empty());
    }

    #[test]
    fn feet_without_toes_pin_their_ankles_and_have_no_sole_depth() {
        let frame = [DVec3::new(0.0, 90.0, 0.0), DVec3::new(-10.0, 8.0, 0.0), DVec3::new(10.0, 8.0, 0.0)];
        let poses = Poses { joint_count: 3, positions_cm: frame.repeat(10) };
        let parents = [None, Some(0), Some(0)];
        let feet = FootJoints { left: 1, right: 2 };
        let result =
            contact_translation(&poses, &parents, feet, 0, None, FPS, &ContactParams::default()).unwrap();
        assert_eq!(result.sole_depth_cm, None);
        assert!(result.shift_cm.iter().all(|s| (*s - result.shift_cm[0]).length() < 1e-9));
        let given = ContactParams { sole_depth_cm: Some(3.0), ..ContactParams::default() };
        assert_eq!(
            contact_translation(&poses, &parents, feet, 0, None, FPS, &given).unwrap().sole_depth_cm,
            None
        );
        let (toed, _) = run(10, 0.0, true);
        let result = contact_translation(&toed, &PARENTS, FEET, 0, None, FPS, &given).unwrap();
        assert_eq!(result.sole_depth_cm, Some(3.0));
    }

    #[test]
    fn bad_input_is_an_error() {
        let empty = Poses { joint_count: 5, positions_cm: Vec::new() };
        assert!(
            contact_translation(&empty, &PARENTS, FEET, 0, None, FPS, &ContactParams::default()).is_err()
        );
        let (poses, _) = run(10, 100.0, true);
        let error = contact_translation(&poses, &PARENTS, FEET, 0, None, 0.0, &ContactParams::default());
        assert!(error.unwrap_err().contains("frame rate"));
        for depth in [-1.0, f64::NAN, f64::INFINITY] {
            let params = ContactParams { sole_depth_cm: Some(depth), ..ContactParams::default() };
            let error = contact_translation(&poses, &PARENTS, FEET, 0, None, FPS, &params);
            assert!(error.unwrap_err().contains("sole depth"));
        }
        // A joint far off (finite, but its differences would not be) is an
        // error naming its frame, not a NaN written into the output.
        for far in [1.0e308, f64::NAN] {
            let mut broken = poses.clone();
            broken.positions_cm[3 * broken.joint_count] = DVec3::new(far, 0.0, 0.0);
            let error = contact_translation(&broken, &PARENTS, FEET, 0, None, FPS, &ContactParams::default());
            assert!(error.unwrap_err().contains("in frame 3"), "{far}");
        }
    }
}
