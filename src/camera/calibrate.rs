//! The camera from a board's corners seen in stills: its pose when the lens
//! is known (PnP), or its lens and pose when it is not (Zhang's method).
//!
//! Every solve is a closed-form start refined by Levenberg–Marquardt on the
//! reprojection error, the pixels projected through [`Camera::point_in_image`]
//! (OpenCV's lens model), so that the error minimised is the one reported.
//! The starts come from the plane-to-image homography of each view:
//! - **pose, lens known**: the pixels undistorted to normalised image
//!   points, whose homography from the board is `[r1 r2 t]` up to scale;
//! - **lens from one view** (all there is for a camera that filmed one
//!   board still): the principal point assumed at the image centre
//!   `((w − 1)/2, (h − 1)/2)`, square pixels, no skew and no distortion
//!   leave the focal length as the one unknown, which Zhang's two
//!   constraints on the homography give in closed form; then focal length
//!   and pose (and `k1` when asked) are refined;
//! - **lens from several views**: Zhang's closed form for `K` (zero skew),
//!   then `fx, fy, cx, cy, k1, k2` and every view's pose refined together.
//!
//! The homographies and the starts they give are `homography`'s, the
//! minimiser `least_squares`'s.

use glam::{DAffine3, DMat3, DVec2, DVec3};

use super::board::{Board, BoardCorner};
use super::homography::{
    FocalSolve, PoseFit, focal_from_homography, homography, pose_from_homography, zhang_intrinsics,
};
use super::least_squares::{CentralDifferences, minimise};
use super::pinhole::{Camera, Distortion, ImageSize, Intrinsics};
use super::rotation::rotation_from_rodrigues;
use crate::error::Error;

/// The corners of one board found in one still.
#[derive(Clone, Copy, Debug)]
pub struct BoardView<'a> {
    /// The still's name, for errors.
    pub file: &'a str,
    pub board: &'a Board,
    pub corners: &'a [BoardCorner],
}

/// A camera fitted to one view, and how well it reprojects the corners.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    pub camera: Camera,
    /// Root mean square of the corners' reprojection distances (px).
    pub rms_px: f64,
    /// The largest corner's reprojection distance (px).
    pub max_px: f64,
    pub corners: usize,
}

/// What the lens-free calibrations refine besides the focal length and pose.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LensFit {
    /// One view: refine the radial `k1` too (weakly seen from a small board;
    /// off by default). Several views always refine `k1` and `k2`.
    pub k1: bool,
}

/// Fewest corners for a pose (a homography needs four points).
const MIN_CORNERS_POSE: usize = 4;
/// Fewest corners for a focal length as well: a margin over the minimum,
/// since an error in one corner then moves the focal length too.
const MIN_CORNERS_LENS: usize = 6;

/// The pose of a camera whose lens is known (`lens`'s image size,
/// intrinsics and distortion; its pose is not read) from one view.
pub fn calibrate_pose(view: &BoardView, lens: &Camera) -> Result<Calibration, Error> {
    let (on_board, pixels) = correspondences(view, MIN_CORNERS_POSE)?;
    let normalised: Vec<DVec2> =
        pixels.iter().map(|&p| lens.distortion.undistort(lens.intrinsics.normalised(p))).collect();
    let h = homography(&on_board, &normalised).ok_or_else(|| degenerate(view))?;
    let start = pose_from_homography(&h, &DMat3::IDENTITY.inverse(), PoseFit::NearestRotationXy)
        .ok_or_else(|| degenerate(view))?;
    let mut fit = BoardFit {
        size: lens.image_size,
        intrinsics: lens.intrinsics,
        distortion: lens.distortion,
        poses: vec![start],
    };
    fit.refine(std::slice::from_ref(view), Free::Nothing);
    Ok(fit.calibration(view, 0))
}

/// Lens and pose from one view, with the principal point at the image
/// centre, square pixels, no skew and (unless `fit.k1`) no distortion.
pub fn calibrate_one_view(view: &BoardView, size: ImageSize, fit: LensFit) -> Result<Calibration, Error> {
    let (on_board, pixels) = correspondences(view, MIN_CORNERS_LENS)?;
    let centre = DVec2::new(size.width_px as f64 - 1.0, size.height_px as f64 - 1.0) / 2.0;
    let h = homography(&on_board, &pixels).ok_or_else(|| degenerate(view))?;
    let focal = focal_from_homography(&h, FocalSolve::UnitRows { centre }).ok_or_else(|| {
        Error::whole(
            view.file,
            "the board is seen too nearly face on to tell the focal length; give --intrinsics",
        )
    })?;
    let intrinsics = Intrinsics { fx_px: focal, fy_px: focal, cx_px: centre.x, cy_px: centre.y };
    let start = pose_from_homography(&h, &intrinsics.matrix().inverse(), PoseFit::NearestRotationXy)
        .ok_or_else(|| degenerate(view))?;
    let mut solved = BoardFit { size, intrinsics, distortion: Distortion::default(), poses: vec![start] };
    solved.refine(std::slice::from_ref(view), if fit.k1 { Free::FocalK1 } else { Free::Focal });
    Ok(solved.calibration(view, 0))
}

