//! The choice of contacts on one grid of frames: the one sequence of
//! candidates over the whole recording along which the centre of mass's
//! changes of velocity are best explained by the floor's push, found exactly
//! by dynamic programming (Viterbi).
//!
//! Why the whole recording and not frame by frame: when one foot lands as
//! the other pushes off, both are low and one of them moves. A choice made
//! from the past alone follows whichever foot agrees with the velocity so
//! far, and after one late switch that velocity is already wrong, so the
//! next switch is late too. The frames after the switch tell which foot the
//! body went on with.
//!
//! Why the centre of mass: Newton's law holds for it, not for the hips
//! joint, which swings around it (in a walk the hips' speed varies by half
//! within each step, fastest just when the feet change over).
//!
//! Costs, in units of one `slip_cm_per_s` of velocity change, summed over
//! frames; evidence that lasts is weighed per `cost_time_s` of time, so a
//! second of evidence weighs the same at any frame rate (see
//! [`ContactParams`]):
//! - a velocity change `Δv` that the floor's push does not explain (the
//!   centre of pressure placed where on its segment it fits best, see
//!   [`super::pressure`]) costs `(Δv / slip_cm_per_s)²`, times
//!   `cost_time_s / dt`;
//! - a sole point `c` cm above the floor costs `(c / touch_cm)²` per
//!   `cost_time_s`, and above `lift_cm` it cannot be pinned;
//! - with accelerometers, a pinned foot reading `a` g costs
//!   `((a − 1) / accel_slip_g)²` per `cost_time_s`;
//! - a pinned point `d` cm from the centre of mass's floor projection costs
//!   `(d / com_prior_cm)²` per `cost_time_s`;
//! - a double support whose feet move apart faster than the pose's noise
//!   explains costs each foot's slide, half the excess, as a slip:
//!   `(s / slip_cm_per_s)²` per `cost_time_s` (not where the body is in
//!   place, see [`Problem::double_slide_cost`]);
//! - coasting costs `coast_cost_per_s` per second
//!   (`in_place_coast_cost_per_s` where a noisy pose's body is in place,
//!   see [`super::still::in_place`]), more where a foot's accelerometer says
//!   it rests on the floor; the floor does not push a coasting body, which
//!   keeps the velocity it came in with;
//! - a take may start coasting with a velocity yet unknown, set by the first
//!   pin, which is then checked against its own next move
//!   ([`Problem::start_state`]).
//!
//! The optimum is exact for the pinned candidates, whose velocity each frame
//! is fixed; a coasting stretch carries the velocity it entered with along
//! its best way in, for at most `max_coast_s`.

use glam::DVec3;

use super::ContactParams;
use super::footing::{Candidate, Footing};
use super::horizontal;
use super::pressure::FloorPush;
use crate::body::feet::{Foot, PerFoot};

/// What one grid's choice of contacts is made from; frames are the grid's.
pub(super) struct Problem {
    pub footing: Footing,
    /// Per frame, the centre of mass relative to the hips (cm).
    pub hips_to_com_cm: Vec<DVec3>,
    /// Per foot and frame, how far its accelerometer reads from 1 g; `None`
    /// without a reading.
    pub accel_off_g: PerFoot<Vec<Option<f64>>>,
    /// The time between the grid's frames (s).
    pub dt: f64,
    /// Whether the take may start coasting with a velocity yet unknown (see
    /// [`Problem::start_state`]).
    pub open_start: bool,
    /// Per frame, whether the body stays in place there
    /// ([`super::still::in_place`]): coasting costs
    /// `in_place_coast_cost_per_s` instead of `coast_cost_per_s`, and two
    /// feet down may drift apart.
    pub in_place: Vec<bool>,
    /// Every candidate, in the order of [`Footing::candidates`]: coasting
    /// last.
    candidates: Vec<Candidate>,
}

