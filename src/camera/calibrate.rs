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
//! The small dense solvers (symmetric eigenvectors, Cholesky, the
//! minimiser) are written here rather than pulled in: the problems have at
//! most a few dozen unknowns, and the core must build for wasm lean.

use glam::{DAffine3, DMat3, DVec2, DVec3};

use super::board::{Board, BoardCorner};
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
    let start = pose_from_homography(&h, &DMat3::IDENTITY).ok_or_else(|| degenerate(view))?;
    let mut fit = Fit {
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
    let focal = focal_from_homography(&h, centre).ok_or_else(|| {
        Error::whole(
            view.file,
            "the board is seen too nearly face on to tell the focal length; give --intrinsics",
        )
    })?;
    let intrinsics = Intrinsics { fx_px: focal, fy_px: focal, cx_px: centre.x, cy_px: centre.y };
    let start = pose_from_homography(&h, &intrinsics.matrix()).ok_or_else(|| degenerate(view))?;
    let mut solved = Fit { size, intrinsics, distortion: Distortion::default(), poses: vec![start] };
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
        poses.push(pose_from_homography(h, &k).ok_or_else(|| degenerate(view))?);
    }
    let mut fit = Fit { size, intrinsics, distortion: Distortion::default(), poses };
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

/// A lens and one pose per view, being refined.
struct Fit {
    size: ImageSize,
    intrinsics: Intrinsics,
    distortion: Distortion,
    poses: Vec<Pose>,
}

impl Fit {
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

    fn with_params(&self, free: Free, starts: &[Pose], params: &[f64]) -> Fit {
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
        Fit { size: self.size, intrinsics: k, distortion: d, poses }
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
        minimise(&mut params, |p, out| self.with_params(free, &starts, p).residuals(views, out));
        *self = self.with_params(free, &starts, &params);
    }

