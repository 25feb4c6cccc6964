//! The camera from a still of a ChArUco board on the floor, as the app and
//! `embusen calibrate` (and `embusen track --board`) all make it: the still
//! decoded to grey (as every still is, `io::image_file`), the board found
//! (`camera::charuco`), the pose (and without a lens given, the focal
//! length) fitted (`camera::calibrate`), a lens given checked against the
//! still's size;
//! and the floor grid drawn over a picture to check a camera by eye, and the
//! camera drawn where it stands in the 3D view.

use glam::{DVec2, DVec3};

use crate::camera::Camera;
// The calibration needs the board's detector (feature `board`); the grid
// does not.
#[cfg(feature = "board")]
use crate::app::tracking::NamedBytes;
#[cfg(feature = "board")]
use crate::camera::ImageSize;
#[cfg(feature = "board")]
use crate::camera::board::Board;
#[cfg(feature = "board")]
use crate::camera::calibrate::{BoardView, Calibration, LensFit, calibrate_one_view, calibrate_pose};
#[cfg(feature = "board")]
use crate::camera::charuco::{Detection, detect};
#[cfg(feature = "board")]
use crate::error::Error;
#[cfg(feature = "board")]
use crate::io::image_file::png_to_grey;

/// A still's calibration, with what was found in it.
#[cfg(feature = "board")]
#[derive(Clone, Debug)]
pub struct StillCalibration {
    pub calibration: Calibration,
    pub detection: Detection,
    pub size: ImageSize,
}

/// A still decoded and the board found in it: the first half of
/// [`calibrate_from_still`], for a caller that reports what was found
/// before the camera is fitted (`embusen calibrate`).
#[cfg(feature = "board")]
#[derive(Clone, Debug)]
pub struct BoardInStill {
    pub detection: Detection,
    pub size: ImageSize,
}

/// The camera that took `still` (a PNG) of `board` on the floor: its pose
/// with `lens`'s intrinsics when given (an error when the still is of
/// another size), else its focal length too, from this one view, the
/// principal point assumed at the image's centre. An error naming the
/// still when the board is not found.
#[cfg(feature = "board")]
pub fn calibrate_from_still(
    still: NamedBytes,
    board: &Board,
    lens: Option<&Camera>,
) -> Result<StillCalibration, Error> {
    let found = find_board_in_still(still, board)?;
    let calibration = calibrate_from_board_in_still(still.name, board, &found, lens, LensFit::default())?;
    Ok(StillCalibration { calibration, detection: found.detection, size: found.size })
}

/// `still` (a PNG) decoded to grey as every still is, and `board` found in
/// it; an error naming the still when it is not.
#[cfg(feature = "board")]
pub fn find_board_in_still(still: NamedBytes, board: &Board) -> Result<BoardInStill, Error> {
    let grey = png_to_grey(still.bytes, still.name)?;
    let size = ImageSize { width_px: grey.width_px, height_px: grey.height_px };
    let detection = detect(board, &grey.pixels, size, still.name)?;
    Ok(BoardInStill { detection, size })
}

/// The camera from the board `found` in the still `still_name`: posed with
/// `lens` when given (an error when the still is not of its image size),
/// else its focal length too (and `k1` when `lens_fit` says), the principal
/// point at the image's centre.
#[cfg(feature = "board")]
pub fn calibrate_from_board_in_still(
    still_name: &str,
    board: &Board,
    found: &BoardInStill,
    lens: Option<&Camera>,
    lens_fit: LensFit,
) -> Result<Calibration, Error> {
    let size = found.size;
    let view = BoardView { file: still_name, board, corners: &found.detection.corners };
    match lens {
        Some(lens) => {
            if lens.image_size != size {
                return Err(Error::whole(
                    still_name,
                    format!(
                        "the still is {}×{} px, the intrinsics are for {}×{}",
                        size.width_px, size.height_px, lens.image_size.width_px, lens.image_size.height_px
                    ),
                ));
            }
            calibrate_pose(&view, lens)
        }
        None => calibrate_one_view(&view, size, lens_fit),
    }
}

