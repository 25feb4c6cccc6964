//! A camera-tracking job as the app runs it: a take (the suit's recording,
//! a camera file, a background still and the video's size and rate) is
//! opened from the bytes the page read, the video's frames come in one at a
//! time as the decoder's luma planes, and the end is the same corrected
//! recording and hips CSV `embusen track` writes for the same files. Kept
//! browser-free so native tests drive it with ffmpeg's frames; `web` runs
//! it in a Web Worker, and `embusen track` and `eval-track` run it on
//! ffmpeg's frames: the checks, the warnings, the background, the offset
//! estimate and the export are this one module's for all three.

use glam::{DVec2, DVec3};

use crate::app::frame_report::{Candidate, FrameProgress, RiecickyCandidates};
use crate::app::plot::CameraSeries;
use crate::body::shape::{BodyShape, PosedBody};
use crate::camera::Camera;
use crate::error::Error;
use crate::eval::track::{TrackErrors, frame_errors_cm, track_errors};
use crate::image::GreyImage;
use crate::image::background::median_background;
use crate::image::pipeline::Features;
use crate::io::hips_csv::parse_hips_csv;
use crate::io::image_file::png_to_grey;
use crate::io::recording::Recording;
use crate::signal::stats::median;
use crate::track::offset::{OFFSET_REACH_S, OffsetEstimate, estimate_offset_s, is_offset_sample};
use crate::track::path::PathRequest;
use crate::track::path_scorer::PathScorer;
use crate::track::silhouette::SilhouetteRenderer;
use crate::track::suit_motion::VideoTiming;
use crate::track::take::{Take, TakeExport};
use crate::track::tracker::{Track, TrackDetails, TrackMethod, Tracker};
use crate::track::views::{ViewSightings, fuse_views};

/// The video as the page's decoder describes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoDescription {
    pub width_px: u32,
    pub height_px: u32,
    pub fps: f64,
    /// How many frames the video is expected to have (for the warnings
    /// about a video and BVH of different lengths; more may come).
    pub frame_count: usize,
}

/// A file the page read: its name (for messages) and bytes.
#[derive(Clone, Copy, Debug)]
pub struct NamedBytes<'a> {
    pub name: &'a str,
    pub bytes: &'a [u8],
}

impl<'a> NamedBytes<'a> {
    /// The bytes as UTF-8 text; an error naming the file when they are not.
    pub fn text(&self) -> Result<&'a str, Error> {
        std::str::from_utf8(self.bytes).map_err(|e| Error::whole(self.name, format!("not UTF-8 text: {e}")))
    }
}

/// The still of the empty room the frames are compared with, and what the
/// user should be told about it.
#[derive(Clone, Debug)]
pub struct Background {
    pub image: GreyImage,
    pub warning: Option<String>,
}

impl Background {
    /// A still taken of the empty room.
    pub fn still(image: GreyImage) -> Background {
        Background { image, warning: None }
    }

    /// Without a still: the per-pixel median of `frames` spread over the
    /// video `video_name` stands for the empty room
    /// (`image::background::MEDIAN_FRAMES` of them, as `embusen track`
    /// samples them).
    pub fn median_of(frames: &[GreyImage], video_name: &str) -> Result<Background, Error> {
        let warning = format!(
            "no background still: the median of {} frames of the video stands for the empty room",
            frames.len()
        );
        Ok(Background { image: median_background(frames, video_name)?, warning: Some(warning) })
    }
}

/// A take's inputs once read: the suit's recording, the camera that filmed
/// it, the empty room.
#[derive(Clone, Debug)]
pub struct TakeInputs {
    pub recording: Recording,
    pub camera: Camera,
    pub background: Background,
}

/// One take being tracked.
pub struct TrackingJob {
    take: Take,
    video_name: String,
    tracker: Option<Tracker>,
    /// Scores other jobs' path requests (made when first asked).
    path_scorer: Option<PathScorer>,
    /// The frames kept to estimate the time offset from, when asked to
    /// ([`TrackingJob::keep_offset_samples`]): video frame index and frame.
    offset_samples: Option<Vec<(usize, GreyImage)>>,
    /// The finished track, for the outlines.
    track: Option<Track>,
}