    fn calibration(&self, view: &BoardView, i: usize) -> Calibration {
        let alone = Fit { poses: vec![self.poses[i]], ..*self };
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

/// The homography `H` with `to ≈ H · from` (homogeneous), by the direct
/// linear transform on Hartley-normalised points; `None` for fewer than 4
/// points or points on a line.
pub fn homography(from: &[DVec2], to: &[DVec2]) -> Option<DMat3> {
    if from.len() < 4 || from.len() != to.len() {
        return None;
    }
    let (tf, tt) = (hartley(from)?, hartley(to)?);
    let mut ata = vec![0.0; 81];
    for (&a, &b) in from.iter().zip(to) {
        let p = tf.transform_point2(a);
        let q = tt.transform_point2(b);
        let rows = [
            [p.x, p.y, 1.0, 0.0, 0.0, 0.0, -q.x * p.x, -q.x * p.y, -q.x],
            [0.0, 0.0, 0.0, p.x, p.y, 1.0, -q.y * p.x, -q.y * p.y, -q.y],
        ];
        for row in rows {
            for i in 0..9 {
                for j in 0..9 {
                    ata[i * 9 + j] += row[i] * row[j];
                }
            }
        }
    }
    let (values, vectors) = symmetric_eigen(&ata, 9);
    // The null vector; a second (near-)zero eigenvalue means collinear points.
    let mut order: Vec<usize> = (0..9).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    if values[order[1]] <= 1e-9 * values[order[8]] {
        return None;
    }
    let h = &vectors[order[0] * 9..order[0] * 9 + 9];
    let normalised = DMat3::from_cols_array(&[h[0], h[3], h[6], h[1], h[4], h[7], h[2], h[5], h[8]]);
    let h = affine_matrix(&tt.inverse()) * normalised * affine_matrix(&tf);
    (h.determinant().abs() > 0.0 && h.is_finite()).then_some(h)
}

/// The similarity that moves points' centroid to the origin and their mean
/// distance from it to √2.
fn hartley(points: &[DVec2]) -> Option<glam::DAffine2> {
    let centroid = points.iter().copied().sum::<DVec2>() / points.len() as f64;
    let mean = points.iter().map(|p| (*p - centroid).length()).sum::<f64>() / points.len() as f64;
    (mean > 0.0 && mean.is_finite()).then(|| {
        let s = std::f64::consts::SQRT_2 / mean;
        glam::DAffine2::from_scale_angle_translation(DVec2::splat(s), 0.0, -centroid * s)
    })
}

fn affine_matrix(a: &glam::DAffine2) -> DMat3 {
    DMat3::from_cols(a.matrix2.x_axis.extend(0.0), a.matrix2.y_axis.extend(0.0), a.translation.extend(1.0))
}

/// The focal length (px) of a camera with square pixels, no skew and its
/// principal point at `centre` that sees the board plane through `h`
/// (board → pixels), from Zhang's two constraints (r1 ⟂ r2, |r1| = |r2|)
/// solved together for 1/f² by least squares; `None` when they do not
/// give a positive value (a board seen face on).
pub fn focal_from_homography(h: &DMat3, centre: DVec2) -> Option<f64> {
    let shifted = DMat3::from_cols(DVec3::X, DVec3::Y, (-centre).extend(1.0)) * *h;
    let (a, b) = (shifted.x_axis, shifted.y_axis);
    // (a.x b.x + a.y b.y)/f² + a.z b.z = 0 and
    // (a.x² + a.y² − b.x² − b.y²)/f² + a.z² − b.z² = 0.
    let rows = [
        (a.x * b.x + a.y * b.y, -a.z * b.z),
        (a.x * a.x + a.y * a.y - b.x * b.x - b.y * b.y, b.z * b.z - a.z * a.z),
    ];
    // Each row scaled to unit coefficient so neither dominates by units.
    let (mut num, mut den) = (0.0, 0.0);
    for (coefficient, value) in rows {
        let weight = 1.0 / (coefficient * coefficient + value * value * 1e12).sqrt().max(1e-300);
        num += coefficient * value * weight * weight;
        den += coefficient * coefficient * weight * weight;
    }
    let inverse_f2 = num / den;
    (inverse_f2 > 0.0 && inverse_f2.is_finite()).then(|| 1.0 / inverse_f2.sqrt())
}

/// The pose `[R t]` (board → camera) from the homography `h` (board →
/// pixels) of a camera with matrix `k`: `K⁻¹ h ∝ [r1 r2 t]`, scaled so that
/// the board lies in front of the camera, `R` made a rotation.
fn pose_from_homography(h: &DMat3, k: &DMat3) -> Option<Pose> {
    let m = k.inverse() * *h;
    let scale = 2.0 / (m.x_axis.length() + m.y_axis.length());
    let sign = if m.z_axis.z < 0.0 { -1.0 } else { 1.0 };
    let (r1, r2, t) = (m.x_axis * scale * sign, m.y_axis * scale * sign, m.z_axis * scale * sign);
    let rotation = nearest_rotation(DMat3::from_cols(r1, r2, r1.cross(r2)))?;
    (t.is_finite() && t.z > 0.0).then(|| DAffine3::from_mat3_translation(rotation, t))
}

/// The rotation nearest `m` (its polar factor), through the eigenvectors of
/// `mᵀm`.
fn nearest_rotation(m: DMat3) -> Option<DMat3> {
    let mtm = m.transpose() * m;
    let a = mtm.to_cols_array();
    let (values, vectors) = symmetric_eigen(&a, 3);
    if values.iter().any(|v| v.is_nan() || *v <= 1e-12) {
        return None;
    }
    // (mᵀm)^(−½) = V diag(1/√λ) Vᵀ; R = m (mᵀm)^(−½).
    let mut inverse_root = DMat3::ZERO;
    for i in 0..3 {
        let v = DVec3::new(vectors[i * 3], vectors[i * 3 + 1], vectors[i * 3 + 2]);
        inverse_root += DMat3::from_cols(v * v.x, v * v.y, v * v.z) * (1.0 / values[i].sqrt());
    }
    let r = m * inverse_root;
    (r.determinant() > 0.0).then_some(r)
}

/// `K` (zero skew) from the homographies of several views of a plane
/// (Zhang 2000, §3.1): the image of the absolute conic `B = K⁻ᵀK⁻¹` is the
/// null vector of two constraints per view and `B12 = 0`.
fn zhang_intrinsics(homographies: &[DMat3]) -> Option<DMat3> {
    let v = |h: &DMat3, i: usize, j: usize| {
        let (hi, hj) = (h.col(i), h.col(j));
        [
            hi.x * hj.x,
            hi.x * hj.y + hi.y * hj.x,
            hi.y * hj.y,
            hi.z * hj.x + hi.x * hj.z,
            hi.z * hj.y + hi.y * hj.z,
            hi.z * hj.z,
        ]
    };
    let mut vtv = vec![0.0; 36];
    let mut add = |row: [f64; 6]| {
        let norm = row.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-300);
        for i in 0..6 {
            for j in 0..6 {
                vtv[i * 6 + j] += row[i] * row[j] / (norm * norm);
            }
        }
    };
    for h in homographies {
        let h = *h / h.to_cols_array().iter().map(|x| x * x).sum::<f64>().sqrt();
        add(v(&h, 0, 1));
        let (a, b) = (v(&h, 0, 0), v(&h, 1, 1));
        add(std::array::from_fn(|i| a[i] - b[i]));
    }
    add([0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
    let (values, vectors) = symmetric_eigen(&vtv, 6);
    let smallest = (0..6).min_by(|&a, &b| values[a].total_cmp(&values[b]))?;
    let mut b: [f64; 6] = std::array::from_fn(|i| vectors[smallest * 6 + i]);
    if b[0] < 0.0 {
        b.iter_mut().for_each(|x| *x = -*x);
    }
    let [b11, b12, b22, b13, b23, b33] = b;
    let d = b11 * b22 - b12 * b12;
    let v0 = (b12 * b13 - b11 * b23) / d;
    let lambda = b33 - (b13 * b13 + v0 * (b12 * b13 - b11 * b23)) / b11;
    let alpha = (lambda / b11).sqrt();
    let beta = (lambda * b11 / d).sqrt();
    let u0 = -b13 * alpha * alpha / lambda;
    let k =
        DMat3::from_cols(DVec3::new(alpha, 0.0, 0.0), DVec3::new(0.0, beta, 0.0), DVec3::new(u0, v0, 1.0));
    (k.is_finite() && alpha > 0.0 && beta > 0.0).then_some(k)
}

/// Eigenvalues and eigenvectors (`vectors[i*n..(i+1)*n]` belongs to
/// `values[i]`) of the symmetric `n × n` matrix `a` (row major), by cyclic
/// Jacobi rotations.
fn symmetric_eigen(a: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut a = a.to_vec();
    let mut v = vec![0.0; n * n];
    for i in 0..n {
        v[i * n + i] = 1.0;
    }
    let scale = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    for _ in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i * n + j].powi(2))
            .sum();
        if off.is_nan() || off.sqrt() <= 1e-15 * scale {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (a[k * n + p], a[k * n + q]);
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[p * n + k], a[q * n + k]);
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let (vkp, vkq) = (v[k * n + p], v[k * n + q]);
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    let values = (0..n).map(|i| a[i * n + i]).collect();
    // Columns of v are the eigenvectors; hand them out as rows.
    let vectors = (0..n).flat_map(|i| (0..n).map(move |k| (i, k))).map(|(i, k)| v[k * n + i]).collect();
    (values, vectors)
}

/// `x` with `a x = b` for a symmetric positive definite `a` (row major,
/// `n × n`), by Cholesky; `None` when `a` is not positive definite.
fn solve_positive(a: &[f64], b: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let sum: f64 = a[i * n + j] - (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum::<f64>();
            if i == j {
                if sum.is_nan() || sum <= 0.0 {
                    return None;
                }
                l[i * n + i] = sum.sqrt();
            } else {
                l[i * n + j] = sum / l[j * n + j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (b[i] - (0..i).map(|k| l[i * n + k] * y[k]).sum::<f64>()) / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|k| l[k * n + i] * x[k]).sum::<f64>()) / l[i * n + i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Levenberg–Marquardt (Marquardt's diagonal scaling) on the sum of squared
/// `residuals`, the Jacobian by central differences. Stops when a step no
/// longer lowers the cost by a relative 1e-12, or after 200 steps.
fn minimise(params: &mut [f64], residuals: impl Fn(&[f64], &mut Vec<f64>)) {
    let n = params.len();
    let mut r = Vec::new();
    residuals(params, &mut r);
    let mut cost: f64 = r.iter().map(|x| x * x).sum();
    let m = r.len();
    let mut lambda = 1e-3;
    let (mut plus, mut minus) = (Vec::new(), Vec::new());
    let mut jacobian = vec![0.0; m * n];
    for _ in 0..200 {
        let mut probe = params.to_vec();
        for j in 0..n {
            let step = 1e-6 * params[j].abs().max(1e-2);
            probe[j] = params[j] + step;
            residuals(&probe, &mut plus);
            probe[j] = params[j] - step;
            residuals(&probe, &mut minus);
            probe[j] = params[j];
            for i in 0..m {
                jacobian[i * n + j] = (plus[i] - minus[i]) / (2.0 * step);
            }
        }
        let mut jtj = vec![0.0; n * n];
        let mut jtr = vec![0.0; n];
        for i in 0..m {
            let row = &jacobian[i * n..(i + 1) * n];
            for a in 0..n {
                jtr[a] += row[a] * r[i];
                for b in 0..n {
                    jtj[a * n + b] += row[a] * row[b];
                }
            }
        }
        let largest = (0..n).map(|i| jtj[i * n + i]).fold(0.0, f64::max);
        let mut improved = false;
        while lambda < 1e12 {
            let mut damped = jtj.clone();
            for i in 0..n {
                damped[i * n + i] += lambda * (jtj[i * n + i] + 1e-12 * largest);
            }
            let negative: Vec<f64> = jtr.iter().map(|x| -x).collect();
            if let Some(delta) = solve_positive(&damped, &negative, n) {
                let trial: Vec<f64> = params.iter().zip(&delta).map(|(p, d)| p + d).collect();
                let mut trial_r = Vec::new();
                residuals(&trial, &mut trial_r);
                let trial_cost: f64 = trial_r.iter().map(|x| x * x).sum();
                if trial_cost < cost {
                    let gain = (cost - trial_cost) / cost.max(1e-300);
                    params.copy_from_slice(&trial);
                    (cost, r) = (trial_cost, trial_r);
                    lambda = (lambda / 10.0).max(1e-12);
                    improved = gain > 1e-12;
                    break;
                }
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
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
    fn homography_maps_the_points_it_was_fitted_to() {
        let from = [
            DVec2::new(0.0, 0.0),
            DVec2::new(3.0, 0.0),
            DVec2::new(3.0, 2.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(1.0, 1.0),
        ];
        let truth = DMat3::from_cols(
            DVec3::new(2.0, 0.1, 0.001),
            DVec3::new(-0.3, 1.5, 0.002),
            DVec3::new(40.0, 30.0, 1.0),
        );
        let to: Vec<DVec2> = from
            .iter()
            .map(|&p| {
                let q = truth * p.extend(1.0);
                q.truncate() / q.z
            })
            .collect();
        let h = homography(&from, &to).unwrap();
        for (&p, &q) in from.iter().zip(&to) {
            let m = h * p.extend(1.0);
            assert!((m.truncate() / m.z - q).length() < 1e-9);
        }
        let line: Vec<DVec2> = (0..5).map(|i| DVec2::new(i as f64, 2.0 * i as f64)).collect();
        assert_eq!(homography(&line, &to), None);
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