/// The contacts chosen for a [`Problem`].
pub(super) struct Solution {
    /// Per frame, the candidate chosen for the move into it.
    pub chosen: Vec<Candidate>,
    /// Per frame, the hips' horizontal velocity (cm/s) the choice gives.
    pub hips_velocity: Vec<DVec3>,
    /// The total cost of the choice.
    pub cost: f64,
}

/// The dynamic programming's tables after its last frame. Its states are
/// the candidates and, where the take may start open, one more after them
/// ([`Problem::start_state`]).
struct Trellis {
    /// Per state, the least cost of a sequence ending in it.
    cost: Vec<f64>,
    /// Frame-major, per frame and state, the state before it on that
    /// sequence.
    back: Vec<u32>,
    /// Per frame, the centre of mass's velocity (cm/s) carried into it by
    /// coasting along coasting's best way in.
    carried: Vec<DVec3>,
}

/// Per state, the best sequence ending in it in one frame.
struct Column {
    /// Its cost.
    cost: Vec<f64>,
    /// The centre of mass's horizontal velocity it ends with (cm/s).
    com_velocity: Vec<DVec3>,
}

/// The best way into one candidate in one frame.
struct WayIn {
    cost: f64,
    from: usize,
}

impl Problem {
    pub fn new(
        footing: Footing,
        hips_to_com_cm: Vec<DVec3>,
        accel_off_g: PerFoot<Vec<Option<f64>>>,
        dt: f64,
        open_start: bool,
        in_place: Vec<bool>,
    ) -> Problem {
        let candidates = footing.candidates();
        Problem { footing, hips_to_com_cm, accel_off_g, dt, open_start, in_place, candidates }
    }

    pub fn frame_count(&self) -> usize {
        self.hips_to_com_cm.len()
    }

    /// The trellis's state after the candidates': coasting since the first
    /// frame, with no velocity yet.
    ///
    /// Why: a take starts with no velocity to compare its first moves with.
    /// A pin's velocity in frame 1 would stand unchecked, and a coast after
    /// it carry that velocity on (a take that starts on a landing foot
    /// pinned its still-sliding heel, and the hips ran backwards for 0.4 s).
    /// Nor can the start be taken as rest: a take cut mid-run would lose
    /// its first strides. So the body may coast from the start for up to
    /// `max_coast_s` with a velocity yet unknown, which the first pin after
    /// it sets; that pin, having nothing before it to compare with, is
    /// checked against its own next move instead (a point that holds still
    /// gives the same velocity twice; a foot still landing, or already
    /// lifting off, does not). Kept apart from [`Candidate::Coast`], whose
    /// one state carries a velocity: merged, the unknown velocity would
    /// stand in for any history that cost more.
    fn start_state(&self) -> usize {
        self.candidates.len()
    }

    /// How many states the trellis has: the candidates, and the start's
    /// where the take may start open.
    fn state_count(&self) -> usize {
        self.candidates.len() + usize::from(self.open_start)
    }

    /// The candidate trellis state `state` holds: its own, and coasting
    /// for the start's.
    fn state_candidate(&self, state: usize) -> Candidate {
        self.candidates.get(state).copied().unwrap_or(Candidate::Coast)
    }

    /// The floor's push on the centre of mass at frame `f`, the lowest sole
    /// point on the floor.
    fn floor_push(&self, f: usize, params: &ContactParams) -> FloorPush {
        FloorPush::new(
            self.hips_to_com_cm[f],
            self.footing.lowest.standing_cm[f],
            self.dt,
            params.min_com_height_cm,
        )
    }

    /// The best sequence of candidates (see the module documentation).
    pub fn solve(&self, params: &ContactParams) -> Solution {
        let trellis = self.forward(params);
        self.backtrack(&trellis)
    }

    /// The hips' horizontal velocity from frame `f - 1` to `f` (cm/s) if
    /// `candidate` holds; zero in frame 0 and for `Coast`, whose velocity is
    /// carried.
    fn hips_velocity(&self, candidate: Candidate, f: usize) -> DVec3 {
        if f == 0 {
            return DVec3::ZERO;
        }
        self.footing.hips_velocity(candidate, f, self.dt).unwrap_or(DVec3::ZERO)
    }

