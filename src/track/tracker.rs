//! The camera tracker, frame by frame, whichever tracker it is: each video
//! frame's features (`image::pipeline`: edges, foreground, distance
//! transforms) are computed once (`setup`), the suit's pose of that instant
//! is posed as a body (`body::shape`), and the chosen tracker fits its
//! silhouette (`silhouette`) to the frame near where the body should be:
//! Riečický et al.'s as published (`riecicky`) or embusen's (`fused`);
//! once every frame is read, the path is smoothed. Frames come in one at a
//! time, so a long video is never held in memory, and the same code runs
//! in the CLI (frames from ffmpeg) and in the browser (the worker's
//! WebCodecs decoder hands the frames' luma planes, `app::tracking`).

use glam::{DMat2, DVec2, DVec3};

use crate::error::Error;
use crate::image::pipeline::Features;
use crate::image::{GreyImage, Shrink};
use crate::track::fused::{FusedParams, FusedTrack, FusedTracker, SmoothedFrame};
use crate::track::path::PathRequest;
use crate::track::riecicky::{RiecickyParams, RiecickyTracker};
use crate::track::setup::{FrameEstimate, TrackSetup};
use crate::track::working_scale::{WorkingScales, shrunk_frame};

/// Which tracker, with its parameters. On the command line (`--method`)
/// and in the page it is named `paper` or `fused`, with the defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrackMethod {
    /// Riečický et al.'s, as published: 25 positions around the last, 10 cm apart.
    Riecicky(RiecickyParams),
    /// embusen's: the suit's motion predicts, the camera corrects, a
    /// forward–backward smoother weighs both.
    Fused(FusedParams),
}

impl Default for TrackMethod {
    fn default() -> Self {
        TrackMethod::Fused(FusedParams::DEFAULT)
    }
}

impl TrackMethod {
    /// Both, with their defaults, in the order the CLI lists them.
    pub const ALL: [TrackMethod; 2] =
        [TrackMethod::Fused(FusedParams::DEFAULT), TrackMethod::Riecicky(RiecickyParams::PUBLISHED)];

    /// The names of [`TrackMethod::ALL`], in its order.
    pub const NAMES: [&'static str; 2] = ["fused", "paper"];

    /// Its name for the user: `paper` or `fused` (Riečický et al.'s is the
    /// paper's tracker, as Hachaj & Ogiela's is the paper's translation).
    pub fn name(&self) -> &'static str {
        match self {
            TrackMethod::Fused(_) => TrackMethod::NAMES[0],
            TrackMethod::Riecicky(_) => TrackMethod::NAMES[1],
        }
    }

    /// What it is, in a line (the CLI's `--help` says it).
    pub fn summary(&self) -> &'static str {
        match self {
            TrackMethod::Riecicky(_) => {
                "Riečický et al.'s, as published: 25 positions around the last, 10 cm apart"
            }
            TrackMethod::Fused(_) => {
                "embusen's: the suit's motion predicts, the camera corrects, a forward–backward smoother weighs both"
            }
        }
    }

    /// The method named `name` ([`TrackMethod::name`]), with its defaults.
    pub fn named(name: &str) -> Option<TrackMethod> {
        TrackMethod::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// One video frame of a track.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackedFrame {
    /// The video frame's time (s).
    pub time_s: f64,
    /// Where the hips are on the floor (x, z, cm), smoothed.
    pub floor_cm: DVec2,
    /// Their height above the floor (cm), as the contact method stands the
    /// body; NaN where the BVH has no pose.
    pub height_cm: f64,
    /// How well the camera saw the body, 0 to 1 (0 where it was not used).
    pub confidence: f64,
    /// The camera's own measurement before smoothing, where one was used.
    pub measured_cm: Option<DVec2>,
    /// How far (cm, one σ) the hips may be from `floor_cm`, as the fused
    /// tracker weighs its evidence; NaN where it is not stated (the
    /// paper's tracker, a frame without a pose).
    pub uncertainty_cm: f64,
    /// The same per floor axis (x, z; cm²): where the camera measured, long
    /// along its line of sight and short across it; round where the suit's
    /// steps alone place the body; NaN where no uncertainty is stated.
    pub covariance_cm2: DMat2,
    /// The share of the image that differs from the background (0 to 1;
    /// NaN where the frame was not read, having no pose).
    pub foreground_share: f64,
    /// The noise measured on the frame's difference to the background
    /// (grey levels, one σ; NaN where not read).
    pub difference_noise: f64,
}

