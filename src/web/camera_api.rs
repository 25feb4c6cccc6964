//! The typed boundary between the page and the camera and board modules
//! (`dist/pkg-camera/`, `dist/pkg-board/`), as [`api`](super) is the
//! player's: what crosses it are plain JavaScript objects, (de)serialised by
//! serde through serde-wasm-bindgen, their TypeScript types derived from
//! these (tsify) into those modules' `embusen.d.ts`, which `www/camera/`
//! and `www/track-worker.js` are checked against. An unknown field or value
//! is an error that names it, never ignored. Bytes cross as `Uint8Array`
//! (or an `ArrayBuffer`, as a worker's message carries them); big number
//! buffers as typed arrays, their layout in their doc.

use serde::de::{self, DeserializeOwned, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use tsify::{Ts, Tsify};
use wasm_bindgen::JsCast;

use super::js_object::{field, read_ts, refuse_unknown_fields, refuse_unknown_fields_of_each};
use crate::app::frame_layers::Layer;
/// The page's floor point, a frame's progress and its candidates are the
/// app's own (serialised there, typed for the page when built for it).
pub use crate::app::frame_report::{Candidate, FloorPoint, FrameProgress, RiecickyCandidates};
use crate::app::tracking::{FinishedView, NamedBytes, VideoDescription};
use crate::image::Shrink;
use crate::track::offset::OffsetEstimate;
use crate::track::path::PathRequest;
use crate::track::suit_motion::VideoTiming;
use crate::track::tracker::TrackMethod;
use crate::track::views::{Sighting, ViewSightings};
use glam::{DMat2, DVec2};

/// A file the page read: its name (errors name it) and its bytes. Two
/// types with [`NamedBytes`], not one: this one owns the bytes copied out
/// of the page's `Uint8Array`, the app's borrows them, so that the CLI and
/// the tests hand the app the bytes they hold without a copy.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct NamedFile {
    pub name: String,
    #[serde(deserialize_with = "bytes_in", serialize_with = "bytes_out")]
    #[tsify(type = "Uint8Array | ArrayBuffer")]
    pub bytes: Vec<u8>,
}

impl NamedFile {
    pub fn named_bytes(&self) -> NamedBytes<'_> {
        NamedBytes { name: &self.name, bytes: &self.bytes }
    }

    /// The bytes as text, as the page's `TextDecoder` reads them: UTF-8, a
    /// byte order mark dropped, a bad sequence replaced.
    pub fn text(&self) -> String {
        let text = String::from_utf8_lossy(&self.bytes);
        text.strip_prefix('\u{feff}').unwrap_or(&text).to_string()
    }
}

/// Bytes from a `Uint8Array` or an `ArrayBuffer`, copied once (serde's
/// default for `Vec<u8>` would read them number by number).
fn bytes_in<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<u8>, D::Error> {
    struct Bytes;
    impl Visitor<'_> for Bytes {
        type Value = Vec<u8>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a Uint8Array or an ArrayBuffer")
        }
        fn visit_bytes<E: de::Error>(self, v: &[u8]) -> Result<Vec<u8>, E> {
            Ok(v.to_vec())
        }
        fn visit_byte_buf<E: de::Error>(self, v: Vec<u8>) -> Result<Vec<u8>, E> {
            Ok(v)
        }
    }
    deserializer.deserialize_byte_buf(Bytes)
}

/// Bytes out as a `Uint8Array`.
fn bytes_out<S: Serializer>(bytes: &[u8], serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_bytes(bytes)
}

/// A tracker across the boundary: its name ([`TrackMethod::name`],
/// `fused` or `paper`), the tracker with its defaults as `embusen track
/// --method` takes it.
mod track_method_by_name {
    use super::*;

    pub fn serialize<S: Serializer>(method: &TrackMethod, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(method.name())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<TrackMethod, D::Error> {
        let name = String::deserialize(deserializer)?;
        TrackMethod::named(&name).ok_or_else(|| de::Error::unknown_variant(&name, &TrackMethod::NAMES))
    }
}

/// The video as the page (or the worker's demuxer) describes it. The
/// app's [`VideoDescription`] is the same but for the name, which the app
/// takes apart (`Copy`, and the CLI's and the tests' name their video
/// from its file); one `From` makes it. Not the description flattened
/// beside a name: serde reads a flattened struct as a map, so neither
/// `deny_unknown_fields` nor `js_object`'s reader sees its fields (an
/// unknown one would pass serde, and the reader would refuse every one).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct VideoFacts {
    pub name: String,
    pub width_px: u32,
    pub height_px: u32,
    pub fps: f64,
    /// The frames expected (for the warning about a video and a BVH of
    /// different lengths; more may come).
    pub frame_count: usize,
}

