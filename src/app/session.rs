//! What the app has open: a recording, the method settings, and their result,
//! plus everything derived from them for display and export. Browser-free, so
//! the wasm player stays a thin shell over it and tests can drive it natively.

use crate::app::plot::{CameraSeries, PlotData, Stance, StanceReason};
use crate::body::feet::{Foot, PerFoot};
use crate::error::Error;
use crate::io::recording::{FeetChoice, Recording, base_name};
use crate::translate::contact::{ContactParams, Support};
use crate::translate::hachaj::{HachajParams, Smoothing};
use crate::translate::{Decisions, Method, MethodKind, Translated};

/// The user's method settings. Both methods keep their parameters, so
/// switching back and forth loses nothing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    pub method: MethodKind,
    pub hachaj: HachajParams,
    pub contact: ContactParams,
    pub feet: FeetChoice,
}

impl Settings {
    /// The method in use, with its parameters.
    pub fn method_with_params(&self) -> Method {
        match self.method {
            MethodKind::Hachaj => Method::Hachaj(self.hachaj),
            MethodKind::Contact => Method::Contact(self.contact.clone()),
        }
    }
}

/// An open recording with its translation computed.
#[derive(Clone, Debug)]
pub struct Session {
    pub recording: Recording,
    pub settings: Settings,
    pub translated: Translated,
    /// What the plots show; with a camera take shown, its track too
    /// ([`Session::set_camera_take`]), kept across new settings.
    pub plot_data: PlotData,
}

impl Session {
    /// Computes the translation of `recording` with `settings`.
    pub fn open(recording: Recording, settings: Settings) -> Result<Session, Error> {
        let translated = translate(&recording, &settings)?;
        let plot_data = plot_data(&recording, &translated, &settings);
        Ok(Session { recording, settings, translated, plot_data })
    }

    /// Recomputes with new settings. On error the session keeps its previous
    /// settings and result, so the user never loses what was on screen.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), Error> {
        let translated = translate(&self.recording, &settings)?;
        let camera = std::mem::take(&mut self.plot_data.camera);
        self.plot_data = PlotData { camera, ..plot_data(&self.recording, &translated, &settings) };
        self.translated = translated;
        self.settings = settings;
        Ok(())
    }

    /// Shows a camera take in the plots: its path in (d) beside the
    /// inertial one, its uncertainty and error per video frame in (f); an
    /// empty `camera` shows none. Errors, changing nothing: a path not one
    /// point per recording frame, per-video-frame series of different
    /// lengths, or times that are not finite and increasing.
    pub fn set_camera_take(&mut self, camera: CameraSeries) -> Result<(), Error> {
        let name = &self.recording.name;
        let frames = self.recording.frame_count();
        let video_frames = camera.recording_time_s.len();
        if camera.is_shown() && camera.hips_cm.len() != frames {
            let message = format!(
                "a camera track of {} frames does not fit this recording of {frames}",
                camera.hips_cm.len()
            );
            return Err(Error::whole(name, message));
        }
        for (series, len) in
            [("uncertainty_cm", camera.uncertainty_cm.len()), ("error_cm", camera.error_cm.len())]
        {
            if len != video_frames && !(series == "error_cm" && len == 0) {
                let message =
                    format!("the camera take's {series} has {len} video frames, its times {video_frames}");
                return Err(Error::whole(name, message));
            }
        }
        if let Some(i) = (0..video_frames).find(|&i| {
            let t = camera.recording_time_s[i];
            !t.is_finite() || (i > 0 && t <= camera.recording_time_s[i - 1])
        }) {
            let message =
                format!("the camera take's time of video frame {i} is not finite and after the one before");
            return Err(Error::whole(name, message));
        }
        self.plot_data.camera = camera;
        Ok(())
    }

    /// The corrected recording in its own format, and a file name for it.
    pub fn export_recording(&self) -> (String, String) {
        let text = self.recording.write_shifted(&self.translated.shift_cm);
        (export_name(&self.recording.name, &format!("embusen.{}", self.recording.extension())), text)
    }

    /// The hips trajectory, original and corrected, as CSV:
    /// `frame,time_s,original_x_cm,…,corrected_z_cm`.
    pub fn export_hips_csv(&self) -> (String, String) {
        let before = self.recording.poses.trajectory(self.translated.hips);
        let after = self.translated.poses.trajectory(self.translated.hips);
        let mut out = String::from(
            "frame,time_s,original_x_cm,original_y_cm,original_z_cm,corrected_x_cm,corrected_y_cm,corrected_z_cm\n",
        );
        for (f, (b, a)) in before.iter().zip(&after).enumerate() {
            out.push_str(&format!(
                "{f},{},{},{},{},{},{},{}\n",
                f as f64 / self.recording.fps,
                b.x,
                b.y,
                b.z,
                a.x,
                a.y,
                a.z
            ));
        }
        (export_name(&self.recording.name, "hips.csv"), out)
    }
}

/// `dir/heian.bvh` + `embusen.bvh` → `heian.embusen.bvh`.
fn export_name(name: &str, suffix: &str) -> String {
    let base = base_name(name);
    let stem = base.rsplit_once('.').map_or(base, |(stem, _)| stem);
    let stem = if stem.is_empty() || stem.contains(' ') { "recording" } else { stem };
    format!("{stem}.{suffix}")
}

