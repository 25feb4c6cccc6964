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
//!    pinned foot (the inverted pendulum), solved exactly by dynamic
//!    programming. Where no foot explains the motion — in the air, or while
//!    one foot slides in as the other slides out — the centre of mass
//!    *coasts*: it keeps its horizontal velocity, as in flight it must.
//! 3. **The floor pushes but never pulls.** The hips' height puts the lowest
//!    sole point on the floor. Over a coasting stretch the centre of mass
//!    follows the parabola that gravity gives between take-off and landing;
//!    where that lifts both feet off the floor, and the body was thrown up
//!    into it, it is a flight, and no foot ever goes below the floor.
//!
//! Everything is in seconds and centimetres, and the costs are integrals over
//! time. The contacts are chosen on frames about 1/30 s apart (every one at
//! 30 fps, every third at 100 Hz; step 2 from 45 fps), once for each way of
//! taking them, and the paths averaged ([`grid_step`]): a jump of velocity,
//! where the pinned point changes, weighs within a factor 1.5 of what it
//! weighs at 30 fps at any rate, where on every frame of a 100 Hz recording
//! it would weigh 3.3 times as much. Each grid's sequence is the exact
//! optimum; their average is not a sequence of its own. The cost is
//! O(frames × sole points²) per sole depth tried, plus O(frames × step) to
//! bring the grids back to every frame.

use glam::DVec3;

use crate::body::feet::{Foot, FootJoints, PerFoot, above_hips, foot_points};
use crate::body::skeleton::Poses;
use crate::body::sole::{Sole, SolePart, foot_shapes};
use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;
use crate::signal::smoothing::smooth_paths;
use crate::signal::stats::upper_median;

/// Parameters of the contact method. The defaults are physical quantities,
/// not fitted to any recording.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactParams {
    /// A sole point this high above the floor costs as much to pin as a
    /// velocity change of `slip_cm_per_s`: a sole's thickness plus the
    /// centimetre or so that tracking noise moves a planted foot.
    pub touch_cm: f64,
    /// A sole point higher than this is never pinned.
    pub lift_cm: f64,
    /// The unit of velocity change (cm/s) in the cost: a foot
    /// sliding this fast costs as much as a point `touch_cm` off the floor.
    /// Walking is ~130 cm/s and a swinging foot twice that; 25 cm/s is well
    /// below both and well above tracking noise.
    pub slip_cm_per_s: f64,
    /// A coasting stretch is a flight when gravity's arc lifts the feet at
    /// least this far above the floor, so a few millimetres of tracking
    /// noise never look like a jump.
    pub flight_margin_cm: f64,
    /// How far the sole lies below the foot's lowest joint when the foot
    /// stands flat ([`crate::body::sole`]); `None`: estimated from the recording,
    /// as the depth among [`SOLE_DEPTHS_CM`] whose best contacts fit the
    /// physics best.
    pub sole_depth_cm: Option<f64>,
}

impl ContactParams {
    /// An error when a parameter is out of its range: a sole depth, when
    /// given, is 0 to [`MAX_SOLE_DEPTH_CM`].
    pub fn check(&self) -> Result<(), String> {
        match self.sole_depth_cm {
            Some(depth) if !(0.0..=MAX_SOLE_DEPTH_CM).contains(&depth) => {
                Err(format!("the sole depth must be between 0 and {MAX_SOLE_DEPTH_CM} cm, not {depth}"))
            }
            _ => Ok(()),
        }
    }
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            touch_cm: 2.5,
            lift_cm: 5.0,
            slip_cm_per_s: 25.0,
            flight_margin_cm: 1.0,
            sole_depth_cm: None,
        }
    }
}

/// The sole depths (cm) tried when the recording does not say: a toe end
/// site marks the skin (0), a ball-of-foot joint centre sits 2–3 cm above the
/// skin, and a shoe adds up to 3 cm more.
pub const SOLE_DEPTHS_CM: [f64; 7] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0];

/// The deepest sole that can be given (cm): a platform shoe's.
pub const MAX_SOLE_DEPTH_CM: f64 = 20.0;

/// The costs below add up evidence over time, in units of this duration: a
/// height or an accelerometer reading held for this long costs its square
/// once, and so does a velocity change spread over it. (They were first
/// written per frame at 30 fps; as integrals over time a 100 Hz recording
/// weighs a second of evidence as a 30 fps one does.)
const COST_TIME_S: f64 = 1.0 / 30.0;

/// A second of coasting costs as much as this many velocity changes of one
/// `slip_cm_per_s`. Pinning a foot that slides at `u` costs `(u / slip)²`
/// when it starts and again when it stops, however long it slides; a running
/// flight (~0.15 s, every foot ≥ 100 cm/s off: ≥ 32 against 9) coasts, and a
/// walk's handover (~0.1 s, feet ~40 cm/s off: ~5 against 6) mostly does
/// not. (Measured on the ground-truth files, 30 and 100 per second each do
/// worse on some motion, so this is the middle of a broad optimum, not a
/// sharp one.)
const COAST_COST_PER_S: f64 = 60.0;