impl From<&VideoFacts> for VideoDescription {
    fn from(v: &VideoFacts) -> VideoDescription {
        VideoDescription {
            width_px: v.width_px,
            height_px: v.height_px,
            fps: v.fps,
            frame_count: v.frame_count,
        }
    }
}

/// Everything a take is tracked from, as `embusen track` takes it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct TakeOptions {
    /// The suit's recording (BVH).
    pub recording: NamedFile,
    /// camera.json.
    pub camera: NamedFile,
    /// The still of the empty room (PNG).
    pub background: NamedFile,
    pub video: VideoFacts,
    #[serde(with = "track_method_by_name")]
    #[tsify(type = "\"fused\" | \"paper\"")]
    pub method: TrackMethod,
    /// Added to a video frame's time to read the BVH (s), as `--offset-s`.
    pub offset_s: f64,
}

impl TakeOptions {
    /// The options from the page's object; an unknown field or value is an
    /// error that names it.
    pub fn from_js(value: Ts<TakeOptions>) -> Result<TakeOptions, String> {
        read_take(&value, &["recording", "camera", "background"])
    }
}

/// A take tracked before, to be shown as it is (`FinishedTakeView`): the
/// corrected recording and the track CSV `embusen track` wrote, the camera,
/// the video they were tracked from, and the offset they were tracked at.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
#[tsify(missing_as_null)]
pub struct FinishedTakeOptions {
    /// The corrected recording (BVH).
    pub recording: NamedFile,
    /// camera.json.
    pub camera: NamedFile,
    /// The track CSV, a row per video frame; `null` for a view other than
    /// the first of a take filmed by several cameras (the CSV is on the
    /// first's frames: the recording's hips place the body).
    pub track: Option<NamedFile>,
    pub video: VideoFacts,
    /// Added to a video frame's time to read the BVH (s), as `--offset-s`.
    pub offset_s: f64,
}

impl FinishedTakeOptions {
    /// The options from the page's object; an unknown field or value is an
    /// error that names it.
    pub fn from_js(value: Ts<FinishedTakeOptions>) -> Result<FinishedTakeOptions, String> {
        read_take(&value, &["recording", "camera", "track"])
    }
}

/// A take's options from the page's object: its `files` and its video
/// looked at first, so that an unknown field in one of them is named where
/// it is.
fn read_take<T>(value: &Ts<T>, files: &[&str]) -> Result<T, String>
where
    T: DeserializeOwned + Tsify,
    T::JsType: JsCast,
{
    let object = value.js_value();
    for file in files {
        refuse_unknown_fields::<NamedFile>(&field(&object, file), &format!("the take's {file}"))?;
    }
    refuse_unknown_fields::<VideoFacts>(&field(&object, "video"), "the take's video")?;
    read_ts(value, "the take")
}

/// A point in an image (px; pixel centres at whole numbers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct PixelPoint {
    pub x_px: f64,
    pub y_px: f64,
}

impl From<DVec2> for PixelPoint {
    fn from(p: DVec2) -> PixelPoint {
        PixelPoint { x_px: p.x, y_px: p.y }
    }
}

/// What a frame leaves the path scorer (a second job of the same take) to
/// score: the fused energy at each candidate, in the frame's terms.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
#[tsify(missing_as_null)]
pub struct PathWork {
    pub frame: usize,
    /// Where the frame's terms were made: the prediction, or where a lost
    /// tracker's best guess put the body.
    pub terms_at: FloorPoint,
    /// The cap of the frame's distance transforms (px); `null`: none.
    pub truncate_px: Option<f32>,
    /// How much the frame is shrunk before it is read, in quarters: 4
    /// reads it whole, 9 shrinks it 2.25 times each way.
    pub working_scale_quarters: u32,
    pub candidates: Vec<FloorPoint>,
}

impl PathWork {
    pub fn from_request(r: PathRequest) -> PathWork {
        PathWork {
            frame: r.frame,
            terms_at: r.terms_at_cm.into(),
            truncate_px: r.truncate_px,
            working_scale_quarters: r.working_scale.quarters(),
            candidates: r.candidates_cm.into_iter().map(FloorPoint::from).collect(),
        }
    }

