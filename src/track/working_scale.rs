//! A frame worked on at the scale the measurement needs: a body 1000 px
//! tall in a 2-megapixel frame is placed as well from a frame shrunk five
//! times each way, at a twenty-fifth of the cost of every stage that
//! scales with its pixels (the background subtraction, Canny, the distance
//! transforms, each silhouette tried). The tracker chooses a frame's
//! factor from the body's predicted distance before reading it
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
use crate::image::GreyImage;
use crate::track::energy::Scorer;
use crate::track::setup::TrackSetup;

/// The coarsest pixel (cm at the body) a frame is worked on at. The body
/// model's girths and the suit's limb angles are off by a centimetre or
/// two, so a finer pixel measures the model, not where the body stands;
/// and a pixel of 1 cm still leaves a body 170 px tall, its contour
/// hundreds of pixels long (the shared 640×480 scenes put a pixel at
/// 0.5–1.2 cm at the body: they are read whole).
pub const WORKING_PIXEL_CM: f64 = 1.0;

/// A working image is never shrunk below this many pixels either way: the
/// search's margins and the soles' windows want room around the body.
pub const MIN_WORKING_SIDE_PX: u32 = 160;

/// How many times each way a frame of `camera` is shrunk before it is read
/// (1: whole) when the body is `depth_cm` from the camera: as many as keep
/// a working pixel within [`WORKING_PIXEL_CM`] at the body, and each side
/// at least [`MIN_WORKING_SIDE_PX`]. A body 1000 px tall in a 1080×1920
/// frame is read at a fifth of it; one 200 px tall is read whole.
pub fn working_scale(camera: &Camera, depth_cm: f64) -> u32 {
    let pixel_cm = depth_cm / camera.intrinsics.fx_px.max(camera.intrinsics.fy_px);
    let by_pixel = (WORKING_PIXEL_CM / pixel_cm).floor();
    let size = camera.image_size;
    let by_side = size.width_px.min(size.height_px) / MIN_WORKING_SIDE_PX;
    if by_pixel.is_finite() && by_pixel >= 1.0 { (by_pixel.min(by_side as f64) as u32).max(1) } else { 1 }
}

/// `factor` when it is one [`working_scale`] can give for `camera`: 1, or
/// one that leaves each side at least [`MIN_WORKING_SIDE_PX`]; an error for
/// `label` otherwise (a request from elsewhere — the page's second worker —
/// is checked before anything is shrunk by it).
pub fn checked_working_scale(camera: &Camera, factor: u32, label: &str) -> Result<u32, Error> {
    let side = camera.image_size.width_px.min(camera.image_size.height_px);
    if factor == 1 || (factor > 1 && side / factor >= MIN_WORKING_SIDE_PX) {
        return Ok(factor);
    }
    Err(Error::whole(
        label,
        format!(
            "a working scale of {factor} for a {side} px side (1, or one leaving {MIN_WORKING_SIDE_PX} px)"
        ),
    ))
}

/// The take at each working scale a frame has asked for, each with a
/// scorer for its camera: made the first time, then kept (a take uses a
/// few).
pub struct WorkingScales {
    scales: Vec<(u32, TrackSetup, Scorer)>,
}

impl WorkingScales {
    /// The take at `setup`'s own scale only, for now.
    pub fn new(setup: TrackSetup) -> WorkingScales {
        let scorer = Scorer::new(&setup.camera);
        WorkingScales { scales: vec![(1, setup, scorer)] }
    }

    /// The take as given, read whole.
    pub fn whole(&self) -> &TrackSetup {
        &self.scales[0].1
    }

    /// The take at `factor` and its scorer.
    pub fn at(&mut self, factor: u32) -> (&TrackSetup, &mut Scorer) {
        let factor = factor.max(1);
        let k = match self.scales.iter().position(|(f, _, _)| *f == factor) {
            Some(k) => k,
            None => {
                let setup = self.scales[0].1.shrunk(factor);
                let scorer = Scorer::new(&setup.camera);
                self.scales.push((factor, setup, scorer));
                self.scales.len() - 1
            }
        };
        let (_, setup, scorer) = &mut self.scales[k];
        (setup, scorer)
    }
}

/// `frame` shrunk `factor` times each way, borrowed as it is at 1.
pub fn shrunk_frame(frame: &GreyImage, factor: u32) -> std::borrow::Cow<'_, GreyImage> {
    if factor <= 1 {
        std::borrow::Cow::Borrowed(frame)
    } else {
        std::borrow::Cow::Owned(frame.shrunk(factor))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Distortion, ImageSize, Intrinsics};
    use glam::DAffine3;

    fn camera(width_px: u32, height_px: u32, f_px: f64) -> Camera {
        Camera {
            image_size: ImageSize { width_px, height_px },
            intrinsics: Intrinsics {
                fx_px: f_px,
                fy_px: f_px,
                cx_px: width_px as f64 / 2.0,
                cy_px: height_px as f64 / 2.0,
            },
            distortion: Distortion::default(),
            camera_from_world: DAffine3::IDENTITY,
        }
    }

    #[test]
    fn a_frame_is_shrunk_as_far_as_a_pixel_stays_within_a_centimetre_at_the_body() {
        // 640×480 at 500 px: a pixel is 0.8 cm at 4 m, read whole.
        assert_eq!(working_scale(&camera(640, 480, 500.0), 400.0), 1);
        // The same camera at 1440×1080: 0.36 cm, read at half.
        assert_eq!(working_scale(&camera(1440, 1080, 1125.0), 400.0), 2);
        // A portrait phone at 1.5 m: 0.1 cm, but no side under 160 px.
        assert_eq!(working_scale(&camera(1080, 1920, 1500.0), 150.0), 6);
        assert_eq!(working_scale(&camera(1080, 1920, 1500.0), 50.0), 6);
        // Far away, or no depth at all: whole.
        assert_eq!(working_scale(&camera(1440, 1080, 1125.0), 5000.0), 1);
        assert_eq!(working_scale(&camera(1440, 1080, 1125.0), f64::NAN), 1);
    }

    #[test]
    fn a_working_scale_from_elsewhere_is_checked_against_the_camera() {
        let portrait = camera(1080, 1920, 1500.0);
        assert_eq!(checked_working_scale(&portrait, 1, "frame 3").unwrap(), 1);
        assert_eq!(checked_working_scale(&portrait, 6, "frame 3").unwrap(), 6);
        for wrong in [0, 7, 4000] {
            let said = checked_working_scale(&portrait, wrong, "video frame 3").unwrap_err().to_string();
            assert!(said.contains("video frame 3") && said.contains(&format!("{wrong}")), "{said}");
        }
    }
}