/// The longest a body can coast (s): the time in the air of a standing
/// jump 30 cm high. Without a limit one wrong velocity would be carried
/// across a whole recording.
const MAX_COAST_S: f64 = 0.5;

/// Where frames are left out (a [`grid_step`] above one, from 45 fps),
/// tracking jitter is first smoothed away over this time scale (s), the
/// standard deviation of a Gaussian: three frames at 100 Hz, well under a
/// heel-to-toe roll (50-100 ms). The grid keeps no detail finer than its
/// step, and an inertial suit's millimetres of jitter, left in, decide which
/// frame of a step looks smoothest (unsmoothed, the katas' closures swing by
/// tens of centimetres with the sampling phase). Only the choice of contacts
/// sees the smoothed paths; the pinned points hold still unsmoothed. Below
/// 45 fps every frame is used, unsmoothed, as at 30 fps.
const JITTER_S: f64 = 0.03;

/// The distance between a pinned point and the centre of mass's floor
/// projection that costs as much as one `slip_cm_per_s` of velocity change:
/// a body's length, so that it never outweighs the evidence of motion.
const COM_PRIOR_CM: f64 = 100.0;

/// A flight needs a body on the floor rising into it, or falling out of it,
/// faster than this (cm/s) over the last (first) [`BALLISTIC_EVIDENCE_S`] on
/// the floor: a hop of one centimetre leaves the floor at 44 cm/s, and a
/// body standing in a stance bobs far slower. (Measured: the ground-truth
/// run's take-offs rise at 34-65 cm/s; Heian Shodan's turns, which coast
/// but never leave the floor, at -29 to +3 cm/s.)
const MIN_TAKEOFF_CM_PER_S: f64 = 20.0;
const BALLISTIC_EVIDENCE_S: f64 = 0.05;

/// A centre of mass lower than this above the floor (cm) is taken to be this
/// high when reckoning the floor's push: a body crouched or lying down is not
/// an inverted pendulum, and the push would grow without bound.
const MIN_COM_HEIGHT_CM: f64 = 30.0;

