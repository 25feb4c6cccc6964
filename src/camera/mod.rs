//! The camera that films the actor: its model, how it is stored, and how it
//! is calibrated. May import `signal` and `error` (it needs only `error`);
//! nothing above (no images, files or bodies: a still's pixels come in as
//! grey bytes, and go out as corners).
//!
//! Conventions, stated here once (they are OpenCV's, so that a calibration
//! made with OpenCV and one made here are the same numbers):
//! - **World**: the BVH world, Y up, cm, the floor at y = 0.
//! - **Camera axes**: x right, y down, z forward along the optical axis;
//!   `point_in_camera = camera_from_world · point_in_world`, in cm.
//! - **Pixels**: (0, 0) is the *centre* of the top-left pixel, x right, y
//!   down; a pixel `(u, v)` covers `[u − ½, u + ½) × [v − ½, v + ½)`.
//! - **Lens**: OpenCV's distortion model with `k1, k2, p1, p2, k3` (radial
//!   to r⁶, tangential), applied to the normalised image point `x/z, y/z`
//!   before the focal lengths and principal point, as `cv2.projectPoints`.
//! - **Rotations** in files are OpenCV's Rodrigues vectors (`rotation`).
//!
//! The camera (`pinhole`, its rotations in `rotation`) is kept as
//! `camera.json` (`json`: `Camera::from_json`, `Camera::to_json`),
//! calibrated from stills of a ChArUco board (`board`, its layout and file;
//! `charuco`, finding it, feature `board`, its markers found on their own
//! in `aruco`; `calibrate`, the camera from its
//! corners: its pose, or its lens and pose, Zhang's method from several),
//! and made by hand from four floor points (`floor_rectangle`) when there
//! is no board. The calibrations share one toolbox: `homography` (the
//! plane-to-image homography and the focal length, pose and intrinsics it
//! gives) and `least_squares` (the small dense solvers and the one
//! Levenberg–Marquardt minimiser, its damping rules per calibration).

#[cfg(feature = "board")]
mod aruco;
pub mod board;
pub mod calibrate;
#[cfg(feature = "board")]
pub mod charuco;
pub mod floor_rectangle;
pub mod homography;
pub mod json;
pub mod least_squares;
pub mod pinhole;
pub mod rotation;

pub use floor_rectangle::{FloorCalibration, FloorRectangle, FocalLength};
pub use pinhole::{Camera, Distortion, ImageSize, Intrinsics};