impl TrackingJob {
    /// Opens the take: the recording and the camera parsed, the background
    /// still decoded (each error names its file and, in text, the line and
    /// column), then [`TrackingJob::new`]'s checks.
    pub fn open(
        recording: NamedBytes,
        camera: NamedBytes,
        background: NamedBytes,
        video_name: &str,
        video: VideoDescription,
        method: TrackMethod,
        offset_s: f64,
    ) -> Result<TrackingJob, Error> {
        let recording = Recording::parse(recording.bytes, recording.name, None)?;
        let camera = Camera::from_json(camera.text()?, camera.name)?;
        let background = Background::still(png_to_grey(background.bytes, background.name)?);
        TrackingJob::new(TakeInputs { recording, camera, background }, video_name, video, method, offset_s)
    }

    /// Opens the take from its `inputs` already read, filmed in `video`
    /// (named `video_name` in messages), to be tracked with `method` at
    /// `offset_s`. An error when the video has no frames or no rate, the
    /// offset is not a time, or the camera's image size is not the video's
    /// or the background's.
    pub fn new(
        inputs: TakeInputs,
        video_name: &str,
        video: VideoDescription,
        method: TrackMethod,
        offset_s: f64,
    ) -> Result<TrackingJob, Error> {
        check_video(video_name, &video, offset_s)?;
        let TakeInputs { recording, camera, background } = inputs;
        camera.check_image_size(video.width_px, video.height_px, video_name)?;
        let timing = VideoTiming { fps: video.fps, frame_count: video.frame_count, offset_s };
        let warnings = background.warning.into_iter().collect();
        let take = Take::new(recording, camera, background.image, timing, method, warnings)?;
        TrackingJob::of_take(take, video_name)
    }

    /// The job of tracking `take`, whose video is named `video_name`.
    fn of_take(take: Take, video_name: &str) -> Result<TrackingJob, Error> {
        let tracker = Tracker::new(take.setup.clone(), take.method)?;
        Ok(TrackingJob {
            take,
            video_name: video_name.to_string(),
            tracker: Some(tracker),
            path_scorer: None,
            offset_samples: None,
            track: None,
        })
    }

    /// A new job of the same take at the offset `estimate` found, when it
    /// is more than half a frame from the one tracked (`None`: the track
    /// stands), as `embusen track --estimate-offset` does.
    pub fn retrack_at(&self, estimate: &OffsetEstimate) -> Result<Option<TrackingJob>, Error> {
        let timing = self.take.setup.timing;
        if (estimate.offset_s - timing.offset_s).abs() * timing.fps <= 0.5 {
            return Ok(None);
        }
        let mut take = self.take.clone();
        take.setup.timing.offset_s = estimate.offset_s;
        TrackingJob::of_take(take, &self.video_name).map(Some)
    }

    /// What the user should know before the frames come (frames without a
    /// pose, a video and BVH of different lengths).
    pub fn warnings(&self) -> &[String] {
        &self.take.warnings
    }

    /// The frames read so far.
    pub fn frames_done(&self) -> usize {
        self.tracker.as_ref().map_or(0, |t| t.frame_count())
    }

    /// Tracks the next frame from its luma plane (see
    /// [`GreyImage::from_luma`]).
    pub fn push_luma(
        &mut self,
        luma: &[u8],
        stride: usize,
        full_range: bool,
    ) -> Result<FrameProgress, Error> {
        let grey = self.grey_of(luma, stride, full_range, self.frames_done())?;
        self.push_grey(&grey)
    }

    /// Video frame `frame` grey from its luma plane (see
    /// [`GreyImage::from_luma`]), the error naming it.
    fn grey_of(
        &self,
        luma: &[u8],
        stride: usize,
        full_range: bool,
        frame: usize,
    ) -> Result<GreyImage, Error> {
        let size = self.take.setup.camera.image_size;
        let label = format!("{} frame {frame}", self.video_name);
        GreyImage::from_luma(size.width_px, size.height_px, luma, stride, full_range, &label)
    }

