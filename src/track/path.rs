//! The fused tracker's offline path search along the camera's lines of
//! sight. The forward filter (`smoother`) carries one position per frame,
//! so where the energy has two valleys along the line of sight — a body
//! nearer and one farther that fit about as well — it stays in whichever it
//! entered, and a standing actor's tiny inertial steps keep it there. Here
//! every frame offers a line of candidates along its line of sight, and the
//! path through them is chosen as a whole (Viterbi): a valley that fits
//! better over many frames wins over one frame's better fit, and a jump the
//! suit's steps cannot explain costs what it should.
//!
//! Costs, in nats: a candidate's energy above the frame's least, over
//! `temperature_px` (the energy taken as the negative log-likelihood's
//! scale); a move between frames, `|Δ − s|² / 2σ²` with `s` the expected
//! (inertial) step and `σ` its uncertainty.
//!
//! [`PathSearch`] keeps what the search needs of each frame while the
//! video is read, the energies perhaps scored elsewhere ([`PathRequest`]),
//! and runs the forward filter again through the chosen path.

use glam::{DMat2, DVec2};

use crate::error::Error;
use crate::image::Shrink;
use crate::track::smoother::FloorFilter;
use crate::track::smoother::frames_per_error;

/// One frame's candidates and how the body was expected to move into it.
#[derive(Clone, Debug, PartialEq)]
pub struct PathFrame {
    /// Floor positions (x, z, cm).
    pub candidates_cm: Vec<DVec2>,
    /// Their energies (px); NaN where the body is not in the image.
    pub energies_px: Vec<f64>,
    /// The step expected from the frame before (cm).
    pub expected_step_cm: DVec2,
    /// How far that step may be off (cm, one σ per axis); infinite where
    /// nothing ties this frame to the one before.
    pub step_sigma_cm: f64,
}

/// The least-cost path: per frame, the index of its chosen candidate.
/// A frame without candidates (no pose there) is passed through: the path
/// on either side of it is chosen as two paths, each whole, and the frame
/// itself gets the index its last frame before had.
pub fn best_path(frames: &[PathFrame], temperature_px: f64) -> Vec<usize> {
    let mut cost: Vec<f64> = Vec::new();
    let mut from: Vec<Vec<usize>> = Vec::with_capacity(frames.len());
    for (i, frame) in frames.iter().enumerate() {
        if frame.candidates_cm.is_empty() {
            // The costs so far stand; back through here, each stays itself.
            from.push((0..cost.len()).collect());
            continue;
        }
        let unary = unary_costs(&frame.energies_px, temperature_px);
        let tied = i > 0
            && frame.step_sigma_cm.is_finite()
            && !cost.is_empty()
            && frames[i - 1].candidates_cm.len() == cost.len();
        let mut next = vec![0.0; unary.len()];
        let mut back = vec![0usize; unary.len()];
        let best_before = cost.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).map(|(j, c)| (j, *c));
        for (k, u) in unary.iter().enumerate() {
            let (j, c) = if tied {
                let previous = &frames[i - 1].candidates_cm;
                let sigma2 = frame.step_sigma_cm * frame.step_sigma_cm;
                let mut least = (0usize, f64::INFINITY);
                for (j, before) in cost.iter().enumerate() {
                    let miss = frame.candidates_cm[k] - previous[j] - frame.expected_step_cm;
                    let c = before + miss.length_squared() / (2.0 * sigma2.max(1e-12));
                    if c < least.1 {
                        least = (j, c);
                    }
                }
                least
            } else {
                best_before.unwrap_or((0, 0.0))
            };
            next[k] = c + u;
            back[k] = j;
        }
        cost = next;
        from.push(back);
    }
    let mut path = vec![0usize; frames.len()];
    let Some((mut k, _)) = cost.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)) else {
        return path;
    };
    for i in (0..frames.len()).rev() {
        path[i] = k;
        k = from[i].get(k).copied().unwrap_or(0);
    }
    path
}

/// Each candidate's energy above the frame's least over `temperature_px`;
/// a candidate off the image costs as much as the frame's worst (it says
/// nothing, but must not be a refuge), a frame with no energy at all costs
/// nothing anywhere.
fn unary_costs(energies_px: &[f64], temperature_px: f64) -> Vec<f64> {
    let finite = energies_px.iter().copied().filter(|e| e.is_finite());
    let least = finite.clone().fold(f64::INFINITY, f64::min);
    let most = finite.fold(f64::NEG_INFINITY, f64::max);
    if !least.is_finite() {
        return vec![0.0; energies_px.len()];
    }
    energies_px
        .iter()
        .map(|e| if e.is_finite() { *e - least } else { most - least } / temperature_px.max(1e-12))
        .collect()
}

