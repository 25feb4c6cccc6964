//! One filmed take ready to track, and what a track of it writes: the
//! corrected BVH and the hips CSV. The CLI (`embusen track`) and the browser
//! app both go through here, so the same inputs give the same bytes.

use glam::DVec3;

use crate::body::shape::BodyShape;
use crate::camera::Camera;
use crate::error::Error;
use crate::image::GreyImage;
use crate::image::pipeline::PipelineParams;
use crate::io::hips_csv::{HipsSample, format_hips_csv};
use crate::io::recording::Recording;
use crate::track::setup::TrackSetup;
use crate::track::suit_motion::{SuitMotion, VideoTiming};
use crate::track::tracker::{Track, TrackMethod};

/// A take read and checked: the suit's recording, the tracker's setup and method, and
/// what the user should be told before tracking (frames without a pose,
/// video and BVH of different lengths).
#[derive(Clone, Debug)]
pub struct Take {
    pub recording: Recording,
    pub setup: TrackSetup,
    /// The tracker it is to be tracked with.
    pub method: TrackMethod,
    pub warnings: Vec<String>,
}

/// What a track of a take writes.
#[derive(Clone, Debug, PartialEq)]
pub struct TakeExport {
    /// The recording with its hips where the track puts them (the BVH's or
    /// table's own format).
    pub recording_text: String,
    /// The hips per video frame with the camera's confidence.
    pub track_csv: String,
}

impl Take {
    /// The take of `recording` filmed by `camera` against `background`,
    /// its video timed by `timing`; `warnings` so far are kept in front.
    /// An error when the background's size is not the camera's, or the
    /// recording has no skeleton a body can be built on.
    pub fn new(
        recording: Recording,
        camera: Camera,
        background: GreyImage,
        timing: VideoTiming,
        method: TrackMethod,
        mut warnings: Vec<String>,
    ) -> Result<Take, Error> {
        camera.check_image_size(background.width_px, background.height_px, "the background")?;
        let suit = SuitMotion::new(&recording)?;
        let (video_fps, video_frames) = (timing.fps, timing.frame_count);
        for (first, last) in timing.frames_without_pose(&suit) {
            warnings
                .push(format!("video frames {first}–{last} have no pose in {}: not tracked", recording.name));
        }
        let video_s = video_frames as f64 / video_fps;
        let bvh_s = suit.frame_count() as f64 / suit.bvh_fps;
        if (video_s - bvh_s).abs() > 1.5 / video_fps.min(suit.bvh_fps) {
            warnings.push(format!(
                "the video lasts {video_s:.2} s ({video_frames} frames at {video_fps:.3} fps), the BVH {bvh_s:.2} s ({} frames at {:.3} fps)",
                suit.frame_count(),
                suit.bvh_fps
            ));
        }
        let shape = body_shape_of(&recording)?;
        let setup = TrackSetup {
            camera,
            suit: suit.into(),
            shape,
            timing,
            background,
            pipeline: PipelineParams::default(),
        };
        Ok(Take { recording, setup, method, warnings })
    }

    /// Where `track` (tracked with `timing`) puts the hips in each of the
    /// recording's frames (its own coordinates, cm): the corrected
    /// recording's hips, as the 3D view draws the camera's path.
    pub fn tracked_hips_cm(&self, track: &Track, timing: &VideoTiming) -> Vec<DVec3> {
        let shift = bvh_shift_cm(&self.recording, &self.setup.suit, timing, track);
        shift.iter().enumerate().map(|(f, s)| self.recording.poses.at(f, self.setup.suit.hips) + *s).collect()
    }

    /// The corrected recording and the hips CSV of `track`, tracked with
    /// `timing` (the take's own, or the one an offset estimate chose).
    pub fn export(&self, track: &Track, timing: &VideoTiming) -> TakeExport {
        let shift = bvh_shift_cm(&self.recording, &self.setup.suit, timing, track);
        TakeExport {
            recording_text: self.recording.write_shifted(&shift),
            track_csv: format_hips_csv(&track_samples(track)),
        }
    }
}

/// The body model a take of `recording` is tracked with: the standard
/// shape of its skeleton, scaled to its stature.
pub fn body_shape_of(recording: &Recording) -> Result<BodyShape, Error> {
    BodyShape::standard(&recording.joint_names, &recording.parents, recording.poses.frame(0))
}

/// The hips per BVH frame from the track (the video's frames read at the
/// BVH's times; past the video's ends the suit's own steps carry on), as the
/// shift of every joint that puts them there.
fn bvh_shift_cm(recording: &Recording, suit: &SuitMotion, timing: &VideoTiming, track: &Track) -> Vec<DVec3> {
    let n = recording.frame_count();
    let frames = &track.frames;
    let inertial = &suit.inertial_floor_cm;
    (0..n)
        .map(|f| {
            let video_position = timing.video_position(f as f64 / suit.bvh_fps);
            let floor = if frames.is_empty() {
                inertial[f]
            } else if video_position <= 0.0 {
                // Before the video (a positive offset): the suit's steps up
                // to the BVH frame at the video's first, which is on it.
                let first = ((timing.offset_s * suit.bvh_fps).round().max(0.0) as usize).min(n - 1);
                frames[0].floor_cm + inertial[f] - inertial[first]
            } else if video_position >= (frames.len() - 1) as f64 {
                let last_time_s = (frames.len() - 1) as f64 / timing.fps + timing.offset_s;
                let last = ((last_time_s * suit.bvh_fps).round().max(0.0) as usize).min(n - 1);
                frames[frames.len() - 1].floor_cm + inertial[f] - inertial[last]
            } else {
                let a = video_position.floor() as usize;
                let t = video_position - a as f64;
                frames[a].floor_cm.lerp(frames[a + 1].floor_cm, t)
            };
            let hips_now = recording.poses.at(f, suit.hips);
            let height = suit.body_cm.at(f, suit.hips).y;
            DVec3::new(floor.x, height, floor.y) - hips_now
        })
        .collect()
}

/// The track's hips per video frame, as the CSV has them.
fn track_samples(track: &Track) -> Vec<HipsSample> {
    track
        .frames
        .iter()
        .map(|f| HipsSample {
            time_s: f.time_s,
            hips_cm: DVec3::new(f.floor_cm.x, f.height_cm, f.floor_cm.y),
            confidence: Some(f.confidence),
            uncertainty_cm: f.uncertainty_cm.is_finite().then_some(f.uncertainty_cm),
        })
        .collect()
}