/// How many frames apart the contacts are chosen: the whole number of frames
/// nearest [`COST_TIME_S`], at least one. The costs weigh evidence per unit
/// of time, but a change of pinned point is a jump of velocity, and a jump
/// costs once per frame it happens in, whatever the rate: at 100 Hz it would
/// weigh three times what it does at 30 fps against everything else, and
/// velocities from 10 ms differences carry three times the jitter. On frames
/// about 1/30 s apart (22.5 to 45 per second) a recording at any rate is
/// weighed nearly as a 30 fps one is. Each of the `step` ways of taking
/// every `step`-th frame (fewer when the recording is shorter) is solved and
/// their paths averaged, so the result does not depend on which frames
/// happened to be taken; between its frames, a phase's pinned point still
/// holds still frame by frame.
fn grid_step(fps: f64) -> usize {
    ((fps * COST_TIME_S).round() as usize).max(1)
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
    /// Per foot `[left, right]`: the part of the sole pinned while that foot
    /// is down, else the part nearest the floor.
    pub contact_part: [Vec<SolePart>; 2],
    /// Per foot: the height of its lowest sole point above the floor (cm),
    /// as corrected. Zero for the lower foot on the floor; the other foot's
    /// lowest point may stand a little above it even while pinned.
    pub clearance_cm: [Vec<f64>; 2],
    /// The floor's height in the recording's coordinates (cm): where the
    /// corrected recording puts its lowest foot points.
    pub ground_cm: f64,
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
    if n == 0 {
        return Err("the recording has no frames".into());
    }
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("the frame rate must be positive, not {fps}"));
    }
    let dt = 1.0 / fps;
    params.check()?;
    // The contacts are chosen on every `step`-th frame, about COST_TIME_S
    // apart, once for each of the `step` ways of taking them (phases), and
    // the phases' paths are averaged; see [`grid_step`].
    let step = grid_step(fps);
    let phases: Vec<Vec<usize>> = (0..step.min(n)).map(|phase| (phase..n).step_by(step).collect()).collect();
    // Before every `step`-th frame is taken, tracking jitter is smoothed
    // away (see JITTER_S); at 30 fps no frame is left out and none is smoothed.
    let sigma_samples = if step > 1 { JITTER_S * fps } else { 0.0 };
    let com_from_hips = smooth_paths(&centre_of_mass_from_hips(poses, parents, feet, hips), 1, sigma_samples);
    // With accelerometers: how far each foot's reading is from 1 g.
    let calm_g = |side: usize, f: usize| -> Option<f64> {
        foot_accel_g.and_then(|a| a[foot(side)].get(f).copied()).map(|a| (a - 1.0).abs())
    };
    // Horizontal: for each sole depth, the contact sequence along which the
    // centre of mass moves most as the floor pushes it; the depth whose best
    // sequences fit best.
    let depths = params.sole_depth_cm.map_or(SOLE_DEPTHS_CM.to_vec(), |depth| vec![depth]);
    let shapes = foot_shapes(poses, parents, [feet.left, feet.right], hips);
    let mut best: Option<(f64, f64, Vec<Contacts>)> = None;
    let mut toes = true;
    for sole_depth_cm in depths {
        let soles = shapes.each_ref().map(|shape| shape.sole(sole_depth_cm).smoothed(sigma_samples));
        // FootJoints without toes have no sole below their joints to place: every
        // depth gives the same.
        toes = soles.iter().any(Sole::has_toes);
        let chosen: Vec<Contacts> = phases
            .iter()
            .map(|frames| {
                let calm_g = |side: usize, g: usize| calm_g(side, frames[g]);
                let soles = soles.each_ref().map(|sole| sole.at_frames(frames));
                let com_from_hips = frames.iter().map(|&f| com_from_hips[f]).collect();
                Contacts::choose(soles, com_from_hips, dt * step as f64, &calm_g, params)
            })
            .collect();
        let cost = chosen.iter().map(|c| c.cost).sum::<f64>();
        // Ties keep the shallower sole: where depth makes no difference (no
        // foot rolls), the joints themselves are the plainest answer.
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, sole_depth_cm, chosen));
        }
        if !toes {
            break;
        }
    }
    let Some((_, sole_depth_cm, chosen)) = best else {
        return Err("no sole depth to try".into());
    };

    // Back to every frame: each phase's decision for the step that holds
    // frame f, `chosen[phase]` at step `at(phase, f)`.
    let soles = shapes.each_ref().map(|shape| shape.sole(sole_depth_cm));
    let (lowest, low, standing) = lowest_points(&soles, n);
    // (The frames before a phase's first step go with that step.)
    let at = |phase: usize, f: usize| -> usize {
        let last = phases[phase].len() - 1;
        f.saturating_sub(phase).div_ceil(step).clamp(1.min(last), last)
    };
    let mut path = vec![horizontal(poses.at(0, hips)); n];
    for f in 1..n {
        let velocity = (0..phases.len())
            .map(|phase| {
                let contacts = &chosen[phase];
                let g = at(phase, f);
                // Pinned points hold still frame by frame; a coasting body
                // keeps the velocity of its step.
                let pinned = |side: usize, point: usize| {
                    -horizontal(soles[side].at(f, point) - soles[side].at(f - 1, point)) / dt
                };
                match contacts.chosen[g] {
                    Candidate::Point { side, point } => pinned(side, point),
                    Candidate::Double => (pinned(0, lowest[0][f - 1]) + pinned(1, lowest[1][f - 1])) * 0.5,
                    Candidate::Coast => contacts.hips_velocity[g],
                }
            })
            .sum::<DVec3>()
            / phases.len() as f64;
        path[f] = path[f - 1] + velocity * dt;
    }

    // Vertical: standing on the lowest sole point, lifted where most phases'
    // coasting stretches are flights (their lift above standing, linearly
    // between their frames, averaged).
    let lifts: Vec<(Vec<f64>, Vec<bool>)> = chosen.iter().map(|contacts| contacts.flights(params)).collect();
    let mut height = standing.clone();
    let mut flight = vec![false; n];
    for f in 0..n {
        let mut lift = 0.0;
        let mut flying = 0;
        for (phase, (lifted, flights)) in lifts.iter().enumerate() {
            let s = (f as f64 - phase as f64) / step as f64;
            let (a, b) = (s.floor().max(0.0) as usize, s.ceil().max(0.0) as usize);
            let (a, b) = (a.min(lifted.len() - 1), b.min(lifted.len() - 1));
            let t = if b > a { s - a as f64 } else { 0.0 };
            lift += lifted[a] * (1.0 - t) + lifted[b] * t;
            flying += usize::from(flights[if t < 0.5 { a } else { b }]);
        }
        // A flight where most phases fly, and only there: a foot that the
        // method says is on the floor is on it.
        flight[f] = 2 * flying > lifts.len();
        if flight[f] {
            height[f] += lift / lifts.len() as f64;
        }
    }
    let clearance_cm: [Vec<f64>; 2] = [0, 1].map(|side| (0..n).map(|f| height[f] + low[side][f]).collect());
    // What the method decided in frame f: what most phases decided (ties go
    // to the earliest).
    let decisions: Vec<Candidate> = (0..n)
        .map(|f| {
            most_common(
                &(0..phases.len()).map(|phase| chosen[phase].chosen[at(phase, f)]).collect::<Vec<_>>(),
            )
        })
        .collect();
    let support: Vec<Support> = (0..n)
        .map(|f| match decisions[f] {
            Candidate::Point { side, .. } => Support::Single(foot(side)),
            Candidate::Double => Support::Double,
            Candidate::Coast if flight[f] => Support::Flight,
            // Coasting with a foot on the floor: it slides; the lower one.
            Candidate::Coast => Support::Single(foot(usize::from(low[1][f] < low[0][f]))),
        })
        .collect();
    let contact_part = [0, 1].map(|side| {
        (0..n)
            .map(|f| match decisions[f] {
                Candidate::Point { side: s, point } if s == side => soles[side].parts[point],
                _ => soles[side].parts[lowest[side][f]],
            })
            .collect()
    });

    // The floor in the recording's coordinates: where its lowest foot points
    // sit in most frames, so a vendor's roughly right vertical is kept and a
    // frozen one gets a sensible level. Frame 0 alone would let one
    // mis-tracked frame shift the whole recording.
    let ground_cm = upper_median(&(0..n).map(|f| poses.at(f, hips).y - standing[f]).collect::<Vec<_>>());
    let shift_cm = (0..n)
        .map(|f| {
            let hips_now = poses.at(f, hips);
            DVec3::new(path[f].x - hips_now.x, ground_cm + height[f] - hips_now.y, path[f].z - hips_now.z)
        })
        .collect();
    let mut warnings = Vec::new();
    let flight_frames = flight.iter().filter(|&&x| x).count();
    // A fast run is in the air up to about two thirds of the time; more than
    // three quarters is not a body on its feet.
    if flight_frames * 4 > n * 3 {
        warnings.push(format!(
            "{:.0}% of the frames are in flight; check that the feet are right and Y is up",
            100.0 * flight_frames as f64 / n as f64
        ));
    }
    let sole_depth_cm = toes.then_some(sole_depth_cm);
    Ok(ContactResult { shift_cm, support, contact_part, clearance_cm, ground_cm, sole_depth_cm, warnings })
}

