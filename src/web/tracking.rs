//! The camera-tracking job for the page's Web Worker (`www/track-worker.js`):
//! [`app::tracking::TrackingJob`](crate::app::tracking::TrackingJob) behind
//! wasm-bindgen. The take's files and each frame's luma plane in (the
//! worker decodes the frames itself, or the page reads them and sends
//! them), typed results out ([`camera_api`](super::camera_api)); nothing
//! here touches the DOM, so it runs where there is no window.

use glam::DVec3;
use tsify::{Ts, Tsify};
use wasm_bindgen::prelude::*;

use crate::app::finished_take::FinishedTake;
use crate::app::tracking::TrackingJob;
use crate::web::camera_api::{
    FinishedTakeOptions, FinishedViewFrames, FrameProgress, NamedFile, OffsetFound, PathWork,
    RiecickyCandidates, TakeFiles, TakeOptions, TruthErrors,
};
use crate::web::js_object::read_ts;
use crate::web::take_series::TakeSeries;

/// Points as the page takes them: x, y, z (cm) point after point.
fn xyz_cm(points: &[DVec3]) -> Vec<f64> {
    points.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// Per frame the outline's pixels as `x, y` pixel after pixel, as the page
/// draws them over the video.
fn outlines_js(outlines: &[Vec<[u32; 2]>]) -> Vec<js_sys::Uint32Array> {
    outlines.iter().map(|outline| js_sys::Uint32Array::from(outline.as_flattened())).collect()
}

/// One take being tracked in the page.
#[wasm_bindgen]
pub struct CameraJob {
    job: TrackingJob,
    /// The opening's warnings (`finish` adds its own).
    warnings: Vec<String>,
    /// The features of the last `path_work`'s frame, until `path_features`
    /// gives them away.
    path_features: Option<Vec<u8>>,
}

pub(crate) fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

#[wasm_bindgen]
impl CameraJob {
    /// Opens a take; the error names the file or field at fault.
    #[wasm_bindgen(constructor)]
    pub fn new(options: Ts<TakeOptions>) -> Result<CameraJob, JsError> {
        let o = TakeOptions::from_js(options).map_err(js_error)?;
        let v = &o.video;
        let job = TrackingJob::open(
            o.recording.named_bytes(),
            o.camera.named_bytes(),
            o.background.named_bytes(),
            &v.name,
            v.into(),
            o.method,
            o.offset_s,
        )
        .map_err(js_error)?;
        let warnings = job.warnings().to_vec();
        Ok(CameraJob { job, warnings, path_features: None })
    }

    /// The warnings of the opening.
    pub fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The frames tracked so far.
    pub fn frames_done(&self) -> usize {
        self.job.frames_done()
    }

    /// Tracks the next frame from its luma plane (rows `stride` bytes apart;
    /// `full_range` as the decoder's colour space says): where the filter
    /// has the hips so far.
    pub fn push_luma(
        &mut self,
        luma: &[u8],
        stride: usize,
        full_range: bool,
    ) -> Result<Ts<FrameProgress>, JsError> {
        let progress = self.job.push_luma(luma, stride, full_range).map_err(js_error)?;
        Ok(progress.into_ts()?)
    }

    /// Leaves the path search's energies to a second job of the same take,
    /// in another worker (see `Tracker::defer_path_energies`).
    pub fn defer_path_energies(&mut self) {
        self.job.defer_path_energies();
    }

    /// What the frame just tracked leaves to score, for the second job's
    /// `score_path`; `undefined` when nothing. The frame's features go with
    /// it: `path_features` gives them, once.
    pub fn path_work(&mut self) -> Result<Option<Ts<PathWork>>, JsError> {
        let Some((request, features)) = self.job.take_path_work() else { return Ok(None) };
        self.path_features = Some(features.to_bytes());
        Ok(Some(PathWork::from_request(request).into_ts()?))
    }

    /// The features of the frame of the last `path_work`, as bytes for the
    /// second job (given away: an error when asked twice).
    pub fn path_features(&mut self) -> Result<Vec<u8>, JsError> {
        self.path_features
            .take()
            .ok_or_else(|| JsError::new("no path work's features to give: call path_work first"))
    }

    /// The energies (px) of another job's `path_work`, one per candidate in
    /// its order, from the `path_features` that job gave with it.
    pub fn score_path(&mut self, work: Ts<PathWork>, features: &[u8]) -> Result<Vec<f64>, JsError> {
        let request = PathWork::from_js(work).map_err(js_error)?;
        self.job.score_path(&request, features).map_err(js_error)
    }

    /// Hands back the energies of this job's work for `frame`.
    pub fn set_path_energies(&mut self, frame: usize, energies_px: Vec<f64>) -> Result<(), JsError> {
        self.job.set_path_energies(frame, energies_px).map_err(js_error)
    }

    /// Smooths the track and writes it: the bytes `embusen track` writes.
    pub fn finish(&mut self) -> Result<Ts<TakeFiles>, JsError> {
        let (export, warnings) = self.job.finish().map_err(js_error)?;
        self.warnings.extend(warnings);
        let files = TakeFiles {
            recording_text: export.recording_text,
            track_csv: export.track_csv,
            warnings: self.warnings.clone(),
        };
        Ok(files.into_ts()?)
    }

    /// This view, tracked to the end, for the first view's job to weigh
    /// in (`weigh`, in that view's worker).
    pub fn finished_view(&self) -> Result<Ts<FinishedViewFrames>, JsError> {
        let view = self.job.finished_view().map_err(js_error)?;
        Ok(FinishedViewFrames::from(&view).into_ts()?)
    }

    /// After `finish`, this view's track (the first view's) weighed with the
    /// other views' (`finished_view` of their jobs): the bytes `embusen
    /// track` writes for all the videos; the outlines, the series and the
    /// errors against a truth are then the weighed track's. The warnings
    /// are this view's and the weighing's (each other view says its own).
    /// An error naming the view that does not agree about the floor.
    pub fn weigh(&mut self, others: Vec<Ts<FinishedViewFrames>>) -> Result<Ts<TakeFiles>, JsError> {
        let others = others
            .into_iter()
            .map(FinishedViewFrames::from_js)
            .collect::<Result<Vec<_>, _>>()
            .map_err(js_error)?;
        let (export, warnings) = self.job.weigh(&others).map_err(js_error)?;
        let files = TakeFiles {
            recording_text: export.recording_text,
            track_csv: export.track_csv,
            warnings: self.warnings.iter().chain(&warnings).cloned().collect(),
        };
        Ok(files.into_ts()?)
    }

    /// The body's outline over each video frame where the finished track
    /// puts it: per frame its pixels, `x, y` pixel after pixel.
    pub fn outlines_px(&self) -> Vec<js_sys::Uint32Array> {
        outlines_js(&self.job.outlines_px())
    }

    /// The finished track against the true hips of a CSV (the shared
    /// scenes' `NAME.truth.csv`). The error names the file.
    pub fn against_truth(&self, truth: Ts<NamedFile>) -> Result<Ts<TruthErrors>, JsError> {
        let truth: NamedFile = read_ts(&truth, "the truth").map_err(js_error)?;
        let (per_frame_cm, figures) = self.job.against_truth(truth.named_bytes()).map_err(js_error)?;
        let errors = TruthErrors {
            mean_cm: figures.mean_cm,
            p90_cm: figures.p90_cm,
            max_cm: figures.max_cm,
            per_frame_cm,
        };
        Ok(errors.into_ts()?)
    }

    /// Where the finished track puts the hips in each of the recording's
    /// frames, for `Player.show_camera_take`: x, y, z (cm, the recording's
    /// coordinates) frame after frame.
    pub fn tracked_hips_cm(&self) -> Vec<f64> {
        xyz_cm(&self.job.camera_series().hips_cm)
    }

    /// Per video frame of the finished track, for `Player.show_camera_take`:
    /// the recording's time it was read at and the uncertainty it states
    /// (the page adds the error against a truth).
    pub fn take_series(&self) -> Result<Ts<TakeSeries>, JsError> {
        Ok(TakeSeries::of(self.job.camera_series()).into_ts()?)
    }

    /// Keeps the frames the time offset is estimated from (call before the
    /// first frame), for `estimate_offset`.
    pub fn keep_offset_samples(&mut self) {
        self.job.keep_offset_samples();
    }

    /// After `finish`, as `embusen track --estimate-offset`; `undefined`
    /// when no kept frame had a pose to fit.
    pub fn estimate_offset(&self) -> Result<Option<Ts<OffsetFound>>, JsError> {
        let estimate = self.job.estimate_offset().map_err(js_error)?;
        Ok(estimate.map(|e| OffsetFound::from(e).into_ts()).transpose()?)
    }

    /// Riečický et al.'s candidates of each video frame of the finished track
    /// (none for `fused`).
    pub fn riecicky_candidates(&self) -> Result<Vec<Ts<RiecickyCandidates>>, JsError> {
        let frames = self.job.riecicky_candidates().into_iter().map(|c| c.into_ts());
        Ok(frames.collect::<Result<_, _>>()?)
    }
}

/// A take tracked before, opened to be shown as it is, with no tracking
/// ([`FinishedTake`]): what the page shows after a track.
#[wasm_bindgen]
pub struct FinishedTakeView {
    take: FinishedTake,
}

#[wasm_bindgen]
impl FinishedTakeView {
    /// Opens the take; the error names the file or field at fault, or says
    /// which file is not this take's.
    #[wasm_bindgen(constructor)]
    pub fn new(options: Ts<FinishedTakeOptions>) -> Result<FinishedTakeView, JsError> {
        let o = FinishedTakeOptions::from_js(options).map_err(js_error)?;
        let (recording, camera, video) =
            (o.recording.named_bytes(), o.camera.named_bytes(), (&o.video).into());
        let take = match &o.track {
            Some(track) => {
                FinishedTake::open(recording, camera, track.named_bytes(), &o.video.name, video, o.offset_s)
            }
            None => FinishedTake::open_other_view(recording, camera, &o.video.name, video, o.offset_s),
        }
        .map_err(js_error)?;
        Ok(FinishedTakeView { take })
    }

    /// Per video frame, where the track put the hips and how well the
    /// camera saw the body, as the tracker reported them while it ran.
    pub fn path(&self) -> Result<Vec<Ts<FrameProgress>>, JsError> {
        Ok(self.take.path.iter().map(|p| p.into_ts()).collect::<Result<_, _>>()?)
    }

    /// The body's outline over each video frame where the track put it.
    pub fn outlines_px(&self) -> Vec<js_sys::Uint32Array> {
        outlines_js(&self.take.outlines_px)
    }

    /// The recording's hips in each of its frames, for
    /// `Player.show_camera_take`: x, y, z (cm) frame after frame.
    pub fn tracked_hips_cm(&self) -> Vec<f64> {
        xyz_cm(&self.take.series.hips_cm)
    }

    /// Per video frame, for `Player.show_camera_take`: the recording's
    /// time it was read at and the uncertainty the track CSV states.
    pub fn take_series(&self) -> Result<Ts<TakeSeries>, JsError> {
        Ok(TakeSeries::of(self.take.series.clone()).into_ts()?)
    }
}