/// The floor's grid lines as `camera` sees them: lines every `spacing_cm`
/// along x and z within `half_extent_cm` of the world's origin, each as
/// pixels sampled every `spacing_cm / 8` (through the lens: straight lines
/// bend), a line broken where it leaves the picture or goes behind the
/// camera. Each polyline is a list of pixels.
pub fn floor_grid_px(camera: &Camera, spacing_cm: f64, half_extent_cm: f64) -> Vec<Vec<DVec2>> {
    let mut lines = Vec::new();
    if !(spacing_cm > 0.0 && half_extent_cm >= 0.0) {
        return lines;
    }
    let n = (half_extent_cm / spacing_cm).floor() as i32;
    let (w, h) = (camera.image_size.width_px as f64, camera.image_size.height_px as f64);
    let step = spacing_cm / 8.0;
    let samples = (2.0 * half_extent_cm / step).ceil() as i32;
    for k in -n..=n {
        let at = k as f64 * spacing_cm;
        for along_x in [true, false] {
            let mut line = Vec::new();
            for s in 0..=samples {
                let t = -half_extent_cm + s as f64 * step;
                let point = if along_x { DVec3::new(t, 0.0, at) } else { DVec3::new(at, 0.0, t) };
                match camera.point_in_image(point) {
                    Some(p) if p.x >= -0.5 && p.y >= -0.5 && p.x <= w - 0.5 && p.y <= h - 0.5 => line.push(p),
                    _ => {
                        if line.len() > 1 {
                            lines.push(std::mem::take(&mut line));
                        }
                        line.clear();
                    }
                }
            }
            if line.len() > 1 {
                lines.push(line);
            }
        }
    }
    lines
}

/// The camera as the 3D view draws it, a frustum: the lines (pairs of
/// world points, cm) from its centre to where the image's four corners'
/// rays are `depth_cm` ahead, and the rectangle between those four points.
pub fn frustum_lines_cm(camera: &Camera, depth_cm: f64) -> Vec<[DVec3; 2]> {
    let (w, h) = (camera.image_size.width_px as f64, camera.image_size.height_px as f64);
    let world_from_camera = camera.world_from_camera();
    let centre = world_from_camera.translation;
    // The image's outer corners (pixel centres at 0 .. w − 1, so its edge
    // is half a pixel beyond).
    let corners = [(-0.5, -0.5), (w - 0.5, -0.5), (w - 0.5, h - 0.5), (-0.5, h - 0.5)].map(|(x, y)| {
        let ray = camera.ray_in_camera(DVec2::new(x, y));
        world_from_camera.transform_point3(ray * (depth_cm / ray.z))
    });
    let mut lines: Vec<[DVec3; 2]> = corners.iter().map(|&c| [centre, c]).collect();
    lines.extend((0..4).map(|i| [corners[i], corners[(i + 1) % 4]]));
    lines
}

#[cfg(test)]
mod frustum_tests {
    use super::*;

    #[test]
    fn the_frustum_reaches_from_the_centre_to_what_the_corners_see() {
        use crate::camera::{Distortion, ImageSize, Intrinsics};
        use glam::{DAffine3, DMat3};
        // 5 m back and 1.5 m up, looking along −Z, tilted down a little.
        let axes = DMat3::from_rotation_x(-0.3) * DMat3::from_cols(DVec3::X, DVec3::NEG_Y, DVec3::NEG_Z);
        let camera = Camera {
            image_size: ImageSize { width_px: 640, height_px: 480 },
            intrinsics: Intrinsics { fx_px: 500.0, fy_px: 502.0, cx_px: 319.5, cy_px: 239.5 },
            distortion: Distortion::default(),
            camera_from_world: DAffine3::from_mat3_translation(axes, DVec3::new(20.0, 150.0, 500.0))
                .inverse(),
        };
        let lines = frustum_lines_cm(&camera, 200.0);
        assert_eq!(lines.len(), 8);
        for [a, b] in &lines[..4] {
            assert!((*a - camera.center_in_world()).length() < 1e-9);
            let p = camera.point_in_camera(*b);
            assert!((p.z - 200.0).abs() < 1e-6, "{p}");
            let pixel = camera.point_in_image(*b).unwrap();
            let (w, h) = (camera.image_size.width_px as f64, camera.image_size.height_px as f64);
            assert!((pixel.x + 0.5).abs() < 1e-6 || (pixel.x - (w - 0.5)).abs() < 1e-6, "{pixel}");
            assert!((pixel.y + 0.5).abs() < 1e-6 || (pixel.y - (h - 0.5)).abs() < 1e-6, "{pixel}");
        }
    }
}