    /// The work from the page's object (unknown fields refused).
    pub fn from_js(value: Ts<PathWork>) -> Result<PathRequest, String> {
        let object = value.js_value();
        refuse_unknown_fields::<FloorPoint>(&field(&object, "terms_at"), "the path request's terms_at")?;
        refuse_unknown_fields_of_each::<FloorPoint>(
            &field(&object, "candidates"),
            "the path request's candidates",
        )?;
        let work: PathWork = read_ts(&value, "the path request")?;
        let working_scale = Shrink::from_quarters(work.working_scale_quarters).ok_or_else(|| {
            format!(
                "the path request's working_scale_quarters: {} (4 or more: 4 reads the frame whole)",
                work.working_scale_quarters
            )
        })?;
        Ok(PathRequest {
            frame: work.frame,
            terms_at_cm: work.terms_at.into(),
            truncate_px: work.truncate_px,
            working_scale,
            candidates_cm: work.candidates.into_iter().map(DVec2::from).collect(),
        })
    }
}

/// A view tracked to the end in its own worker
/// ([`FinishedView`](crate::app::tracking::FinishedView)), as the first
/// view's worker weighs it in (`CameraJob.weigh`); the page only carries
/// it between them. Per video frame of the view: `floor_cm` x, z (cm),
/// `covariance_cm2` xx, xz, zx, zz (cm², NaN where none is stated),
/// `confidence` 0 to 1.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct FinishedViewFrames {
    pub video_name: String,
    pub fps: f64,
    pub frame_count: usize,
    pub offset_s: f64,
    pub floor_cm: Vec<f64>,
    pub covariance_cm2: Vec<f64>,
    pub confidence: Vec<f64>,
    pub warnings: Vec<String>,
}

impl From<&FinishedView> for FinishedViewFrames {
    fn from(view: &FinishedView) -> FinishedViewFrames {
        let frames = &view.sightings.frames;
        let timing = view.sightings.timing;
        FinishedViewFrames {
            video_name: view.video_name.clone(),
            fps: timing.fps,
            frame_count: timing.frame_count,
            offset_s: timing.offset_s,
            floor_cm: frames.iter().flat_map(|f| f.floor_cm.to_array()).collect(),
            covariance_cm2: frames.iter().flat_map(|f| f.covariance_cm2.to_cols_array()).collect(),
            confidence: frames.iter().map(|f| f.confidence).collect(),
            warnings: view.sightings.warnings.clone(),
        }
    }
}

impl FinishedViewFrames {
    /// The view from the page's object; an unknown field, or lists of
    /// other lengths than its frames', an error naming the view.
    pub fn from_js(value: Ts<FinishedViewFrames>) -> Result<FinishedView, String> {
        let v: FinishedViewFrames = read_ts(&value, "a view to weigh")?;
        let n = v.confidence.len();
        if v.floor_cm.len() != 2 * n || v.covariance_cm2.len() != 4 * n {
            return Err(format!(
                "the view of {}: {} confidences, {} floor numbers (2 a frame), {} covariance numbers (4 a frame)",
                v.video_name,
                n,
                v.floor_cm.len(),
                v.covariance_cm2.len()
            ));
        }
        let frames = (0..n)
            .map(|i| Sighting {
                floor_cm: DVec2::from_slice(&v.floor_cm[2 * i..]),
                covariance_cm2: DMat2::from_cols_slice(&v.covariance_cm2[4 * i..]),
                confidence: v.confidence[i],
            })
            .collect();
        let timing = VideoTiming { fps: v.fps, frame_count: v.frame_count, offset_s: v.offset_s };
        Ok(FinishedView {
            video_name: v.video_name,
            sightings: ViewSightings { timing, frames, warnings: v.warnings },
        })
    }
}

/// What a finished take wrote: the bytes `embusen track` writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct TakeFiles {
    /// The corrected recording (BVH).
    pub recording_text: String,
    /// The hips per video frame with the camera's confidence (CSV).
    pub track_csv: String,
    /// The opening's warnings and the finish's.
    pub warnings: Vec<String>,
}

/// The paper's candidates in one video frame, read from the page's object
/// (the app's [`RiecickyCandidates`], a `FrameCandidates` to the page); an
/// unknown field, a candidate's or its floor point's too, an error that
/// names it.
pub fn candidates_from_js(value: &Ts<RiecickyCandidates>) -> Result<RiecickyCandidates, String> {
    let tried = field(&value.js_value(), "tried");
    refuse_unknown_fields_of_each::<Candidate>(&tried, "the candidates' tried")?;
    if js_sys::Array::is_array(&tried) {
        for (i, candidate) in tried.unchecked_ref::<js_sys::Array>().iter().enumerate() {
            let floor = field(&candidate, "floor");
            refuse_unknown_fields::<FloorPoint>(&floor, &format!("the candidates' tried[{i}].floor"))?;
        }
    }
    read_ts(value, "the candidates")
}