/// The part of the velocity change `change` (cm/s) that the floor's push
/// does not explain, when the push is `push + s · along` for the `s` in
/// [0, 1] that explains most: the centre of pressure placed where on its
/// segment it fits best (see [`Contacts::pressure_segment`]).
fn unexplained_change(change: DVec3, push: DVec3, along: DVec3) -> DVec3 {
    let r = change - push;
    let s = if along.length_squared() > 0.0 {
        (r.dot(along) / along.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    r - s * along
}

/// The body's centre of mass relative to the hips, per frame (cm), from
/// Dempster's segment masses: per leg the thigh 10%, the shank 4.65% and the
/// foot 1.45% of the body, each at its segment's middle (the foot at the
/// ankle), and the rest (68%: trunk, head, arms) at the mean of the joints
/// that are not in a leg nor above the hips. An unweighted mean of all joints would give the
/// arms a third of the body's mass instead of a tenth.
fn centre_of_mass_from_hips(
    poses: &Poses,
    parents: &[Option<usize>],
    feet: FootJoints,
    hips: usize,
) -> Vec<DVec3> {
    // A leg: the joints from the foot up to, not including, the hips.
    let leg = |foot: usize| {
        let mut chain = vec![foot];
        while let Some(parent) = parents.get(*chain.last().unwrap_or(&hips)).copied().flatten() {
            if parent == hips || chain.contains(&parent) {
                break;
            }
            chain.push(parent);
        }
        chain // foot, knee, hip joint, …
    };
    let legs = [leg(feet.left), leg(feet.right)];
    let toes = [foot_points(parents, feet.left), foot_points(parents, feet.right)];
    let above = above_hips(parents, hips);
    let rest: Vec<usize> = (0..poses.joint_count)
        .filter(|j| !legs.iter().chain(&toes).chain([&above]).any(|joints| joints.contains(j)))
        .collect();
    (0..poses.frame_count())
        .map(|f| {
            let at = |j: usize| poses.at(f, j);
            let mut com = DVec3::ZERO;
            let mut mass = 0.0;
            for chain in &legs {
                let (foot, knee, hip) = (chain[0], chain.get(1).copied(), chain.get(2).copied());
                com += 0.0145 * at(foot);
                mass += 0.0145;
                if let Some(knee) = knee {
                    com += 0.0465 * (at(knee) + at(foot)) * 0.5;
                    mass += 0.0465;
                    let hip_at = hip.map_or(at(hips), at);
                    com += 0.10 * (hip_at + at(knee)) * 0.5;
                    mass += 0.10;
                }
            }
            if !rest.is_empty() {
                let upper = 1.0 - mass;
                com += upper * rest.iter().map(|&j| at(j)).sum::<DVec3>() / rest.len() as f64;
                mass = 1.0;
            }
            com / mass - at(hips)
        })
        .collect()
}

/// The candidate that most of `votes` name; of equally many, the first named.
fn most_common(votes: &[Candidate]) -> Candidate {
    // Votes name few distinct candidates: count each once.
    let mut counts: Vec<(Candidate, usize)> = Vec::new();
    for &vote in votes {
        match counts.iter_mut().find(|(c, _)| *c == vote) {
            Some((_, count)) => *count += 1,
            None => counts.push((vote, 1)),
        }
    }
    let mut best = counts.first().copied().unwrap_or((Candidate::Coast, 0));
    for &(candidate, count) in &counts {
        if count > best.1 {
            best = (candidate, count);
        }
    }
    best.0
}

/// The maximal stretches `[start, end)` of frames where `chosen` is `what`.
fn runs(chosen: &[Candidate], what: Candidate) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut f = 0;
    while f < chosen.len() {
        if chosen[f] != what {
            f += 1;
            continue;
        }
        let start = f;
        while f < chosen.len() && chosen[f] == what {
            f += 1;
        }
        out.push((start, f));
    }
    out
}

/// How the hips move from frame `f - 1` to `f`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Candidate {
    /// Point `point` of the sole of foot `side` stays where it was.
    Point { side: usize, point: usize },
    /// Both feet stay where they were (their lowest points): the mean.
    Double,
    /// No foot holds still: the centre of mass keeps its velocity.
    Coast,
}

