//! How far a hips track is from the truth on the floor, frame by frame: the
//! figures `embusen eval-track` prints per scene and as medians. The camera
//! defines the world, so positions are compared as they are, not aligned at
//! the start as a translation method's are.

use glam::DVec2;

use crate::signal::stats::{median, quantile};

/// A frame farther than this from the truth (cm) is a frame the track lost:
/// about a stride, a mistake any viewer of the video sees.
pub const LOST_CM: f64 = 20.0;

/// The horizontal hips error of a track against the truth (cm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackErrors {
    pub mean_cm: f64,
    pub median_cm: f64,
    pub p90_cm: f64,
    pub max_cm: f64,
    /// At the last frame.
    pub final_cm: f64,
    /// The share of frames farther than [`LOST_CM`], 0 to 1.
    pub lost_share: f64,
}

impl TrackErrors {
    /// Each figure's median over `scenes` (NaN where none has it): the row
    /// a table of scenes ends with.
    pub fn medians(scenes: &[&TrackErrors]) -> TrackErrors {
        let figure = |k: usize| median(&scenes.iter().map(|e| e.figures()[k]).collect::<Vec<_>>());
        TrackErrors::from_figures(std::array::from_fn(figure))
    }

    /// The figures in the order of the fields.
    fn figures(&self) -> [f64; 6] {
        [self.mean_cm, self.median_cm, self.p90_cm, self.max_cm, self.final_cm, self.lost_share]
    }

    fn from_figures([mean_cm, median_cm, p90_cm, max_cm, final_cm, lost_share]: [f64; 6]) -> TrackErrors {
        TrackErrors { mean_cm, median_cm, p90_cm, max_cm, final_cm, lost_share }
    }
}

/// The horizontal distance (cm) of `track` from `truth`, floor positions
/// (x, z, cm) per frame, over the frames both have.
pub fn frame_errors_cm(track: &[DVec2], truth: &[DVec2]) -> Vec<f64> {
    track.iter().zip(truth).map(|(e, t)| (*e - *t).length()).collect()
}

/// The errors of `track` against `truth`, floor positions (x, z, cm) per
/// frame, over the frames both have; NaN figures when there are none.
pub fn track_errors(track: &[DVec2], truth: &[DVec2]) -> TrackErrors {
    let errors = frame_errors_cm(track, truth);
    let n = errors.len();
    TrackErrors {
        mean_cm: if n > 0 { errors.iter().sum::<f64>() / n as f64 } else { f64::NAN },
        median_cm: median(&errors),
        p90_cm: quantile(&errors, 0.9),
        max_cm: errors.iter().copied().fold(f64::NAN, f64::max),
        final_cm: errors.last().copied().unwrap_or(f64::NAN),
        lost_share: if n > 0 {
            errors.iter().filter(|&&e| e > LOST_CM).count() as f64 / n as f64
        } else {
            f64::NAN
        },
    }
}

/// The share of frames (0 to 1) whose error against `truth` is within the
/// uncertainty the tracker stated for it (`uncertainty_cm`, one σ, per
/// frame; NaN: none stated); NaN when no frame has one. An honest one σ
/// holds the truth in about two frames of three.
pub fn share_within_uncertainty(track: &[DVec2], uncertainty_cm: &[f64], truth: &[DVec2]) -> f64 {
    let stated: Vec<bool> = frame_errors_cm(track, truth)
        .iter()
        .zip(uncertainty_cm)
        .filter(|(_, u)| u.is_finite())
        .map(|(e, u)| e <= u)
        .collect();
    if stated.is_empty() {
        return f64::NAN;
    }
    stated.iter().filter(|&&within| within).count() as f64 / stated.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_medians_over_scenes_are_each_figures_median() {
        let scene = |k: f64| TrackErrors {
            mean_cm: k,
            median_cm: 2.0 * k,
            p90_cm: 3.0 * k,
            max_cm: 4.0 * k,
            final_cm: 5.0 * k,
            lost_share: 0.1 * k,
        };
        let (a, b, c) = (scene(1.0), scene(2.0), scene(7.0));
        assert_eq!(TrackErrors::medians(&[&c, &a, &b]), scene(2.0));
        assert!(TrackErrors::medians(&[]).mean_cm.is_nan());
    }

    #[test]
    fn errors_of_a_track_against_its_truth() {
        let truth: Vec<DVec2> = (0..10).map(|i| DVec2::new(i as f64, 0.0)).collect();
        let track: Vec<DVec2> =
            truth.iter().enumerate().map(|(i, t)| *t + DVec2::new(0.0, 3.0 * i as f64)).collect();
        let e = track_errors(&track, &truth);
        assert_eq!(e.mean_cm, 13.5);
        assert_eq!(e.max_cm, 27.0);
        assert_eq!(e.final_cm, 27.0);
        assert_eq!(e.median_cm, 13.5);
        assert!((e.p90_cm - 24.3).abs() < 1e-12);
        assert_eq!(e.lost_share, 0.3);
        assert!(track_errors(&[], &[]).mean_cm.is_nan());
        // Errors 0, 3, 6, … 27 cm against a stated 10 cm: 4 of 10 within.
        let within = share_within_uncertainty(&track, &[10.0; 10], &truth);
        assert_eq!(within, 0.4);
        assert!(share_within_uncertainty(&track, &[f64::NAN; 10], &truth).is_nan());
    }
}