/// The finished track against the true hips of a CSV.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct TruthErrors {
    pub mean_cm: f64,
    pub p90_cm: f64,
    pub max_cm: f64,
    /// The error of every video frame (cm).
    pub per_frame_cm: Vec<f64>,
}

/// One time offset tried.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct OffsetTried {
    pub offset_s: f64,
    /// The mean fused energy over the sampled frames (px).
    pub mean_energy_px: f64,
}

/// The time offset estimated after a track, as `embusen track
/// --estimate-offset`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct OffsetFound {
    /// The offset (s) to add to a video frame's time to read the BVH.
    pub offset_s: f64,
    pub tried: Vec<OffsetTried>,
}

impl From<OffsetEstimate> for OffsetFound {
    fn from(e: OffsetEstimate) -> OffsetFound {
        OffsetFound {
            offset_s: e.offset_s,
            tried: e
                .tried
                .into_iter()
                .map(|(offset_s, mean_energy_px)| OffsetTried { offset_s, mean_energy_px })
                .collect(),
        }
    }
}

/// One encoded frame of a demuxed video, for a `VideoDecoder`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct EncodedFrame {
    /// Where its bytes start in the file, and how many.
    pub offset: f64,
    pub size: u32,
    /// Its presentation time (µs).
    pub timestamp_us: f64,
    pub keyframe: bool,
}

/// A stage of the image pipeline, as a picture over the video
/// ([`crate::app::frame_layers`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Tsify)]
#[serde(rename_all = "lowercase")]
pub enum FrameLayer {
    Mask,
    Edges,
    Distance,
}

impl From<FrameLayer> for Layer {
    fn from(l: FrameLayer) -> Layer {
        match l {
            FrameLayer::Mask => Layer::Mask,
            FrameLayer::Edges => Layer::Edges,
            FrameLayer::Distance => Layer::Distance,
        }
    }
}

/// A video frame's luma plane, as the decoder gives it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct LumaPlane {
    /// Rows `stride` bytes apart.
    #[serde(deserialize_with = "bytes_in", serialize_with = "bytes_out")]
    #[tsify(type = "Uint8Array | ArrayBuffer")]
    pub luma: Vec<u8>,
    pub stride: usize,
    /// Whether black is 0 (else 16: limited range).
    pub full_range: bool,
}

/// The clicks of a floor rectangle's four corners, for `embusen calibrate
/// --floor-corners`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
#[tsify(missing_as_null)]
pub struct FloorCorners {
    /// The image's size.
    pub width_px: u32,
    pub height_px: u32,
    /// The corners clicked: the origin, along +X, the far corner, along +Z.
    pub corners: Vec<PixelPoint>,
    /// The rectangle's sides: along world +X, and along +Z.
    pub width_cm: f64,
    pub depth_cm: f64,
    /// The focal length (px); `null`: estimated too.
    pub focal_px: Option<f64>,
}

/// A camera calibrated here (from clicks or a board) and how well.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
#[tsify(missing_as_null)]
pub struct CameraFit {
    /// The camera as camera.json (what `embusen calibrate` writes).
    pub camera_json: String,
    /// The reprojection error (px): root mean square, and (from a board)
    /// the largest.
    pub rms_px: f64,
    pub max_px: Option<f64>,
    /// The focal length (px).
    pub focal_px: f64,
    /// From clicks: how far (cm, one σ) a pixel of click error moves the
    /// camera centre; `null` from a board.
    pub center_sigma_cm_per_px: Option<f64>,
    /// From a board: the corners found in the still; none from clicks.
    pub corners: Vec<PixelPoint>,
    /// From a board: the markers read.
    pub markers: usize,
}

/// What a board still is calibrated from, as `embusen calibrate`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
#[tsify(missing_as_null)]
pub struct BoardStill {
    /// The still (PNG).
    pub still: NamedFile,
    /// The board's layout (BOARD.json).
    pub board: NamedFile,
    /// A camera.json whose lens to use; `null`: the focal length from this view.
    pub lens: Option<NamedFile>,
}

impl BoardStill {
    /// The inputs from the page's object (unknown fields refused).
    pub fn from_js(value: Ts<BoardStill>) -> Result<BoardStill, String> {
        let object = value.js_value();
        for file in ["still", "board", "lens"] {
            refuse_unknown_fields::<NamedFile>(&field(&object, file), &format!("the board still's {file}"))?;
        }
        read_ts(&value, "the board still")
    }
}
