//! The camera panel's plots and overlay colours: the shapes laid out in
//! [`app::plot::camera`](crate::app::plot::camera), painted on the panel's
//! canvases by the player's painter ([`canvas2d`](super::canvas2d)); the
//! colours of what the page draws over the video, from the theme.

use tsify::{Ts, Tsify};
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

use crate::app::plot::Figure;
use crate::app::plot::camera::{ErrorSeries, candidates_view, frame_series, top_view};
use crate::app::theme;
use crate::web::camera_api::{FloorPoint, RiecickyCandidates, TruthErrors, candidates_from_js};
use crate::web::canvas2d;
use crate::web::js_object::read_ts;

/// Paints `figure` over the whole of `canvas`.
fn paint(canvas: &HtmlCanvasElement, figure: &Figure) -> Result<(), JsError> {
    let ctx = canvas
        .get_context("2d")
        .map_err(|_| JsError::new("no 2D context"))?
        .and_then(|c| c.dyn_into::<CanvasRenderingContext2d>().ok())
        .ok_or_else(|| JsError::new("no 2D context"))?;
    canvas2d::paint(&ctx, figure);
    Ok(())
}

/// The hips' track so far seen from above, on `canvas`.
#[wasm_bindgen]
pub fn paint_top_view(canvas: &HtmlCanvasElement, path: Vec<Ts<FloorPoint>>) -> Result<(), JsError> {
    let path = path
        .iter()
        .map(|p| read_ts(p, "a point of the top view's path").map(glam::DVec2::from))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| JsError::new(&e))?;
    paint(canvas, &top_view(canvas.width() as f32, canvas.height() as f32, &path))
}

/// The camera's confidence per frame (0 to 1) and, with `errors` against
/// the truth named `truth_name`, the track's error, over `frame_count`
/// frames, a cursor at `shown_frame`, on `canvas`.
#[wasm_bindgen]
pub fn paint_frame_series(
    canvas: &HtmlCanvasElement,
    confidence: &[f64],
    errors: Option<Ts<TruthErrors>>,
    truth_name: &str,
    frame_count: usize,
    shown_frame: usize,
) -> Result<(), JsError> {
    let errors = errors.map(|e| read_ts(&e, "the truth errors")).transpose().map_err(|e| JsError::new(&e))?;
    let series = errors.as_ref().map(|e| ErrorSeries { per_frame_cm: &e.per_frame_cm, truth_name });
    let (w, h) = (canvas.width() as f32, canvas.height() as f32);
    paint(canvas, &frame_series(w, h, confidence, series, frame_count, shown_frame))
}

/// The paper's candidates of the frame shown (`frame`: none there), on `canvas`.
#[wasm_bindgen]
pub fn paint_candidates(
    canvas: &HtmlCanvasElement,
    frame: Option<Ts<RiecickyCandidates>>,
    shown_frame: usize,
) -> Result<(), JsError> {
    let frame = frame.map(|f| candidates_from_js(&f)).transpose().map_err(|e| JsError::new(&e))?;
    let tried = frame.as_ref().map_or(&[][..], |f| &f.tried[..]);
    let chosen = frame.as_ref().and_then(|f| f.chosen);
    let (w, h) = (canvas.width() as f32, canvas.height() as f32);
    paint(canvas, &candidates_view(w, h, tried, chosen, shown_frame))
}

/// The colours of what the page draws over the video, as CSS takes them.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize, Tsify)]
pub struct OverlayColours {
    pub floor_grid_css: String,
    pub board_corner_css: String,
    pub outline_css: String,
    pub clicked_css: String,
}

/// The overlay's colours ([`theme`]).
#[wasm_bindgen]
pub fn overlay_colours() -> Result<Ts<OverlayColours>, JsError> {
    let colours = OverlayColours {
        floor_grid_css: theme::VIDEO_FLOOR_GRID.to_css(),
        board_corner_css: theme::CONFIDENCE.to_css(),
        outline_css: theme::BODY_OUTLINE.to_css(),
        clicked_css: theme::CLICKED_CORNER.to_css(),
    };
    Ok(colours.into_ts()?)
}
