//! Calibration by hand, the fallback the paper names for when there is no
//! board: four clicked image points of the corners of a known rectangle on
//! the floor, plus a focal length or a field of view (or neither: a
//! rectangle seen in perspective tells the focal length too).
//!
//! The rectangle fixes the world. Its corners are given in this order:
//! 1. the world origin, `(0, 0, 0)`;
//! 2. `(width, 0, 0)`: the first edge runs along world +X;
//! 3. `(width, 0, depth)`;
//! 4. `(0, 0, depth)`: the second edge runs along world +Z.
//!
//! The floor is y = 0 with Y up, so, seen from a camera above the floor,
//! the corners go round *clockwise* in the image (x right, y down). The
//! camera is assumed to be a plain pinhole: square pixels (`fx = fy`), the
//! principal point at the image centre `((w − 1)/2, (h − 1)/2)` (pixel
//! centres at whole numbers), no lens distortion: four points cannot tell
//! more. A lens with visible distortion is better calibrated with the board.
//!
//! The method: the floor-to-image homography of the four points (exact for
//! four), the focal length from it when it is not given (Zhang's two
//! constraints of a plane, `r₁ ⟂ r₃` and `|r₁| = |r₃|`), the pose from its
//! columns, then Levenberg–Marquardt on the pose (6 parameters, 7 with the
//! focal length) minimising the reprojection error, since the homography's
//! pose is exact only for exact clicks. Its normal matrix at the end gives
//! how far one pixel of click error moves the camera and the focal length;
//! an estimated focal length that a pixel moves by more than
//! [`FOCAL_SIGMA_LIMIT`] is refused (the view is too close to
//! fronto-parallel, where the focal length and the distance trade off).

use glam::{DAffine3, DMat3, DVec2, DVec3};

use super::homography::{FocalSolve, PoseFit, focal_from_homography, pose_from_homography, square_to_quad};
use super::least_squares::{LeastSquares, minimise, solve_pivoting};
use super::rotation::{rotation_from_rodrigues, skew};
use super::{Camera, Distortion, ImageSize, Intrinsics};
use crate::error::Error;

/// What the errors of this calibration name as their source.
pub const SOURCE: &str = "floor rectangle";

/// The most an estimated focal length may move (as a fraction of itself)
/// per pixel of click error, as a standard deviation; above it the four
/// points do not tell the focal length and it must be given.
pub const FOCAL_SIGMA_LIMIT: f64 = 0.1;

/// Why no focal length was estimated.
const NO_FOCAL_LENGTH: &str = "no focal length makes these four points a rectangle of that size (a \
                               fronto-parallel view, or the wrong size); give the focal length or the \
                               field of view";

/// Corners closer than this (px) to the line through their neighbours are
/// collinear: a click is no better than a pixel.
const MIN_CORNER_HEIGHT_PX: f64 = 1.0;

/// A rectangle on the floor, its corners as the module says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorRectangle {
    /// Along world +X (cm).
    pub width_cm: f64,
    /// Along world +Z (cm).
    pub depth_cm: f64,
}

/// What is known of the focal length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FocalLength {
    /// In pixels (`fx = fy`).
    Px(f64),
    /// The horizontal field of view in degrees, edge to edge of the image:
    /// `f = width / (2 tan(fov / 2))`.
    HorizontalFovDeg(f64),
    /// Estimated from the four points.
    Unknown,
}

/// A camera from four floor points, with how much to trust it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorCalibration {
    pub camera: Camera,
    /// The root mean square distance (px) between the clicked corners and
    /// the corners the camera projects.
    pub reprojection_rms_px: f64,
    /// The standard deviation (cm, of the 3D position) of the camera centre
    /// per pixel of click error, to first order.
    pub center_sigma_cm_per_px: f64,
    /// When the focal length was estimated, its standard deviation per pixel
    /// of click error, as a fraction of it.
    pub focal_sigma_per_px: Option<f64>,
}

impl FloorRectangle {
    /// The corners in the world (cm), in the order the clicks are given.
    pub fn corners_in_world(&self) -> [DVec3; 4] {
        let (w, d) = (self.width_cm, self.depth_cm);
        [DVec3::ZERO, DVec3::new(w, 0.0, 0.0), DVec3::new(w, 0.0, d), DVec3::new(0.0, 0.0, d)]
    }

