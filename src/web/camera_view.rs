//! The camera as the page shows it, parsed once into a handle: the floor
//! grid over the video and the frustum in the player's 3D view; the camera
//! calibrated from four clicked floor corners; and what the tracker sees in
//! a frame, painted over the video ([`crate::app::frame_layers`]).

use tsify::{Ts, Tsify};
use wasm_bindgen::Clamped;
use wasm_bindgen::prelude::*;

use crate::app::calibration::{floor_grid_px, frustum_lines_cm};
use crate::app::frame_layers::{FrameLayers, layer_rgba};
use crate::camera::{Camera, FloorRectangle, FocalLength, ImageSize};
use crate::image::pipeline::Features;
use crate::web::camera_api::{CameraFit, FloorCorners, FrameLayer, LumaPlane, PixelPoint};
use crate::web::js_object::{field, read_ts, refuse_unknown_fields_of_each};
use crate::web::tracking::js_error;

/// A camera.json, parsed once.
#[wasm_bindgen]
pub struct CameraView {
    camera: Camera,
}

#[wasm_bindgen]
impl CameraView {
    /// The camera of `text` (a camera.json); the error names `name`.
    #[wasm_bindgen(constructor)]
    pub fn new(name: &str, text: &str) -> Result<CameraView, JsError> {
        Ok(CameraView { camera: Camera::from_json(text, name).map_err(js_error)? })
    }

    /// The floor grid as the camera sees it (lines every `spacing_cm`
    /// within `half_extent_cm` of the origin): each line its pixels.
    pub fn floor_grid_px(&self, spacing_cm: f64, half_extent_cm: f64) -> Result<Vec<Ts<PixelLine>>, JsError> {
        let lines = floor_grid_px(&self.camera, spacing_cm, half_extent_cm).into_iter();
        let lines = lines
            .map(|line| PixelLine { points: line.into_iter().map(PixelPoint::from).collect() }.into_ts());
        Ok(lines.collect::<Result<_, _>>()?)
    }

    /// The camera as the player's 3D view draws it ([`frustum_lines_cm`]),
    /// for `Player.show_camera_take`: per line its two ends, x, y, z (world
    /// cm) each.
    pub fn frustum_cm(&self, depth_cm: f64) -> Vec<f64> {
        frustum_lines_cm(&self.camera, depth_cm).iter().flatten().flat_map(|p| [p.x, p.y, p.z]).collect()
    }
}

/// A line in an image, point after point.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize, Tsify)]
pub struct PixelLine {
    pub points: Vec<PixelPoint>,
}

/// The camera calibrated by hand from four clicked floor corners
/// ([`crate::camera::floor_rectangle`]), as `embusen calibrate
/// --floor-corners` makes it; the error says what is wrong with the clicks.
#[wasm_bindgen]
pub fn calibrate_floor_corners(clicks: Ts<FloorCorners>) -> Result<Ts<CameraFit>, JsError> {
    let corners = field(&clicks.js_value(), "corners");
    refuse_unknown_fields_of_each::<PixelPoint>(&corners, "the floor corners' corners").map_err(js_error)?;
    let c: FloorCorners = read_ts(&clicks, "the floor corners").map_err(js_error)?;
    let [a, b, d, e] = c.corners[..] else {
        return Err(JsError::new(&format!("four corners, not {}", c.corners.len())));
    };
    let corners = [a, b, d, e].map(|p| glam::DVec2::new(p.x_px, p.y_px));
    let focal = c.focal_px.map_or(FocalLength::Unknown, FocalLength::Px);
    let fit = FloorRectangle { width_cm: c.width_cm, depth_cm: c.depth_cm }
        .calibrate(ImageSize { width_px: c.width_px, height_px: c.height_px }, corners, focal)
        .map_err(js_error)?;
    let fit = CameraFit {
        camera_json: fit.camera.to_json(),
        rms_px: fit.reprojection_rms_px,
        max_px: None,
        focal_px: fit.camera.intrinsics.fx_px,
        center_sigma_cm_per_px: Some(fit.center_sigma_cm_per_px),
        corners: Vec::new(),
        markers: 0,
    };
    Ok(fit.into_ts()?)
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

    /// Runs the pipeline on a frame (`label` names it in errors), for
    /// `layer` to paint.
    pub fn set_frame(&mut self, frame: Ts<LumaPlane>, label: &str) -> Result<(), JsError> {
        let p: LumaPlane = read_ts(&frame, label).map_err(js_error)?;
        self.features = Some(self.layers.features(&p.luma, p.stride, p.full_range, label).map_err(js_error)?);
        Ok(())
    }

    /// A stage of the last frame as RGBA pixels (for an `ImageData` of the
    /// frame's size).
    pub fn layer(&self, layer: Ts<FrameLayer>) -> Result<Clamped<Vec<u8>>, JsError> {
        let layer = read_ts(&layer, "the frame layer").map_err(js_error)?;
        let features = self.features.as_ref().ok_or_else(|| JsError::new("no frame given yet"))?;
        Ok(Clamped(layer_rgba(features, layer.into())))
    }
}