/// The contacts chosen on one grid of frames for one sole depth, and what
/// they were chosen from; frames here are the grid's.
struct Contacts {
    soles: [Sole; 2],
    /// Per foot and frame, its sole point nearest the floor.
    lowest: [Vec<usize>; 2],
    /// Per frame, the hips' height with the lowest sole point on the floor.
    standing: Vec<f64>,
    /// Per frame, the centre of mass relative to the hips (cm).
    com_from_hips: Vec<DVec3>,
    dt: f64,
    /// Per frame, the candidate chosen, and the hips' horizontal velocity
    /// (cm/s) it gives.
    chosen: Vec<Candidate>,
    hips_velocity: Vec<DVec3>,
    /// The total cost of the choice (see [`Contacts::best_sequence`]).
    cost: f64,
}

/// Per foot and frame, its sole point nearest the floor and that point's
/// height above its flat-foot level (relative to the hips); per frame, the
/// hips' height with the lowest of them on the floor.
fn lowest_points(soles: &[Sole; 2], n: usize) -> ([Vec<usize>; 2], [Vec<f64>; 2], Vec<f64>) {
    let mut lowest = [vec![0usize; n], vec![0usize; n]];
    let mut low = [vec![0.0; n], vec![0.0; n]];
    for f in 0..n {
        for side in 0..2 {
            (lowest[side][f], low[side][f]) = soles[side].lowest(f);
        }
    }
    let standing = (0..n).map(|f| -low[0][f].min(low[1][f])).collect();
    (lowest, low, standing)
}

impl Contacts {
    /// The best contacts on `soles`, whose frames are `dt` apart.
    fn choose(
        soles: [Sole; 2],
        com_from_hips: Vec<DVec3>,
        dt: f64,
        calm_g: &dyn Fn(usize, usize) -> Option<f64>,
        params: &ContactParams,
    ) -> Self {
        let n = com_from_hips.len();
        let (lowest, _, standing) = lowest_points(&soles, n);
        let mut contacts = Contacts {
            soles,
            lowest,
            standing,
            com_from_hips,
            dt,
            chosen: Vec::new(),
            hips_velocity: Vec::new(),
            cost: 0.0,
        };
        (contacts.chosen, contacts.hips_velocity, contacts.cost) = contacts.best_sequence(calm_g, params);
        contacts
    }

    /// Per frame, how far the hips rise above standing (cm) and whether the
    /// body is in flight: over a coasting stretch the centre of mass follows
    /// the parabola gravity gives between take-off and landing, where that
    /// lifts both feet off the floor and the body was rising into the
    /// take-off or falls into the landing.
    fn flights(&self, params: &ContactParams) -> (Vec<f64>, Vec<bool>) {
        let n = self.chosen.len();
        let dt = self.dt;
        let mut lift = vec![0.0; n];
        let mut flight = vec![false; n];
        let com_height = |f: usize| self.standing[f] + self.com_from_hips[f].y;
        for (start, end) in runs(&self.chosen, Candidate::Coast) {
            // `chosen[f]` is the move from frame f - 1 to f, so a coasting run
            // [start, end) leaves the floor after frame start - 1 and is back on
            // it at frame end - 1, unless it runs off the recording's start or
            // end; there the arc is taken level.
            let take_off = start.checked_sub(1);
            let landing = (end < n).then(|| end - 1);
            let (a, b) = (take_off.unwrap_or(0), landing.unwrap_or(n - 1));
            let Some(level) = take_off.or(landing).map(com_height) else { continue };
            let (height_a, height_b) =
                (take_off.map_or(level, com_height), landing.map_or(level, com_height));
            let air = start..landing.unwrap_or(n);
            let (ta, tb) = (a as f64 * dt, b as f64 * dt);
            let arc = |f: usize| -> f64 {
                let t = f as f64 * dt;
                let s = if tb > ta { (t - ta) / (tb - ta) } else { 0.0 };
                height_a + s * (height_b - height_a) + 0.5 * STANDARD_GRAVITY_CM_PER_S2 * (t - ta) * (tb - t)
            };
            // A flight lifts the feet clear of the floor and never pushes one
            // into it: where the arc would, a foot was holding the body up.
            let above = |f: usize| arc(f) - self.com_from_hips[f].y - self.standing[f];
            let lifts = air.clone().all(|f| above(f) >= 0.0)
                && air.clone().any(|f| above(f) > params.flight_margin_cm);
            // And a body leaves the floor because the floor threw it up: it was
            // rising in its last moments on the floor, or falls into the landing.
            // (A kata's turn coasts too, on a level body, and is no flight.)
            let span = ((BALLISTIC_EVIDENCE_S / dt).round() as usize).max(1);
            let fast = MIN_TAKEOFF_CM_PER_S * span as f64 * dt;
            let rising = take_off.is_some_and(|a| a >= span && com_height(a) - com_height(a - span) > fast);
            let falling =
                landing.is_some_and(|b| b + span < n && com_height(b) - com_height(b + span) > fast);
            if lifts && (rising || falling) {
                for f in air {
                    lift[f] = above(f).max(0.0);
                    flight[f] = true;
                }
            }
        }
        (lift, flight)
    }