    /// The camera that sees this rectangle's corners at `corners_px` (in
    /// the module's order) in an image of `image_size`. Errors: a rectangle
    /// or focal length that is not positive, a corner outside the image,
    /// two corners at one place, three in a line, crossing edges or a
    /// concave quadrilateral (not the image of a rectangle in front of the
    /// camera), corners that go round the wrong way (a mirrored world), and
    /// a focal length that the points cannot tell.
    pub fn calibrate(
        &self,
        image_size: ImageSize,
        corners_px: [DVec2; 4],
        focal: FocalLength,
    ) -> Result<FloorCalibration, Error> {
        let fail = |message: String| Error::whole(SOURCE, message);
        let FloorRectangle { width_cm, depth_cm } = *self;
        if !(width_cm > 0.0 && depth_cm > 0.0 && width_cm.is_finite() && depth_cm.is_finite()) {
            return Err(fail(format!(
                "the rectangle must have a positive size, not {width_cm} × {depth_cm} cm"
            )));
        }
        let (w, h) = (image_size.width_px, image_size.height_px);
        if w == 0 || h == 0 {
            return Err(fail(format!("the image must have a positive size, not {w}×{h} px")));
        }
        check_quadrilateral(image_size, &corners_px).map_err(fail)?;

        let principal = DVec2::new((w as f64 - 1.0) / 2.0, (h as f64 - 1.0) / 2.0);
        let centred = corners_px.map(|p| p - principal);
        // Floor (x, z) cm → centred pixels, up to scale.
        let homography =
            square_to_quad(&centred) * DMat3::from_diagonal(DVec3::new(1.0 / width_cm, 1.0 / depth_cm, 1.0));
        let focal_px = match focal {
            FocalLength::Px(f) if f > 0.0 && f.is_finite() => f,
            FocalLength::Px(f) => return Err(fail(format!("the focal length must be positive, not {f} px"))),
            FocalLength::HorizontalFovDeg(fov) if fov > 0.0 && fov < 180.0 => {
                w as f64 / (2.0 * libm::tan(fov.to_radians() / 2.0))
            }
            FocalLength::HorizontalFovDeg(fov) => {
                return Err(fail(format!("the field of view must lie between 0 and 180°, not {fov}°")));
            }
            FocalLength::Unknown => {
                let solve = FocalSolve::HalfDiagonal { size: image_size };
                focal_from_homography(&homography, solve).ok_or_else(|| fail(NO_FOCAL_LENGTH.into()))?
            }
        };
        let degenerate = || fail("the reprojection could not be minimised (a degenerate view)".into());
        let normalised_from_image = DMat3::from_diagonal(DVec3::new(1.0 / focal_px, 1.0 / focal_px, 1.0));
        let pose = pose_from_homography(&homography, &normalised_from_image, PoseFit::SymmetricXz)
            .ok_or_else(degenerate)?;

        let refine_focal = focal == FocalLength::Unknown;
        let world = self.corners_in_world();
        let fit = refine(pose, focal_px, &world, &centred, refine_focal).ok_or_else(degenerate)?;

        let camera = Camera {
            image_size,
            intrinsics: Intrinsics {
                fx_px: fit.focal_px,
                fy_px: fit.focal_px,
                cx_px: principal.x,
                cy_px: principal.y,
            },
            distortion: Distortion::default(),
            camera_from_world: fit.pose,
        };
        if !world.iter().all(|&corner| camera.point_in_camera(corner).z > 0.0)
            || camera.center_in_world().y <= 0.0
        {
            return Err(fail(
                "no camera above the floor sees the rectangle so (check the corners' order)".into(),
            ));
        }
        if let Some(sigma) = fit.focal_sigma
            && (sigma.is_nan() || sigma > FOCAL_SIGMA_LIMIT)
        {
            return Err(fail(format!(
                "the four points do not tell the focal length: one pixel of click error moves it by {:.0} % \
                 (the rectangle is too small in the image, or seen too nearly face-on); give the focal \
                 length or the field of view",
                100.0 * sigma
            )));
        }
        Ok(FloorCalibration {
            camera,
            reprojection_rms_px: fit.rms_px,
            center_sigma_cm_per_px: fit.center_sigma_cm,
            focal_sigma_per_px: fit.focal_sigma,
        })
    }
}