    /// Tracks the next frame, already grey.
    pub fn push_grey(&mut self, grey: &GreyImage) -> Result<FrameProgress, Error> {
        let frame = self.frames_done();
        let Some(tracker) = self.tracker.as_mut() else {
            return Err(Error::whole(&self.video_name, "the tracking has ended: open the take again"));
        };
        let tracked = tracker.push_frame(grey)?;
        if let Some(samples) = &mut self.offset_samples
            && is_offset_sample(frame, self.take.setup.timing.frame_count)
        {
            samples.push((frame, grey.clone()));
        }
        Ok(FrameProgress { frame, floor_cm: tracked.floor_cm, confidence: tracked.confidence })
    }

    /// Keeps the frames the time offset is estimated from (as `embusen
    /// track --estimate-offset` does: [`crate::track::offset`]), for
    /// [`TrackingJob::estimate_offset`] after `finish`.
    pub fn keep_offset_samples(&mut self) {
        self.offset_samples.get_or_insert_with(Vec::new);
    }

    /// The offset between video and BVH at which the pose fits the kept
    /// frames best, within [`OFFSET_REACH_S`] of the offset tracked with;
    /// `None` when no kept frame had a pose to fit. An error before
    /// `finish` or when no frames were kept.
    pub fn estimate_offset(&self) -> Result<Option<OffsetEstimate>, Error> {
        let (Some(track), Some(samples)) = (&self.track, &self.offset_samples) else {
            return Err(Error::whole(
                &self.video_name,
                "to estimate the offset, keep its frames and track first",
            ));
        };
        Ok(estimate_offset_s(&self.take.setup, track, samples, OFFSET_REACH_S))
    }

    /// Leaves the path search's energies to another job of the same take
    /// ([`Tracker::defer_path_energies`]: in the page, a second worker).
    pub fn defer_path_energies(&mut self) {
        if let Some(tracker) = self.tracker.as_mut() {
            tracker.defer_path_energies();
        }
    }

    /// What the frame just tracked leaves to score, when deferred, with the
    /// frame's features for the scorer ([`Tracker::take_path_work`]; to
    /// another worker as [`Features::to_bytes`]).
    pub fn take_path_work(&mut self) -> Option<(PathRequest, Features)> {
        self.tracker.as_mut().and_then(Tracker::take_path_work)
    }

    /// Scores another job's request from the features that job made of the
    /// frame ([`TrackingJob::take_path_work`], [`Features::to_bytes`]):
    /// the page's second worker, which shares no memory with the tracker's,
    /// reads the frame no more than the CLI's second thread does. This job
    /// tracks nothing itself.
    pub fn score_path(&mut self, request: &PathRequest, features: &[u8]) -> Result<Vec<f64>, Error> {
        let features = Features::from_bytes(features, &format!("video frame {}", request.frame))?;
        self.path_scorer()?.energies_with(request, &features)
    }

    /// The scorer of the fused energy apart from the tracker (made when
    /// first asked); an error for the paper's tracker.
    fn path_scorer(&mut self) -> Result<&mut PathScorer, Error> {
        if self.path_scorer.is_none() {
            self.path_scorer = self.path_scorer_apart();
        }
        self.path_scorer
            .as_mut()
            .ok_or_else(|| Error::whole("<path scorer>", "only the fused tracker searches a path"))
    }

    /// A scorer of this job's deferred [`PathRequest`]s to run beside it,
    /// from the same frames (the CLI's second thread; the page's second
    /// worker opens a job of its own); `None` for the paper's tracker,
    /// which searches no path.
    pub fn path_scorer_apart(&self) -> Option<PathScorer> {
        match self.take.method {
            TrackMethod::Fused(params) => Some(PathScorer::new(self.take.setup.clone(), params)),
            TrackMethod::Riecicky(_) => None,
        }
    }

