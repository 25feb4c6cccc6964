//! The sampling grid: the contacts are chosen on frames about
//! `cost_time_s` apart, once for each way of taking them (the phases), and
//! the phases' results are brought back to every frame and averaged, or
//! voted on.
//!
//! The costs weigh evidence per unit of time, but a change of pinned point
//! is a jump of velocity, and a jump costs once per frame it happens in,
//! whatever the rate: on every frame at 100 Hz it would weigh three times
//! what it does at 30 fps against everything else, and velocities from
//! 10 ms differences carry three times the jitter. On frames about 1/30 s
//! apart (22.5 to 45 per second) a recording at any rate is weighed nearly
//! as a 30 fps one is. Solving every phase and averaging makes the result
//! independent of which frames happened to be taken; between its frames, a
//! phase's pinned point still holds still frame by frame. Each phase's
//! sequence is the exact optimum; their average is not a sequence of its
//! own.

use glam::DVec3;

use super::ContactParams;
use super::carry::{ExitReading, Stance, StanceExit, pressed_at};
use super::flight::{Lifts, flights};
use super::footing::{Candidate, Footing};
use super::noise::smoothing_samples;
use super::solve::{Problem, Solution};
use super::still::eased_widths;
use crate::body::feet::PerFoot;
use crate::body::sole::Sole;
use crate::signal::smoothing::{smooth_paths, smooth_paths_wider_where};

/// The choice of contacts on `frames` (in that order, `dt` s apart) of
/// `soles` and `motion`.
fn problem_at(frames: &[usize], soles: &PerFoot<Sole>, motion: &Motion, dt: f64) -> Problem {
    Problem::new(
        Footing::new(soles.as_ref().map(|sole| sole.at_frames(frames))),
        frames.iter().map(|&f| motion.hips_to_com_cm[f]).collect(),
        motion.accel_off_g.as_ref().map(|off| frames.iter().map(|&f| off[f]).collect()),
        dt,
        motion.open_start,
        frames.iter().map(|&f| motion.in_place[f]).collect(),
    )
}

/// How many frames apart the contacts are chosen: the whole number of frames
/// nearest `cost_time_s`, at least one (every frame at 30 fps, every third at
/// 100 Hz, every second from 45 fps).
pub(super) fn grid_step(fps: f64, cost_time_s: f64) -> usize {
    ((fps * cost_time_s).round() as usize).max(1)
}

/// The recording's motion that the choice of contacts weighs besides the
/// soles, at every frame.
pub(super) struct Motion {
    /// Per frame, the centre of mass relative to the hips (cm), smoothed as
    /// the soles are.
    pub hips_to_com_cm: Vec<DVec3>,
    /// Per foot and frame, how far its accelerometer reads from 1 g; `None`
    /// without a reading.
    pub accel_off_g: PerFoot<Vec<Option<f64>>>,
    /// The time between frames (s).
    pub dt: f64,
    /// Whether the take may start coasting with a velocity yet unknown.
    pub open_start: bool,
    /// Per frame, whether the body stays in place there (see
    /// [`super::solve::Problem::in_place`]).
    pub in_place: Vec<bool>,
}

/// One phase's choice of contacts and what it was chosen from.
pub(super) struct PhaseChoice {
    pub problem: Problem,
    pub solution: Solution,
}

/// The phases' height above standing and flights, brought back to every
/// frame.
pub(super) struct Vertical {
    /// Per frame, the hips' height above the floor (cm) with the lowest sole
    /// point on it, lifted in flight.
    pub height_cm: Vec<f64>,
    /// Per frame, whether most phases fly.
    pub flight: Vec<bool>,
}

/// Where frame `f` falls among a phase's frames: between its frames `a` and
/// `b`, `t` of the way from `a`.
struct Between {
    a: usize,
    b: usize,
    t: f64,
}

pub(super) struct Grid {
    /// How many frames apart a phase's frames are.
    pub step: usize,
    /// Per phase, the frames it takes: every `step`-th from the phase's
    /// index (fewer phases when the recording is shorter than a step).
    pub phases: Vec<Vec<usize>>,
    /// How far (samples) tracking jitter and noise are smoothed before the
    /// contacts are chosen: none where every frame is taken on a clean pose.
    pub sigma_samples: f64,
    /// The part of that smoothing the pose's noise asks for (samples): the
    /// time scale over which the noise, carried into the hips by the pinned
    /// points, is smoothed out of the hips' path.
    pub noise_sigma_samples: f64,
    /// Per frame, the smoothing for the choice (samples) where the pose's
    /// noise bursts and asks for more than `sigma_samples`; empty where it
    /// nowhere does ([`Grid::widen_where_noise_bursts`]).
    pub burst_sigma_samples: Vec<f64>,
}

