//! What the plots show: one frame-by-frame record of a translation, built by
//! [`crate::app::session::plot_data`].

use glam::DVec3;

use crate::body::feet::{Foot, PerFoot};

/// Why a frame's stance is what it is: which foot the method held still, and
/// which rule made it do so.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum StanceReason {
    /// Paper pass 1: the foot with the lower smoothed acceleration.
    Acceleration,
    /// Paper pass 2: the lower foot, where the heights differ by more than dyEps.
    Height,
    /// Both passes pinned this foot.
    Both,
    /// The contact method: this foot alone is on the floor.
    Contact,
}

/// One frame of the stance strip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Stance {
    /// No foot pinned (e.g. the paper method's zeroed tails).
    Free,
    Pinned(Foot, StanceReason),
    /// Neither foot on the floor (running, jumps).
    Flight,
    /// Both feet on the floor: the contact method's double support.
    Double,
}

impl Stance {
    /// True for the contact method's decisions that the paper method never
    /// makes: one foot alone on the floor, or both.
    pub const fn is_contact(self) -> bool {
        matches!(self, Stance::Pinned(_, StanceReason::Contact) | Stance::Double)
    }
}

/// Everything the plots show, frame by frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlotData {
    pub fps: f64,
    /// (a) the signal that chose the planted foot, and its label with unit,
    /// e.g. "smoothed acceleration (g)".
    pub foot_signal: PerFoot<Vec<f64>>,
    pub foot_signal_label: String,
    /// (b) foot heights before correction, cm.
    pub heights_before_cm: PerFoot<Vec<f64>>,
    /// (c) foot heights after correction, cm.
    pub heights_after_cm: PerFoot<Vec<f64>>,
    /// (d) hips on the floor, before and after (X/Z used; Y is up).
    pub hips_before_cm: Vec<DVec3>,
    pub hips_after_cm: Vec<DVec3>,
    /// (e) the stance strip.
    pub stance: Vec<Stance>,
    /// (d) and (f) with a camera take shown; empty without one.
    pub camera: CameraSeries,
}

/// A camera take as the plots show it: its hips path in (d) beside the
/// suit's own and the inertial estimate's, and in (f) per video frame the
/// track's stated uncertainty and, given a truth, its error against it.
/// The video's frames are placed on the recording's time axis where the
/// tracker read the recording for them, so a video at another rate (or
/// offset) lines up with the recording's plots.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraSeries {
    /// Per recording frame, the track's hips (the recording's coordinates, cm).
    pub hips_cm: Vec<DVec3>,
    /// Per video frame, the recording's time it was read at (s): the video
    /// frame's time plus the take's offset.
    pub recording_time_s: Vec<f64>,
    /// Per video frame, how far the hips may be from the track (cm, one σ);
    /// NaN where the tracker states none.
    pub uncertainty_cm: Vec<f64>,
    /// Per video frame, the horizontal error against `truth_name` (cm); empty
    /// without a truth.
    pub error_cm: Vec<f64>,
    /// The truth's file name, for the legend.
    pub truth_name: String,
}

impl CameraSeries {
    /// True when a take is shown: (d) draws its path.
    pub fn is_shown(&self) -> bool {
        !self.hips_cm.is_empty()
    }

    /// True when the take has its per-video-frame series: (f) is laid out.
    pub fn has_video_frames(&self) -> bool {
        self.is_shown() && !self.recording_time_s.is_empty()
    }
}

impl PlotData {
    /// The number of frames the plots span: the length of the longest series.
    /// They normally all have one entry per frame; a shorter one is drawn as
    /// far as it goes.
    pub fn frame_count(&self) -> usize {
        let feet = [&self.foot_signal, &self.heights_before_cm, &self.heights_after_cm]
            .into_iter()
            .flat_map(|series| Foot::BOTH.map(|foot| series[foot].len()));
        let rest = [
            self.hips_before_cm.len(),
            self.hips_after_cm.len(),
            self.camera.hips_cm.len(),
            self.stance.len(),
        ];
        feet.chain(rest).max().unwrap_or(0)
    }
}