fn translate(recording: &Recording, settings: &Settings) -> Result<Translated, Error> {
    recording.translate(&settings.feet, &settings.method_with_params())
}

/// What the plots show: (a) the signal that chose the foot and (e) the
/// decisions come from the method; (b)–(d) are the same for both.
pub fn plot_data(recording: &Recording, t: &Translated, settings: &Settings) -> PlotData {
    let heights = |poses: &crate::body::skeleton::Poses, foot: Foot| -> Vec<f64> {
        poses.trajectory(t.feet[foot]).iter().map(|p| p.y).collect()
    };
    let (foot_signal, foot_signal_label, stance) = match &t.decisions {
        Decisions::Hachaj(paper) => (
            paper.accel_smoothed_g.clone(),
            match settings.hachaj.smoothing {
                Smoothing::Faithful => "smoothed acceleration (g), R smoother".to_string(),
                Smoothing::Clean => "smoothed acceleration (g)".to_string(),
            },
            paper
                .pass1_pinned
                .iter()
                .zip(&paper.pass2_pinned)
                .map(|(p1, p2)| match (p1, p2) {
                    (Some(a), Some(b)) if a == b => Stance::Pinned(*a, StanceReason::Both),
                    // Pass 2 runs after pass 1 and has the last word on the frame.
                    (_, Some(b)) => Stance::Pinned(*b, StanceReason::Height),
                    (Some(a), None) => Stance::Pinned(*a, StanceReason::Acceleration),
                    (None, None) => Stance::Free,
                })
                .collect(),
        ),
        Decisions::Contact(contact) => (
            contact.clearance_cm.clone(),
            "foot clearance above the floor (cm)".to_string(),
            contact
                .support
                .iter()
                .map(|support| match support {
                    Support::Single(foot) => Stance::Pinned(*foot, StanceReason::Contact),
                    Support::Double => Stance::Double,
                    Support::Flight => Stance::Flight,
                })
                .collect(),
        ),
    };
    PlotData {
        fps: recording.fps,
        foot_signal,
        foot_signal_label,
        heights_before_cm: PerFoot::from_fn(|foot| heights(&recording.poses, foot)),
        heights_after_cm: PerFoot::from_fn(|foot| heights(&t.poses, foot)),
        hips_before_cm: recording.poses.trajectory(t.hips),
        hips_after_cm: t.poses.trajectory(t.hips),
        stance,
        camera: CameraSeries::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn export_names() {
        assert_eq!(export_name("a/b/heian.bvh", "embusen.bvh"), "heian.embusen.bvh");
        assert_eq!(export_name("walk", "hips.csv"), "walk.hips.csv");
        assert_eq!(export_name("demo (synthetic kata)", "hips.csv"), "recording.hips.csv");
    }

    #[test]
    fn a_camera_take_stays_in_the_plots_across_settings_and_must_fit() {
        let mut session = Session::open(crate::synth::demo::demo().recording(), Settings::default()).unwrap();
        let frames = session.recording.frame_count();
        let take = CameraSeries {
            hips_cm: (0..frames).map(|f| DVec3::new(f as f64, 90.0, 0.0)).collect(),
            recording_time_s: vec![0.0, 0.5, 1.0],
            uncertainty_cm: vec![2.0, 2.5, 3.0],
            error_cm: Vec::new(),
            truth_name: String::new(),
        };
        let short = CameraSeries { hips_cm: take.hips_cm[1..].to_vec(), ..take.clone() };
        let uneven = CameraSeries { error_cm: vec![1.0], ..take.clone() };
        let backwards = CameraSeries { recording_time_s: vec![0.0, 1.0, 0.5], ..take.clone() };
        for (bad, why) in [(short, "does not fit"), (uneven, "error_cm"), (backwards, "video frame 2")] {
            let e = session.set_camera_take(bad).unwrap_err().to_string();
            assert!(e.contains(why), "{e}");
            assert!(!session.plot_data.camera.is_shown());
        }
        session.set_camera_take(take.clone()).unwrap();
        let paper = Settings { method: MethodKind::Hachaj, ..Settings::default() };
        session.set_settings(paper).unwrap();
        assert_eq!(session.plot_data.camera, take);
        assert_eq!(session.plot_data.frame_count(), frames);
        session.set_camera_take(CameraSeries::default()).unwrap();
        assert!(!session.plot_data.camera.is_shown());
    }

    #[test]
    fn bad_settings_keep_the_previous_result() {
        let mut session = Session::open(crate::synth::demo::demo().recording(), Settings::default()).unwrap();
        let before = session.translated.shift_cm.clone();
        let mut bad = Settings::default();
        bad.feet.left = Some("NoSuchJoint".to_string());
        assert!(session.set_settings(bad).is_err());
        assert_eq!(session.translated.shift_cm, before);
        assert_eq!(session.settings, Settings::default());
        let (name, text) = session.export_hips_csv();
        assert_eq!(name, "recording.hips.csv");
        assert_eq!(text.lines().count(), session.recording.frame_count() + 1);
    }
}