impl Grid {
    /// The grid for `n` frames at `fps`, on a pose whose noise
    /// ([`super::noise::pose_noise`] on frames `step` apart) is `noise_cm`:
    /// the smoothing is the larger of the jitter smoothing (where frames are
    /// left out) and the one that brings the velocity of noise white on every
    /// frame down to `max_velocity_noise_cm_per_s` (a velocity over the
    /// grid's longer steps carries less of it).
    pub fn new(n: usize, fps: f64, noise_cm: f64, params: &ContactParams) -> Grid {
        let step = grid_step(fps, params.cost_time_s);
        let phases = (0..step.min(n)).map(|phase| (phase..n).step_by(step).collect()).collect();
        let jitter_samples = if step > 1 { params.jitter_s * fps } else { 0.0 };
        let noise_samples = smoothing_samples(noise_cm, 1.0 / fps, params.max_velocity_noise_cm_per_s);
        let noise_sigma_samples = noise_samples.min(params.max_noise_smoothing_s * fps);
        let sigma_samples = jitter_samples.max(noise_sigma_samples);
        Grid { step, phases, sigma_samples, noise_sigma_samples, burst_sigma_samples: Vec::new() }
    }

    /// Widens the choice's smoothing where the pose's noise read near a
    /// frame (`local_noise_cm`, see [`super::noise::local_noise_cm`]) is over
    /// `slip_cm_per_s / max_velocity_noise_cm_per_s` (twice) the recording's
    /// `noise_cm`: there, to what that noise asks (at most
    /// `max_noise_smoothing_s`), the widths changing as smoothly as the
    /// stillness's ([`eased_widths`]). Frames at `fps`.
    ///
    /// Why: the recording's smoothing brings its median noise down to
    /// `max_velocity_noise_cm_per_s`, half a slip unit. Where the noise is
    /// over twice that median, what is left of it is over a whole unit, and
    /// a planted foot's noise costs what its sliding would: the choice
    /// coasted through the kicks, where the body stands on one foot while
    /// the other kicks at 5–7 m/s, and carried on the velocity it came in
    /// with. Why not everywhere: a run's noise is its median throughout, and
    /// smoothing that reaches further blurs its stances (a shared run at
    /// level 0.5 lost its strides, 3.9 → 15.8 %, with the widths read near
    /// every frame).
    pub fn widen_where_noise_bursts(
        &mut self,
        local_noise_cm: &[f64],
        noise_cm: f64,
        fps: f64,
        params: &ContactParams,
    ) {
        let burst_cm = noise_cm * params.slip_cm_per_s / params.max_velocity_noise_cm_per_s;
        let widest = params.max_noise_smoothing_s * fps;
        let widths: Vec<f64> = local_noise_cm
            .iter()
            .map(|&cm| {
                if cm <= burst_cm {
                    return self.sigma_samples;
                }
                let asked = smoothing_samples(cm, 1.0 / fps, params.max_velocity_noise_cm_per_s).min(widest);
                asked.max(self.sigma_samples)
            })
            .collect();
        if widths.iter().all(|&w| w <= self.sigma_samples) {
            return;
        }
        let widths = eased_widths(&widths, 1.0 / fps);
        // Never below the recording's own smoothing; where the widening has
        // faded to rounding, that smoothing exactly.
        self.burst_sigma_samples = widths
            .into_iter()
            .map(|w| if w < self.sigma_samples + 1e-6 { self.sigma_samples } else { w })
            .collect();
    }

    /// `points` (`stride` paths interleaved frame by frame, as in
    /// [`smooth_paths`]) smoothed for the choice: over `sigma_samples`, and
    /// wider where the noise bursts.
    pub fn smooth_for_choice(&self, points: &[DVec3], stride: usize) -> Vec<DVec3> {
        if self.burst_sigma_samples.is_empty() {
            smooth_paths(points, stride, self.sigma_samples)
        } else {
            smooth_paths_wider_where(points, stride, self.sigma_samples, &self.burst_sigma_samples)
        }
    }

    /// Whether two successive moves' velocities, on the soles smoothed for
    /// the choice, are measured apart: a pin checked against its own next
    /// move (see [`super::solve`]'s start) is only checked if smoothing does
    /// not make them agree by itself. White noise smoothed by a Gaussian of
    /// `s` samples and differenced has a correlation of
    /// `(1 − 1/(2 s²)) e^(−1/(4 s²))` one sample apart: none at `s = 1/√2`,
    /// 0.39 at one sample, 0.82 at two. Clean recordings are smoothed by
    /// 0.4 samples or less, suit-grade ones by 0.1 (a bow) to 2.3 (a dash).
    pub fn moves_measured_apart(&self) -> bool {
        self.sigma_samples / self.step as f64 <= std::f64::consts::FRAC_1_SQRT_2
    }