/// One lens and a pose per view from several views (Zhang's method); each
/// calibration carries the shared lens and its own view's pose. One view
/// falls back to [`calibrate_one_view`].
pub fn calibrate_views(views: &[BoardView], size: ImageSize) -> Result<Vec<Calibration>, Error> {
    match views {
        [] => return Err(Error::whole("<calibrate>", "no board view to calibrate from")),
        [view] => return calibrate_one_view(view, size, LensFit::default()).map(|c| vec![c]),
        _ => {}
    }
    // Pixels scaled about the image centre to about ±0.5 keep the
    // homographies' and Zhang's systems well conditioned.
    let scale = size.width_px.max(size.height_px) as f64;
    let centre = DVec2::new(size.width_px as f64 - 1.0, size.height_px as f64 - 1.0) / 2.0;
    let mut homographies = Vec::new();
    for view in views {
        let (on_board, pixels) = correspondences(view, MIN_CORNERS_LENS)?;
        let scaled: Vec<DVec2> = pixels.iter().map(|&p| (p - centre) / scale).collect();
        homographies.push(homography(&on_board, &scaled).ok_or_else(|| degenerate(view))?);
    }
    let k = zhang_intrinsics(&homographies).ok_or_else(|| {
        Error::whole(
            views[0].file,
            "the views do not determine one lens (too few, too alike, or from different cameras); give --intrinsics",
        )
    })?;
    let intrinsics = Intrinsics {
        fx_px: k.x_axis.x * scale,
        fy_px: k.y_axis.y * scale,
        cx_px: k.z_axis.x * scale + centre.x,
        cy_px: k.z_axis.y * scale + centre.y,
    };
    let mut poses = Vec::new();
    for (view, h) in views.iter().zip(&homographies) {
        poses.push(
            pose_from_homography(h, &k.inverse(), PoseFit::NearestRotationXy)
                .ok_or_else(|| degenerate(view))?,
        );
    }
    let mut fit = BoardFit { size, intrinsics, distortion: Distortion::default(), poses };
    fit.refine(views, Free::Lens);
    Ok((0..views.len()).map(|i| fit.calibration(&views[i], i)).collect())
}

/// The board-plane points and pixels of a view's corners.
fn correspondences(view: &BoardView, needed: usize) -> Result<(Vec<DVec2>, Vec<DVec2>), Error> {
    let mut on_board = Vec::new();
    let mut pixels = Vec::new();
    for corner in view.corners {
        let point = view.board.corner_on_board(corner.id).ok_or_else(|| {
            Error::whole(
                view.file,
                format!(
                    "corner id {} is not on a {}×{} board",
                    corner.id, view.board.squares_x, view.board.squares_y
                ),
            )
        })?;
        if !(corner.pixel.x.is_finite() && corner.pixel.y.is_finite()) {
            return Err(Error::whole(view.file, format!("corner {} has no finite pixel", corner.id)));
        }
        on_board.push(point);
        pixels.push(corner.pixel);
    }
    if on_board.len() < needed {
        return Err(Error::whole(
            view.file,
            format!("{} board corners found; this calibration needs at least {needed}", on_board.len()),
        ));
    }
    Ok((on_board, pixels))
}

fn degenerate(view: &BoardView) -> Error {
    Error::whole(
        view.file,
        "the corners found lie on one line or the view is degenerate: no pose can be fitted",
    )
}

/// The camera's pose relative to the board: board cm → camera cm.
type Pose = DAffine3;

/// Which lens parameters a refinement frees (the poses always are).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Free {
    Nothing,
    Focal,
    FocalK1,
    Lens,
}

/// A lens and one pose per view, being refined to the board's corners.
struct BoardFit {
    size: ImageSize,
    intrinsics: Intrinsics,
    distortion: Distortion,
    poses: Vec<Pose>,
}

impl BoardFit {
    fn camera(&self, view: &BoardView, i: usize) -> Camera {
        Camera {
            image_size: self.size,
            intrinsics: self.intrinsics,
            distortion: self.distortion,
            camera_from_world: self.poses[i] * view.board.world_from_board.inverse(),
        }
    }

