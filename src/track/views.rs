//! One take filmed by several cameras: each view tracked alone (the same
//! tracker, its own camera, background, rate and offset), then the views'
//! tracks weighed together per instant by how well each sees.
//!
//! Why this works: one camera places the body well across its line of
//! sight (the silhouette moves by pixels) and poorly along it (a body 20 cm
//! farther is a body 3 % smaller); the soles and the suit's steps carry
//! that depth. Each view's track states as much in its covariance
//! (`TrackedFrame::covariance_cm2`: long along its line of sight). A
//! second camera at an angle sees the first one's depth across its own
//! line of sight, so the two covariances' informations add up to a small,
//! round one. A view that did not see the body (out of frame, hidden, a
//! frame with no pose) states a wide covariance or none there and weighs
//! little or drops out; the others carry those frames.
//!
//! The views' tracks share the suit's steps as their prediction, so their
//! errors are not independent where neither camera measured: the fused
//! covariance is then optimistic (on the shared scenes 25–60 % of the
//! frames lie within its 1σ, docs/track.md).

use glam::{DMat2, DVec2};

use crate::track::suit_motion::VideoTiming;
use crate::track::tracker::{Track, TrackedFrame};

/// What weighing reads of one view's finished track: per video frame
/// where it put the body, how sure it was and how well it saw, how its
/// video is timed against the recording, and its warnings. Plain data, so
/// that a view tracked in another Web Worker crosses to the first view's as
/// it is (`web::camera_api::FinishedViewFrames`): the weighing is one code for
/// the CLI and the page.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSightings {
    pub timing: VideoTiming,
    /// Per video frame of the view.
    pub frames: Vec<Sighting>,
    pub warnings: Vec<String>,
}

impl ViewSightings {
    /// What weighing reads of `track`, filmed at `timing`.
    pub fn of(track: &Track, timing: VideoTiming) -> ViewSightings {
        ViewSightings {
            timing,
            frames: track.frames.iter().map(Sighting::of).collect(),
            warnings: track.warnings.clone(),
        }
    }

    /// The view's estimate at `recording_s` of the recording: between its
    /// two video frames read nearest that instant; none outside its video.
    pub fn at(&self, recording_s: f64) -> Option<Sighting> {
        let frames = &self.frames;
        let position = self.timing.video_position(recording_s);
        if !(position >= 0.0 && position <= (frames.len() as f64 - 1.0)) {
            return None;
        }
        let (a, t) = (position.floor() as usize, position.fract());
        let at = *frames.get(a)?;
        let next = frames.get(a + 1).copied().filter(|_| t > 1e-9);
        match next {
            Some(next) if at.is_usable() && next.is_usable() => Some(Sighting {
                floor_cm: at.floor_cm.lerp(next.floor_cm, t),
                covariance_cm2: at.covariance_cm2 * (1.0 - t) + next.covariance_cm2 * t,
                confidence: at.confidence * (1.0 - t) + next.confidence * t,
            }),
            // One of the two has no reading: the nearer one alone, if it has.
            Some(next) if t > 0.5 => Some(next),
            _ => Some(at),
        }
    }
}

/// The first view's track (filmed at `first_timing`) weighed with the
/// `others` on its video frames: per frame the first view's, and every
/// other view's at the same instant of the recording (between its two
/// nearest frames), each by the inverse of its covariance. A view with no
/// finite floor point or covariance at that instant drops out of that
/// frame. The first view's frames keep their times, heights and per-view
/// facts (its confidence, its camera's measurement); the fused frame's
/// confidence is the best of the views'. With no others, the first's
/// track as it is.
pub fn fuse_views(first: &Track, first_timing: &VideoTiming, others: &[ViewSightings]) -> Track {
    let mut fused = first.clone();
    if others.is_empty() {
        return fused;
    }
    for (i, frame) in fused.frames.iter_mut().enumerate() {
        let recording_s = first_timing.bvh_time_s(i);
        let seen: Vec<Sighting> = std::iter::once(Some(Sighting::of(frame)))
            .chain(others.iter().map(|view| view.at(recording_s)))
            .flatten()
            .filter(Sighting::is_usable)
            .collect();
        if let Some((floor_cm, covariance_cm2)) = weigh(&seen) {
            frame.floor_cm = floor_cm;
            frame.covariance_cm2 = covariance_cm2;
            frame.uncertainty_cm = (covariance_cm2.x_axis.x + covariance_cm2.y_axis.y).sqrt();
            frame.confidence = seen.iter().map(|s| s.confidence).fold(frame.confidence, f64::max);
        }
    }
    for (k, view) in others.iter().enumerate() {
        fused.warnings.extend(view.warnings.iter().map(|w| format!("view {}: {w}", k + 2)));
    }
    fused
}

/// One view's estimate at an instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sighting {
    /// Where it puts the hips on the floor (x, z, cm).
    pub floor_cm: DVec2,
    /// How sure (cm², the floor's x and z); NaN where it states none.
    pub covariance_cm2: DMat2,
    /// How well its camera saw the body, 0 to 1.
    pub confidence: f64,
}

