//! Homographies of a plane seen by a camera, and what they tell: the
//! plane-to-image homography from point pairs (the direct linear transform,
//! Hartley-normalised) or from a quadrilateral's four corners in closed form
//! (Heckbert), the focal length from one homography, the camera's pose from
//! it, and the intrinsics from several (Zhang 2000). The board's
//! calibration, the four floor corners and Zhang's method all take their
//! starts from here; where two of them compute a quantity differently (the
//! focal length, the pose's rotation), the way is an argument, each kept to
//! the figures its calibration is held to.

use glam::{DAffine2, DAffine3, DMat3, DVec2, DVec3};

use super::least_squares::symmetric_eigen;
use super::pinhole::ImageSize;

/// The point `H · p` (homogeneous, divided out); `None` where it goes to
/// infinity (a point on the plane's horizon).
pub fn map_point(h: &DMat3, p: DVec2) -> Option<DVec2> {
    let q = *h * p.extend(1.0);
    (q.z.abs() > 1e-12).then(|| q.truncate() / q.z).filter(|p| p.is_finite())
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
fn hartley(points: &[DVec2]) -> Option<DAffine2> {
    let centroid = points.iter().copied().sum::<DVec2>() / points.len() as f64;
    let mean = points.iter().map(|p| (*p - centroid).length()).sum::<f64>() / points.len() as f64;
    (mean > 0.0 && mean.is_finite()).then(|| {
        let s = std::f64::consts::SQRT_2 / mean;
        DAffine2::from_scale_angle_translation(DVec2::splat(s), 0.0, -centroid * s)
    })
}

fn affine_matrix(a: &DAffine2) -> DMat3 {
    DMat3::from_cols(a.matrix2.x_axis.extend(0.0), a.matrix2.y_axis.extend(0.0), a.translation.extend(1.0))
}

/// The homography (columns u, v, 1) that takes the unit square's corners
/// (0,0), (1,0), (1,1), (0,1) to `q` (Heckbert's closed form), its bottom
/// right entry 1. `q` is a convex quadrilateral (checked before).
pub fn square_to_quad(q: &[DVec2; 4]) -> DMat3 {
    let sum = q[0] - q[1] + q[2] - q[3];
    let (d1, d2) = (q[1] - q[2], q[3] - q[2]);
    let det = d1.perp_dot(d2);
    let g = sum.perp_dot(d2) / det;
    let h = d1.perp_dot(sum) / det;
    DMat3::from_cols((q[1] - q[0] + g * q[1]).extend(g), (q[3] - q[0] + h * q[3]).extend(h), q[0].extend(1.0))
}

/// How [`focal_from_homography`] solves Zhang's two constraints of a plane
/// (`r1 ⟂ r2`, `|r1| = |r2|`) for the one unknown of a camera with square
/// pixels, no skew and a known principal point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FocalSolve {
    /// The homography maps to pixels, the principal point at `centre`;
    /// each constraint scaled to a unit coefficient so that neither
    /// dominates by units, solved for `1/f²` (the board's one view).
    UnitRows { centre: DVec2 },
    /// The homography maps to pixels less the principal point; pixels
    /// scaled by the image's half diagonal `s`, the constraints solved
    /// unweighted for `ω = (s / f)²`, near 1 (the four floor corners).
    HalfDiagonal { size: ImageSize },
}

