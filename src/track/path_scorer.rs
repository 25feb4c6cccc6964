//! The fused tracker's path energies scored apart from it: a second worker
//! in the page scores the path search's candidates from the same frames,
//! to the last bit what the tracker would have computed. And, for
//! evaluations only, the camera's best near a known truth.

use glam::DVec2;

use crate::error::Error;
use crate::image::GreyImage;
use crate::image::Shrink;
use crate::image::pipeline::Features;
use crate::track::fused::{FrameScoring, FusedParams, line_of_sight};
use crate::track::path::PathRequest;
use crate::track::setup::TrackSetup;
use crate::track::working_scale::{WorkingScales, checked_working_scale, shrunk_frame};

/// Scores [`PathRequest`]s apart from the tracker, from the same frames:
/// what the tracker would have computed, to the last bit. And, for
/// evaluations, the camera's best near a known truth.
pub struct PathScorer {
    /// The take at each working scale a request was made at.
    scales: WorkingScales,
    params: FusedParams,
}

impl PathScorer {
    /// Scores with the fused tracker's `params`.
    pub fn new(setup: TrackSetup, params: FusedParams) -> PathScorer {
        PathScorer { scales: WorkingScales::new(setup), params }
    }

    /// The fused energy (px) at each of `request`'s candidates in `frame`,
    /// video frame `request.frame`; NaN where the body is not in the image.
    pub fn energies(&mut self, request: &PathRequest, frame: &GreyImage) -> Result<Vec<f64>, Error> {
        let label = format!("video frame {}", request.frame);
        let camera = &self.scales.whole().camera;
        camera.check_image_size(frame.width_px, frame.height_px, &label)?;
        let shrink = checked_working_scale(camera, request.working_scale, &label)?;
        let (setup, _) = self.scales.at(shrink);
        let frame = shrunk_frame(frame, shrink);
        let features = setup.features(&frame, request.truncate_px, &label)?;
        self.energies_with(request, &features)
    }

    /// [`PathScorer::energies`] from the frame's `features` as the tracker
    /// made them ([`crate::track::tracker::Tracker::take_path_work`]); an
    /// error when they are not of the request's working scale.
    pub fn energies_with(&mut self, request: &PathRequest, features: &Features) -> Result<Vec<f64>, Error> {
        let label = format!("video frame {}", request.frame);
        let shrink = checked_working_scale(&self.scales.whole().camera, request.working_scale, &label)?;
        let (setup, scorer) = self.scales.at(shrink);
        let size = &features.difference;
        setup.camera.check_image_size(size.width_px, size.height_px, &label)?;
        let Some(body) = setup.posed_body(request.frame)? else {
            return Err(Error::whole(&label, "no pose in the BVH here: no path to score"));
        };
        let mut scoring =
            FrameScoring::new(setup, &self.params, scorer, &body, features, request.terms_at_cm);
        Ok(request.candidates_cm.iter().map(|&p| scoring.energy(p)).collect())
    }

    /// For evaluations only (a tracker knows no `around_cm`): the least of
    /// the fused energy in video frame `i`, tried every 2 cm along the
    /// camera's line of sight through `around_cm` within `reach_cm` of it,
    /// and every 1 cm across within 8 cm — how close the camera alone can
    /// place the body in that frame when the truth is known. `None` where
    /// the BVH has no pose or the body is nowhere in the image.
    pub fn camera_oracle(
        &mut self,
        frame: &GreyImage,
        i: usize,
        around_cm: DVec2,
        reach_cm: f64,
    ) -> Result<Option<DVec2>, Error> {
        let label = format!("video frame {i}");
        let (setup, scorer) = self.scales.at(Shrink::NONE);
        setup.camera.check_image_size(frame.width_px, frame.height_px, &label)?;
        let Some(body) = setup.posed_body(i)? else { return Ok(None) };
        let features = setup.features(frame, setup.pipeline.truncate_px, &label)?;
        let mut scoring = FrameScoring::new(setup, &self.params, scorer, &body, &features, around_cm);
        let along = line_of_sight(&setup.camera, around_cm);
        let steps = (reach_cm / 2.0).ceil() as i32;
        let mut best: Option<(DVec2, f64)> = None;
        for a in -steps..=steps {
            for b in -8..=8 {
                let p = around_cm + along * (2.0 * a as f64) + along.perp() * b as f64;
                let e = scoring.energy(p);
                if e.is_finite() && best.is_none_or(|(_, least)| e < least) {
                    best = Some((p, e));
                }
            }
        }
        Ok(best.map(|(p, _)| p))
    }
}
