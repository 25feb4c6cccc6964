//! The browser side, two wasm modules built from this folder (`build.sh`):
//! the **player** (feature `web-player`, `dist/pkg/`): a `Player` that
//! JavaScript creates over two canvases (the 3D view and the plots) and
//! drives from its animation loop. It holds a [`Session`](crate::app::session::Session)
//! and a playback [`Clock`](crate::app::clock::Clock) and only translates
//! between the page and the core: parsing, kinematics, the method, plot
//! layout and rendering all happen in Rust. What crosses to the page is
//! typed ([`api`]). And the **camera tracker** (feature `web-camera`,
//! `dist/pkg-camera/`): the `CameraJob` a Web Worker runs and the floor
//! grid over the video ([`tracking`]), fetched only when a take is opened;
//! and the **board** module (feature `web-board`, `dist/pkg-board/`): the
//! ChArUco detector and the calibration from a board still
//! ([`calibration`]), fetched only when a board is used. So the player's
//! download stays small. Built only for wasm32; may import everything below it, and
//! nothing of the core imports it.

#[cfg(feature = "web-player")]
pub mod api;
#[cfg(feature = "web-board")]
pub mod calibration;
#[cfg(feature = "web-player")]
mod canvas2d;
mod panic;
#[cfg(feature = "web-player")]
mod player;
#[cfg(feature = "web-player")]
mod scene;
#[cfg(feature = "web-camera")]
pub mod tracking;

use wasm_bindgen::prelude::*;

pub use panic::{PANIC_EVENT, report_panic};
#[cfg(feature = "web-player")]
pub use player::*;

/// Runs once when the module is instantiated.
#[wasm_bindgen(start)]
fn start() {
    panic::install();
}