    /// The centre of mass's horizontal velocity relative to the hips, from
    /// frame `f - 1` to `f` (cm/s).
    pub fn hips_to_com_velocity(&self, f: usize) -> DVec3 {
        if f == 0 {
            return DVec3::ZERO;
        }
        horizontal(self.hips_to_com_cm[f] - self.hips_to_com_cm[f - 1]) / self.dt
    }

    /// What pinning `point` of `foot` for the move into frame `f` costs by
    /// itself: its height, its accelerometer's reading and its distance from
    /// the weight, held for one frame; infinite when it is too high to pin.
    fn point_cost(&self, foot: Foot, point: usize, f: usize, params: &ContactParams) -> f64 {
        let before = self.footing.clearance_cm(foot, point, f.saturating_sub(1));
        let after = self.footing.clearance_cm(foot, point, f);
        if before.max(after) > params.lift_cm {
            return f64::INFINITY;
        }
        let c = 0.5 * (before + after).max(0.0) / params.touch_cm;
        let shake = self.accel_off_g[foot][f].unwrap_or(0.0) / params.accel_slip_g;
        // The weight: a foot bears it at its centre of pressure, near the
        // centre of mass's floor projection (behind the heel at heel
        // strike, ahead of the toes at push-off, over the ball in a turn
        // on it).
        let weight = horizontal(self.footing.soles[foot].at(f, point) - self.hips_to_com_cm[f]).length()
            / params.com_prior_cm;
        (c * c + shake * shake + weight * weight) * (self.dt / params.cost_time_s)
    }

    /// What `candidate` for the move into frame `f` costs by itself.
    ///
    /// Always inlined: it is called for every candidate of every frame, and
    /// since the coast's price is read per frame the compiler no longer
    /// inlines it by itself, which made the contact method on Heian Shodan
    /// 20 % slower (25.0 → 30.2 ms in `cargo bench --bench core`).
    #[inline(always)]
    fn own_cost(&self, candidate: Candidate, f: usize, params: &ContactParams) -> f64 {
        match candidate {
            Candidate::Point { foot, point } => self.point_cost(foot, point, f, params),
            Candidate::Double => {
                let pins = self.footing.lowest.double_support(f.saturating_sub(1));
                self.point_cost(Foot::Left, pins.left, f, params)
                    + self.point_cost(Foot::Right, pins.right, f, params)
                    + self.double_slide_cost(f, params)
            }
            Candidate::Coast => {
                // With accelerometers: a foot reading 1 g rests on the
                // floor, so the body is not coasting; a foot
                // `accel_slip_g` off says nothing.
                let resting = Foot::BOTH
                    .into_iter()
                    .map(|foot| {
                        self.accel_off_g[foot][f]
                            .map_or(0.0, |off| (1.0 - off / params.accel_slip_g).max(0.0))
                    })
                    .fold(0.0, f64::max);
                let coast_cost_per_s =
                    if self.in_place[f] { params.in_place_coast_cost_per_s } else { params.coast_cost_per_s };
                coast_cost_per_s * self.dt
                    + (resting / params.accel_slip_g).powi(2) * (self.dt / params.cost_time_s)
            }
        }
    }