    /// Lens parameters as the minimiser's unknowns, then 6 per view: a
    /// rotation vector applied before the start's rotation, and the
    /// translation.
    fn lens_params(&self, free: Free) -> Vec<f64> {
        let (k, d) = (self.intrinsics, self.distortion);
        match free {
            Free::Nothing => vec![],
            Free::Focal => vec![k.fx_px],
            Free::FocalK1 => vec![k.fx_px, d.k1],
            Free::Lens => vec![k.fx_px, k.fy_px, k.cx_px, k.cy_px, d.k1, d.k2],
        }
    }

    fn with_params(&self, free: Free, starts: &[Pose], params: &[f64]) -> BoardFit {
        let (mut k, mut d) = (self.intrinsics, self.distortion);
        let lens = match free {
            Free::Nothing => 0,
            Free::Focal => {
                (k.fx_px, k.fy_px) = (params[0], params[0]);
                1
            }
            Free::FocalK1 => {
                (k.fx_px, k.fy_px, d.k1) = (params[0], params[0], params[1]);
                2
            }
            Free::Lens => {
                (k.fx_px, k.fy_px, k.cx_px, k.cy_px, d.k1, d.k2) =
                    (params[0], params[1], params[2], params[3], params[4], params[5]);
                6
            }
        };
        let poses = starts
            .iter()
            .enumerate()
            .map(|(i, start)| {
                let p = &params[lens + 6 * i..lens + 6 * i + 6];
                let turn = rotation_from_rodrigues(DVec3::new(p[0], p[1], p[2]));
                DAffine3::from_mat3_translation(turn * start.matrix3, DVec3::new(p[3], p[4], p[5]))
            })
            .collect();
        BoardFit { size: self.size, intrinsics: k, distortion: d, poses }
    }

    /// Per corner of every view, the projected minus the seen pixel.
    fn residuals(&self, views: &[BoardView], out: &mut Vec<f64>) {
        out.clear();
        for (i, view) in views.iter().enumerate() {
            let camera = self.camera(view, i);
            for corner in view.corners {
                let seen = view.board.corner_in_world(corner.id).and_then(|p| camera.point_in_image(p));
                // A corner behind the camera: a large, smooth-enough
                // penalty, so that the minimiser backs away from the step.
                let d = seen.map_or(DVec2::splat(1e4), |p| p - corner.pixel);
                out.extend([d.x, d.y]);
            }
        }
    }

    fn refine(&mut self, views: &[BoardView], free: Free) {
        let starts = self.poses.clone();
        let mut params = self.lens_params(free);
        for pose in &starts {
            params.extend([0.0, 0.0, 0.0, pose.translation.x, pose.translation.y, pose.translation.z]);
        }
        let problem = CentralDifferences {
            unknowns: params.len(),
            residuals: |p: &[f64], out: &mut Vec<f64>| {
                self.with_params(free, &starts, p).residuals(views, out)
            },
        };
        let params = match minimise(&problem, params.clone()) {
            Some((solved, _)) => solved,
            None => params,
        };
        *self = self.with_params(free, &starts, &params);
    }