    /// The hips' horizontal velocity from frame `f - 1` to `f` (cm/s) if
    /// `candidate` holds (not for `Coast`, whose velocity is carried).
    fn hips_velocity(&self, candidate: Candidate, f: usize) -> DVec3 {
        if f == 0 {
            return DVec3::ZERO;
        }
        let pinned = |side: usize, point: usize| {
            -horizontal(self.soles[side].at(f, point) - self.soles[side].at(f - 1, point)) / self.dt
        };
        match candidate {
            Candidate::Point { side, point } => pinned(side, point),
            Candidate::Double => (pinned(0, self.lowest[0][f - 1]) + pinned(1, self.lowest[1][f - 1])) * 0.5,
            Candidate::Coast => DVec3::ZERO,
        }
    }

    /// The centre of mass's horizontal velocity relative to the hips, from
    /// frame `f - 1` to `f` (cm/s).
    fn com_from_hips_velocity(&self, f: usize) -> DVec3 {
        if f == 0 {
            return DVec3::ZERO;
        }
        horizontal(self.com_from_hips[f] - self.com_from_hips[f - 1]) / self.dt
    }

    /// The height above the floor of sole point `point` of foot `side` in
    /// frame `f`, with the lowest sole point on the floor.
    fn clearance_cm(&self, side: usize, point: usize, f: usize) -> f64 {
        self.standing[f] + self.soles[side].height_above_flat_cm(f, point)
    }

    /// Every candidate, in a fixed order.
    fn candidates(&self) -> Vec<Candidate> {
        let mut all: Vec<Candidate> = (0..2)
            .flat_map(|side| {
                (0..self.soles[side].point_count()).map(move |point| Candidate::Point { side, point })
            })
            .collect();
        all.extend([Candidate::Double, Candidate::Coast]);
        all
    }

    /// Where the floor can push the body from in frame `f` if `candidate`
    /// holds: the segment `[from, to]` (relative to the hips) on which the
    /// centre of pressure lies. A foot presses anywhere between its heel and
    /// its toes, whichever point of it rolls; two feet anywhere between them.
    fn pressure_segment(&self, candidate: Candidate, f: usize) -> Option<(DVec3, DVec3)> {
        match candidate {
            Candidate::Point { side, .. } => {
                let sole = &self.soles[side];
                Some((sole.at(f, 0), sole.at(f, sole.tip)))
            }
            Candidate::Double => {
                Some((self.soles[0].at(f, self.lowest[0][f]), self.soles[1].at(f, self.lowest[1][f])))
            }
            Candidate::Coast => None,
        }
    }

