//! A camera take's series per video frame as they cross from the camera
//! module (which tracked or opened the take) through the page to the
//! player, whose plot (f) shows them: one type, in both modules' `.d.ts`.

use serde::{Deserialize, Serialize};
use tsify::Tsify;

use crate::app::plot::CameraSeries;

/// Per video frame of a camera take: the recording's time it was read at
/// (s: the frame's time plus the take's offset), the uncertainty the
/// tracker states (cm, one σ; NaN where none), and the error against a
/// truth (cm; empty without one, and `truth_name` then empty too).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
pub struct TakeSeries {
    pub recording_time_s: Vec<f64>,
    pub uncertainty_cm: Vec<f64>,
    pub error_cm: Vec<f64>,
    pub truth_name: String,
}

impl TakeSeries {
    /// The per-video-frame part of `series` (its hips path stays behind).
    pub fn of(series: CameraSeries) -> TakeSeries {
        let CameraSeries { recording_time_s, uncertainty_cm, error_cm, truth_name, .. } = series;
        TakeSeries { recording_time_s, uncertainty_cm, error_cm, truth_name }
    }

    /// The plots' series: these with the hips path `hips_cm`.
    #[cfg(feature = "web-player")]
    pub fn with_path(self, hips_cm: Vec<glam::DVec3>) -> CameraSeries {
        let TakeSeries { recording_time_s, uncertainty_cm, error_cm, truth_name } = self;
        CameraSeries { hips_cm, recording_time_s, uncertainty_cm, error_cm, truth_name }
    }
}