    /// What the feet's sliding costs a double support for the move into
    /// frame `f`.
    ///
    /// The hips follow the mean of the two feet's lowest points, so where
    /// those points move apart each foot slides by half their difference.
    /// Why it costs: the mean of two feet carries √2 less of the pose's
    /// noise than either, so on a noisy pose a double support explained the
    /// motion better than either foot alone even where one foot was still
    /// landing or already lifting, and the hips, following half of that
    /// foot's motion, fell short of every step (on 40 suit-grade walks at
    /// level 0.5, 252 cm over 568 such frames, where the truth's own
    /// contacts on the same pose were 169 cm long). Two feet that stand move
    /// apart only by the noise the choice keeps
    /// (`max_velocity_noise_cm_per_s` per axis and foot), and by more than
    /// 43 cm/s in one frame of twenty: beyond that, each foot's slide costs
    /// as a slip, `slip_cm_per_s` per `cost_time_s`, like a point `touch_cm`
    /// above the floor. Where the body stays in place the feet's
    /// moving apart is the pose's drift, which holding the hips still
    /// answers (`still.rs`), and costs nothing here.
    fn double_slide_cost(&self, f: usize, params: &ContactParams) -> f64 {
        if f == 0 || self.in_place[f] || !params.double_support_slides {
            return 0.0;
        }
        let pins = self.footing.lowest.double_support(f - 1);
        let pinned = |foot: Foot, point: usize| {
            self.footing.hips_velocity(Candidate::Point { foot, point }, f, self.dt).unwrap_or(DVec3::ZERO)
        };
        let apart_cm_per_s = (pinned(Foot::Left, pins.left) - pinned(Foot::Right, pins.right)).length();
        // The difference of two feet's noises has √2 times a foot's deviation
        // per axis; its length on the floor exceeds √(2 ln 20) = 2.448 times
        // that in one frame of twenty.
        let noise_apart_cm_per_s = std::f64::consts::SQRT_2 * 2.448 * params.max_velocity_noise_cm_per_s;
        let slide = 0.5 * (apart_cm_per_s - noise_apart_cm_per_s).max(0.0) / params.slip_cm_per_s;
        2.0 * slide * slide * (self.dt / params.cost_time_s)
    }

    /// The forward pass: frame by frame, per candidate, the best sequence
    /// ending in it.
    fn forward(&self, params: &ContactParams) -> Trellis {
        let candidates = &self.candidates;
        let n = self.frame_count();
        let coast = candidates.len() - 1;
        let m = self.state_count();
        let mut column = Column {
            cost: (0..m).map(|i| self.own_cost(self.state_candidate(i), 0, params)).collect(),
            com_velocity: vec![DVec3::ZERO; m],
        };
        let mut next = Column { cost: vec![0.0; m], com_velocity: vec![DVec3::ZERO; m] };
        let mut back = vec![0u32; n * m];
        let mut carried = vec![DVec3::ZERO; n];
        // How many frames coasting's best way in has been coasting.
        let mut coast_frames = 0usize;
        let max_coast_frames = (params.max_coast_s / self.dt).round().max(1.0) as usize;
        for (f, back) in back.chunks_exact_mut(m).enumerate().skip(1) {
            // A coasting stretch that has lasted its longest can only land.
            let coast_is_over = coast_frames >= max_coast_frames;
            self.advance(f, &column, &mut next, back, coast_is_over, params);
            if self.open_start {
                self.advance_start(f, &column, &mut next, back, f > max_coast_frames, params);
            }
            carried[f] = next.com_velocity[coast];
            coast_frames = if back[coast] as usize == coast { coast_frames + 1 } else { 1 };
            std::mem::swap(&mut column, &mut next);
        }
        Trellis { cost: column.cost, back, carried }
    }

