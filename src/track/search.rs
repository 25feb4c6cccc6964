//! The fused tracker's search of one frame: the least energy on the floor
//! near the prediction, found coarse to fine to a set resolution — not the
//! paper's 10 cm steps, whose error is half a step at best and which cannot
//! catch up once the body is farther than their reach.

use glam::DVec2;

/// The least of `energy` within `radius_cm` of `centre` (a square), found
/// on a 5 × 5 grid spanning the square, then 3 × 3 grids of half the spacing
/// around the best so far, until the spacing is at most `resolution_cm`.
/// Returns the position and its energy; `None` when no energy tried is
/// finite (the silhouette nowhere in the image). About `25 + 9 ×
/// log2(radius / (2 · resolution))` evaluations.
pub fn coarse_to_fine(
    centre: DVec2,
    radius_cm: f64,
    resolution_cm: f64,
    mut energy: impl FnMut(DVec2) -> f64,
) -> Option<(DVec2, f64)> {
    let mut best: Option<(DVec2, f64)> = None;
    let mut consider = |p: DVec2, best: &mut Option<(DVec2, f64)>| {
        let e = energy(p);
        if e.is_finite() && best.is_none_or(|(_, b)| e < b) {
            *best = Some((p, e));
        }
    };
    let mut spacing = radius_cm.max(resolution_cm) / 2.0;
    for i in -2..=2 {
        for j in -2..=2 {
            consider(centre + DVec2::new(i as f64, j as f64) * spacing, &mut best);
        }
    }
    // The loop halves a finite positive spacing down to the resolution; the
    // cap only guards against a resolution of 0.
    for _ in 0..60 {
        let (around, _) = best?;
        if spacing <= resolution_cm {
            break;
        }
        spacing /= 2.0;
        for i in -1..=1 {
            for j in -1..=1 {
                if i != 0 || j != 0 {
                    consider(around + DVec2::new(i as f64, j as f64) * spacing, &mut best);
                }
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_smooth_minimum_to_the_resolution() {
        let target = DVec2::new(12.34, -7.89);
        let bowl = |p: DVec2| (p - target).length_squared() + 0.3 * (p.x - target.x) * (p.y - target.y);
        let mut calls = 0;
        let (found, _) = coarse_to_fine(DVec2::ZERO, 40.0, 0.5, |p| {
            calls += 1;
            bowl(p)
        })
        .unwrap();
        assert!((found - target).length() < 0.5, "{found}");
        assert!(calls <= 25 + 9 * 6, "{calls} evaluations");
        assert_eq!(coarse_to_fine(DVec2::ZERO, 40.0, 0.5, |_| f64::INFINITY), None);
    }
}
