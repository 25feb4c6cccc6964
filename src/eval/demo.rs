//! The built-in demo scored against its truth: the figures `embusen` prints
//! with no arguments. The demo is a suit's recording (see
//! [`crate::synth::demo`]); each method estimates its translation from the
//! recording the tool opens, the vendor's guess is scored beside them.

use glam::DVec3;

use crate::body::kinematics::forward_kinematics;
use crate::error::Error;
use crate::eval::metrics::{final_floor_error_cm, floor_path_cm, mean_floor_error_cm};
use crate::io::recording::FeetChoice;
use crate::synth::demo::Demo;
use crate::translate::{Method, Translated};

/// How far a hips path is from the demo's true one, on the floor (first
/// frames aligned).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathError {
    pub mean_cm: f64,
    /// The last frame's.
    pub final_cm: f64,
    pub true_path_cm: f64,
    /// The estimated path's length over the truth's: above 1, a trail that
    /// shakes; below, strides lost.
    pub path_ratio: f64,
}

impl PathError {
    /// `estimated` (hips per frame) against `truth`.
    pub fn new(estimated: &[DVec3], truth: &[DVec3]) -> PathError {
        PathError {
            mean_cm: mean_floor_error_cm(estimated, truth),
            final_cm: final_floor_error_cm(estimated, truth),
            true_path_cm: floor_path_cm(truth),
            path_ratio: floor_path_cm(estimated) / floor_path_cm(truth),
        }
    }

    pub fn mean_pct(&self) -> f64 {
        100.0 * self.mean_cm / self.true_path_cm
    }

    pub fn final_pct(&self) -> f64 {
        100.0 * self.final_cm / self.true_path_cm
    }
}

/// `method` on the demo as the tool opens it, and its error against the truth.
pub fn evaluate_demo(demo: &Demo, method: &Method) -> Result<(Translated, PathError), Error> {
    let recording = demo.recording();
    let translated = recording.translate(&FeetChoice::default(), method)?;
    let error = PathError::new(&translated.poses.trajectory(translated.hips), &demo.true_root_cm);
    Ok((translated, error))
}

/// The suit vendor's own translation (the demo's Hips position channels
/// before they are stripped) against the truth.
pub fn vendor_error(demo: &Demo) -> PathError {
    let poses = forward_kinematics(&demo.skeleton, &demo.motion);
    PathError::new(&poses.trajectory(0), &demo.true_root_cm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::demo::demo;

    /// By little on the mean (18.6 against 19.3 cm), by much on the final
    /// error (17.1 against 40.9 cm).
    #[test]
    fn contact_beats_paper_on_the_demo() {
        let demo = demo();
        let (_, hachaj) = evaluate_demo(&demo, &Method::Hachaj(Default::default())).unwrap();
        let (_, contact) = evaluate_demo(&demo, &Method::default()).unwrap();
        assert!(contact.mean_cm < hachaj.mean_cm, "contact {contact:?}, paper {hachaj:?}");
    }

    /// The trail a newcomer sees first is as long as the truth's (issue 23:
    /// 0.85–1.2 of it): 2.2 times it, before the path of a noisy pose was
    /// smoothed below the contacts' grid and where the body stands still.
    #[test]
    fn the_demo_s_contact_trail_does_not_shake() {
        let (_, contact) = evaluate_demo(&demo(), &Method::default()).unwrap();
        assert!((0.85..=1.2).contains(&contact.path_ratio), "{contact:?}");
    }
}