/// What one tracker says of a whole track beyond its frames.
#[derive(Clone, Debug, PartialEq)]
pub enum TrackDetails {
    Riecicky {
        params: RiecickyParams,
        /// Per video frame, the 25 positions tried (x, z, cm) with their
        /// energies (px); none in a frame without a pose.
        candidates: Vec<Vec<(DVec2, f64)>>,
    },
    Fused {
        params: FusedParams,
        /// The mean squared Mahalanobis distance of the camera's
        /// measurements from the predictions (NaN when no frame had a pose).
        mean_innovation: f64,
    },
}

/// A whole track.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    pub frames: Vec<TrackedFrame>,
    pub warnings: Vec<String>,
    pub details: TrackDetails,
}

impl Track {
    /// The tracker that made it.
    pub fn method(&self) -> TrackMethod {
        match &self.details {
            TrackDetails::Riecicky { params, .. } => TrackMethod::Riecicky(*params),
            TrackDetails::Fused { params, .. } => TrackMethod::Fused(*params),
        }
    }
}

/// The one tracker's own state between frames.
enum TrackerState {
    Riecicky(RiecickyTracker),
    Fused(Box<FusedTracker>),
}

/// The tracker in the middle of a video.
pub struct Tracker {
    /// The take (`WorkingScales::whole`) and the same at each working scale
    /// frames were read at, with their scorers (the paper's tracker reads
    /// every frame whole).
    scales: WorkingScales,
    state: TrackerState,
    frames: Vec<TrackedFrame>,
    /// With the path energies deferred: the features of the frame just
    /// read (cleared as the next is read), for a scorer beside the tracker
    /// in the same process to score its request from
    /// ([`Tracker::take_path_work`]).
    last_features: Option<Features>,
}

impl Tracker {
    /// An error when the background's size is not the camera's or the
    /// method's parameters make no search.
    pub fn new(setup: TrackSetup, method: TrackMethod) -> Result<Tracker, Error> {
        setup.camera.check_image_size(
            setup.background.width_px,
            setup.background.height_px,
            "the background",
        )?;
        let state = match method {
            TrackMethod::Riecicky(params) => TrackerState::Riecicky(RiecickyTracker::new(params)?),
            TrackMethod::Fused(params) => TrackerState::Fused(Box::new(FusedTracker::new(params))),
        };
        Ok(Tracker { scales: WorkingScales::new(setup), state, frames: Vec::new(), last_features: None })
    }

    /// From now on the fused tracker does not score the path search's
    /// candidates itself (half its work): after each frame
    /// [`Tracker::take_path_request`] says what to score, a
    /// [`crate::track::path_scorer::PathScorer`] scores it from the same frame
    /// (in the page, in a second worker, while this one reads the next
    /// frame), and [`Tracker::set_path_energies`] hands the energies back
    /// before [`Tracker::finish`]. The track is the same to the last bit.
    /// Nothing for the paper's tracker, which has no path search.
    pub fn defer_path_energies(&mut self) {
        if let TrackerState::Fused(fused) = &mut self.state {
            fused.path().defer();
        }
    }

    /// What the frame just read leaves to score (deferred only; `None`
    /// where it has nothing: no pose, a fit not believable, the paper's).
    pub fn take_path_request(&mut self) -> Option<PathRequest> {
        self.last_features = None;
        match &mut self.state {
            TrackerState::Fused(fused) => fused.path().take_request(),
            TrackerState::Riecicky(_) => None,
        }
    }

    /// [`Tracker::take_path_request`] with the frame's features the
    /// tracker made, for a scorer in the same process
    /// ([`crate::track::path_scorer::PathScorer::energies_with`]): the frame
    /// is read once, not once for each (the page's second worker has no
    /// share in this one's memory, and reads it again).
    pub fn take_path_work(&mut self) -> Option<(PathRequest, Features)> {
        // Both are made by the same push_frame, whenever deferred.
        let features = self.last_features.take();
        Some((self.take_path_request()?, features?))
    }

    /// The energies of a [`PathRequest`]'s candidates, as
    /// `PathScorer::energies` gave them. An error when the frame asked for
    /// none or the count differs.
    pub fn set_path_energies(&mut self, frame: usize, energies_px: Vec<f64>) -> Result<(), Error> {
        match &mut self.state {
            TrackerState::Fused(fused) => fused.path().set_energies(frame, energies_px),
            TrackerState::Riecicky(_) => Err(Error::whole(
                &format!("video frame {frame}"),
                format!("{} path energies that no request of this frame asked for", energies_px.len()),
            )),
        }
    }