    /// One frame of the forward pass: from the best sequences ending in
    /// frame `f - 1` (`column`), those ending in frame `f` (`next`), and per
    /// candidate the one before it (`back`). A candidate that cannot hold in
    /// frame `f` costs infinitely and keeps its stale velocity.
    fn advance(
        &self,
        f: usize,
        column: &Column,
        next: &mut Column,
        back: &mut [u32],
        coast_is_over: bool,
        params: &ContactParams,
    ) {
        let candidates = &self.candidates;
        let coast = candidates.len() - 1;
        let start = self.start_state();
        // A velocity change within one frame, in units of `cost_time_s`.
        let per_change = params.cost_time_s / self.dt;
        let hips_to_com_velocity = self.hips_to_com_velocity(f);
        // The floor's push between the velocity of frames f - 2 → f - 1 and
        // that of f - 1 → f, at frame f - 1.
        let pushed = f - 1;
        let push = self.floor_push(pushed, params);
        for (i, &candidate) in candidates.iter().enumerate() {
            let own = self.own_cost(candidate, f, params);
            if !own.is_finite() {
                next.cost[i] = f64::INFINITY;
                continue;
            }
            let now = self.footing.hips_velocity(candidate, f, self.dt).map(|v| v + hips_to_com_velocity);
            let range = push.range_from(self.footing.pressure_segment(candidate, pushed));
            // A coast that has lasted its longest can only land; a coast
            // from the start lands, it has no velocity to carry on.
            let barred = |j: usize| i == coast && (j == start || (j == coast && coast_is_over));
            // Coasting keeps the velocity it comes in with. A pin with no
            // velocity before it (in frame 1, or after the start's coast)
            // is compared with its own next move.
            let own_next = || now.map_or(0.0, |v| self.own_next_change(candidate, f, v, params));
            let unexplained = |j: usize| match now {
                Some(_) if self.open_start && (f == 1 || j == start) => own_next(),
                Some(_) if f == 1 => 0.0,
                Some(v) => {
                    range.unexplained(horizontal(v - column.com_velocity[j])).length() / params.slip_cm_per_s
                }
                None => 0.0,
            };
            let way_in = best_way_in(&column.cost, barred, coast, |j| {
                let u = unexplained(j);
                u * u * per_change
            });
            next.cost[i] = way_in.cost + own;
            next.com_velocity[i] =
                now.unwrap_or(if f > 1 { column.com_velocity[way_in.from] } else { DVec3::ZERO });
            back[i] = way_in.from as u32;
        }
    }

    /// One frame of the forward pass for [`Problem::start_state`]: coasting
    /// on from the start, until `is_over`.
    fn advance_start(
        &self,
        f: usize,
        column: &Column,
        next: &mut Column,
        back: &mut [u32],
        is_over: bool,
        params: &ContactParams,
    ) {
        let start = self.start_state();
        next.cost[start] = if is_over {
            f64::INFINITY
        } else {
            column.cost[start] + self.own_cost(Candidate::Coast, f, params)
        };
        next.com_velocity[start] = DVec3::ZERO;
        back[start] = start as u32;
    }

    /// How far (in `slip_cm_per_s`) the centre of mass's velocity `now`,
    /// which `candidate` gives for the move into frame `f`, changes beyond
    /// the floor's push if `candidate` holds for the move after it too; zero
    /// in the last frame, infinite where it cannot hold then.
    fn own_next_change(&self, candidate: Candidate, f: usize, now: DVec3, params: &ContactParams) -> f64 {
        if f + 1 >= self.frame_count() {
            return 0.0;
        }
        if !self.own_cost(candidate, f + 1, params).is_finite() {
            return f64::INFINITY;
        }
        let Some(after) = self.footing.hips_velocity(candidate, f + 1, self.dt) else { return 0.0 };
        let after = after + self.hips_to_com_velocity(f + 1);
        let range = self.floor_push(f, params).range_from(self.footing.pressure_segment(candidate, f));
        range.unexplained(horizontal(after - now)).length() / params.slip_cm_per_s
    }

    /// The best sequence, read back from the trellis's cheapest end.
    fn backtrack(&self, trellis: &Trellis) -> Solution {
        let n = self.frame_count();
        let start = self.start_state();
        let m = self.state_count();
        let cost = &trellis.cost;
        let mut i = (0..m).min_by(|&a, &b| cost[a].total_cmp(&cost[b])).unwrap_or(m - 1);
        let total_cost = cost[i];
        let mut chosen = vec![self.state_candidate(i); n];
        // Where the coast from the start ends: the frame of the first pin
        // after it (`n` when none follows), `None` without one.
        let mut start_ends = (i == start).then_some(n);
        for f in (1..n).rev() {
            chosen[f] = self.state_candidate(i);
            i = trellis.back[f * m + i] as usize;
            if i == start && start_ends.is_none() {
                start_ends = Some(f);
            }
        }
        chosen[0] = chosen.get(1).copied().unwrap_or(self.state_candidate(i));
        // It carries the velocity its first pin sets (none without one).
        let start_com_velocity = match start_ends {
            Some(k) if k < n => self.hips_velocity(chosen[k], k) + self.hips_to_com_velocity(k),
            _ => DVec3::ZERO,
        };
        let hips_velocity = (0..n)
            .map(|f| match chosen[f] {
                Candidate::Coast if start_ends.is_some_and(|k| f < k) => {
                    start_com_velocity - self.hips_to_com_velocity(f)
                }
                Candidate::Coast => trellis.carried[f] - self.hips_to_com_velocity(f),
                c => self.hips_velocity(c, f),
            })
            .collect();
        Solution { chosen, hips_velocity, cost: total_cost }
    }
}

