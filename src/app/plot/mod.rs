//! The app's plots as pure data: the figure is laid out here into a list of
//! shapes, which the browser merely paints (see `web::canvas2d`), so layout,
//! decimation and hit-testing are tested natively and the wasm side stays
//! thin. Like all of `app`, it may import the layers below (`eval`,
//! `translate`, `synth`, `io`, `body`, `signal`), never `web`; its colours
//! come from [`crate::app::theme`].
//!
//! All coordinates are pixels of the canvas the figure is painted on (its
//! own `width` × `height`, device pixels in the app, not CSS pixels), origin
//! at the top left, y down.
//!
//! The figure is the paper's, live, in five panels:
//! - (a) the smoothed foot signal that pass 1 compares,
//! - (b) the foot heights before correction and (c) after it,
//! - (d) the hips' path on the floor seen from above, original and corrected,
//! - (e) the stance strip: which foot was held still in each frame, and why
//!   (or, for the contact method, which feet were on the floor).
//!
//! The time panels (a), (b), (c) and (e) share one time axis, numbered under
//! (e), so a single cursor lines up across them. Each foot is always its
//! [`theme::FEET`](crate::app::theme::FEET) colour; "before" is drawn ghosted,
//! "after" solid.
//!
//! Drawing is split in two because a recording can have 100,000 frames: the
//! static part ([`draw_static`]) holds the long series, decimated to at most
//! two points per pixel column, and is meant to be painted once into an
//! offscreen canvas; the cursor ([`draw_cursor`]) is a handful of shapes
//! drawn over it each frame. Text widths come from a [`TextMeasure`].
//!
//! The camera panel's plots (the track from above, the confidence and error
//! per frame, the paper's candidates) are laid out here too ([`camera`]).

mod axes;
pub mod camera;
mod cursor;
mod data;
mod decimate;
mod figure;
mod layout;
mod legend;
mod panels;
#[cfg(test)]
mod testing;
mod text;

pub use cursor::{camera_path_px, draw, draw_cursor, frame_at};
pub use data::{CameraSeries, PlotData, Stance, StanceReason};
pub use figure::{Align, DASH_PX, FONT_FAMILY, Figure, Rect, Shape};
pub use layout::{Layout, Panel, PanelRects, layout, layout_for, panel_at};
pub use panels::draw_static;
pub use text::TextMeasure;