/// What the path search asks of one frame when its energies are deferred
/// ([`PathSearch::defer`]): the fused energy at each candidate, in the
/// frame's terms as the tracker made them.
#[derive(Clone, Debug, PartialEq)]
pub struct PathRequest {
    /// The video frame.
    pub frame: usize,
    /// Where the frame's terms were made (x, z, cm): the prediction, or
    /// where a lost tracker's best guess put the body.
    pub terms_at_cm: DVec2,
    /// The cap of the distance transforms the frame's features had.
    pub truncate_px: Option<f32>,
    /// How much the frame was shrunk before it was read
    /// (`track::working_scale`).
    pub working_scale: Shrink,
    /// Where to score (x, z, cm).
    pub candidates_cm: Vec<DVec2>,
}

/// What the path search keeps of one frame.
#[derive(Clone, Debug)]
pub struct PathRecord {
    pub frame: PathFrame,
    /// Its energies are deferred and have not come yet.
    pub pending: bool,
    /// The suit's own step into this frame, as the forward filter took it.
    pub inertial_step_cm: DVec2,
    /// How uncertain the frame's fit was across the line of sight (cm²).
    pub across_variance_cm2: f64,
    /// The line of sight's direction on the floor.
    pub along: DVec2,
}

/// The path search's frames over a take, as they are read.
#[derive(Clone, Debug, Default)]
pub struct PathSearch {
    /// One per frame read while the search is on; `None` without a pose.
    records: Vec<Option<PathRecord>>,
    /// Whether the energies are left to the caller, and the last frame's request.
    deferred: bool,
    request: Option<PathRequest>,
}

impl PathSearch {
    /// From now on the energies of a frame whose fit is believable are not
    /// scored by the tracker but asked for ([`PathSearch::take_request`]).
    pub fn defer(&mut self) {
        self.deferred = true;
    }

    pub fn is_deferred(&self) -> bool {
        self.deferred
    }

    /// What the frame just read leaves to score.
    pub fn take_request(&mut self) -> Option<PathRequest> {
        self.request.take()
    }

    /// Forgets the last frame's request: a new frame is read.
    pub fn next_frame(&mut self) {
        self.request = None;
    }

    /// Keeps a frame's record (`None`: no pose there), and its request
    /// when its energies are deferred.
    pub fn push(&mut self, record: Option<PathRecord>, request: Option<PathRequest>) {
        self.records.push(record);
        self.request = request;
    }

    /// The energies of a [`PathRequest`]'s candidates. An error when the
    /// frame asked for none or the count differs.
    pub fn set_energies(&mut self, frame: usize, energies_px: Vec<f64>) -> Result<(), Error> {
        let record = self.records.get_mut(frame).and_then(|r| r.as_mut());
        match record {
            Some(r) if r.pending && r.frame.candidates_cm.len() == energies_px.len() => {
                r.frame.energies_px = energies_px;
                r.pending = false;
                Ok(())
            }
            _ => Err(Error::whole(
                &format!("video frame {frame}"),
                format!("{} path energies that no request of this frame asked for", energies_px.len()),
            )),
        }
    }

    /// How many frames still wait for their energies.
    pub fn pending(&self) -> usize {
        self.records.iter().flatten().filter(|r| r.pending).count()
    }

    /// The frames still waiting get energies that say nothing (a fit not
    /// believed); how many they were.
    pub fn give_up_pending(&mut self) -> usize {
        let mut count = 0;
        for r in self.records.iter_mut().flatten().filter(|r| r.pending) {
            r.frame.energies_px = vec![f64::NAN; r.frame.candidates_cm.len()];
            r.pending = false;
            count += 1;
        }
        count
    }