/// Corner numbers in messages count from 1, as the user clicked them.
fn check_quadrilateral(size: ImageSize, corners: &[DVec2; 4]) -> Result<(), String> {
    let (w, h) = (size.width_px as f64, size.height_px as f64);
    for (i, p) in corners.iter().enumerate() {
        let inside = p.x >= -0.5 && p.y >= -0.5 && p.x < w - 0.5 && p.y < h - 0.5;
        if !inside {
            return Err(format!("corner {} at ({}, {}) px is not in the {}×{} image", i + 1, p.x, p.y, w, h));
        }
    }
    for i in 0..4 {
        for j in i + 1..4 {
            if corners[i].distance(corners[j]) < MIN_CORNER_HEIGHT_PX {
                return Err(format!("corners {} and {} are at the same place", i + 1, j + 1));
            }
        }
    }
    for i in 0..4 {
        let (before, at, after) = (corners[(i + 3) % 4], corners[i], corners[(i + 1) % 4]);
        let height = (after - before).perp_dot(at - before).abs() / (after - before).length();
        if height < MIN_CORNER_HEIGHT_PX {
            return Err(format!(
                "corners {}, {} and {} are in a line: not the image of a rectangle",
                (i + 3) % 4 + 1,
                i + 1,
                (i + 1) % 4 + 1
            ));
        }
    }
    if crosses(corners[0], corners[1], corners[2], corners[3])
        || crosses(corners[1], corners[2], corners[3], corners[0])
    {
        return Err("the edges cross: give the corners in order round the rectangle".into());
    }
    // The turn at each corner, positive when clockwise on the image (y down).
    let turns: Vec<f64> = (0..4)
        .map(|i| (corners[(i + 1) % 4] - corners[i]).perp_dot(corners[(i + 2) % 4] - corners[(i + 1) % 4]))
        .collect();
    if turns.iter().all(|&t| t < 0.0) {
        return Err(
            "the corners go round anticlockwise in the image: from above the floor, origin, +X, then +Z \
                    go clockwise; give them in the other order"
                .into(),
        );
    }
    if !turns.iter().all(|&t| t > 0.0) {
        return Err(
            "the quadrilateral is concave: not the image of a rectangle in front of the camera".into()
        );
    }
    Ok(())
}

/// Whether the segments `ab` and `cd` cross.
fn crosses(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0
}

/// The camera refined to the four corners, with how far a pixel of click
/// error moves it.
struct FloorFit {
    pose: DAffine3,
    focal_px: f64,
    rms_px: f64,
    center_sigma_cm: f64,
    focal_sigma: Option<f64>,
}

/// The reprojection of the four corners as a least-squares problem: the
/// pose as left-multiplied rotation increments and a translation, and the
/// focal length when `with_focal`; `Σ |projected − clicked|²` over the
/// corners (`centred`: pixels less the principal point).
struct FloorCorners<'a> {
    world: &'a [DVec3; 4],
    centred: &'a [DVec2; 4],
    with_focal: bool,
    /// Units in which a step of 1 is comparable for all unknowns: the
    /// translation in units of the camera's distance, the focal length in
    /// its own.
    t_unit: f64,
    f_unit: f64,
}

impl FloorCorners<'_> {
    /// `(JᵀJ, Jᵀr)` in the leading `unknowns() × unknowns()` block of 7.
    fn normal(&self, pose: &DAffine3, f: f64, r: &[f64]) -> ([[f64; 7]; 7], [f64; 7]) {
        let n = self.unknowns();
        let mut a = [[0.0; 7]; 7];
        let mut g = [0.0; 7];
        for i in 0..4 {
            let p = pose.transform_point3(self.world[i]);
            let rotated = pose.matrix3 * self.world[i];
            let d_pixel = [
                DVec3::new(f / p.z, 0.0, -f * p.x / (p.z * p.z)),
                DVec3::new(0.0, f / p.z, -f * p.y / (p.z * p.z)),
            ];
            for (k, dp) in d_pixel.iter().enumerate() {
                // ∂p/∂δ = −[R X]×, ∂p/∂t = I.
                let d_rotation = -(skew(rotated).transpose() * *dp);
                let mut row = [0.0; 7];
                row[..3].copy_from_slice(&d_rotation.to_array());
                row[3..6].copy_from_slice(&(*dp * self.t_unit).to_array());
                row[6] = if k == 0 { p.x / p.z } else { p.y / p.z } * self.f_unit;
                let residual = r[2 * i + k];
                for j in 0..n {
                    g[j] += row[j] * residual;
                    for l in 0..n {
                        a[j][l] += row[j] * row[l];
                    }
                }
            }
        }
        (a, g)
    }
}