    /// The candidate for every frame along which the centre of mass moves
    /// most as the floor pushes it, over the whole recording; the hips'
    /// horizontal velocity (cm/s) it gives each frame; and its total cost.
    ///
    /// Why the whole recording and not frame by frame: when one foot lands as
    /// the other pushes off, both are low and one of them moves. A choice made
    /// from the past alone follows whichever foot agrees with the velocity so
    /// far, and after one late switch that velocity is already wrong, so the
    /// next switch is late too: a walk comes out several percent short. The
    /// frames after the switch tell which foot the body went on with.
    ///
    /// Why the centre of mass: Newton's law holds for it, not for the hips
    /// joint, which swings around it (in a walk the hips' speed varies by
    /// half within each step, fastest just when the feet change over).
    ///
    /// How the floor pushes: along the line from the centre of pressure to
    /// the centre of mass, holding the body up (the inverted pendulum). A
    /// centre of mass `d` cm ahead of the pressure point and `h` cm above the
    /// floor is pushed forward at `g d / h`: a walker speeds up once past the
    /// stance foot and slows down before it, and a body held by a foot far
    /// behind it cannot be moving backwards. The change of velocity the
    /// choice implies is compared with that push, the pressure point placed
    /// where on its segment ([`Contacts::pressure_segment`]) it fits best.
    ///
    /// Costs, in units of one `slip_cm_per_s` of velocity change, summed over
    /// frames (Viterbi; exact for the pinned candidates, whose velocity each
    /// frame is fixed; a coasting stretch carries the velocity it entered
    /// with along its best way in). Evidence that lasts is weighed per
    /// [`COST_TIME_S`] of time, so a second of evidence weighs the same at
    /// any frame rate (and on the grid of [`grid_step`], so does a jump):
    /// - a velocity change `Δv` that the floor's push does not explain costs
    ///   `(Δv / slip)²`, times `COST_TIME_S / dt`;
    /// - a sole point `c` cm above the floor costs `(c / touch_cm)²` per
    ///   `COST_TIME_S`, and above `lift_cm` it cannot be pinned;
    /// - with accelerometers, a pinned foot reading `a` g costs
    ///   `(2 (a − 1))²` per `COST_TIME_S`: a still foot reads 1 g, and half
    ///   a g off weighs like a clearly sliding foot;
    /// - a pinned point `d` cm from the centre of mass's floor projection
    ///   costs `(d / COM_PRIOR_CM)²` per `COST_TIME_S` (see there);
    /// - coasting costs [`COAST_COST_PER_S`] per second; the floor does not
    ///   push a coasting body.
    fn best_sequence(
        &self,
        calm_g: &dyn Fn(usize, usize) -> Option<f64>,
        params: &ContactParams,
    ) -> (Vec<Candidate>, Vec<DVec3>, f64) {
        let n = self.standing.len();
        let candidates = self.candidates();
        let m = candidates.len();
        let coast = m - 1;
        // Evidence held for one frame, and a velocity change within one,
        // in units of COST_TIME_S.
        let per_frame = self.dt / COST_TIME_S;
        let per_change = COST_TIME_S / self.dt;
        let point_cost = |side: usize, point: usize, f: usize| -> f64 {
            let before = self.clearance_cm(side, point, f.saturating_sub(1));
            let after = self.clearance_cm(side, point, f);
            if before.max(after) > params.lift_cm {
                return f64::INFINITY;
            }
            let c = 0.5 * (before + after).max(0.0) / params.touch_cm;
            let shake = 2.0 * calm_g(side, f).unwrap_or(0.0);
            // The weight: a foot bears it at its centre of pressure, near the
            // centre of mass's floor projection (behind the heel at heel
            // strike, ahead of the toes at push-off, over the ball in a turn
            // on it). Weak: it only decides between points that are equally
            // low and equally smooth, as in a flat foot turning on the spot.
            let weight =
                horizontal(self.soles[side].at(f, point) - self.com_from_hips[f]).length() / COM_PRIOR_CM;
            (c * c + shake * shake + weight * weight) * per_frame
        };
        let own_cost = |candidate: Candidate, f: usize| -> f64 {
            match candidate {
                Candidate::Point { side, point } => point_cost(side, point, f),
                Candidate::Double => {
                    let before = f.saturating_sub(1);
                    point_cost(0, self.lowest[0][before], f) + point_cost(1, self.lowest[1][before], f)
                }
                Candidate::Coast => {
                    // With accelerometers: a foot reading 1 g rests on the
                    // floor, so the body is not coasting; a foot half a g
                    // off says nothing.
                    let resting = (0..2)
                        .map(|side| calm_g(side, f).map_or(0.0, |off| (1.0 - 2.0 * off).max(0.0)))
                        .fold(0.0, f64::max);
                    COAST_COST_PER_S * self.dt + (2.0 * resting).powi(2) * per_frame
                }
            }
        };
        let slip = params.slip_cm_per_s;
        // Per candidate: the best cost of a sequence ending in it, and the
        // centre of mass's velocity it ends with.
        let mut cost: Vec<f64> = candidates.iter().map(|&c| own_cost(c, 0)).collect();
        let mut com_velocity = vec![DVec3::ZERO; m];
        let mut back = vec![0u32; n * m];
        // The coasting velocity carried into each frame, along its best way
        // in, and how many frames that way has been coasting.
        let mut carried = vec![DVec3::ZERO; n];
        let mut coast_frames = 0usize;
        let max_coast_frames = (MAX_COAST_S / self.dt).round().max(1.0) as usize;
        let mut next_cost = vec![0.0; m];
        let mut next_velocity = vec![DVec3::ZERO; m];
        for f in 1..n {
            let com_from_hips_velocity = self.com_from_hips_velocity(f);
            // The floor's push between the velocity of frames f - 2 → f - 1
            // and that of f - 1 → f, at frame f - 1: per cm of centre of mass
            // ahead of the pressure point, this change of velocity (cm/s).
            let pushed = f - 1;
            let com = self.com_from_hips[pushed];
            let com_height_cm = (self.standing[pushed] + com.y).max(MIN_COM_HEIGHT_CM);
            let push_per_cm = STANDARD_GRAVITY_CM_PER_S2 / com_height_cm * self.dt;
            for (i, &candidate) in candidates.iter().enumerate() {
                let own = own_cost(candidate, f);
                if !own.is_finite() {
                    next_cost[i] = f64::INFINITY;
                    continue;
                }
                let now = if i == coast {
                    None
                } else {
                    Some(self.hips_velocity(candidate, f) + com_from_hips_velocity)
                };
                // The push from the segment's start, and how it changes
                // along the segment: `push + s along` for s in [0, 1].
                let (push, along) = self
                    .pressure_segment(candidate, pushed)
                    .map_or((DVec3::ZERO, DVec3::ZERO), |(from, to)| {
                        (horizontal(com - from) * push_per_cm, -horizontal(to - from) * push_per_cm)
                    });
                let (mut best, mut best_from) = (f64::INFINITY, coast);
                for j in 0..m {
                    // A coasting stretch that has lasted its longest can
                    // only land.
                    if !cost[j].is_finite() || (i == coast && j == coast && coast_frames >= max_coast_frames)
                    {
                        continue;
                    }
                    // Coasting keeps the velocity it comes in with; frame 0
                    // has no velocity to compare with.
                    let unexplained = match now {
                        Some(v) if f > 1 => {
                            unexplained_change(horizontal(v - com_velocity[j]), push, along).length() / slip
                        }
                        _ => 0.0,
                    };
                    let total = cost[j] + unexplained * unexplained * per_change;
                    if total < best {
                        (best, best_from) = (total, j);
                    }
                }
                next_cost[i] = best + own;
                next_velocity[i] = now.unwrap_or(if f > 1 { com_velocity[best_from] } else { DVec3::ZERO });
                back[f * m + i] = best_from as u32;
            }
            carried[f] = next_velocity[coast];
            coast_frames = if back[f * m + coast] as usize == coast { coast_frames + 1 } else { 1 };
            std::mem::swap(&mut cost, &mut next_cost);
            std::mem::swap(&mut com_velocity, &mut next_velocity);
        }
        let mut i = (0..m).min_by(|&a, &b| cost[a].total_cmp(&cost[b])).unwrap_or(coast);
        let total_cost = cost[i];
        let mut chosen = vec![candidates[i]; n];
        for f in (1..n).rev() {
            chosen[f] = candidates[i];
            i = back[f * m + i] as usize;
        }
        chosen[0] = chosen.get(1).copied().unwrap_or(candidates[i]);
        let hips_velocity = (0..n)
            .map(|f| match chosen[f] {
                Candidate::Coast => carried[f] - self.com_from_hips_velocity(f),
                c => self.hips_velocity(c, f),
            })
            .collect();
        (chosen, hips_velocity, total_cost)
    }
}

