//! A take tracked before, opened to be watched, not tracked again: the
//! corrected recording `embusen track` wrote, its track CSV, the camera and
//! the video's size and rate give per video frame the body's outline where
//! the track put it, the track's figures for the plots, and the camera's
//! path for the 3D view: what the page shows after a track, without the
//! wait (a project page showing a tracked take to every visitor).
//!
//! The three files must be one take's: the CSV a row per video frame at
//! its time, the recording the one that track corrected. Anything else is
//! an error that says which file does not fit, never a picture of
//! something else.

use glam::DVec2;

use crate::app::frame_report::FrameProgress;
use crate::app::plot::CameraSeries;
use crate::app::tracking::{NamedBytes, VideoDescription, check_video, outlines_px};
use crate::camera::Camera;
use crate::error::Error;
use crate::io::hips_csv::parse_hips_csv;
use crate::io::recording::Recording;
use crate::track::setup::posed_body;
use crate::track::suit_motion::{SuitMotion, VideoTiming};
use crate::track::take::body_shape_of;

/// How far (cm) the corrected recording's hips may lie from its track's on
/// the floor at a video frame's instant. `embusen track` puts the hips of
/// each recording frame on the track read at that frame's time, linear
/// between video frames, so read back at the video's instants they meet it
/// up to the bend of the path between two video frames and the files'
/// rounding: millimetres. The suit's own recording, before correction, is
/// decimetres to metres off.
pub const TRACK_FIT_CM: f64 = 2.0;

/// A finished take, ready to show.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishedTake {
    /// Per video frame, where the track put the hips on the floor and how
    /// well the camera saw the body: what the plots show.
    pub path: Vec<FrameProgress>,
    /// Per video frame, the outline of the body model where the track put
    /// it, as the camera sees it: pixels `[x, y]`; none in a frame without
    /// a pose.
    pub outlines_px: Vec<Vec<[u32; 2]>>,
    /// The take as the player shows it: per recording frame its hips (the
    /// recording's coordinates, cm), the camera's path as the 3D view and
    /// the plots draw it; per video frame the recording's time it was read
    /// at and the uncertainty the track CSV states.
    pub series: CameraSeries,
}

impl FinishedTake {
    /// Opens the take from its corrected `recording`, its `track` CSV and
    /// its `camera`, filmed in `video` (named `video_name` in messages), the
    /// recording read `offset_s` after each video frame's time. Errors:
    /// a file that does not read (with its line and column), a video with
    /// no frames, a camera of another image size, a track with a row count
    /// or times not the video's, a recording whose hips are not on the
    /// track (more than [`TRACK_FIT_CM`] off).
    pub fn open(
        recording: NamedBytes,
        camera: NamedBytes,
        track: NamedBytes,
        video_name: &str,
        video: VideoDescription,
        offset_s: f64,
    ) -> Result<FinishedTake, Error> {
        let (recording, camera, timing) = read_view(recording, camera, video_name, &video, offset_s)?;
        let samples = parse_hips_csv(track.text()?, track.name)?;
        if samples.len() != video.frame_count {
            return Err(Error::whole(
                track.name,
                format!(
                    "has {} rows, {video_name} {} frames: it is not this video's track",
                    samples.len(),
                    video.frame_count
                ),
            ));
        }
        // Row `i` is video frame `i`, at its time (the rows follow the
        // header, line 1).
        let frame_time_s = |i: usize| i as f64 / video.fps;
        if let Some(i) =
            (0..samples.len()).find(|&i| (samples[i].time_s - frame_time_s(i)).abs() > 0.5 / video.fps)
        {
            return Err(Error::at(
                track.name,
                i + 2,
                1,
                format!(
                    "the row of frame {i} is at {:.6} s, {video_name}'s frame {i} at {:.6} s: it is not this video's track",
                    samples[i].time_s,
                    frame_time_s(i)
                ),
            ));
        }
        let suit = SuitMotion::new(&recording)?;
        let floor_cm: Vec<DVec2> = samples.iter().map(|s| DVec2::new(s.hips_cm.x, s.hips_cm.z)).collect();
        check_fit(&suit, &timing, &floor_cm, &recording.name, track.name)?;
        let confidence = samples.iter().map(|s| s.confidence.unwrap_or(0.0)).collect();
        let uncertainty_cm = samples.iter().map(|s| s.uncertainty_cm.unwrap_or(f64::NAN)).collect();
        view_of(&recording, &suit, &camera, &timing, floor_cm, confidence, uncertainty_cm)
    }