/// The focal length (px) for which the homography's first two columns are
/// orthogonal and of equal length after `K⁻¹`, by least squares as `solve`
/// says; `None` when the constraints give no positive value (a plane seen
/// face on, or not the plane of that size).
pub fn focal_from_homography(h: &DMat3, solve: FocalSolve) -> Option<f64> {
    match solve {
        FocalSolve::UnitRows { centre } => {
            let shifted = DMat3::from_cols(DVec3::X, DVec3::Y, (-centre).extend(1.0)) * *h;
            let (a, b) = (shifted.x_axis, shifted.y_axis);
            // (a.x b.x + a.y b.y)/f² + a.z b.z = 0 and
            // (a.x² + a.y² − b.x² − b.y²)/f² + a.z² − b.z² = 0.
            let rows = [
                (a.x * b.x + a.y * b.y, -a.z * b.z),
                (a.x * a.x + a.y * a.y - b.x * b.x - b.y * b.y, b.z * b.z - a.z * a.z),
            ];
            let (mut num, mut den) = (0.0, 0.0);
            for (coefficient, value) in rows {
                let weight = 1.0 / (coefficient * coefficient + value * value * 1e12).sqrt().max(1e-300);
                num += coefficient * value * weight * weight;
                den += coefficient * coefficient * weight * weight;
            }
            let inverse_f2 = num / den;
            (inverse_f2 > 0.0 && inverse_f2.is_finite()).then(|| 1.0 / inverse_f2.sqrt())
        }
        FocalSolve::HalfDiagonal { size } => {
            let s = 0.5 * DVec2::new(size.width_px as f64, size.height_px as f64).length();
            let scaled = DMat3::from_diagonal(DVec3::new(1.0 / s, 1.0 / s, 1.0)) * *h;
            let (a, b) = (scaled.x_axis, scaled.y_axis);
            // ω (a.x b.x + a.y b.y) + a.z b.z = 0 and ω (|a.xy|² − |b.xy|²) + a.z² − b.z² = 0.
            let rows = [
                (a.x * b.x + a.y * b.y, a.z * b.z),
                (a.x * a.x + a.y * a.y - b.x * b.x - b.y * b.y, a.z * a.z - b.z * b.z),
            ];
            let omega = -(rows[0].0 * rows[0].1 + rows[1].0 * rows[1].1)
                / (rows[0].0 * rows[0].0 + rows[1].0 * rows[1].0);
            (omega > 0.0 && omega.is_finite()).then(|| s / omega.sqrt())
        }
    }
}

/// How [`pose_from_homography`] reads the plane's axes and makes the
/// rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoseFit {
    /// The plane's axes are the pose's x and y (a board, `[r1 r2 t]`); the
    /// scale's sign puts the plane ahead, the rotation is the nearest to
    /// `[r1 r2 r1×r2]` (its polar factor); `None` unless the plane's origin
    /// is in front of the camera.
    NearestRotationXy,
    /// The plane's axes are the pose's x and z (the floor, Y up,
    /// `[r1 r3 t]`), the homography's bottom-right entry positive (the
    /// origin in front); the two axes made orthonormal symmetrically, each
    /// turned half the way.
    SymmetricXz,
}

/// The pose `[R t]` (plane → camera) from the homography `h` (plane →
/// image) and `normalised_from_image` (`K⁻¹`): `K⁻¹ h` is two columns of
/// `R` and `t`, up to scale, read and made a rotation as `fit` says.
pub fn pose_from_homography(h: &DMat3, normalised_from_image: &DMat3, fit: PoseFit) -> Option<DAffine3> {
    let m = *normalised_from_image * *h;
    match fit {
        PoseFit::NearestRotationXy => {
            let scale = 2.0 / (m.x_axis.length() + m.y_axis.length());
            let sign = if m.z_axis.z < 0.0 { -1.0 } else { 1.0 };
            let (r1, r2, t) = (m.x_axis * scale * sign, m.y_axis * scale * sign, m.z_axis * scale * sign);
            let rotation = nearest_rotation(DMat3::from_cols(r1, r2, r1.cross(r2)))?;
            (t.is_finite() && t.z > 0.0).then(|| DAffine3::from_mat3_translation(rotation, t))
        }
        PoseFit::SymmetricXz => {
            let (h1, h3, t) = (m.x_axis, m.y_axis, m.z_axis);
            let scale = 0.5 * (h1.length() + h3.length());
            let (a, b) = (h1.normalize(), h3.normalize());
            let (sum, difference) = ((a + b).normalize(), (a - b).normalize());
            let x = (sum + difference) * std::f64::consts::FRAC_1_SQRT_2;
            let z = (sum - difference) * std::f64::consts::FRAC_1_SQRT_2;
            Some(DAffine3::from_mat3_translation(DMat3::from_cols(x, z.cross(x), z), t / scale))
        }
    }
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
pub fn zhang_intrinsics(homographies: &[DMat3]) -> Option<DMat3> {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