    /// Hands back the energies of a request this job made.
    pub fn set_path_energies(&mut self, frame: usize, energies_px: Vec<f64>) -> Result<(), Error> {
        match self.tracker.as_mut() {
            Some(tracker) => tracker.set_path_energies(frame, energies_px),
            None => Err(Error::whole(&self.video_name, "the tracking has ended: no path energies wanted")),
        }
    }

    /// Smooths the track and writes it; the warnings the tracking adds (frames
    /// the camera did not see) are in the returned list. An error when no
    /// frame was read, deferred path energies have not all come back, or
    /// the job has already finished.
    pub fn finish(&mut self) -> Result<(TakeExport, Vec<String>), Error> {
        if self.frames_done() == 0 {
            return Err(Error::whole(&self.video_name, "no frame was read: nothing to write"));
        }
        let pending = self.tracker.as_ref().map_or(0, Tracker::path_energies_pending);
        if pending > 0 {
            return Err(Error::whole(
                &self.video_name,
                format!("{pending} frames still wait for their path energies: hand them back first"),
            ));
        }
        let Some(tracker) = self.tracker.take() else {
            return Err(Error::whole(&self.video_name, "the tracking has already ended"));
        };
        let track = tracker.finish();
        let export = self.take.export(&track, &self.take.setup.timing);
        let warnings = track.warnings.clone();
        self.track = Some(track);
        Ok((export, warnings))
    }

    /// The finished track against the true hips of `truth` (a CSV of the
    /// hips per video frame, as the shared scenes' `NAME.truth.csv`): the
    /// horizontal error per frame (cm) over the frames both have, and its
    /// figures as `embusen eval-track` prints them. An error naming the file
    /// (`file:line:column`) when it does not read, or before `finish`.
    pub fn against_truth(&self, truth: NamedBytes) -> Result<(Vec<f64>, TrackErrors), Error> {
        let Some(track) = &self.track else {
            return Err(Error::whole(truth.name, "the take is not tracked yet: nothing to compare"));
        };
        let truth_cm: Vec<DVec2> = parse_hips_csv(truth.text()?, truth.name)?
            .iter()
            .map(|s| DVec2::new(s.hips_cm.x, s.hips_cm.z))
            .collect();
        let track_cm: Vec<DVec2> = track.frames.iter().map(|f| f.floor_cm).collect();
        Ok((frame_errors_cm(&track_cm, &truth_cm), track_errors(&track_cm, &truth_cm)))
    }

    /// The finished track as the player's plots show it: where it puts the
    /// hips in each of the recording's frames (cm, the recording's
    /// coordinates), and per video frame the recording's time it was
    /// read at and the uncertainty the tracker states (no error: that needs
    /// a truth, [`TrackingJob::against_truth`]); empty before `finish`.
    pub fn camera_series(&self) -> CameraSeries {
        let Some(track) = &self.track else { return CameraSeries::default() };
        let timing = &self.take.setup.timing;
        CameraSeries {
            hips_cm: self.take.tracked_hips_cm(track, timing),
            recording_time_s: timing.bvh_times_s(track.frames.len()),
            uncertainty_cm: track.frames.iter().map(|f| f.uncertainty_cm).collect(),
            ..CameraSeries::default()
        }
    }