    /// Opens another view of a take tracked by several cameras: its
    /// corrected `recording` (the one track of all the views) as `camera`
    /// films it in `video`, the recording read `offset_s` after each video
    /// frame's time. The track CSV is on the first view's frames, so this
    /// view's places come from the recording's own hips, which `embusen
    /// track` put on the track; it states no confidence (0) or uncertainty
    /// (NaN). Errors as [`FinishedTake::open`]'s, and a recording with no
    /// pose in any frame of this video.
    pub fn open_other_view(
        recording: NamedBytes,
        camera: NamedBytes,
        video_name: &str,
        video: VideoDescription,
        offset_s: f64,
    ) -> Result<FinishedTake, Error> {
        let (recording, camera, timing) = read_view(recording, camera, video_name, &video, offset_s)?;
        let suit = SuitMotion::new(&recording)?;
        let floor_cm = suit.suit_floor_at(&timing.bvh_times_s(video.frame_count));
        if floor_cm.iter().all(|p| !p.is_finite()) {
            return Err(Error::whole(
                &recording.name,
                format!("has no pose at any frame of {video_name}: check the offset"),
            ));
        }
        let (unseen, unstated) = (vec![0.0; floor_cm.len()], vec![f64::NAN; floor_cm.len()]);
        view_of(&recording, &suit, &camera, &timing, floor_cm, unseen, unstated)
    }
}

/// The recording and camera of a view read, checked against its `video`
/// (a video with no frames, a camera of another image size are errors),
/// and the video's timing.
fn read_view(
    recording: NamedBytes,
    camera: NamedBytes,
    video_name: &str,
    video: &VideoDescription,
    offset_s: f64,
) -> Result<(Recording, Camera, VideoTiming), Error> {
    check_video(video_name, video, offset_s)?;
    let recording = Recording::parse(recording.bytes, recording.name, None)?;
    let camera = Camera::from_json(camera.text()?, camera.name)?;
    camera.check_image_size(video.width_px, video.height_px, video_name)?;
    let timing = VideoTiming { fps: video.fps, frame_count: video.frame_count, offset_s };
    Ok((recording, camera, timing))
}

/// A view of a finished take from the hips' place per video frame
/// (`floor_cm`, NaN where unknown) and what the track states there.
fn view_of(
    recording: &Recording,
    suit: &SuitMotion,
    camera: &Camera,
    timing: &VideoTiming,
    floor_cm: Vec<DVec2>,
    confidence: Vec<f64>,
    uncertainty_cm: Vec<f64>,
) -> Result<FinishedTake, Error> {
    let shape = body_shape_of(recording)?;
    let outlines_px = outlines_px(camera, &floor_cm, |i| posed_body(suit, &shape, timing, i));
    let path = floor_cm
        .iter()
        .zip(&confidence)
        .enumerate()
        .map(|(frame, (&floor_cm, &confidence))| FrameProgress { frame, floor_cm, confidence })
        .collect();
    let series = CameraSeries {
        hips_cm: recording.poses.trajectory(suit.hips),
        recording_time_s: timing.bvh_times_s(floor_cm.len()),
        uncertainty_cm,
        ..CameraSeries::default()
    };
    Ok(FinishedTake { path, outlines_px, series })
}

/// An error naming `recording_name` when the recording's own hips (`suit`'s
/// translation) are more than [`TRACK_FIT_CM`] from the track's
/// `floor_cm` at any video frame where the recording has a pose.
fn check_fit(
    suit: &SuitMotion,
    timing: &VideoTiming,
    floor_cm: &[DVec2],
    recording_name: &str,
    track_name: &str,
) -> Result<(), Error> {
    let times_s = timing.bvh_times_s(floor_cm.len());
    let own = suit.suit_floor_at(&times_s);
    // NaN where the recording has no pose: not compared.
    let worst = (0..floor_cm.len())
        .filter(|&i| own[i].is_finite())
        .map(|i| (i, own[i].distance(floor_cm[i])))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    match worst {
        None => Err(Error::whole(
            recording_name,
            format!("has no pose at any frame of the video {track_name} tracks: check the offset"),
        )),
        Some((i, off_cm)) if off_cm > TRACK_FIT_CM => Err(Error::whole(
            recording_name,
            format!(
                "its hips are {off_cm:.1} cm from {track_name}'s at video frame {i}: it is not the recording \
                 this track corrected (open the BVH `embusen track` wrote with it), or not at the offset it \
                 was tracked at ({} s here)",
                timing.offset_s
            ),
        )),
        Some(_) => Ok(()),
    }
}