impl Sighting {
    fn of(frame: &TrackedFrame) -> Sighting {
        Sighting {
            floor_cm: frame.floor_cm,
            covariance_cm2: frame.covariance_cm2,
            confidence: frame.confidence,
        }
    }

    /// A finite point with a covariance that can be inverted.
    fn is_usable(&self) -> bool {
        let c = self.covariance_cm2;
        self.floor_cm.is_finite() && c.is_finite() && c.determinant() > 1e-12 && c.x_axis.x > 0.0
    }
}

/// The estimates weighed by their informations (inverse covariances): the
/// point and covariance of their product.
fn weigh(seen: &[Sighting]) -> Option<(DVec2, DMat2)> {
    let (information, weighted) = seen.iter().fold((DMat2::ZERO, DVec2::ZERO), |(info, sum), s| {
        let inverse = s.covariance_cm2.inverse();
        (info + inverse, sum + inverse * s.floor_cm)
    });
    if seen.is_empty() || information.determinant().abs() < 1e-12 {
        return None;
    }
    let covariance_cm2 = information.inverse();
    Some((covariance_cm2 * weighted, covariance_cm2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::fused::FusedParams;
    use crate::track::tracker::TrackDetails;

    /// A view of a body standing at `truth_cm`, off by `off_cm` in every
    /// frame, uncertain by `sigma_along_cm` along `along` and 1 cm across.
    fn view(frames: usize, off_cm: DVec2, along: DVec2, sigma_along_cm: f64) -> Track {
        let across = along.perp();
        let covariance_cm2 =
            sigma_along_cm * sigma_along_cm * DMat2::from_cols(along * along.x, along * along.y)
                + DMat2::from_cols(across * across.x, across * across.y);
        let frame = |i: usize| TrackedFrame {
            time_s: i as f64 / 30.0,
            floor_cm: DVec2::new(100.0, 200.0) + off_cm,
            height_cm: 90.0,
            confidence: 0.8,
            measured_cm: None,
            uncertainty_cm: (covariance_cm2.x_axis.x + covariance_cm2.y_axis.y).sqrt(),
            covariance_cm2,
            foreground_share: 0.1,
            difference_noise: 2.0,
        };
        Track {
            frames: (0..frames).map(frame).collect(),
            warnings: Vec::new(),
            details: TrackDetails::Fused { params: FusedParams::default(), mean_innovation: 1.0 },
        }
    }

    #[test]
    fn two_views_at_an_angle_take_each_others_depth() {
        let timing = VideoTiming { fps: 30.0, frame_count: 10, offset_s: 0.0 };
        // Each camera 8 cm off along its own line of sight, 60° apart.
        let (a, b) =
            (DVec2::new(0.0, 1.0), DVec2::from_angle(60f64.to_radians()).rotate(DVec2::new(0.0, 1.0)));
        let (first, second) = (view(10, 8.0 * a, a, 8.0), view(10, -8.0 * b, b, 8.0));
        let fused = fuse_views(&first, &timing, &[ViewSightings::of(&second, timing)]);
        let error = (fused.frames[5].floor_cm - DVec2::new(100.0, 200.0)).length();
        assert!(error < 1.5, "fused {error} cm off, each view 8 cm");
        assert!(fused.frames[5].uncertainty_cm < first.frames[5].uncertainty_cm / 2.0);
        // One view: as it is.
        let alone = fuse_views(&first, &timing, &[]);
        assert_eq!(alone, first);
    }

    #[test]
    fn a_view_that_lost_the_body_drops_out_and_another_rate_lines_up() {
        let timing = VideoTiming { fps: 30.0, frame_count: 10, offset_s: 0.0 };
        let a = DVec2::new(0.0, 1.0);
        let first = view(10, 5.0 * a, a, 8.0);
        // The second view films at 60 fps, 0.1 s late, and lost the body
        // in its frames 0-9 (no covariance stated).
        let late = VideoTiming { fps: 60.0, frame_count: 20, offset_s: 0.1 };
        let mut second = view(20, DVec2::new(3.0, 0.0), DVec2::new(1.0, 0.0), 8.0);
        for f in &mut second.frames[..10] {
            f.covariance_cm2 = DMat2::NAN;
        }
        let fused = fuse_views(&first, &timing, &[ViewSightings::of(&second, late)]);
        // Frame 2 (0.067 s) is before the second video (and frame 5, its
        // frame 4, where it lost the body): the first view's alone.
        for i in [2, 5] {
            assert_eq!(fused.frames[i].floor_cm, first.frames[i].floor_cm, "frame {i}");
        }
        // Frame 8 (0.267 s) is its frame 10: both weigh in.
        assert!((fused.frames[8].floor_cm - first.frames[8].floor_cm).length() > 1.0);
    }
}