    /// Riečický et al.'s candidates of each video frame of the finished track:
    /// the 25 positions it tried (x, z, cm) with their energies (px), and
    /// the index of the one it chose; none for the fused tracker, before
    /// `finish`, or in a frame without a pose.
    pub fn riecicky_candidates(&self) -> Vec<RiecickyCandidates> {
        let Some(track) = &self.track else { return Vec::new() };
        let none = Vec::new();
        let candidates = match &track.details {
            TrackDetails::Riecicky { candidates, .. } => candidates,
            TrackDetails::Fused { .. } => &none,
        };
        track
            .frames
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let tried: Vec<Candidate> = candidates
                    .get(i)
                    .map(|c| {
                        c.iter().map(|&(floor_cm, energy_px)| Candidate { floor_cm, energy_px }).collect()
                    })
                    .unwrap_or_default();
                RiecickyCandidates {
                    chosen: f.measured_cm.and_then(|m| tried.iter().position(|c| c.floor_cm == m)),
                    tried,
                }
            })
            .collect()
    }

    /// The finished track; none before `finish`.
    pub fn track(&self) -> Option<&Track> {
        self.track.as_ref()
    }

    /// The finished track, or an error naming the video when it is not.
    fn finished_track(&self) -> Result<&Track, Error> {
        self.track.as_ref().ok_or_else(|| Error::whole(&self.video_name, "this view is not tracked yet"))
    }

    /// How the take's video is timed against its recording.
    pub fn timing(&self) -> VideoTiming {
        self.take.setup.timing
    }

    /// For evaluations (`embusen eval-track --camera-oracle`): where the
    /// fused energy alone puts the body in video frame `i`, searched
    /// densely within `reach_cm` of the true `around_cm`
    /// ([`PathScorer::camera_oracle`]); the job tracks nothing itself.
    pub fn camera_oracle(
        &mut self,
        grey: &GreyImage,
        i: usize,
        around_cm: DVec2,
        reach_cm: f64,
    ) -> Result<Option<DVec2>, Error> {
        self.path_scorer()?.camera_oracle(grey, i, around_cm, reach_cm)
    }

    /// The body model the take is tracked with (as the 3D view draws it).
    pub fn body_shape(&self) -> &BodyShape {
        &self.take.setup.shape
    }

    /// The outer contour of the body (the tracker's model) where the
    /// finished track puts it in each video frame, as the camera sees it:
    /// pixels `[x, y]`, none in a frame without a pose or before `finish`.
    /// What the page draws over the video to show how the track fits.
    pub fn outlines_px(&self) -> Vec<Vec<[u32; 2]>> {
        let Some(track) = &self.track else { return Vec::new() };
        let floor_cm: Vec<DVec2> = track.frames.iter().map(|frame| frame.floor_cm).collect();
        let setup = &self.take.setup;
        outlines_px(&setup.camera, &floor_cm, |i| setup.posed_body(i))
    }
}

/// A view of a take tracked to the end by its own job, as the first
/// view's job weighs it in ([`TrackingJob::weigh`]): its video's name (for
/// messages) and what weighing reads of its track. In the page it crosses
/// from its worker to the first view's.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishedView {
    pub video_name: String,
    pub sightings: ViewSightings,
}

impl TrackingJob {
    /// This view, tracked to the end, for the first view's job to weigh in;
    /// an error before `finish`.
    pub fn finished_view(&self) -> Result<FinishedView, Error> {
        let track = self.finished_track()?;
        Ok(FinishedView {
            video_name: self.video_name.clone(),
            sightings: ViewSightings::of(track, self.take.setup.timing),
        })
    }

