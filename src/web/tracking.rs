//! The camera-tracking job for the page's Web Worker (`www/track-worker.js`):
//! [`app::tracking::TrackingJob`](crate::app::tracking::TrackingJob) behind
//! wasm-bindgen. Bytes in (the files the page read, each frame's luma
//! plane), numbers and texts out; nothing here touches the DOM, so it runs
//! where there is no window.

use wasm_bindgen::prelude::*;

use crate::app::calibration::{floor_grid_px, frustum_lines_cm};
use crate::app::frame_layers::{FrameLayers, Layer, layer_rgba};
use crate::app::tracking::{NamedBytes, TrackingJob, VideoDescription};
use crate::camera::floor_rectangle::FloorCalibration;
use crate::camera::{Camera, FloorRectangle, FocalLength, ImageSize};
use crate::image::GreyImage;
use crate::image::background::{MEDIAN_FRAMES, median_background, sample_indices};
use crate::image::pipeline::Features;
use crate::io::container::{EncodedVideo, demux, nominal_fps};
use crate::io::image_file::grey_to_png;
use crate::io::recording::Recording;
use crate::track::fused::FusedParams;
use crate::track::path::PathRequest;
use crate::track::riecicky::RiecickyParams;
use crate::track::take::body_shape_of;
use crate::track::tracker::TrackMethod;
use glam::DVec2;
use wasm_bindgen::Clamped;

/// One take being tracked in the page.
#[wasm_bindgen]
pub struct CameraJob {
    job: TrackingJob,
    /// What `finish` wrote, kept for the page to read.
    recording_text: String,
    track_csv: String,
    warnings: Vec<String>,
}

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

#[wasm_bindgen]
impl CameraJob {
    /// Opens a take; `method` is `"fused"` or `"paper"`. The error names the
    /// file at fault.
    #[allow(clippy::too_many_arguments)]
    #[wasm_bindgen(constructor)]
    pub fn new(
        recording_name: &str,
        recording: &[u8],
        camera_name: &str,
        camera: &[u8],
        background_name: &str,
        background: &[u8],
        video_name: &str,
        width_px: u32,
        height_px: u32,
        fps: f64,
        frame_count: usize,
        method: &str,
        offset_s: f64,
    ) -> Result<CameraJob, JsError> {
        let method = match method {
            "fused" => TrackMethod::Fused(FusedParams::default()),
            "paper" => TrackMethod::Paper(RiecickyParams::default()),
            other => return Err(JsError::new(&format!("method {other:?}: \"fused\" or \"paper\""))),
        };
        let job = TrackingJob::open(
            NamedBytes { name: recording_name, bytes: recording },
            NamedBytes { name: camera_name, bytes: camera },
            NamedBytes { name: background_name, bytes: background },
            video_name,
            VideoDescription { width_px, height_px, fps, frame_count },
            method,
            offset_s,
        )
        .map_err(js_error)?;
        let warnings = job.warnings().to_vec();
        Ok(CameraJob { job, recording_text: String::new(), track_csv: String::new(), warnings })
    }

    /// The warnings so far (before tracking; after `finish`, its own too).
    pub fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The frames tracked so far.
    pub fn frames_done(&self) -> usize {
        self.job.frames_done()
    }

    /// Tracks the next frame from its luma plane (rows `stride` bytes apart;
    /// `full_range` as the decoder's colour space says). Returns
    /// `[x_cm, z_cm, confidence]`: where the filter has the hips so far.
    pub fn push_luma(&mut self, luma: &[u8], stride: usize, full_range: bool) -> Result<Vec<f64>, JsError> {
        let p = self.job.push_luma(luma, stride, full_range).map_err(js_error)?;
        Ok(vec![p.floor_cm.x, p.floor_cm.y, p.confidence])
    }

    /// Leaves the path search's energies to a second job of the same take,
    /// in another worker (see `Tracker::defer_path_energies`).
    pub fn defer_path_energies(&mut self) {
        self.job.defer_path_energies();
    }

    /// What the frame just tracked leaves to score, for the second job's
    /// `score_path`: `[frame, prediction x, z (cm), truncation (px; NaN:
    /// none), then x, z (cm) per candidate]`; `undefined` when nothing.
    pub fn path_request(&mut self) -> Option<Vec<f64>> {
        let r = self.job.take_path_request()?;
        let mut out = vec![
            r.frame as f64,
            r.prediction_cm.x,
            r.prediction_cm.y,
            r.truncate_px.map_or(f64::NAN, f64::from),
        ];
        out.extend(r.candidates_cm.iter().flat_map(|p| [p.x, p.y]));
        Some(out)
    }