impl LeastSquares for FloorCorners<'_> {
    /// The pose and the focal length (px).
    type State = (DAffine3, f64);

    fn unknowns(&self) -> usize {
        if self.with_focal { 7 } else { 6 }
    }

    fn residuals(&self, &(pose, f): &(DAffine3, f64)) -> Option<Vec<f64>> {
        if f.is_nan() || f <= 0.0 {
            return None;
        }
        let mut r = vec![0.0; 8];
        for i in 0..4 {
            let p = pose.transform_point3(self.world[i]);
            if p.z.is_nan() || p.z <= 1e-9 {
                return None;
            }
            r[2 * i] = f * p.x / p.z - self.centred[i].x;
            r[2 * i + 1] = f * p.y / p.z - self.centred[i].y;
        }
        Some(r)
    }

    fn normal_equations(&self, &(pose, f): &(DAffine3, f64), r: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = self.unknowns();
        let (a, g) = self.normal(&pose, f, r);
        (a[..n].iter().flat_map(|row| row[..n].iter().copied()).collect(), g[..n].to_vec())
    }

    fn moved(&self, &(pose, f): &(DAffine3, f64), delta: &[f64]) -> (DAffine3, f64) {
        let turn = rotation_from_rodrigues(DVec3::new(delta[0], delta[1], delta[2]));
        let moved = DVec3::new(delta[3], delta[4], delta[5]) * self.t_unit;
        let pose = DAffine3::from_mat3_translation(turn * pose.matrix3, pose.translation + moved);
        (pose, if self.with_focal { f + delta[6] * self.f_unit } else { f })
    }
}

/// Levenberg–Marquardt (`least_squares`'s one policy) on the pose, and on the focal
/// length when `with_focal`, from `start` and `focal_px`; then the
/// first-order spread of the camera centre and the focal length per pixel
/// of click error. `None` when the start does not see the corners.
fn refine(
    start: DAffine3,
    focal_px: f64,
    world: &[DVec3; 4],
    centred: &[DVec2; 4],
    with_focal: bool,
) -> Option<FloorFit> {
    let t_unit = start.translation.length().max(1.0);
    let f_unit = focal_px;
    let problem = FloorCorners { world, centred, with_focal, t_unit, f_unit };
    let n = problem.unknowns();
    let ((pose, f), r) = minimise(&problem, (start, focal_px))?;

    // First-order covariance for one pixel of noise per coordinate: (JᵀJ)⁻¹.
    let (a, _) = problem.normal_equations(&(pose, f), &r);
    let mut covariance = [[0.0; 7]; 7];
    for j in 0..n {
        let mut unit = vec![0.0; n];
        unit[j] = 1.0;
        let column = solve_pivoting(&a, &unit, n);
        for l in 0..n {
            covariance[l][j] = column.as_ref().map_or(f64::INFINITY, |c| c[l]);
        }
    }
    // The centre c = −Rᵀt: with R ← exp([δ]×)R, ∂c/∂δ = −Rᵀ[t]×; ∂c/∂t = −Rᵀ.
    let rt = pose.matrix3.transpose();
    let d_center_d_rotation = -(rt * skew(pose.translation));
    let d_center_d_t = -rt * t_unit;
    let mut center_variance = 0.0;
    for row in 0..3 {
        let mut jac = [0.0; 7];
        for k in 0..3 {
            jac[k] = d_center_d_rotation.col(k)[row];
            jac[3 + k] = d_center_d_t.col(k)[row];
        }
        for j in 0..n {
            for l in 0..n {
                center_variance += jac[j] * covariance[j][l] * jac[l];
            }
        }
    }
    let rms_px = (r.iter().map(|x| x * x).sum::<f64>() / 4.0).sqrt();
    let focal_sigma = with_focal.then(|| covariance[6][6].max(0.0).sqrt() * f_unit / f);
    Some(FloorFit {
        pose,
        focal_px: f,
        rms_px,
        center_sigma_cm: center_variance.max(0.0).sqrt(),
        focal_sigma,
    })
}
