//! Measures of a floor trajectory, shared by the CLI's summaries, the tests and
//! the accuracy evaluation. All work on the floor plane (X/Z; Y is up).

use glam::DVec3;

/// Length of the path `points` travel on the floor, in cm.
pub fn floor_path_cm(points: &[DVec3]) -> f64 {
    points.windows(2).map(|w| (w[1] - w[0]).with_y(0.0).length()).fold(0.0, |a, b| a + b)
}

/// Mean horizontal distance between `estimated` and `truth`, after moving
/// `estimated` so that both start at the same point (a translation method
/// cannot know where on the floor a recording began).
pub fn mean_floor_error_cm(estimated: &[DVec3], truth: &[DVec3]) -> f64 {
    let (Some(e0), Some(t0)) = (estimated.first(), truth.first()) else { return 0.0 };
    let align = *t0 - *e0;
    let total: f64 = estimated.iter().zip(truth).map(|(e, t)| (*e + align - *t).with_y(0.0).length()).sum();
    total / estimated.len().min(truth.len()) as f64
}

/// Horizontal distance between the last points of `estimated` and `truth`,
/// with `estimated` moved to start where `truth` does (0 for no points).
pub fn final_floor_error_cm(estimated: &[DVec3], truth: &[DVec3]) -> f64 {
    let n = estimated.len().min(truth.len());
    if n == 0 {
        return 0.0;
    }
    let align = truth[0] - estimated[0];
    (estimated[n - 1] + align - truth[n - 1]).with_y(0.0).length()
}

/// Horizontal distance between the first and the last point: how far a
/// recording that should end where it started (a kata) misses its start.
pub fn floor_closure_cm(points: &[DVec3]) -> f64 {
    match (points.first(), points.last()) {
        (Some(a), Some(b)) => (*b - *a).with_y(0.0).length(),
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures() {
        let truth = [DVec3::ZERO, DVec3::new(3.0, 5.0, 4.0), DVec3::new(3.0, 0.0, 0.0)];
        assert_eq!(floor_path_cm(&truth), 9.0);
        assert_eq!(floor_closure_cm(&truth), 3.0);
        let estimated: Vec<DVec3> = truth.iter().map(|p| *p + DVec3::new(100.0, 7.0, 0.0)).collect();
        assert_eq!(mean_floor_error_cm(&estimated, &truth), 0.0);
        let off = [DVec3::ZERO, DVec3::new(3.0, 0.0, 4.0), DVec3::new(3.0, 0.0, 3.0)];
        assert_eq!(mean_floor_error_cm(&off, &truth), 1.0);
        assert_eq!(mean_floor_error_cm(&[], &truth), 0.0);
    }
}