    /// How many frames still wait for their path energies.
    pub fn path_energies_pending(&self) -> usize {
        match &self.state {
            TrackerState::Fused(fused) => fused.path_energies_pending(),
            TrackerState::Riecicky(_) => 0,
        }
    }

    /// The frames read so far.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Reads the next video frame.
    pub fn push_frame(&mut self, frame: &GreyImage) -> Result<&TrackedFrame, Error> {
        let i = self.frames.len();
        let label = format!("video frame {i}");
        let Tracker { scales, state, frames, last_features } = self;
        let setup = scales.whole();
        *last_features = None;
        setup.camera.check_image_size(frame.width_px, frame.height_px, &label)?;
        let time_s = i as f64 / setup.timing.fps;
        let instant = setup.suit.instant(setup.timing.bvh_time_s(i));
        let Some(body_cm) = setup.suit.body_at(instant) else {
            let floor_cm = frames.last().map_or(DVec2::ZERO, |f| f.floor_cm);
            match state {
                TrackerState::Riecicky(paper) => paper.skip_frame(floor_cm),
                TrackerState::Fused(fused) => fused.skip_frame(),
            }
            let estimate = FrameEstimate { floor_cm, confidence: 0.0, measured_cm: None };
            frames.push(tracked_frame(time_s, f64::NAN, estimate));
            return Ok(&frames[i]);
        };
        let height_cm = body_cm[setup.suit.hips].y;
        let body = setup.shape.pose(&body_cm, DVec3::ZERO)?;
        let (estimate, foreground) = match state {
            TrackerState::Riecicky(paper) => {
                let features = setup.published_features(frame, &label)?;
                (paper.frame(scales.at(Shrink::NONE).1, &body, &features), features)
            }
            TrackerState::Fused(fused) => {
                let prediction = fused.predict(setup, instant, i);
                let (scaled, scorer) = scales.at(prediction.working_scale);
                let frame = shrunk_frame(frame, prediction.working_scale);
                let features = scaled.features(&frame, prediction.truncate_px, &label)?;
                (fused.frame(scaled, scorer, &body, &features, &prediction, i), features)
            }
        };
        let mask = &foreground.foreground;
        let foreground_share = mask.count() as f64 / mask.on.len().max(1) as f64;
        let difference_noise = foreground.noise_sd as f64;
        if let TrackerState::Fused(fused) = state
            && fused.path().is_deferred()
        {
            *last_features = Some(foreground);
        }
        frames.push(TrackedFrame {
            foreground_share,
            difference_noise,
            ..tracked_frame(time_s, height_cm, estimate)
        });
        Ok(&frames[i])
    }

    /// The track, smoothed. Deferred path energies that never came count
    /// as a fit not believed (and are said in the warnings).
    pub fn finish(self) -> Track {
        let mut frames = self.frames;
        let (smoothed, mut warnings, details) = match self.state {
            TrackerState::Riecicky(paper) => {
                let params = paper.params();
                let (smoothed, candidates) = paper.finish();
                // The paper states no uncertainty.
                let smoothed =
                    smoothed.into_iter().map(|floor_cm| SmoothedFrame::round(floor_cm, f64::NAN)).collect();
                (smoothed, Vec::new(), TrackDetails::Riecicky { params, candidates })
            }
            TrackerState::Fused(fused) => {
                let params = fused.params();
                let FusedTrack { path, mean_innovation, warnings } =
                    fused.finish(&self.scales.whole().camera, 1.0 / self.scales.whole().timing.fps);
                let smoothed: Vec<SmoothedFrame> = path.unwrap_or_else(|| {
                    frames.iter().map(|f| SmoothedFrame::round(f.floor_cm, f64::NAN)).collect()
                });
                (smoothed, warnings, TrackDetails::Fused { params, mean_innovation })
            }
        };
        // The filter starts at the first frame with a pose: align the ends.
        let offset = frames.len().saturating_sub(smoothed.len());
        for (frame, smoothed) in frames.iter_mut().skip(offset).zip(smoothed) {
            frame.floor_cm = smoothed.floor_cm;
            if frame.height_cm.is_finite() {
                frame.uncertainty_cm = smoothed.uncertainty_cm;
                frame.covariance_cm2 = smoothed.covariance_cm2;
            }
        }
        // A frame without a pose has no height; one the camera did not see
        // has no confidence.
        let without_pose = frames.iter().filter(|f| f.height_cm.is_nan()).count();
        if without_pose > 0 {
            warnings
                .push(format!("{without_pose} video frames have no pose in the BVH (outside its time span)"));
        }
        warnings.extend(foreground_warnings(&frames));
        let unseen: Vec<bool> =
            frames.iter().map(|f| f.confidence == 0.0 && f.height_cm.is_finite()).collect();
        if let Some(unseen) = flagged_frames(&unseen) {
            warnings.push(format!(
                "the camera did not see the body well enough in video frames {unseen}: the suit's motion carries them"
            ));
        }
        Track { frames, warnings, details }
    }
}

