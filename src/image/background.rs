//! What differs from the empty room: the absolute difference to a
//! background, the background itself when there is no still of it (the
//! per-pixel median of frames), and the threshold that tells the actor from
//! the sensor's noise, measured on the difference image itself.

use crate::error::Error;
use crate::image::{GreyImage, Mask};

/// `|frame − background|` per pixel; an error for `label` (the frame's
/// name) when the two differ in size.
pub fn difference(frame: &GreyImage, background: &GreyImage, label: &str) -> Result<GreyImage, Error> {
    if !frame.same_size(background.width_px, background.height_px) {
        return Err(Error::whole(
            label,
            format!(
                "a frame of {}×{} pixels against a background of {}×{}",
                frame.width_px, frame.height_px, background.width_px, background.height_px
            ),
        ));
    }
    let pixels = frame.pixels.iter().zip(&background.pixels).map(|(&f, &b)| f.abs_diff(b)).collect();
    Ok(GreyImage { width_px: frame.width_px, height_px: frame.height_px, pixels })
}

/// How many frames, spread over a video, its median background is taken of
/// when there is no still of the empty room: an odd count, plenty for a
/// median (see [`median_background`]).
pub const MEDIAN_FRAMES: usize = 31;

/// The indices of `count` frames (at least 1, at most `frame_count`) spread
/// evenly over a video of `frame_count` frames, from the first to the last,
/// in order: the frames a median background is taken of.
pub fn sample_indices(frame_count: usize, count: usize) -> Vec<usize> {
    let count = count.clamp(1, frame_count.max(1));
    (0..count).map(|k| if count == 1 { 0 } else { k * (frame_count - 1) / (count - 1) }).collect()
}

/// The per-pixel median of `frames` (the lower median of an even count): the
/// empty room, wherever the actor stood on fewer than half of them. Frames
/// spread over the whole video (see `io::video::sample_frames`) see each
/// spot of the floor free most of the time unless the actor stays put; an
/// odd count of 15–31 is plenty. An error for `label` when there are no
/// frames or their sizes differ.
pub fn median_background(frames: &[GreyImage], label: &str) -> Result<GreyImage, Error> {
    let Some(first) = frames.first() else {
        return Err(Error::whole(label, "no frames to take a median background of"));
    };
    if let Some((i, other)) =
        frames.iter().enumerate().find(|(_, f)| !f.same_size(first.width_px, first.height_px))
    {
        return Err(Error::whole(
            label,
            format!(
                "frame {i} of the median is {}×{} pixels, frame 0 {}×{}",
                other.width_px, other.height_px, first.width_px, first.height_px
            ),
        ));
    }
    let middle = (frames.len() - 1) / 2;
    let mut values = vec![0u8; frames.len()];
    let pixels = (0..first.pixels.len())
        .map(|p| {
            for (value, frame) in values.iter_mut().zip(frames) {
                *value = frame.pixels[p];
            }
            *values.select_nth_unstable(middle).1
        })
        .collect();
    Ok(GreyImage { width_px: first.width_px, height_px: first.height_px, pixels })
}

/// The standard deviation (grey levels) of the noise in a difference image,
/// measured robustly so that the actor (and anything else that moved) does
/// not count: first `1.4826 × median(|d|)`, the median absolute deviation of
/// a Gaussian noise about its zero mean; then, a few rounds, the same from
/// the pixels within 3 σ only (`1.4873 ×` their median, the factor of a
/// half-normal cut at 3 σ), which leaves out an actor covering even a third
/// of the image. Medians are read from the histogram with each level `v`
/// spread over `[v − ½, v + ½)` (level 0 over `[0, ½)`), so that a noise of
/// 1–2 levels is measured and not rounded to a whole level.
pub fn noise_sd(difference: &GreyImage) -> f32 {
    // Every other pixel of every other row: a quarter of the pixels (tens of
    // thousands in any video) measure a noise level as well as all of them.
    let mut histogram = [0u64; 256];
    let w = difference.width_px as usize;
    for row in difference.pixels.chunks_exact(w).step_by(2) {
        for &d in row.iter().step_by(2) {
            histogram[d as usize] += 1;
        }
    }
    let mut sd = 1.4826 * histogram_median(&histogram, 255);
    for _ in 0..8 {
        let within = libm::floor(3.0 * sd).clamp(1.0, 255.0) as usize;
        let next = 1.4873 * histogram_median(&histogram, within);
        if next == sd {
            break;
        }
        sd = next;
    }
    sd as f32
}

