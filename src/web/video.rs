//! The camera module's video helpers: a video file's encoded frames for the
//! worker's `VideoDecoder` ([`crate::io::container`]), its frame rate as
//! ffprobe reports it, a frame as a still, and the median of frames that
//! stands for the empty room when there is no background still.

use tsify::{Ts, Tsify};
use wasm_bindgen::prelude::*;

use crate::image::GreyImage;
use crate::image::background::{MEDIAN_FRAMES, median_background, sample_indices};
use crate::io::container::{EncodedVideo, demux, nominal_fps};
use crate::io::image_file::grey_to_png;
use crate::web::camera_api::{EncodedFrame, LumaPlane, VideoFacts};
use crate::web::js_object::read_ts;
use crate::web::tracking::js_error;

/// The rate a video was recorded at, from one measured off its presented
/// frames' timestamps ([`nominal_fps`]).
#[wasm_bindgen(js_name = nominal_fps)]
pub fn nominal_fps_of(measured: f64) -> f64 {
    nominal_fps(measured)
}

/// A video file's encoded frames, for the worker's `VideoDecoder`.
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

    /// The video as the tracker is told of it (`name` names it), its frame
    /// rate as `ffprobe` would report it ([`nominal_fps`]).
    pub fn facts(&self, name: &str) -> Result<Ts<VideoFacts>, JsError> {
        let v = &self.video;
        let facts = VideoFacts {
            name: name.to_string(),
            width_px: v.width_px,
            height_px: v.height_px,
            fps: nominal_fps(v.fps()),
            frame_count: v.frames.len(),
        };
        Ok(facts.into_ts()?)
    }

    /// The encoded frames in decoding order.
    pub fn frames(&self) -> Result<Vec<Ts<EncodedFrame>>, JsError> {
        let frames = self.video.frames.iter().map(|f| {
            EncodedFrame {
                offset: f.offset as f64,
                size: f.size,
                timestamp_us: f.timestamp_us as f64,
                keyframe: f.keyframe,
            }
            .into_ts()
        });
        Ok(frames.collect::<Result<_, _>>()?)
    }
}

/// The frames (indices) of a video of `frame_count` frames whose median
/// stands for the empty room when there is no background still, as
/// `embusen track` without `--background` takes them.
#[wasm_bindgen]
pub fn median_background_frames(frame_count: usize) -> Vec<u32> {
    sample_indices(frame_count, MEDIAN_FRAMES).iter().map(|&i| i as u32).collect()
}

/// A luma plane made grey as the tracker makes it; `label` names it in errors.
fn grey_of(video: &VideoFacts, plane: Ts<LumaPlane>, label: &str) -> Result<GreyImage, JsError> {
    let p: LumaPlane = read_ts(&plane, label).map_err(js_error)?;
    GreyImage::from_luma(video.width_px, video.height_px, &p.luma, p.stride, p.full_range, label)
        .map_err(js_error)
}

/// The per-pixel median of the frames given (made grey as the tracker makes
/// them), as a greyscale PNG: the background still the take is then tracked
/// against. The error names the video.
#[wasm_bindgen]
pub fn median_background_png(video: Ts<VideoFacts>, frames: Vec<Ts<LumaPlane>>) -> Result<Vec<u8>, JsError> {
    let video: VideoFacts = read_ts(&video, "the video").map_err(js_error)?;
    let greys = frames
        .into_iter()
        .enumerate()
        .map(|(k, plane)| grey_of(&video, plane, &format!("{}, frame {k} of the median", video.name)))
        .collect::<Result<Vec<_>, _>>()?;
    let median = median_background(&greys, &video.name).map_err(js_error)?;
    grey_to_png(&median, &video.name).map_err(js_error)
}

/// A video frame (made grey as the tracker makes it) as a greyscale PNG: a
/// frame to find the board in, as a still would be. The error names `label`.
#[wasm_bindgen]
pub fn frame_png(video: Ts<VideoFacts>, frame: Ts<LumaPlane>, label: &str) -> Result<Vec<u8>, JsError> {
    let video: VideoFacts = read_ts(&video, "the video").map_err(js_error)?;
    let grey = grey_of(&video, frame, label)?;
    grey_to_png(&grey, label).map_err(js_error)
}