    /// This job's finished track (the first view's) weighed with the
    /// `others` ([`fuse_views`]), which becomes the job's track (its
    /// outlines, series and errors against a truth are then the weighed
    /// track's): what `embusen track` with several videos writes, and
    /// what the user should know of the views together (a view that films
    /// another span of the recording than the first: the track is on the
    /// first view's frames, each weighed with the views that film it).
    /// Errors naming the view: this job not finished; a view that puts the
    /// body more than [`VIEWS_DISAGREE_CM`] (the median over the take) from
    /// the first view's, as cameras calibrated into different worlds do.
    /// The job's track is as it was after an error.
    pub fn weigh(&mut self, others: &[FinishedView]) -> Result<(TakeExport, Vec<String>), Error> {
        let first_track = self.finished_track()?;
        let first_timing = &self.take.setup.timing;
        let mut warnings = Vec::new();
        // The span of the recording a view films (s).
        let span_s = |timing: &VideoTiming| {
            (timing.offset_s, timing.offset_s + timing.frame_count as f64 / timing.fps)
        };
        let (first_from, first_to) = span_s(first_timing);
        for (k, view) in others.iter().enumerate() {
            let number = k + 2;
            let timing = &view.sightings.timing;
            let (from, to) = span_s(timing);
            // More than a frame and a half apart at either end: not rounding.
            let frame_s = 1.0 / timing.fps.min(first_timing.fps);
            if (from - first_from).abs() > 1.5 * frame_s || (to - first_to).abs() > 1.5 * frame_s {
                warnings.push(format!(
                    "view {number} ({}) films the recording's {from:.2}–{to:.2} s, view 1 ({}) {first_from:.2}–{first_to:.2} s: the track is on view 1's frames, each weighed with the views that film it",
                    view.video_name, self.video_name,
                ));
            }
            let apart_cm = median_apart_cm(first_track, first_timing, &view.sightings);
            if apart_cm > VIEWS_DISAGREE_CM {
                return Err(Error::whole(
                    &view.video_name,
                    format!(
                        "view {number} puts the body {apart_cm:.0} cm from where view 1 ({}) does, the median over the take: its camera and view 1's do not agree about the floor (calibrate both from the same board, lying where it lay)",
                        self.video_name
                    ),
                ));
            }
        }
        let sightings: Vec<ViewSightings> = others.iter().map(|v| v.sightings.clone()).collect();
        let fused = fuse_views(first_track, first_timing, &sightings);
        let export = self.take.export(&fused, first_timing);
        self.track = Some(fused);
        Ok((export, warnings))
    }
}

/// Where two views may disagree about where the body stands, the median
/// over the take (cm): each camera places it within a few centimetres
/// across its line of sight and 5–15 along it, so views of one world agree
/// far better than this; cameras calibrated into two worlds (two boards,
/// a board moved between the stills) disagree by the board's move.
pub const VIEWS_DISAGREE_CM: f64 = 30.0;

/// The median distance (cm) between where `first` (timed by `timing`) and
/// `view` put the hips at the first's video frames, where both do.
fn median_apart_cm(first: &Track, timing: &VideoTiming, view: &ViewSightings) -> f64 {
    let apart: Vec<f64> = first
        .frames
        .iter()
        .enumerate()
        .filter_map(|(i, frame)| {
            let position = view.timing.video_position(timing.bvh_time_s(i)).round();
            let other = view.frames.get(usize::try_from(position as i64).ok()?)?;
            let d = (other.floor_cm - frame.floor_cm).length();
            d.is_finite().then_some(d)
        })
        .collect();
    if apart.is_empty() { 0.0 } else { median(&apart) }
}

/// Per video frame `i`, the outer contour of `posed(i)` (a body model
/// standing at the floor's origin) moved to `floor_cm[i]` (x, z), as
/// `camera` sees it: pixels `[x, y]`, none in a frame without a pose or
/// a place.
pub(crate) fn outlines_px(
    camera: &Camera,
    floor_cm: &[DVec2],
    posed: impl Fn(usize) -> Result<Option<PosedBody>, Error>,
) -> Vec<Vec<[u32; 2]>> {
    let mut renderer = SilhouetteRenderer::new(camera);
    floor_cm
        .iter()
        .enumerate()
        .map(|(i, floor)| {
            if !floor.is_finite() {
                return Vec::new();
            }
            let Ok(Some(body)) = posed(i) else { return Vec::new() };
            renderer.render(&body, DVec3::new(floor.x, 0.0, floor.y)).contour()
        })
        .collect()
}

/// An error when `video` (named `video_name`) has no frames or no rate, or
/// `offset_s` is not a time.
pub(crate) fn check_video(video_name: &str, video: &VideoDescription, offset_s: f64) -> Result<(), Error> {
    if video.frame_count == 0 || !(video.fps.is_finite() && video.fps > 0.0) {
        return Err(Error::whole(
            video_name,
            format!("{} frames at {} fps: not a video to track", video.frame_count, video.fps),
        ));
    }
    if !offset_s.is_finite() {
        return Err(Error::whole("the time offset", format!("{offset_s} s is not a time")));
    }
    Ok(())
}
