//! Coasting and flight: over a stretch where no foot holds still, the centre
//! of mass follows the parabola that gravity gives between take-off and
//! landing. Where that lifts both feet off the floor, pushes none into it,
//! and the body was thrown up into it, the stretch is a flight.

use std::ops::Range;

use super::ContactParams;
use super::footing::Candidate;
use super::solve::{Problem, Solution};
use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;

/// Per frame of a grid, how far the hips rise above standing and whether
/// the body is in flight.
pub(super) struct Lifts {
    /// The hips' rise above standing (cm); zero outside flights.
    pub lift_cm: Vec<f64>,
    pub flight: Vec<bool>,
}

/// One coasting stretch, `chosen[run] == Coast` for a maximal `run`, as the
/// body's flight would be: `chosen[f]` is the move from frame f - 1 to f, so
/// it leaves the floor after frame `run.start - 1` and is back on it at frame
/// `run.end - 1`, unless it runs off the recording's start or end.
struct Coasting {
    /// The last frame on the floor before it, if any.
    take_off: Option<usize>,
    /// The first frame back on the floor, if any.
    landing: Option<usize>,
    /// The frames off the floor.
    air: Range<usize>,
}

impl Coasting {
    fn new(run: Range<usize>, n: usize) -> Coasting {
        let take_off = run.start.checked_sub(1);
        let landing = (run.end < n).then(|| run.end - 1);
        Coasting { take_off, landing, air: run.start..landing.unwrap_or(n) }
    }
}

/// The lifts and flights of `solution` (see the module documentation).
pub(super) fn flights(problem: &Problem, solution: &Solution, params: &ContactParams) -> Lifts {
    let n = solution.chosen.len();
    let mut lifts = Lifts { lift_cm: vec![0.0; n], flight: vec![false; n] };
    for run in runs(&solution.chosen, Candidate::Coast) {
        let coasting = Coasting::new(run, n);
        let Some(above) = clearance_on_arc(problem, &coasting) else { continue };
        if lifts_the_feet(&coasting.air, &above, params) && thrown(problem, &coasting, params) {
            for f in coasting.air {
                lifts.lift_cm[f] = above(f).max(0.0);
                lifts.flight[f] = true;
            }
        }
    }
    lifts
}

/// Per frame of `coasting`, how far gravity's arc from take-off to landing
/// puts the hips above standing (cm); the arc is taken level where the
/// stretch runs off the recording. `None` for a stretch that is all the
/// recording.
fn clearance_on_arc<'a>(problem: &'a Problem, coasting: &Coasting) -> Option<impl Fn(usize) -> f64 + 'a> {
    let n = problem.frame_count();
    let dt = problem.dt;
    let com_height = |f: usize| com_height_cm(problem, f);
    let (take_off, landing) = (coasting.take_off, coasting.landing);
    let (a, b) = (take_off.unwrap_or(0), landing.unwrap_or(n - 1));
    let level = take_off.or(landing).map(com_height)?;
    let (height_a, height_b) = (take_off.map_or(level, com_height), landing.map_or(level, com_height));
    let (ta, tb) = (a as f64 * dt, b as f64 * dt);
    let arc = move |f: usize| -> f64 {
        let t = f as f64 * dt;
        let s = if tb > ta { (t - ta) / (tb - ta) } else { 0.0 };
        height_a + s * (height_b - height_a) + 0.5 * STANDARD_GRAVITY_CM_PER_S2 * (t - ta) * (tb - t)
    };
    Some(move |f: usize| arc(f) - problem.hips_to_com_cm[f].y - problem.footing.lowest.standing_cm[f])
}

/// The centre of mass's height above the floor in frame `f` (cm), standing
/// on the lowest sole point.
fn com_height_cm(problem: &Problem, f: usize) -> f64 {
    problem.footing.lowest.standing_cm[f] + problem.hips_to_com_cm[f].y
}

/// Whether the arc lifts the feet clear of the floor in the `air` frames and
/// never pushes one into it: where it would, a foot was holding the body up.
fn lifts_the_feet(air: &Range<usize>, above: impl Fn(usize) -> f64, params: &ContactParams) -> bool {
    air.clone().all(|f| above(f) >= 0.0) && air.clone().any(|f| above(f) > params.flight_margin_cm)
}

/// Whether the floor threw the body into `coasting`: it was rising in its
/// last moments on the floor, or falls into the landing. (A kata's turn
/// coasts too, on a level body, and is no flight.)
fn thrown(problem: &Problem, coasting: &Coasting, params: &ContactParams) -> bool {
    let n = problem.frame_count();
    let dt = problem.dt;
    let com_height = |f: usize| com_height_cm(problem, f);
    let span = ((params.ballistic_evidence_s / dt).round() as usize).max(1);
    let fast = params.min_takeoff_cm_per_s * span as f64 * dt;
    let rising = coasting.take_off.is_some_and(|a| a >= span && com_height(a) - com_height(a - span) > fast);
    let falling =
        coasting.landing.is_some_and(|b| b + span < n && com_height(b) - com_height(b + span) > fast);
    rising || falling
}

/// The maximal stretches of frames where `chosen` is `what`.
fn runs(chosen: &[Candidate], what: Candidate) -> Vec<Range<usize>> {
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
        out.push(start..f);
    }
    out
}