    /// The energies of another job's `path_request`, from the same frame's
    /// luma plane.
    pub fn score_path(
        &mut self,
        request: &[f64],
        luma: &[u8],
        stride: usize,
        full_range: bool,
    ) -> Result<Vec<f64>, JsError> {
        let [frame, x, z, truncate_px, candidates @ ..] = request else {
            return Err(JsError::new("a path request of fewer than 4 numbers"));
        };
        if candidates.len() % 2 != 0 || !(frame.is_finite() && *frame >= 0.0) {
            return Err(JsError::new("a path request that is not one"));
        }
        let request = PathRequest {
            frame: *frame as usize,
            prediction_cm: DVec2::new(*x, *z),
            truncate_px: truncate_px.is_finite().then_some(*truncate_px as f32),
            candidates_cm: candidates.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect(),
        };
        self.job.score_path(&request, luma, stride, full_range).map_err(js_error)
    }

    /// Hands back the energies of this job's request for `frame`.
    pub fn set_path_energies(&mut self, frame: usize, energies: Vec<f64>) -> Result<(), JsError> {
        self.job.set_path_energies(frame, energies).map_err(js_error)
    }

    /// Smooths the track and writes it (then read `recording_text`,
    /// `track_csv`, `warnings`).
    pub fn finish(&mut self) -> Result<(), JsError> {
        let (export, warnings) = self.job.finish().map_err(js_error)?;
        self.recording_text = export.recording_text;
        self.track_csv = export.track_csv;
        self.warnings.extend(warnings);
        Ok(())
    }

    /// The body's outline over each video frame where the finished track
    /// puts it: per frame its pixel count `n`, then `n` pairs `x, y`.
    pub fn outlines_px(&self) -> Vec<u32> {
        let mut out = Vec::new();
        for outline in self.job.outlines_px() {
            out.push(outline.len() as u32);
            out.extend(outline.iter().flatten());
        }
        out
    }

    /// The finished track against the true hips of a CSV (the shared
    /// scenes' `NAME.truth.csv`): `[mean, p90, max]` (cm) followed by the
    /// error of every frame (cm). The error names the file.
    pub fn against_truth(&self, name: &str, bytes: &[u8]) -> Result<Vec<f64>, JsError> {
        let (per_frame, figures) = self.job.against_truth(NamedBytes { name, bytes }).map_err(js_error)?;
        let mut out = vec![figures.mean_cm, figures.p90_cm, figures.max_cm];
        out.extend(per_frame);
        Ok(out)
    }

    /// Where the finished track puts the hips in each of the recording's
    /// frames: x, y, z (cm, the recording's coordinates) frame after frame.
    pub fn tracked_hips_cm(&self) -> Vec<f64> {
        self.job.tracked_hips_cm().iter().flat_map(|p| [p.x, p.y, p.z]).collect()
    }

    /// Keeps the frames the time offset is estimated from (call before the
    /// first frame), for `estimate_offset`.
    pub fn keep_offset_samples(&mut self) {
        self.job.keep_offset_samples();
    }

    /// After `finish`, as `embusen track --estimate-offset`: `[offset (s),
    /// then per offset tried: offset (s), mean energy (px)]`, or
    /// `undefined` when no kept frame had a pose to fit.
    pub fn estimate_offset(&self) -> Result<Option<Vec<f64>>, JsError> {
        Ok(self.job.estimate_offset().map_err(js_error)?.map(|e| {
            let mut out = vec![e.offset_s];
            out.extend(e.tried.iter().flat_map(|&(o, cost)| [o, cost]));
            out
        }))
    }

    /// The paper's candidates of each frame of the finished track: per
    /// frame their count `n`, the index of the chosen one (−1: none), then
    /// `n` times x, z (cm) and the energy (px). Counts of 0 for `fused`.
    pub fn paper_candidates(&self) -> Vec<f64> {
        let mut out = Vec::new();
        for frame in self.job.paper_candidates() {
            out.extend([frame.tried.len() as f64, frame.chosen.map_or(-1.0, |c| c as f64)]);
            out.extend(frame.tried.iter().flat_map(|(p, e)| [p.x, p.y, *e]));
        }
        out
    }

    /// The body model the take is tracked with, as JSON (`BodyShape`):
    /// what the player's 3D view draws solid.
    pub fn body_shape_json(&self) -> Result<String, JsError> {
        serde_json::to_string(self.job.body_shape()).map_err(js_error)
    }

    /// The corrected recording (after `finish`).
    pub fn recording_text(&self) -> String {
        self.recording_text.clone()
    }

    /// The hips per video frame with the camera's confidence, as CSV (after
    /// `finish`).
    pub fn track_csv(&self) -> String {
        self.track_csv.clone()
    }
}

