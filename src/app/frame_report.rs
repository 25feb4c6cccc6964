//! What a tracking job ([`crate::app::tracking::TrackingJob`]) reports of
//! the frames it tracks, in the shapes the camera module hands the page as
//! they are: each frame's progress, and Riečický et al.'s candidates. A
//! position on the floor is a `DVec2` (x, z, cm) here as in the core, and a
//! [`FloorPoint`] object in the page.

use glam::DVec2;

/// Where one frame put the actor, as the job reports it while it runs; the
/// camera module hands it to the page as it is (its `floor` a
/// [`FloorPoint`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(
    all(target_arch = "wasm32", any(feature = "web-camera", feature = "web-board")),
    derive(tsify::Tsify)
)]
pub struct FrameProgress {
    /// The frame's index in the video.
    pub frame: usize,
    /// The filter's position so far (x, z, cm; smoothed only at the end).
    #[serde(rename = "floor", with = "floor_point")]
    #[cfg_attr(
        all(target_arch = "wasm32", any(feature = "web-camera", feature = "web-board")),
        tsify(type = "FloorPoint")
    )]
    pub floor_cm: DVec2,
    /// How well the camera saw the body, 0 to 1.
    pub confidence: f64,
}

/// A point on the floor (x, z, cm: the world's Y is up), as the page's
/// objects carry one (the core's is a `DVec2`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(
    all(target_arch = "wasm32", any(feature = "web-camera", feature = "web-board")),
    derive(tsify::Tsify)
)]
#[serde(deny_unknown_fields)]
pub struct FloorPoint {
    pub x_cm: f64,
    pub z_cm: f64,
}

impl From<DVec2> for FloorPoint {
    fn from(p: DVec2) -> FloorPoint {
        FloorPoint { x_cm: p.x, z_cm: p.y }
    }
}

impl From<FloorPoint> for DVec2 {
    fn from(p: FloorPoint) -> DVec2 {
        DVec2::new(p.x_cm, p.z_cm)
    }
}

/// A `DVec2` (x, z, cm) (de)serialised as a [`FloorPoint`].
mod floor_point {
    use glam::DVec2;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::FloorPoint;

    pub fn serialize<S: Serializer>(p: &DVec2, serializer: S) -> Result<S::Ok, S::Error> {
        FloorPoint::from(*p).serialize(serializer)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<DVec2, D::Error> {
        FloorPoint::deserialize(deserializer).map(DVec2::from)
    }
}

/// One of Riečický et al.'s candidates in a frame, as the job reports it
/// and the camera module hands it to the page (its `floor` a
/// [`FloorPoint`]); the plot draws it too. The tracker keeps the pairs of
/// its search (`track::riecicky`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(
    all(target_arch = "wasm32", any(feature = "web-camera", feature = "web-board")),
    derive(tsify::Tsify)
)]
pub struct Candidate {
    /// Where it lies (x, z, cm).
    #[serde(rename = "floor", with = "floor_point")]
    #[cfg_attr(
        all(target_arch = "wasm32", any(feature = "web-camera", feature = "web-board")),
        tsify(type = "FloorPoint")
    )]
    pub floor_cm: DVec2,
    /// Its energy (px; not finite where the body could not be placed).
    pub energy_px: f64,
}

/// Riečický et al.'s search in one video frame (none for `fused`), as the
/// camera module hands it to the page: there it is a `FrameCandidates`, the
/// name the page has always read it by.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(
    all(target_arch = "wasm32", any(feature = "web-camera", feature = "web-board")),
    derive(tsify::Tsify),
    tsify(missing_as_null, rename = "FrameCandidates")
)]
pub struct RiecickyCandidates {
    /// The positions tried; the first is the last frame's position.
    pub tried: Vec<Candidate>,
    /// The index of the one chosen; `null`: none.
    pub chosen: Option<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame's progress has the shape the page reads: its floor a
    /// `FloorPoint` named `floor`, whose unknown fields are refused.
    #[test]
    fn a_frame_s_progress_has_the_page_s_shape() {
        let progress = FrameProgress { frame: 3, floor_cm: DVec2::new(1.5, -2.0), confidence: 0.5 };
        let json = serde_json::to_string(&progress).unwrap();
        assert_eq!(json, r#"{"frame":3,"floor":{"x_cm":1.5,"z_cm":-2.0},"confidence":0.5}"#);
        assert_eq!(serde_json::from_str::<FrameProgress>(&json).unwrap(), progress);
        let misspelt = json.replace("z_cm", "y_cm");
        assert!(serde_json::from_str::<FrameProgress>(&misspelt).is_err(), "{misspelt}");
    }

    /// A frame's candidates have the shape the page reads: each tried one's
    /// floor a `FloorPoint` named `floor` beside its `energy_px`.
    #[test]
    fn a_frame_s_candidates_have_the_page_s_shape() {
        let candidates = RiecickyCandidates {
            tried: vec![Candidate { floor_cm: DVec2::new(1.5, -2.0), energy_px: 4.0 }],
            chosen: Some(0),
        };
        let json = serde_json::to_string(&candidates).unwrap();
        assert_eq!(json, r#"{"tried":[{"floor":{"x_cm":1.5,"z_cm":-2.0},"energy_px":4.0}],"chosen":0}"#);
        assert_eq!(serde_json::from_str::<RiecickyCandidates>(&json).unwrap(), candidates);
        let misspelt = json.replace("z_cm", "y_cm");
        assert!(serde_json::from_str::<RiecickyCandidates>(&misspelt).is_err(), "{misspelt}");
    }
}
