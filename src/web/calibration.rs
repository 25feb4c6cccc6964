//! The camera's calibration from a board still in the page: the board module
//! (`dist/pkg-board/`, the ChArUco detector in it), fetched only when a board
//! is used; [`app::calibration`](crate::app::calibration) behind wasm-bindgen,
//! typed as the camera module is ([`camera_api`](super::camera_api)).

use tsify::{Ts, Tsify};
use wasm_bindgen::prelude::*;

use crate::app::calibration::calibrate_from_still;
use crate::camera::Camera;
use crate::camera::board::Board;
use crate::web::camera_api::{BoardStill, CameraFit, PixelPoint};

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// Finds the board in the still and calibrates the camera from it, as
/// `embusen calibrate`: with the lens's intrinsics when given, else the
/// focal length from this one view. The error names the file at fault (the
/// board not found says how far the search got).
#[wasm_bindgen]
pub fn calibrate_board(inputs: Ts<BoardStill>) -> Result<Ts<CameraFit>, JsError> {
    let BoardStill { still, board, lens } = BoardStill::from_js(inputs).map_err(js_error)?;
    let board = Board::from_json(&board.text(), &board.name).map_err(js_error)?;
    let lens = lens.map(|l| Camera::from_json(&l.text(), &l.name)).transpose().map_err(js_error)?;
    let found = calibrate_from_still(still.named_bytes(), &board, lens.as_ref()).map_err(js_error)?;
    let c = &found.calibration;
    let fit = CameraFit {
        camera_json: c.camera.to_json(),
        rms_px: c.rms_px,
        max_px: Some(c.max_px),
        focal_px: c.camera.intrinsics.fx_px,
        center_sigma_cm_per_px: None,
        corners: found.detection.corners.iter().map(|k| PixelPoint::from(k.pixel)).collect(),
        markers: found.detection.markers,
    };
    Ok(fit.into_ts()?)
}
