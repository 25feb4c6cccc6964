//! A frame worked on at the scale the measurement needs: a body 1000 px
//! tall in a 2-megapixel frame is placed as well from a frame shrunk five
//! times each way, at a twenty-fifth of the cost of every stage that
//! scales with its pixels (the background subtraction, Canny, the distance
//! transforms, each silhouette tried). The tracker chooses how much a
//! frame is shrunk (a [`Shrink`], in half steps) from the body's predicted
//! distance before reading it
//! ([`working_scale`]); the frame, the background and the camera are
//! shrunk together ([`crate::image::GreyImage::shrunk`],
//! [`crate::camera::Camera::shrunk`]), so everything after them is in the
//! smaller image's pixels and the positions on the floor in centimetres as
//! before. The energies, and the settings given in pixels (the opening's,
//! Canny's, the match precision), are then in working pixels: no larger
//! than a centimetre at the body, about what a 640×480 take has. The noise
//! measured on a shrunk difference is lower, as the averaged sensor noise
//! is.

use crate::camera::Camera;
use crate::error::Error;
use crate::image::{GreyImage, Shrink};
use crate::track::energy::Scorer;
use crate::track::setup::TrackSetup;

/// The coarsest pixel (cm at the body) a frame is worked on at. The body
/// model's girths and the suit's limb angles are off by a centimetre or
/// two, so a finer pixel measures the model, not where the body stands;
/// and a pixel of 1 cm still leaves a body 170 px tall, its contour
/// hundreds of pixels long (the shared 640×480 scenes put a pixel at
/// 0.5–1.2 cm at the body: read whole where it is over ⅔ cm).
pub const WORKING_PIXEL_CM: f64 = 1.0;

/// The steps of the working scale, in quarters: halves (1, 1.5, 2, 2.5, …
/// times each way). Whole steps leave a working pixel anywhere from a half
/// to a whole [`WORKING_PIXEL_CM`] (a 1440×1080 take's far body read at
/// 0.5 cm, at five times the pixels of a 640×480 take's at 1.2); finer
/// steps change the factor, and so the pixel grid under the body, more
/// often as it comes nearer, each change moving where its edges fall by
/// up to half a pixel.
const STEP_QUARTERS: u32 = 2;

/// A working image is never shrunk below this many pixels either way: the
/// search's margins and the soles' windows want room around the body.
pub const MIN_WORKING_SIDE_PX: u32 = 160;

/// How much a frame of `camera` is shrunk before it is read when the body
/// is `depth_cm` from the camera: as much, in quarters
/// ([`Shrink`]), as keeps a working pixel within [`WORKING_PIXEL_CM`] at
/// the body and each side at least [`MIN_WORKING_SIDE_PX`]. A body 1000 px
/// tall in a 1080×1920 frame is read at 5.5 times less each way (no side
/// under 160 px); one 200 px tall is read whole.
pub fn working_scale(camera: &Camera, depth_cm: f64) -> Shrink {
    let pixel_cm = depth_cm / camera.intrinsics.fx_px.max(camera.intrinsics.fy_px);
    let by_pixel = (4.0 * WORKING_PIXEL_CM / pixel_cm / STEP_QUARTERS as f64).floor() * STEP_QUARTERS as f64;
    let size = camera.image_size;
    let by_side = 4 * size.width_px.min(size.height_px) / MIN_WORKING_SIDE_PX / STEP_QUARTERS * STEP_QUARTERS;
    if by_pixel.is_finite() && by_pixel >= 4.0 {
        Shrink::from_quarters(by_pixel.min(by_side as f64) as u32).unwrap_or(Shrink::NONE)
    } else {
        Shrink::NONE
    }
}

/// `shrink` when it leaves each side of `camera`'s images at least
/// [`MIN_WORKING_SIDE_PX`] (or keeps them whole), as every
/// [`working_scale`] does; an error for `label` otherwise (a request from
/// elsewhere — the page's second worker — is checked before anything is
/// shrunk by it).
pub fn checked_working_scale(camera: &Camera, shrink: Shrink, label: &str) -> Result<Shrink, Error> {
    let side = camera.image_size.width_px.min(camera.image_size.height_px);
    if shrink.is_none() || shrink.length_px(side) >= MIN_WORKING_SIDE_PX {
        return Ok(shrink);
    }
    Err(Error::whole(
        label,
        format!(
            "a working scale of {} quarters for a {side} px side (4, or one leaving {MIN_WORKING_SIDE_PX} px)",
            shrink.quarters()
        ),
    ))
}