    fn calibration(&self, view: &BoardView, i: usize) -> Calibration {
        let alone = BoardFit { poses: vec![self.poses[i]], ..*self };
        let mut r = Vec::new();
        alone.residuals(std::slice::from_ref(view), &mut r);
        let distances: Vec<f64> = r.chunks(2).map(|d| (d[0] * d[0] + d[1] * d[1]).sqrt()).collect();
        let n = distances.len().max(1) as f64;
        Calibration {
            camera: alone.camera(view, 0),
            rms_px: (distances.iter().map(|d| d * d).sum::<f64>() / n).sqrt(),
            max_px: distances.iter().fold(0.0, |a: f64, &d| a.max(d)),
            corners: distances.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::board::floor_from_board;

    fn board() -> Board {
        Board::on_floor("DICT_4X4_50", 7, 5, 30.0, 23.0, "<test>").unwrap()
    }

    /// A camera 3.5 m out and 1.6 m up, looking at the board's middle.
    fn camera(eye: DVec3, lens: Distortion, k: Intrinsics) -> Camera {
        let target = DVec3::new(100.0, 0.0, 70.0);
        let forward = (target - eye).normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let down = forward.cross(right);
        let world_from_camera = DAffine3::from_mat3_translation(DMat3::from_cols(right, down, forward), eye);
        Camera {
            image_size: ImageSize { width_px: 640, height_px: 480 },
            intrinsics: k,
            distortion: lens,
            camera_from_world: world_from_camera.inverse(),
        }
    }

    fn k() -> Intrinsics {
        Intrinsics { fx_px: 478.6, fy_px: 479.5, cx_px: 318.5, cy_px: 237.8 }
    }

    fn seen(board: &Board, camera: &Camera, noise_px: f64) -> Vec<BoardCorner> {
        (0..board.corner_count())
            .map(|id| {
                let p = camera.point_in_image(board.corner_in_world(id).unwrap()).unwrap();
                // A fixed pattern of sub-pixel errors, no randomness needed.
                let wobble = DVec2::new((id as f64 * 1.7).sin(), (id as f64 * 2.3).cos()) * noise_px;
                BoardCorner { id, pixel: p + wobble }
            })
            .collect()
    }

    fn rotation_deg(a: &Camera, b: &Camera) -> f64 {
        crate::camera::rotation::angle_between(a.camera_from_world.matrix3, b.camera_from_world.matrix3)
            .to_degrees()
    }

    #[test]
    fn the_pose_of_a_known_lens_is_recovered() {
        let board = board();
        let truth = camera(
            DVec3::new(335.0, 159.0, -90.0),
            Distortion { k1: -0.05, k2: 0.02, p1: -0.0003, p2: -0.0002, k3: 0.0 },
            k(),
        );
        let corners = seen(&board, &truth, 0.1);
        let view = BoardView { file: "v.png", board: &board, corners: &corners };
        let fit = calibrate_pose(&view, &truth).unwrap();
        assert!(
            (fit.camera.center_in_world() - truth.center_in_world()).length() < 1.0,
            "{}",
            fit.camera.center_in_world()
        );
        assert!(rotation_deg(&fit.camera, &truth) < 0.1);
        assert!(fit.rms_px < 0.15, "{}", fit.rms_px);
        // Without noise it is exact.
        let exact = seen(&board, &truth, 0.0);
        let fit = calibrate_pose(&BoardView { corners: &exact, ..view }, &truth).unwrap();
        assert!((fit.camera.center_in_world() - truth.center_in_world()).length() < 1e-6);
    }

    #[test]
    fn one_view_gives_the_focal_length_of_a_centred_lens() {
        let board = board();
        let k = Intrinsics { fx_px: 480.0, fy_px: 480.0, cx_px: 319.5, cy_px: 239.5 };
        let truth = camera(DVec3::new(-150.0, 170.0, 380.0), Distortion::default(), k);
        let corners = seen(&board, &truth, 0.0);
        let view = BoardView { file: "v.png", board: &board, corners: &corners };
        let fit = calibrate_one_view(&view, truth.image_size, LensFit::default()).unwrap();
        assert!((fit.camera.intrinsics.fx_px - 480.0).abs() < 1e-3, "{:?}", fit.camera.intrinsics);
        assert!((fit.camera.center_in_world() - truth.center_in_world()).length() < 1e-3);
        let few = &corners[..5];
        assert!(
            calibrate_one_view(&BoardView { corners: few, ..view }, truth.image_size, LensFit::default())
                .is_err()
        );
    }

    #[test]
    fn several_views_give_the_whole_lens() {
        let board = board();
        let lens = Distortion { k1: -0.05, k2: 0.02, ..Distortion::default() };
        let eyes = [
            DVec3::new(335.0, 159.0, -90.0),
            DVec3::new(-150.0, 170.0, 380.0),
            DVec3::new(100.0, 250.0, 400.0),
            DVec3::new(420.0, 120.0, 200.0),
        ];
        let truths: Vec<Camera> = eyes.iter().map(|&e| camera(e, lens, k())).collect();
        let seen_corners: Vec<Vec<BoardCorner>> = truths.iter().map(|c| seen(&board, c, 0.05)).collect();
        let views: Vec<BoardView> =
            seen_corners.iter().map(|c| BoardView { file: "v.png", board: &board, corners: c }).collect();
        let fits = calibrate_views(&views, truths[0].image_size).unwrap();
        let got = fits[0].camera.intrinsics;
        assert!((got.fx_px / k().fx_px - 1.0).abs() < 0.01, "{got:?}");
        assert!((got.fy_px / k().fy_px - 1.0).abs() < 0.01, "{got:?}");
        for (fit, truth) in fits.iter().zip(&truths) {
            assert!((fit.camera.center_in_world() - truth.center_in_world()).length() < 3.0);
            assert!(fit.rms_px < 0.1);
        }
        assert_eq!(floor_from_board(), board.world_from_board);
    }
}