/// Of the sequences ending in each state `j` with `cost[j]`, the one whose
/// move on costs least (`cost[j] + change_cost(j)`), skipping the
/// impossible ones and those `barred`; `fallback` when none is possible.
fn best_way_in(
    cost: &[f64],
    barred: impl Fn(usize) -> bool,
    fallback: usize,
    change_cost: impl Fn(usize) -> f64,
) -> WayIn {
    let mut best = WayIn { cost: f64::INFINITY, from: fallback };
    for (j, &before) in cost.iter().enumerate() {
        if !before.is_finite() || barred(j) {
            continue;
        }
        let total = before + change_cost(j);
        if total < best.cost {
            best = WayIn { cost: total, from: j };
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::sole::{Sole, SolePart};

    const DT: f64 = 1.0 / 30.0;

    /// A flat sole of heel, under-ankle and toe, `x` cm beside the hips,
    /// its heel `heel_z(f)` cm ahead of them in frame `f`.
    fn sole(x: f64, heel_z: impl Fn(usize) -> f64) -> Sole {
        Sole {
            parts: vec![SolePart::Heel, SolePart::UnderAnkle, SolePart::Joint(2)],
            hips_to_points_cm: (0..3)
                .flat_map(|f| [0.0, 6.0, 20.0].map(|ahead| DVec3::new(x, -90.0, heel_z(f) + ahead)))
                .collect(),
            floor_offsets_cm: vec![0.0; 3],
            tip: 2,
        }
    }

    /// Three frames of a body moving along +Z at 100 cm/s over its left
    /// foot, whose right foot slides forward at `slide_cm_per_s`.
    fn problem(slide_cm_per_s: f64, in_place: bool) -> Problem {
        let still = |f: usize| -100.0 * DT * f as f64;
        let right = move |f: usize| still(f) + slide_cm_per_s * DT * f as f64;
        let footing = Footing::new(PerFoot::new(sole(-10.0, still), sole(10.0, right)));
        let none = vec![None; 3];
        Problem::new(
            footing,
            vec![DVec3::ZERO; 3],
            PerFoot::new(none.clone(), none),
            DT,
            false,
            vec![in_place; 3],
        )
    }

    #[test]
    fn a_double_support_pays_for_a_foot_sliding_beyond_the_noise() {
        let params = ContactParams::default();
        // Two standing feet, and two that move apart no faster than the
        // noise the choice keeps reaches in one frame of twenty (12.5 cm/s
        // per axis and foot: 43.3 cm/s), cost nothing.
        assert_eq!(problem(0.0, false).double_slide_cost(1, &params), 0.0);
        assert_eq!(problem(43.0, false).double_slide_cost(1, &params), 0.0);
        // A foot sliding in at 100 cm/s: each foot slides by half of what
        // is beyond the noise, each slide a slip's cost.
        let beyond = 0.5 * (100.0 - 43.27) / 25.0;
        let cost = problem(100.0, false).double_slide_cost(1, &params);
        assert!((cost - 2.0 * beyond * beyond * DT / params.cost_time_s).abs() < 1e-3, "{cost}");
        // Where the body is in place, the feet moving apart is the pose's
        // drift.
        assert_eq!(problem(100.0, true).double_slide_cost(1, &params), 0.0);
        // The first frame has no move into it.
        assert_eq!(problem(100.0, false).double_slide_cost(0, &params), 0.0);
    }
}