    /// The best contacts of every phase on `soles` (at every frame).
    pub fn choose(&self, soles: &PerFoot<Sole>, motion: &Motion, params: &ContactParams) -> Vec<PhaseChoice> {
        let dt = motion.dt * self.step as f64;
        self.phases
            .iter()
            .map(|frames| {
                let problem = problem_at(frames, soles, motion, dt);
                let solution = problem.solve(params);
                PhaseChoice { problem, solution }
            })
            .collect()
    }

    /// `choices` (the best contacts of every phase on `soles`, see
    /// [`Grid::choose`]) with each phase's start read from what follows it.
    /// The choice runs forward, and a coasting stretch carries the velocity
    /// it came in with; but a take that starts mid-stride, in the air, has
    /// no velocity to come in with, and its first frames were pinned to
    /// whatever foot was lowest, their velocity carried on into the flight
    /// and the strides after it (the clean run with its first 4 frames cut
    /// off: 20 % off, from 0.65). Run backwards, the same costs carry the
    /// landing's velocity back into the flight, so the backward choice is
    /// taken up to the first frame where both pin the same point, and the
    /// forward choice from there on. (Where successive moves are measured
    /// apart, [`Grid::moves_measured_apart`], each pass may also start with
    /// a coast whose velocity its first pin sets; see `solve.rs`.)
    pub fn start_from_what_follows(
        &self,
        choices: &mut [PhaseChoice],
        soles: &PerFoot<Sole>,
        motion: &Motion,
        params: &ContactParams,
    ) {
        let dt = motion.dt * self.step as f64;
        for (frames, choice) in self.phases.iter().zip(choices.iter_mut()) {
            let Some(last) = frames.len().checked_sub(1) else { continue };
            let backwards: Vec<usize> = frames.iter().rev().copied().collect();
            let backward = problem_at(&backwards, soles, motion, dt).solve(params);
            // The forward move into step j is the backward move into step
            // last - j + 1, its velocity the other way.
            let into = |j: usize| last + 1 - j;
            let forward = &mut choice.solution;
            let agreed = (1..=last).find(|&j| {
                let both = backward.chosen[into(j)];
                both == forward.chosen[j] && matches!(both, Candidate::Point { .. })
            });
            // Never the same point: the two read the take apart throughout,
            // and the one that explains it at less cost is taken whole.
            let until = match agreed {
                Some(j) => j,
                None if backward.cost < forward.cost => last + 1,
                None => 1,
            };
            for j in 1..until {
                forward.chosen[j] = backward.chosen[into(j)];
                forward.hips_velocity[j] = -backward.hips_velocity[into(j)];
            }
        }
    }

    /// The step of `phase` whose move holds frame `f` (the frames before a
    /// phase's first step go with that step).
    fn step_at(&self, phase: usize, f: usize) -> usize {
        let last = self.phases[phase].len() - 1;
        f.saturating_sub(phase).div_ceil(self.step).clamp(1.min(last), last)
    }

    /// Where frame `f` falls among the `len` frames of `phase`.
    fn between(&self, phase: usize, f: usize, len: usize) -> Between {
        let s = (f as f64 - phase as f64) / self.step as f64;
        let (a, b) = (s.floor().max(0.0) as usize, s.ceil().max(0.0) as usize);
        let (a, b) = (a.min(len - 1), b.min(len - 1));
        let t = if b > a { s - a as f64 } else { 0.0 };
        Between { a, b, t }
    }

    /// The hips' horizontal path (cm) on `footing` (every frame, `dt` s
    /// apart), from `start`: each frame's velocity the mean of the phases'.
    /// Pinned points hold still frame by frame; a coasting body keeps the
    /// velocity of its phase's step, with `exit` scaled by how much faster
    /// the stances around end than that smoothed velocity reads them
    /// (`carry.rs`).
    pub fn hips_path(
        &self,
        footing: &Footing,
        choices: &[PhaseChoice],
        start: DVec3,
        dt: f64,
        exit: Option<&StanceExit>,
    ) -> Vec<DVec3> {
        let n = footing.frame_count();
        let mut velocity = vec![DVec3::ZERO; n];
        for (phase, choice) in choices.iter().enumerate() {
            for (sum, v) in velocity.iter_mut().zip(self.phase_velocities(phase, footing, choice, dt, exit)) {
                *sum += v;
            }
        }
        let mut path = vec![start; n];
        for f in 1..n {
            path[f] = path[f - 1] + velocity[f] / choices.len() as f64 * dt;
        }
        path
    }