fn foot(side: usize) -> Foot {
    if side == 0 { Foot::Left } else { Foot::Right }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let stance_side = (step as usize) % 2; // 0 left, 1 right
            let plant_z = speed * (step * period + stance / 2.0);
            let foot = |side: usize| -> [DVec3; 2] {
                let x = if side == 0 { -10.0 } else { 10.0 };
                if side == stance_side && !in_air {
                    [DVec3::new(x, 8.0, plant_z), DVec3::new(x, 2.0, plant_z + 14.0)]
                } else {
                    let ankle = hips + DVec3::new(x, -60.0, 0.0);
                    [ankle, ankle + DVec3::new(0.0, -6.0, 14.0)]
                }
            };
            let ([la, lt], [ra, rt]) = (foot(0), foot(1));
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
    fn the_push_comes_from_within_the_pressure_segment() {
        // Centre of mass at the origin; pressure anywhere from 10 cm behind
        // it to 20 cm behind it (a foot); `k` cm/s of push per cm.
        let (com, from, to, k) = (DVec3::ZERO, DVec3::new(0.0, 0.0, -10.0), DVec3::new(0.0, 0.0, -20.0), 0.5);
        let push = (com - from) * k;
        let along = -(to - from) * k;
        // Pressed from the middle of the foot: pushed forward 7.5 cm/s,
        // fully explained; from the heel end, 10.
        let explained = |change: DVec3| unexplained_change(change, push, along).length();
        assert!(explained(DVec3::new(0.0, 0.0, 7.5)) < 1e-12);
        assert!(explained(DVec3::new(0.0, 0.0, 10.0)) < 1e-12);
        // Not from beyond the foot (2.5 cm/s short of the nearest end), nor
        // from the far side of the centre of mass.
        assert!((explained(DVec3::new(0.0, 0.0, 2.5)) - 2.5).abs() < 1e-12);
        assert!((explained(DVec3::new(0.0, 0.0, -5.0)) - 10.0).abs() < 1e-12);
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
    }
}
