//! Accelerations from positions, as an accelerometer would read them, and
//! vector magnitudes.

use glam::DVec3;

/// Standard gravity in cm/s², the unit the accelerometer's g is measured in.
pub const STANDARD_GRAVITY_CM_PER_S2: f64 = 980.665;

/// What an accelerometer riding on `positions_cm` would read, as a magnitude
/// in g: `|p'' + (0, g, 0)| / g` with `g` = [`STANDARD_GRAVITY_CM_PER_S2`] and
/// +Y up (an accelerometer at rest reads 1 g). `p''` is the central second
/// difference `(p[f-1] - 2 p[f] + p[f+1]) · fps²`; the first and last frames
/// take their neighbour's value (the one-sided second difference). With fewer
/// than 3 frames there is no acceleration to see and every frame reads 1 g.
///
/// For a BVH without accelerometer data: the caller passes the foot's path
/// with the root translation removed, since that translation is what is unknown.
pub fn kinematic_accel_magnitude_g(positions_cm: &[DVec3], fps: f64) -> Vec<f64> {
    let n = positions_cm.len();
    let gravity = DVec3::new(0.0, STANDARD_GRAVITY_CM_PER_S2, 0.0);
    if n < 3 {
        return vec![1.0; n];
    }
    let fps2 = fps * fps;
    let second_difference =
        |f: usize| (positions_cm[f - 1] - 2.0 * positions_cm[f] + positions_cm[f + 1]) * fps2;
    (0..n)
        .map(|f| {
            let accel_cm_s2 = second_difference(f.clamp(1, n - 2));
            (accel_cm_s2 + gravity).length() / STANDARD_GRAVITY_CM_PER_S2
        })
        .collect()
}

/// The length of each vector.
pub fn magnitudes(v: &[DVec3]) -> Vec<f64> {
    v.iter().map(|a| a.length()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn acceleration_of_a_parabola_is_exact() {
        let fps = 100.0;
        let a = DVec3::new(30.0, -50.0, 20.0);
        let p: Vec<DVec3> = (0..10)
            .map(|f| {
                let t = f as f64 / fps;
                DVec3::new(1.0, 2.0, 3.0) + 0.5 * a * t * t
            })
            .collect();
        let m = kinematic_accel_magnitude_g(&p, fps);
        let expected =
            (a + DVec3::new(0.0, STANDARD_GRAVITY_CM_PER_S2, 0.0)).length() / STANDARD_GRAVITY_CM_PER_S2;
        for v in m {
            assert!((v - expected).abs() < 1e-9, "{v} vs {expected}");
        }
    }

    #[test]
    fn at_rest_reads_one_g() {
        let p = vec![DVec3::new(5.0, 7.0, -1.0); 6];
        assert!(kinematic_accel_magnitude_g(&p, 100.0).iter().all(|&v| v == 1.0));
        assert_eq!(kinematic_accel_magnitude_g(&p[..2], 100.0), vec![1.0, 1.0]);
        assert!(kinematic_accel_magnitude_g(&[], 100.0).is_empty());
    }

    #[test]
    fn magnitudes_are_lengths() {
        assert_eq!(magnitudes(&[DVec3::new(3.0, 4.0, 0.0), DVec3::ZERO]), vec![5.0, 0.0]);
    }
}
