//! The browser side, three wasm modules built from this folder (`build.sh`),
//! each behind its feature so that a page downloads only what it uses. The
//! **player** (feature `web-player`, `dist/pkg/`), which every page loads: a
//! `Player` that JavaScript creates over two canvases (the 3D view and the
//! plots) and drives from its animation loop. It holds a
//! [`Session`](crate::app::session::Session) and a playback
//! [`Clock`](crate::app::clock::Clock) and only translates between the page
//! and the core: parsing, kinematics, the method, plot layout and rendering
//! all happen in Rust; what crosses to the page is typed ([`api`]). The
//! **camera tracker** (feature `web-camera`, `dist/pkg-camera/`), fetched
//! only with a take to track: the `CameraJob` a Web Worker runs
//! ([`tracking`]), the video's frames and stills ([`video`]), the camera
//! parsed once for the overlays and the 3D view, the four clicked floor
//! corners, the tracker's view of a frame ([`camera_view`]), the panel's
//! plots and overlay colours ([`camera_plots`]). The **board**
//! module (feature `web-board`, `dist/pkg-board/`), fetched only when a
//! board is used: the ChArUco detector and the calibration from a board
//! still ([`calibration`]). The camera and board modules' boundary is typed
//! as the player's ([`camera_api`]). Built only for wasm32; may import
//! everything below it, and nothing of the core imports it.

#[cfg(feature = "web-player")]
pub mod api;
#[cfg(feature = "web-board")]
pub mod calibration;
#[cfg(any(feature = "web-camera", feature = "web-board"))]
pub mod camera_api;
#[cfg(feature = "web-camera")]
pub mod camera_plots;
#[cfg(feature = "web-camera")]
pub mod camera_view;
#[cfg(any(feature = "web-player", feature = "web-camera"))]
mod canvas2d;
mod js_object;
mod panic;
#[cfg(feature = "web-player")]
mod player;
#[cfg(feature = "web-player")]
mod scene;
#[cfg(any(feature = "web-player", feature = "web-camera"))]
pub mod take_series;
#[cfg(feature = "web-camera")]
pub mod tracking;
#[cfg(feature = "web-camera")]
pub mod video;

use wasm_bindgen::prelude::*;

pub use panic::{PANIC_EVENT, report_panic};
#[cfg(feature = "web-player")]
pub use player::*;

/// Runs once when the module is instantiated.
#[wasm_bindgen(start)]
fn start() {
    panic::install();
}
