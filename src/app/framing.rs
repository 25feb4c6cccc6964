//! How far the 3D view stands back to show what it frames: the body's
//! floor paths and the body standing on them, whole, whatever the view's
//! shape. The view is a perspective camera orbiting a target; what it
//! frames is held as a sphere around that target, so that the distance
//! holds from every direction the user may orbit to.

/// The distance (m) from which a perspective camera of vertical field of
/// view `vertical_fov_rad`, on a view `aspect` (width over height) wide,
/// sees the whole of a sphere of `radius_m` around its target: the sphere
/// touches the narrower of the two fields of view. A portrait view's
/// horizontal field is the narrower, so it stands further back.
pub fn distance_to_fit(radius_m: f32, vertical_fov_rad: f32, aspect: f32) -> f32 {
    let half_vertical = vertical_fov_rad / 2.0;
    let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
    let half_horizontal = (half_vertical.tan() * aspect).atan();
    radius_m / half_vertical.min(half_horizontal).sin()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    /// Where `p` lands in a perspective view from `eye` at `target`
    /// (normalised: ±1 at the view's edges), as three-d's camera draws it.
    fn in_view(p: Vec3, eye: Vec3, target: Vec3, fov: f32, aspect: f32) -> Vec2 {
        let forward = (target - eye).normalize();
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        let d = p - eye;
        let depth = d.dot(forward);
        let half_height = depth * (fov / 2.0).tan();
        Vec2::new(d.dot(right) / (half_height * aspect), d.dot(up) / half_height)
    }

    #[test]
    fn a_framed_sphere_is_in_view_from_any_side_at_any_aspect() {
        let fov = 45f32.to_radians();
        let target = Vec3::new(3.0, 0.9, -2.0);
        let radius_m = 4.2;
        // The page's 3D view at 1280×800 and at 390×844, a wide embed, a square.
        for aspect in [1.6, 390.0 / 844.0, 3.0, 1.0] {
            let distance = distance_to_fit(radius_m, fov, aspect);
            for (yaw, pitch) in [(0.6f32, 0.35f32), (2.0, 0.1), (-1.2, 1.2)] {
                let eye = target
                    + distance * Vec3::new(pitch.cos() * yaw.sin(), pitch.sin(), pitch.cos() * yaw.cos());
                // Points on the sphere in many directions, and its extremes.
                let mut widest = 0f32;
                for k in 0..400 {
                    let (a, b) = (k as f32 * 0.7, (k as f32 * 0.31).sin() * 1.5);
                    let p = target + radius_m * Vec3::new(b.cos() * a.cos(), b.sin(), b.cos() * a.sin());
                    let ndc = in_view(p, eye, target, fov, aspect);
                    assert!(ndc.x.abs() <= 1.0 + 1e-4 && ndc.y.abs() <= 1.0 + 1e-4, "aspect {aspect}: {ndc}");
                    widest = widest.max(ndc.x.abs().max(ndc.y.abs()));
                }
                // Not far beyond need: the sphere fills most of the narrower side.
                assert!(widest > 0.85, "aspect {aspect}: the sphere spans only {widest}");
            }
        }
        assert!(distance_to_fit(1.0, fov, 0.5) > distance_to_fit(1.0, fov, 1.6));
        assert!(distance_to_fit(1.0, fov, f32::NAN).is_finite());
    }
}