/// A tracked frame of video time `time_s`, the hips `height_cm` above the
/// floor, where a tracker put it.
fn tracked_frame(time_s: f64, height_cm: f64, estimate: FrameEstimate) -> TrackedFrame {
    let FrameEstimate { floor_cm, confidence, measured_cm } = estimate;
    TrackedFrame {
        time_s,
        floor_cm,
        height_cm,
        confidence,
        measured_cm,
        uncertainty_cm: f64::NAN,
        covariance_cm2: DMat2::NAN,
        foreground_share: f64::NAN,
        difference_noise: f64::NAN,
    }
}

/// More of the image than this differing from the background is not an
/// actor: a body covers half a 4:3 image only within about a metre of the
/// camera, where its feet are out of view anyway.
pub const MISMATCHED_BACKGROUND_SHARE: f64 = 0.5;

/// A difference to the background noisier than this (grey levels, one σ)
/// is the scene, not the sensor: a camera's noise and its codec's are 1–4
/// levels, and the foreground threshold, measured on the difference,
/// follows the noise up until nothing is foreground.
pub const MISMATCHED_BACKGROUND_NOISE: f64 = 8.0;

/// Less than this (a few pixels in a thousand: the noise's specks left
/// after opening) is no one in view.
pub const EMPTY_ROOM_SHARE: f64 = 0.001;

/// What the foreground says of a take: frames where the background does
/// not match (most of the image differs: a still from another camera
/// position, the light changed, the camera moved), and frames where no one
/// is in view (the actor not yet in, or gone out and back), each with
/// their ranges.
fn foreground_warnings(frames: &[TrackedFrame]) -> Vec<String> {
    let mut warnings = Vec::new();
    let mismatched: Vec<bool> = frames
        .iter()
        .map(|f| {
            f.foreground_share > MISMATCHED_BACKGROUND_SHARE
                || f.difference_noise > MISMATCHED_BACKGROUND_NOISE
        })
        .collect();
    if let Some(frames) = flagged_frames(&mismatched) {
        warnings.push(format!(
            "the background does not match video frames {frames}: most of each differs from it — was the still taken from another camera position, or did the light change?"
        ));
    }
    let empty: Vec<bool> = frames
        .iter()
        .zip(&mismatched)
        .map(|(f, &mismatched)| !mismatched && f.foreground_share < EMPTY_ROOM_SHARE)
        .collect();
    if let Some(frames) = flagged_frames(&empty) {
        warnings.push(format!(
            "no one is in view in video frames {frames}: nothing there differs from the background"
        ));
    }
    warnings
}

/// The frames where `flags` holds, as `3–7, 12 (6 of 40)`; `None` when
/// there are none.
fn flagged_frames(flags: &[bool]) -> Option<String> {
    let count = flags.iter().filter(|&&f| f).count();
    (count > 0).then(|| format!("{} ({count} of {})", frame_ranges(flags), flags.len()))
}

/// The frames where `flags` holds, as ranges: `3–7, 12, 40–41`.
fn frame_ranges(flags: &[bool]) -> String {
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    for (i, _) in flags.iter().enumerate().filter(|(_, f)| **f) {
        match ranges.last_mut() {
            Some((_, last)) if *last + 1 == i => *last = i,
            _ => ranges.push((i, i)),
        }
    }
    let text: Vec<String> =
        ranges.iter().map(|&(a, b)| if a == b { a.to_string() } else { format!("{a}–{b}") }).collect();
    text.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_name_runs_and_single_frames() {
        let flags = [false, true, true, true, false, true, false, false, true, true];
        assert_eq!(frame_ranges(&flags), "1–3, 5, 8–9");
        assert_eq!(frame_ranges(&[false; 3]), "");
    }

    #[test]
    fn a_method_is_found_by_its_name() {
        assert_eq!(TrackMethod::ALL.map(|m| m.name()), TrackMethod::NAMES);
        for method in TrackMethod::ALL {
            assert_eq!(TrackMethod::named(method.name()), Some(method));
        }
        assert_eq!(TrackMethod::named("kalman"), None);
    }
}
