//! What a tracker needs of a take besides its frames, whichever tracker it
//! is: the camera, the suit's motion, the body model, the video's timing
//! and the empty room; and the one way a video frame becomes the features
//! the trackers match a body against.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::body::shape::{BodyShape, PosedBody};
use crate::camera::Camera;
use crate::error::Error;
use crate::image::pipeline::{Features, PipelineParams, features};
use crate::image::{GreyImage, Shrink};
use crate::track::suit_motion::{SuitMotion, VideoTiming};

/// `shape` in `suit`'s pose at video frame `i` (its time through `timing`),
/// standing at the floor's origin; `None` where the BVH has no pose.
pub fn posed_body(
    suit: &SuitMotion,
    shape: &BodyShape,
    timing: &VideoTiming,
    i: usize,
) -> Result<Option<PosedBody>, Error> {
    let instant = suit.instant(timing.bvh_time_s(i));
    suit.body_at(instant).map(|body_cm| shape.pose(&body_cm, DVec3::ZERO)).transpose()
}

/// What the tracker needs besides the frames.
#[derive(Clone, Debug)]
pub struct TrackSetup {
    pub camera: Camera,
    /// Shared with the same take at its other working scales
    /// ([`TrackSetup::shrunk`]).
    pub suit: Arc<SuitMotion>,
    pub shape: BodyShape,
    pub timing: VideoTiming,
    pub background: GreyImage,
    pub pipeline: PipelineParams,
}

impl TrackSetup {
    /// The body model in the suit's pose at video frame `i` (its time
    /// through `timing`), standing at the floor's origin; `None` where the
    /// BVH has no pose.
    pub fn posed_body(&self, i: usize) -> Result<Option<PosedBody>, Error> {
        posed_body(&self.suit, &self.shape, &self.timing, i)
    }

    /// `frame`'s features against the background, its distance transforms
    /// capped at `truncate_px` (`None`: exact everywhere); an error naming
    /// `label` when its size is not the camera's. Every tracker computes a
    /// frame's features here, once, and hands them down.
    pub fn features(
        &self,
        frame: &GreyImage,
        truncate_px: Option<f32>,
        label: &str,
    ) -> Result<Features, Error> {
        self.camera.check_image_size(frame.width_px, frame.height_px, label)?;
        let params = PipelineParams { truncate_px, ..self.pipeline };
        features(frame, &self.background, &params, label)
    }

    /// The same take worked on at a working scale
    /// ([`crate::track::working_scale::working_scale`]): its camera
    /// and its background shrunk by `shrink`
    /// ([`Camera::shrunk`], [`GreyImage::shrunk`]), for frames shrunk as
    /// much. [`Shrink::NONE`] is a copy.
    pub fn shrunk(&self, shrink: Shrink) -> TrackSetup {
        TrackSetup {
            camera: self.camera.shrunk(shrink),
            background: self.background.shrunk(shrink),
            ..self.clone()
        }
    }

    /// `frame`'s features as Riečický et al. make them: the still
    /// subtracted as it is, wherever and however exposed it was taken.
    pub fn published_features(&self, frame: &GreyImage, label: &str) -> Result<Features, Error> {
        self.camera.check_image_size(frame.width_px, frame.height_px, label)?;
        let params = PipelineParams { match_still: false, ..self.pipeline };
        features(frame, &self.background, &params, label)
    }
}

/// What a tracker makes of one video frame, before smoothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameEstimate {
    /// Where the hips are on the floor (x, z, cm).
    pub floor_cm: DVec2,
    /// How well the camera saw the body, 0 to 1 (0 where it was not used).
    pub confidence: f64,
    /// The camera's own measurement, where one was used.
    pub measured_cm: Option<DVec2>,
}
