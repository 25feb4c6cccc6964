//! Rotations as Rodrigues vectors (OpenCV's `rvec`): the axis scaled by the
//! angle in radians, right-handed. Both directions stay exact where the
//! textbook formulas lose digits: at small angles (where `sin θ / θ` and
//! `1 − cos θ` cancel) and near π (where `sin θ` vanishes and the axis must
//! come from the matrix's symmetric part instead).

use glam::{DMat3, DQuat, DVec3};

/// Below this angle (rad) the series are used: their first dropped term is
/// then under 1e-32, far below an f64's resolution.
const SERIES_BELOW_RAD: f64 = 1e-8;

/// The rotation matrix of the Rodrigues vector `rvec` (OpenCV's
/// `cv2.Rodrigues(rvec)`): `R = I + sin θ [k]× + (1 − cos θ) [k]×²` with
/// `θ = |rvec|`, `k = rvec / θ`.
pub fn rotation_from_rodrigues(rvec: DVec3) -> DMat3 {
    let angle = rvec.length();
    // R = I + a [r]× + b [r]×², with a = sin θ / θ and b = (1 − cos θ) / θ²,
    // the latter as 2 sin²(θ/2) / θ², which has no cancellation.
    let (a, b) = if angle < SERIES_BELOW_RAD {
        (1.0 - angle * angle / 6.0, 0.5 - angle * angle / 24.0)
    } else {
        let half_sin = libm::sin(0.5 * angle) / angle;
        (libm::sin(angle) / angle, 2.0 * half_sin * half_sin)
    };
    let cross = skew(rvec);
    DMat3::IDENTITY + cross * a + cross * cross * b
}

/// The Rodrigues vector of the rotation `rotation` (OpenCV's
/// `cv2.Rodrigues(R)`), its angle in `[0, π]`. `rotation` must be a rotation
/// (orthonormal, determinant +1) to the precision that is wanted back.
///
/// Goes through the unit quaternion, whose construction picks the largest
/// of its four components to divide by, so no branch loses digits; at
/// exactly π the sign of the axis is the quaternion's (both are the same
/// rotation).
pub fn rodrigues_from_rotation(rotation: DMat3) -> DVec3 {
    let q = DQuat::from_mat3(&rotation);
    // q and −q are the same rotation; w ≥ 0 gives the angle in [0, π].
    let q = if q.w < 0.0 { -q } else { q };
    let axis_sin = DVec3::new(q.x, q.y, q.z);
    let s = axis_sin.length(); // sin(θ/2)
    // rvec = θ k = (θ / sin(θ/2)) · sin(θ/2) k, θ = 2 atan2(s, w).
    let scale = if s < 0.5 * SERIES_BELOW_RAD {
        // θ / s = 2 / w · (1 + O(s²)): exact to an f64 here.
        2.0 / q.w
    } else {
        2.0 * libm::atan2(s, q.w) / s
    };
    axis_sin * scale
}

/// The matrix `[v]×` with `[v]× u = v × u`.
pub fn skew(v: DVec3) -> DMat3 {
    DMat3::from_cols(DVec3::new(0.0, v.z, -v.y), DVec3::new(-v.z, 0.0, v.x), DVec3::new(v.y, -v.x, 0.0))
}

/// The angle (rad) of the rotation that takes `a` to `b`: how far apart two
/// rotations are.
pub fn angle_between(a: DMat3, b: DMat3) -> f64 {
    rodrigues_from_rotation(b * a.transpose()).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn close(a: DMat3, b: DMat3, tol: f64) -> bool {
        (a - b).to_cols_array().iter().all(|d| d.abs() <= tol)
    }

    #[test]
    fn matches_glam_at_ordinary_angles() {
        for rvec in
            [DVec3::new(0.3, -0.2, 0.1), DVec3::new(-1.2168, -0.5605, 2.6558), DVec3::new(0.0, 2.0, 0.0)]
        {
            let glam = DMat3::from_axis_angle(rvec.normalize(), rvec.length());
            assert!(close(rotation_from_rodrigues(rvec), glam, 1e-15), "{rvec}");
            assert!((rodrigues_from_rotation(glam) - rvec).length() < 1e-14, "{rvec}");
        }
    }

    #[test]
    fn exact_at_small_angles() {
        for angle in [0.0, 1e-300, 1e-12, 1e-9, 3e-8, 1e-6, 1e-3] {
            let rvec = DVec3::new(1.0, -2.0, 0.5).normalize() * angle;
            let r = rotation_from_rodrigues(rvec);
            // The antisymmetric part is sin θ k: it carries the angle itself.
            let back = rodrigues_from_rotation(r);
            assert!(
                (back - rvec).length() <= 1e-15 * angle.max(1e-300) + 1e-300,
                "{angle}: {back} vs {rvec}"
            );
            assert!(((r.transpose() * r) - DMat3::IDENTITY).to_cols_array().iter().all(|d| d.abs() < 1e-15));
        }
    }

    #[test]
    fn exact_near_pi() {
        let axis = DVec3::new(0.2, -0.9, 0.4).normalize();
        for angle in [PI, PI - 1e-12, PI - 1e-8, PI - 1e-4, PI - 0.1] {
            let rvec = axis * angle;
            let back = rodrigues_from_rotation(rotation_from_rodrigues(rvec));
            // At exactly π the axis may come back negated: the same rotation.
            let err = (back - rvec).length().min((back + rvec).length());
            assert!(err < 1e-14, "{angle}: {back} vs {rvec}");
            assert!((back.length() - angle).abs() < 1e-14);
        }
        // A half turn about a coordinate axis is a diagonal matrix.
        let half_turn = DMat3::from_diagonal(DVec3::new(1.0, -1.0, -1.0));
        let back = rodrigues_from_rotation(half_turn);
        assert!((back.abs() - DVec3::new(PI, 0.0, 0.0)).length() < 1e-15, "{back}");
    }

    #[test]
    fn angle_between_is_the_relative_angle() {
        let a = rotation_from_rodrigues(DVec3::new(0.4, 0.1, -0.3));
        let b = rotation_from_rodrigues(DVec3::new(0.0, 0.0, 1e-7)) * a;
        assert!((angle_between(a, b) - 1e-7).abs() < 1e-15);
    }
}