    /// The forward filter run again with the best path's choices as its
    /// measurements (along the line of sight as uncertain as the
    /// candidates' `spacing_cm`, across as the fits were; frames `dt_s`
    /// apart, each counting as [`frames_per_error`]'s share), ready for
    /// smoothing; `None` when the search had no frames or does not match
    /// `first_pass` (which starts at the first frame with a pose, as the
    /// records do).
    pub fn refilter(
        &self,
        first_pass: &FloorFilter,
        temperature_px: f64,
        spacing_cm: f64,
        dt_s: f64,
        reacquire_after: usize,
    ) -> Option<FloorFilter> {
        let start = self.records.iter().position(|f| f.is_some())?;
        let records = &self.records[start..];
        if records.len() != first_pass.frame_count() {
            return None;
        }
        let frames: Vec<PathFrame> = records
            .iter()
            .map(|r| {
                r.as_ref().map_or(
                    PathFrame {
                        candidates_cm: Vec::new(),
                        energies_px: Vec::new(),
                        expected_step_cm: DVec2::ZERO,
                        step_sigma_cm: f64::INFINITY,
                    },
                    |r| r.frame.clone(),
                )
            })
            .collect();
        // Frames within one error's time repeat it: their energies count
        // as that share of one, and a chosen candidate is as much less sure.
        let share = frames_per_error(dt_s);
        let chosen = best_path(&frames, temperature_px * share);
        let along_variance = spacing_cm * spacing_cm * share;
        let measurement = |r: &PathRecord, k: usize| {
            let across = r.along.perp();
            let basis = DMat2::from_cols(r.along, across);
            let covariance = basis
                * DMat2::from_diagonal(DVec2::new(along_variance, r.across_variance_cm2))
                * basis.transpose();
            (r.frame.candidates_cm[k], covariance)
        };
        let first = records[0].as_ref()?;
        let (start_cm, _) = measurement(first, chosen[0]);
        let mut filter = FloorFilter::new(start_cm, spacing_cm, dt_s, reacquire_after);
        for (record, &k) in records.iter().zip(&chosen).skip(1) {
            match record {
                None => {
                    filter.predict(DVec2::ZERO, 0.0);
                }
                Some(r) => {
                    filter.predict(r.inertial_step_cm, r.frame.step_sigma_cm);
                    if r.frame.energies_px.iter().any(|e| e.is_finite()) {
                        let (p, covariance) = measurement(r, k);
                        filter.update(p, covariance);
                    }
                }
            }
        }
        Some(filter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(energies_px: Vec<f64>, step: f64, sigma: f64) -> PathFrame {
        PathFrame {
            candidates_cm: (0..energies_px.len()).map(|k| DVec2::new(0.0, 10.0 * k as f64)).collect(),
            energies_px,
            expected_step_cm: DVec2::new(0.0, step),
            step_sigma_cm: sigma,
        }
    }

    #[test]
    fn a_valley_that_fits_better_over_many_frames_wins_over_a_single_frame() {
        // Candidates at 0, 10, 20 cm; the body stands still (σ 2 cm a frame).
        // Frames 0–9 prefer 20 cm a little; frame 5 alone prefers 0 cm a lot.
        let mut frames: Vec<PathFrame> = (0..10).map(|_| line(vec![1.0, 0.8, 0.7], 0.0, 2.0)).collect();
        frames[5] = line(vec![0.0, 1.0, 1.0], 0.0, 2.0);
        let path = best_path(&frames, 0.1);
        assert_eq!(path, vec![2; 10]);
        // Untied frames each take their own least.
        let loose: Vec<PathFrame> =
            frames.iter().cloned().map(|f| PathFrame { step_sigma_cm: f64::INFINITY, ..f }).collect();
        assert_eq!(best_path(&loose, 0.1)[5], 0);
    }

    #[test]
    fn frames_without_candidates_split_the_path_in_two_whole_ones() {
        // Before the gap the body is at 20 cm, after it at 0 cm; the gap at
        // the end too (a video longer than its BVH).
        let empty = PathFrame {
            candidates_cm: Vec::new(),
            energies_px: Vec::new(),
            expected_step_cm: DVec2::ZERO,
            step_sigma_cm: f64::INFINITY,
        };
        let mut frames: Vec<PathFrame> = (0..3).map(|_| line(vec![1.0, 0.5, 0.0], 0.0, 2.0)).collect();
        frames.push(empty.clone());
        frames.extend((0..3).map(|_| line(vec![0.0, 0.5, 1.0], 0.0, 2.0)));
        frames.push(empty);
        assert_eq!(best_path(&frames, 0.1), vec![2, 2, 2, 2, 0, 0, 0, 0]);
    }

    #[test]
    fn the_path_follows_the_expected_steps_where_the_energy_says_nothing() {
        // 10 cm a frame expected; energies flat (NaN: off the image) after the first.
        let mut frames = vec![line(vec![1.0, 0.0, 1.0, 1.0, 1.0], 0.0, f64::INFINITY)];
        frames.extend((0..3).map(|_| line(vec![f64::NAN; 5], 10.0, 1.0)));
        assert_eq!(best_path(&frames, 0.1), vec![1, 2, 3, 4]);
    }
}