    /// Per frame, the hips' horizontal velocity (cm/s) that `phase`'s
    /// `choice` gives (see [`Grid::hips_path`]); zero in frame 0. With
    /// `exit`, a coast's smoothed velocity is scaled by the shortfall of the
    /// smoothing read off the stances around it (`carry.rs`).
    fn phase_velocities(
        &self,
        phase: usize,
        footing: &Footing,
        choice: &PhaseChoice,
        dt: f64,
        exit: Option<&StanceExit>,
    ) -> Vec<DVec3> {
        let n = footing.frame_count();
        let solution = &choice.solution;
        let mut velocity = vec![DVec3::ZERO; n];
        let mut stance: Option<Stance> = None;
        let mut exits: Vec<ExitReading> = Vec::new();
        let mut scaled: Vec<usize> = Vec::new();
        let pressed = |f: usize| pressed_at(footing, solution.chosen[self.step_at(phase, f)], f);
        for f in 1..n {
            let g = self.step_at(phase, f);
            let candidate = solution.chosen[g];
            if let Some(pinned) = footing.hips_velocity(candidate, f, dt) {
                velocity[f] = pinned;
                stance = Stance::of(candidate, f, stance);
                continue;
            }
            velocity[f] = solution.hips_velocity[g];
            let Some(exit) = exit else { continue };
            // The stance is read on the first frame of the coast after it.
            if let Some(stance) = stance.take()
                && let Some(com) =
                    exit.velocity(stance, f, &velocity, pressed, &footing.lowest.standing_cm, dt)
            {
                exits.push(ExitReading {
                    frame: f,
                    read: exit.hips_velocity(com, f, dt),
                    smoothed: velocity[f],
                });
            }
            if !exit.in_place[f] {
                scaled.push(f);
            }
        }
        if let Some(exit) = exit {
            for f in scaled {
                velocity[f] *= exit.shortfall_at(f, &exits);
            }
        }
        velocity
    }

    /// The hips' height above standing `standing_cm` (every frame) and the
    /// flights: a flight where most phases fly, and only there (a foot that
    /// the method says is on the floor is on it), lifted by the phases'
    /// mean lift, each linear between its frames.
    pub fn vertical(&self, standing_cm: &[f64], choices: &[PhaseChoice], params: &ContactParams) -> Vertical {
        let lifts: Vec<Lifts> = choices.iter().map(|c| flights(&c.problem, &c.solution, params)).collect();
        let mut height_cm = standing_cm.to_vec();
        let mut flight = vec![false; standing_cm.len()];
        for f in 0..standing_cm.len() {
            let mut lift = 0.0;
            let mut flying = 0;
            for (phase, lifted) in lifts.iter().enumerate() {
                let Between { a, b, t } = self.between(phase, f, lifted.lift_cm.len());
                lift += lifted.lift_cm[a] * (1.0 - t) + lifted.lift_cm[b] * t;
                flying += usize::from(lifted.flight[if t < 0.5 { a } else { b }]);
            }
            flight[f] = 2 * flying > lifts.len();
            if flight[f] {
                height_cm[f] += lift / lifts.len() as f64;
            }
        }
        Vertical { height_cm, flight }
    }

    /// Per frame of `n`, the candidate most phases chose (ties go to the
    /// earliest phase's).
    pub fn decisions(&self, choices: &[PhaseChoice], n: usize) -> Vec<Candidate> {
        (0..n)
            .map(|f| {
                let votes: Vec<Candidate> = (0..choices.len())
                    .map(|phase| choices[phase].solution.chosen[self.step_at(phase, f)])
                    .collect();
                most_common(&votes)
            })
            .collect()
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::feet::Foot;

    #[test]
    fn the_grid_takes_frames_about_a_thirtieth_of_a_second_apart() {
        let cost_time_s = ContactParams::default().cost_time_s;
        for (fps, step) in
            [(24.0, 1), (30.0, 1), (44.0, 1), (45.0, 2), (60.0, 2), (100.0, 3), (10_000.0, 333)]
        {
            assert_eq!(grid_step(fps, cost_time_s), step, "{fps} fps");
        }
        // Fewer phases than the step when the recording is shorter.
        let grid = Grid::new(2, 100.0, 0.0, &ContactParams::default());
        assert_eq!(grid.phases, vec![vec![0], vec![1]]);
    }

    #[test]
    fn the_vote_goes_to_the_most_named_and_ties_to_the_first() {
        let left = Candidate::Point { foot: Foot::Left, point: 0 };
        assert_eq!(most_common(&[left, Candidate::Double, Candidate::Double]), Candidate::Double);
        assert_eq!(most_common(&[left, Candidate::Double]), left);
        assert_eq!(most_common(&[]), Candidate::Coast);
    }
}
