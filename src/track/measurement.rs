//! How well one camera measures a body's floor position: the covariance of
//! a silhouette's fit, from how its pixels move per centimetre of floor
//! shift. Along the camera's line of sight they barely move, so that
//! direction comes out uncertain, as it is.

use glam::{DMat2, DVec2, DVec3};

use crate::body::shape::PosedBody;
use crate::camera::Camera;

/// The square root of the covariance's larger eigenvalue (cm).
pub fn largest_sigma_cm(covariance: DMat2) -> f64 {
    let (a, b, d) = (covariance.x_axis.x, covariance.y_axis.x, covariance.y_axis.y);
    let mean = 0.5 * (a + d);
    let spread = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    (mean + spread).max(0.0).sqrt()
}

/// The covariance (cm²) of a floor position measured to `sigma_px` in the
/// image: `σ² (Jᵀ J)⁻¹`, with `Jᵀ J` the mean over the body's spheres of
/// how their pixels move per cm of floor shift (finite differences through
/// the lens). Along the camera's line of sight the pixels barely move, so
/// that direction comes out uncertain, as it is. `None` when the body is
/// not in front of the camera.
pub fn measurement_covariance(
    camera: &Camera,
    body: &PosedBody,
    floor_cm: DVec2,
    sigma_px: f64,
) -> Option<DMat2> {
    let shift = DVec3::new(floor_cm.x, 0.0, floor_cm.y);
    let mut normal = DMat2::ZERO;
    let mut count = 0usize;
    for sphere in &body.spheres {
        let at = sphere.centre_cm + shift;
        let (Some(p), Some(px), Some(pz)) = (
            camera.point_in_image(at),
            camera.point_in_image(at + DVec3::X),
            camera.point_in_image(at + DVec3::Z),
        ) else {
            continue;
        };
        let j = DMat2::from_cols(px - p, pz - p);
        normal += j.transpose() * j;
        count += 1;
    }
    if count == 0 {
        return None;
    }
    let normal = normal * (1.0 / count as f64);
    if normal.determinant().abs() < 1e-12 {
        return None;
    }
    Some(normal.inverse() * (sigma_px * sigma_px))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_covariance_of_a_camera_s_measurement_is_long_along_its_line_of_sight() {
        // A camera on the -Z side looking along +Z at a body 5 m away: a
        // floor shift across the view (x) moves the pixels far more than one
        // along it (z).
        let camera = Camera {
            image_size: crate::camera::ImageSize { width_px: 640, height_px: 480 },
            intrinsics: crate::camera::Intrinsics { fx_px: 500.0, fy_px: 500.0, cx_px: 319.5, cy_px: 239.5 },
            distortion: crate::camera::Distortion::default(),
            camera_from_world: glam::DAffine3::from_mat3_translation(
                glam::DMat3::from_cols(DVec3::X, DVec3::NEG_Y, DVec3::Z),
                DVec3::new(0.0, 150.0, -500.0),
            )
            .inverse(),
        };
        let body = PosedBody {
            spheres: [0.0, 50.0, 100.0, 150.0]
                .map(|y| crate::body::shape::Sphere { centre_cm: DVec3::new(0.0, y, 0.0), radius_cm: 10.0 })
                .to_vec(),
            cones: vec![(0, 1), (1, 2), (2, 3)],
        };
        let covariance = measurement_covariance(&camera, &body, DVec2::ZERO, 1.0).unwrap();
        let (across, along) = (covariance.x_axis.x, covariance.y_axis.y);
        assert!(along > 10.0 * across, "across {across} cm², along {along} cm²");
        assert!((largest_sigma_cm(covariance) - along.sqrt()).abs() < 1e-6 * along.sqrt());
    }
}
