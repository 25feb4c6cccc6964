//! The camera's calibration from a board still in the page: the board module
//! (`dist/pkg-board/`, the ChArUco detector in it), fetched only when a board
//! is used; [`app::calibration`](crate::app::calibration) behind wasm-bindgen.

use wasm_bindgen::prelude::*;

use crate::app::calibration::calibrate_from_still;
use crate::app::tracking::NamedBytes;
use crate::camera::Camera;
use crate::camera::board::Board;

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// A board still's calibration.
#[wasm_bindgen]
pub struct BoardCalibration {
    camera_json: String,
    corners_px: Vec<f64>,
    rms_px: f64,
    max_px: f64,
    markers: usize,
}

/// Finds the board of `board_json` in the PNG `still` and calibrates the
/// camera from it: with `lens_json`'s intrinsics when given, else the focal
/// length from this one view. The error names the file at fault (the board
/// not found says how far the search got).
#[wasm_bindgen]
pub fn calibrate_board(
    still_name: &str,
    still: &[u8],
    board_name: &str,
    board_json: &str,
    lens_name: &str,
    lens_json: Option<String>,
) -> Result<BoardCalibration, JsError> {
    let board = Board::from_json(board_json, board_name).map_err(js_error)?;
    let lens = lens_json.map(|text| Camera::from_json(&text, lens_name)).transpose().map_err(js_error)?;
    let found = calibrate_from_still(NamedBytes { name: still_name, bytes: still }, &board, lens.as_ref())
        .map_err(js_error)?;
    Ok(BoardCalibration {
        camera_json: found.calibration.camera.to_json(),
        corners_px: found.detection.corners.iter().flat_map(|c| [c.pixel.x, c.pixel.y]).collect(),
        rms_px: found.calibration.rms_px,
        max_px: found.calibration.max_px,
        markers: found.detection.markers,
    })
}

#[wasm_bindgen]
impl BoardCalibration {
    /// The camera, as `camera.json` text.
    pub fn camera_json(&self) -> String {
        self.camera_json.clone()
    }

    /// The corners found, `x, y` pixel after pixel.
    pub fn corners_px(&self) -> Vec<f64> {
        self.corners_px.clone()
    }

    /// The corners' reprojection error (px): root mean square and largest.
    pub fn rms_px(&self) -> f64 {
        self.rms_px
    }

    pub fn max_px(&self) -> f64 {
        self.max_px
    }

    pub fn markers(&self) -> usize {
        self.markers
    }
}