/// The take at each working scale a frame has asked for, each with a
/// scorer for its camera: made the first time, then kept (a take uses a
/// few).
pub struct WorkingScales {
    scales: Vec<(Shrink, TrackSetup, Scorer)>,
}

impl WorkingScales {
    /// The take at `setup`'s own scale only, for now.
    pub fn new(setup: TrackSetup) -> WorkingScales {
        let scorer = Scorer::new(&setup.camera);
        WorkingScales { scales: vec![(Shrink::NONE, setup, scorer)] }
    }

    /// The take as given, read whole.
    pub fn whole(&self) -> &TrackSetup {
        &self.scales[0].1
    }

    /// The take shrunk by `shrink` and its scorer.
    pub fn at(&mut self, shrink: Shrink) -> (&TrackSetup, &mut Scorer) {
        let k = match self.scales.iter().position(|(s, _, _)| *s == shrink) {
            Some(k) => k,
            None => {
                let setup = self.scales[0].1.shrunk(shrink);
                let scorer = Scorer::new(&setup.camera);
                self.scales.push((shrink, setup, scorer));
                self.scales.len() - 1
            }
        };
        let (_, setup, scorer) = &mut self.scales[k];
        (setup, scorer)
    }
}

/// `frame` shrunk by `shrink`, borrowed when it is none.
pub fn shrunk_frame(frame: &GreyImage, shrink: Shrink) -> std::borrow::Cow<'_, GreyImage> {
    if shrink.is_none() {
        std::borrow::Cow::Borrowed(frame)
    } else {
        std::borrow::Cow::Owned(frame.shrunk(shrink))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_shrunk_as_far_as_a_pixel_stays_within_a_centimetre_at_the_body() {
        let quarters = |camera: &Camera, depth_cm| working_scale(camera, depth_cm).quarters();
        // 640×480 at 500 px: a pixel is 1.2 cm at 6 m, read whole.
        assert_eq!(quarters(&Camera::at_origin(640, 480, 500.0), 600.0), 4);
        // The same camera at 1440×1080: 0.36 cm at 4 m, read at 2.5 times
        // less (a pixel of 0.89 cm; 2.75 would be 0.98, but the steps are
        // halves).
        assert_eq!(quarters(&Camera::at_origin(1440, 1080, 1125.0), 400.0), 10);
        // A portrait phone at 1.5 m: 0.1 cm, but no side under 160 px
        // (1080 / 6.5 = 166).
        assert_eq!(quarters(&Camera::at_origin(1080, 1920, 1500.0), 150.0), 26);
        assert_eq!(quarters(&Camera::at_origin(1080, 1920, 1500.0), 50.0), 26);
        // Far away, or no depth at all: whole.
        assert_eq!(working_scale(&Camera::at_origin(1440, 1080, 1125.0), 5000.0), Shrink::NONE);
        assert_eq!(working_scale(&Camera::at_origin(1440, 1080, 1125.0), f64::NAN), Shrink::NONE);
    }

    #[test]
    fn a_working_scale_from_elsewhere_is_checked_against_the_camera() {
        let portrait = Camera::at_origin(1080, 1920, 1500.0);
        let shrink = |quarters| Shrink::from_quarters(quarters).unwrap();
        assert_eq!(checked_working_scale(&portrait, Shrink::NONE, "frame 3").unwrap(), Shrink::NONE);
        assert_eq!(checked_working_scale(&portrait, shrink(26), "frame 3").unwrap(), shrink(26));
        for wrong in [28, 1024] {
            let said =
                checked_working_scale(&portrait, shrink(wrong), "video frame 3").unwrap_err().to_string();
            assert!(said.contains("video frame 3") && said.contains(&format!("{wrong}")), "{said}");
        }
    }
}