/// The rate a video was recorded at, from one measured off its presented
/// frames' timestamps ([`nominal_fps`]).
#[wasm_bindgen(js_name = nominal_fps)]
pub fn nominal_fps_of(measured: f64) -> f64 {
    nominal_fps(measured)
}

/// A video file's encoded frames, for the worker's `VideoDecoder`
/// ([`crate::io::container`]).
#[wasm_bindgen]
pub struct DemuxedVideo {
    video: EncodedVideo,
}

/// Demuxes an MP4/MOV or WebM/Matroska file; the error names the file and
/// says why (another container, a codec not read here, a truncated file).
#[wasm_bindgen]
pub fn demux_video(bytes: &[u8], name: &str) -> Result<DemuxedVideo, JsError> {
    Ok(DemuxedVideo { video: demux(bytes, name).map_err(js_error)? })
}

#[wasm_bindgen]
impl DemuxedVideo {
    /// The codec as WebCodecs names it.
    pub fn codec(&self) -> String {
        self.video.codec.clone()
    }

    /// The decoder's configuration record, where the codec has one.
    pub fn description(&self) -> Option<Vec<u8>> {
        self.video.description.clone()
    }

    pub fn width_px(&self) -> u32 {
        self.video.width_px
    }

    pub fn height_px(&self) -> u32 {
        self.video.height_px
    }

    /// The frame rate, as `ffprobe` would report it ([`nominal_fps`]).
    pub fn fps(&self) -> f64 {
        nominal_fps(self.video.fps())
    }

    pub fn frame_count(&self) -> usize {
        self.video.frames.len()
    }

    /// Per frame in decoding order, four numbers: its byte offset, its size,
    /// its presentation time (µs), 1 for a keyframe (else 0).
    pub fn frames(&self) -> Vec<f64> {
        self.video
            .frames
            .iter()
            .flat_map(|f| {
                [f.offset as f64, f.size as f64, f.timestamp_us as f64, f64::from(u8::from(f.keyframe))]
            })
            .collect()
    }
}

/// The floor grid as the camera of `camera_json` sees it (lines every
/// `spacing_cm` within `half_extent_cm` of the origin): `x, y` pixel after
/// pixel, each line ended by a NaN pair. The error names the camera file.
#[wasm_bindgen]
pub fn floor_grid(
    camera_name: &str,
    camera_json: &str,
    spacing_cm: f64,
    half_extent_cm: f64,
) -> Result<Vec<f64>, JsError> {
    let camera = Camera::from_json(camera_json, camera_name).map_err(js_error)?;
    let mut out = Vec::new();
    for line in floor_grid_px(&camera, spacing_cm, half_extent_cm) {
        out.extend(line.iter().flat_map(|p| [p.x, p.y]));
        out.extend([f64::NAN, f64::NAN]);
    }
    Ok(out)
}

/// The camera of `camera_json` as the 3D view draws it
/// ([`frustum_lines_cm`]): per line its two ends, x, y, z (world cm) each.
/// The error names the camera file.
#[wasm_bindgen]
pub fn camera_frustum(camera_name: &str, camera_json: &str, depth_cm: f64) -> Result<Vec<f64>, JsError> {
    let camera = Camera::from_json(camera_json, camera_name).map_err(js_error)?;
    Ok(frustum_lines_cm(&camera, depth_cm).iter().flatten().flat_map(|p| [p.x, p.y, p.z]).collect())
}

/// The body model `embusen track` builds for a recording (`BodyShape`, as
/// JSON): the one a `CameraJob` of it tracks with. The error names the file.
#[wasm_bindgen]
pub fn body_shape_json(recording_name: &str, recording: &[u8]) -> Result<String, JsError> {
    let recording = Recording::parse(recording, recording_name, None).map_err(js_error)?;
    let shape = body_shape_of(&recording).map_err(js_error)?;
    serde_json::to_string(&shape).map_err(js_error)
}

/// A take's background, ready to paint what the tracker sees in a frame
/// over the video ([`crate::app::frame_layers`]).
#[wasm_bindgen]
pub struct FramePainter {
    layers: FrameLayers,
    /// The pipeline's stages of the last frame given.
    features: Option<Features>,
}

#[wasm_bindgen]
impl FramePainter {
    /// From the background still (PNG); the error names the file.
    #[wasm_bindgen(constructor)]
    pub fn new(background_name: &str, background: &[u8]) -> Result<FramePainter, JsError> {
        Ok(FramePainter {
            layers: FrameLayers::new(background_name, background).map_err(js_error)?,
            features: None,
        })
    }

    /// Runs the pipeline on a frame (its luma plane; `label` names it in
    /// errors), for `layer` to paint.
    pub fn set_frame(
        &mut self,
        luma: &[u8],
        stride: usize,
        full_range: bool,
        label: &str,
    ) -> Result<(), JsError> {
        self.features = Some(self.layers.features(luma, stride, full_range, label).map_err(js_error)?);
        Ok(())
    }