/// The median of the values `0..=top` counted in `histogram`, interpolated
/// within its level; 0 when there are none.
fn histogram_median(histogram: &[u64; 256], top: usize) -> f64 {
    let levels = &histogram[..=top.min(255)];
    let half = levels.iter().sum::<u64>() as f64 / 2.0;
    let mut below = 0.0;
    for (level, &count) in levels.iter().enumerate() {
        let count = count as f64;
        if count > 0.0 && below + count >= half {
            let (start, width) = if level == 0 { (0.0, 0.5) } else { (level as f64 - 0.5, 1.0) };
            return start + width * (half - below) / count;
        }
        below += count;
    }
    0.0
}

/// How the foreground threshold is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Threshold {
    /// `noise_sds × noise_sd(difference)`, never below `min_level`: a pixel
    /// is foreground when it differs from the background by more than the
    /// noise of that very image plausibly does.
    FromNoise { noise_sds: f32, min_level: u8 },
    /// A fixed grey level.
    Level(u8),
}

impl Default for Threshold {
    /// 4 σ of the noise: a Gaussian exceeds it on 6 pixels in 100 000 (about
    /// 20 specks in a 640×480 frame, which one Canny pass and the chamfer
    /// energy shrug off), while an actor against a room differs by tens of
    /// levels. At least 6 levels, so a noiseless (synthetic or heavily
    /// compressed) image does not turn the slightest shading into foreground.
    fn default() -> Self {
        Threshold::FromNoise { noise_sds: 4.0, min_level: 6 }
    }
}

impl Threshold {
    /// The grey level for this difference image: a pixel whose difference
    /// is above it is foreground.
    pub fn level(&self, difference: &GreyImage) -> u8 {
        match *self {
            Threshold::Level(level) => level,
            Threshold::FromNoise { noise_sds, min_level } => {
                let level = libm::ceilf(noise_sds * noise_sd(difference));
                (level.clamp(0.0, 254.0) as u8).max(min_level)
            }
        }
    }
}

/// The pixels whose difference is above `level`.
pub fn foreground(difference: &GreyImage, level: u8) -> Mask {
    Mask {
        width_px: difference.width_px,
        height_px: difference.height_px,
        on: difference.pixels.iter().map(|&d| d > level).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_difference_is_absolute_and_sizes_must_match() {
        let a = GreyImage::new(3, 1, vec![10, 200, 5], "a").unwrap();
        let b = GreyImage::new(3, 1, vec![20, 100, 5], "b").unwrap();
        assert_eq!(difference(&a, &b, "f").unwrap().pixels, vec![10, 100, 0]);
        let e = difference(&a, &GreyImage::filled(1, 3, 0), "frame 4").unwrap_err();
        assert_eq!(e.to_string(), "frame 4: a frame of 3×1 pixels against a background of 1×3");
    }

    #[test]
    fn the_median_ignores_what_passes_by() {
        let frames: Vec<GreyImage> = [[9, 50], [9, 51], [200, 52], [9, 250], [7, 49]]
            .iter()
            .map(|p| GreyImage::new(2, 1, p.to_vec(), "f").unwrap())
            .collect();
        assert_eq!(median_background(&frames, "v").unwrap().pixels, vec![9, 51]);
        assert_eq!(median_background(&frames[..2], "v").unwrap().pixels, vec![9, 50], "the lower median");
        assert!(median_background(&[], "v").is_err());
        let mixed = [frames[0].clone(), GreyImage::filled(1, 2, 0)];
        assert!(median_background(&mixed, "v").unwrap_err().to_string().contains("frame 1"));
    }

    #[test]
    fn the_noise_is_measured_below_a_level_and_ignores_the_actor() {
        // |N(0, 2)| quantised, as a histogram of a difference image: 2σ ≈ 4.
        let sd = 2.0f64;
        let mut pixels = Vec::new();
        for level in 0..20u8 {
            let p = |x: f64| libm::erf(x / (sd * std::f64::consts::SQRT_2));
            let share = if level == 0 { p(0.5) } else { p(level as f64 + 0.5) - p(level as f64 - 0.5) };
            pixels.extend(std::iter::repeat_n(level, (share * 100_000.0).round() as usize));
        }
        // An actor over a third of the image, far above the noise.
        let noise_only = pixels.len();
        pixels.extend(std::iter::repeat_n(90u8, noise_only / 2));
        let image = GreyImage::new(pixels.len() as u32, 1, pixels, "d").unwrap();
        let measured = noise_sd(&image);
        assert!((measured - 2.0).abs() < 0.1, "{measured}");
        assert_eq!(Threshold::default().level(&image), (4.0 * measured).ceil() as u8);
        assert_eq!(Threshold::default().level(&GreyImage::filled(4, 4, 0)), 6, "never below the floor");
        assert_eq!(Threshold::Level(30).level(&image), 30);
    }
}