    /// `"mask"`, `"edges"` or `"distance"` of the last frame as RGBA pixels
    /// (for an `ImageData` of the frame's size).
    pub fn layer(&self, name: &str) -> Result<Clamped<Vec<u8>>, JsError> {
        let layer = Layer::from_name(name).map_err(js_error)?;
        let features = self.features.as_ref().ok_or_else(|| JsError::new("no frame given yet"))?;
        Ok(Clamped(layer_rgba(features, layer)))
    }
}

/// The camera calibrated by hand from four clicked floor corners
/// ([`crate::camera::floor_rectangle`]), as `embusen calibrate
/// --floor-corners` makes it.
#[wasm_bindgen]
pub struct FloorCornersCalibration {
    fit: FloorCalibration,
}

/// The camera of a `width_px × height_px` image in which the corners of a
/// floor rectangle `width_cm` (along world +X) by `depth_cm` (along +Z) were
/// clicked at `corners_px` (x, y four times: the origin, along +X, the far
/// corner, along +Z; pixel centres at whole numbers), with a focal length
/// (px) or, without one, the focal length estimated too. The error says
/// what is wrong with the clicks.
#[wasm_bindgen]
pub fn calibrate_floor_corners(
    width_px: u32,
    height_px: u32,
    corners_px: &[f64],
    width_cm: f64,
    depth_cm: f64,
    focal_px: Option<f64>,
) -> Result<FloorCornersCalibration, JsError> {
    let [x0, y0, x1, y1, x2, y2, x3, y3] = corners_px else {
        return Err(JsError::new(&format!("four corners (8 numbers), not {} numbers", corners_px.len())));
    };
    let corners = [(x0, y0), (x1, y1), (x2, y2), (x3, y3)].map(|(x, y)| DVec2::new(*x, *y));
    let focal = focal_px.map_or(FocalLength::Unknown, FocalLength::Px);
    let fit = FloorRectangle { width_cm, depth_cm }
        .calibrate(ImageSize { width_px, height_px }, corners, focal)
        .map_err(js_error)?;
    Ok(FloorCornersCalibration { fit })
}

#[wasm_bindgen]
impl FloorCornersCalibration {
    /// The camera as camera.json (what `embusen calibrate` writes).
    pub fn camera_json(&self) -> String {
        self.fit.camera.to_json()
    }

    /// The clicks' reprojection error (px, root mean square).
    pub fn rms_px(&self) -> f64 {
        self.fit.reprojection_rms_px
    }

    /// How far (cm, one σ) a pixel of click error moves the camera centre.
    pub fn center_sigma_cm_per_px(&self) -> f64 {
        self.fit.center_sigma_cm_per_px
    }

    /// The focal length (px).
    pub fn focal_px(&self) -> f64 {
        self.fit.camera.intrinsics.fx_px
    }
}

/// The frames (indices) of a video of `frame_count` frames whose median
/// stands for the empty room when there is no background still, as
/// `embusen track` without `--background` takes them.
#[wasm_bindgen]
pub fn median_background_frames(frame_count: usize) -> Vec<u32> {
    sample_indices(frame_count, MEDIAN_FRAMES).iter().map(|&i| i as u32).collect()
}

/// The per-pixel median of the frames given (their luma planes, made grey
/// as the tracker makes them), as a greyscale PNG: the background still
/// the take is then tracked against. The error names `video_name`.
#[wasm_bindgen]
pub fn median_background_png(
    video_name: &str,
    width_px: u32,
    height_px: u32,
    lumas: Vec<js_sys::Uint8Array>,
    stride: usize,
    full_range: bool,
) -> Result<Vec<u8>, JsError> {
    let frames = lumas
        .iter()
        .enumerate()
        .map(|(k, luma)| {
            let label = format!("{video_name}, frame {k} of the median");
            GreyImage::from_luma(width_px, height_px, &luma.to_vec(), stride, full_range, &label)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(js_error)?;
    let median = median_background(&frames, video_name).map_err(js_error)?;
    grey_to_png(&median, video_name).map_err(js_error)
}

/// A video frame (its luma plane, made grey as the tracker makes it) as a
/// greyscale PNG: a frame to find the board in, as a still would be. The
/// error names `label`.
#[wasm_bindgen]
pub fn frame_png(
    label: &str,
    width_px: u32,
    height_px: u32,
    luma: &[u8],
    stride: usize,
    full_range: bool,
) -> Result<Vec<u8>, JsError> {
    let grey =
        GreyImage::from_luma(width_px, height_px, luma, stride, full_range, label).map_err(js_error)?;
    grey_to_png(&grey, label).map_err(js_error)
}
