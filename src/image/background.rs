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

/// How far (px) the camera may have moved between its still of the room
/// and the video, either way on either axis: a tripod touched, a still
/// taken before the camera settled. Farther is another camera position
/// (the track says the background does not match).
pub const MAX_CAMERA_SHIFT_PX: i32 = 4;

/// Where the room of `background` lies in `frame`: the whole-pixel shift
/// `(dx, dy)`, within [`MAX_CAMERA_SHIFT_PX`], for which background pixel
/// `(x + dx, y + dy)` matches frame pixel `(x, y)` best — the least sum of
/// their absolute differences over every fourth row and column (about
/// [`SHIFT_SAMPLES`] pixels in larger images), each capped at
/// [`SHIFT_COST_CAP_LEVELS`] (so the actor, who differs by tens of levels
/// wherever they are, weighs alike at every shift and the room decides).
/// No shift wins ties: a still taken where the video is stays where it is.
/// `(0, 0)` when the sizes differ. Integer arithmetic.
pub fn camera_shift_px(frame: &GreyImage, background: &GreyImage) -> (i32, i32) {
    if !frame.same_size(background.width_px, background.height_px) {
        return (0, 0);
    }
    let (w, h) = (frame.width_px as usize, frame.height_px as usize);
    let reach = MAX_CAMERA_SHIFT_PX;
    let r = reach as usize;
    if w <= 2 * r || h <= 2 * r {
        return (0, 0); // nothing to compare
    }
    // Every fourth row and column at 640×480; sparser in larger images, so
    // that about as many pixels are compared at any size.
    let mut step = 4usize;
    while (w / step) * (h / step) > SHIFT_SAMPLES {
        step += 1;
    }
    // The samples, gathered once so that every shift reads them in a row:
    // the frame's, row after sampled row; and the background's every row
    // split by column into `step` planes (plane φ holds columns φ, φ +
    // step, …), in one of which the sampled columns moved by any dx are
    // consecutive.
    let columns = (r..w - r).step_by(step).len();
    let mut frame_samples: Vec<u8> = Vec::with_capacity(columns * (h / step + 1));
    for y in (r..h - r).step_by(step) {
        frame_samples.extend(frame.pixels[y * w + r..].iter().step_by(step).take(columns));
    }
    let plane_w = w.div_ceil(step);
    let mut planes = vec![0u8; step * plane_w * h];
    for (y, row) in background.pixels.chunks_exact(w).enumerate() {
        for phase in 0..step {
            let at = (phase * h + y) * plane_w;
            for (to, &b) in planes[at..at + plane_w].iter_mut().zip(row[phase..].iter().step_by(step)) {
                *to = b;
            }
        }
    }
    // The cost of a shift, given up (`None`) once it reaches `bound`: it
    // cannot beat the best so far (only a smaller cost wins).
    let cost_below = |dx: i32, dy: i32, bound: u64| {
        let column = r.checked_add_signed(dx as isize)?;
        let (plane, first) = (column % step, column / step);
        let mut sum = 0u64;
        for (seen, y) in frame_samples.chunks_exact(columns).zip((r..h - r).step_by(step)) {
            let at = (plane * h + y.checked_add_signed(dy as isize)?) * plane_w + first;
            let room = &planes[at..at + columns];
            let row: u32 = seen
                .iter()
                .zip(room)
                .map(|(&f, &b)| u32::from(f.abs_diff(b).min(SHIFT_COST_CAP_LEVELS)))
                .sum();
            sum += u64::from(row);
            if sum >= bound {
                return None;
            }
        }
        Some(sum)
    };
    let mut best = ((0, 0), cost_below(0, 0, u64::MAX).unwrap_or(u64::MAX));
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            if (dx, dy) == (0, 0) {
                continue;
            }
            if let Some(cost) = cost_below(dx, dy, best.1) {
                best = ((dx, dy), cost);
            }
        }
    }
    best.0
}

/// About how many pixels [`camera_shift_px`] compares per shift: every
/// fourth row and column of a 640×480 image.
pub const SHIFT_SAMPLES: usize = 160 * 120;

/// A pixel differing by more than this (grey levels) counts as this much
/// in [`camera_shift_px`]: above a camera's noise and the room's texture
/// misplaced by a pixel, below an actor against the room.
pub const SHIFT_COST_CAP_LEVELS: u8 = 24;

/// `background` moved so that its pixel `(x + dx, y + dy)` is at `(x, y)`
/// (see [`camera_shift_px`]); past its edges, its edge pixels repeated.
pub fn shifted(background: &GreyImage, (dx, dy): (i32, i32)) -> GreyImage {
    let (w, h) = (background.width_px as i32, background.height_px as i32);
    let pixels = (0..h)
        .flat_map(|y| {
            (0..w).map(move |x| {
                let (sx, sy) = ((x + dx).clamp(0, w - 1), (y + dy).clamp(0, h - 1));
                background.pixels[(sy * w + sx) as usize]
            })
        })
        .collect();
    GreyImage { width_px: background.width_px, height_px: background.height_px, pixels }
}

/// How a frame's exposure compares with the background's. A
/// camera's exposure, gain and auto exposure scale every pixel's light
/// alike (and so its encoded value, a power of the light, alike too), so a
/// still taken a moment earlier, or a camera that adapted when the actor
/// walked in, differs from the frame by one factor; left alone, 8 % of it
/// turns the whole room into foreground. First the median of frame ÷
/// background (the actor covers well under half of the image, so it is
/// the room's), then, over the pixels that factor explains within
/// [`EXPOSURE_MATCH_LEVELS`], the ratio of their sums: the median's
/// quantised ratios refined by tens of thousands of pixels. Pixels too
/// dark to give a ratio (below 32) or clipped (255) are left out, and every
/// other row and column is enough. [`Exposure::SAME`] when fewer than 1 %
/// of the pixels can be used or the sizes differ. Integer arithmetic: the
/// same in the CLI and the browser.
pub fn exposure(frame: &GreyImage, background: &GreyImage) -> Exposure {
    const TOP: usize = 1024;
    if !frame.same_size(background.width_px, background.height_px) {
        return Exposure::SAME;
    }
    let w = frame.width_px as usize;
    let usable = |i: usize| {
        let (f, b) = (u32::from(frame.pixels[i]), u32::from(background.pixels[i]));
        ((32..255).contains(&b) && f < 255).then_some((f, b))
    };
    let sampled = || {
        (0..frame.height_px as usize)
            .step_by(2)
            .flat_map(move |y| (0..w).step_by(2).map(move |x| y * w + x))
            .filter_map(usable)
    };
    let mut histogram = vec![0u32; TOP];
    let mut count = 0usize;
    for (f, b) in sampled() {
        histogram[(((f * 256 + b / 2) / b) as usize).min(TOP - 1)] += 1;
        count += 1;
    }
    if count * 100 < frame.pixels.len() / 4 {
        return Exposure::SAME;
    }
    let mut below = 0usize;
    let median_256 = histogram
        .iter()
        .position(|&n| {
            below += n as usize;
            2 * below >= count
        })
        .unwrap_or(256) as u64;
    let (mut sum_f, mut sum_b, mut kept) = (0u64, 0u64, 0u64);
    for (f, b) in sampled() {
        let predicted_256 = u64::from(b) * median_256;
        if u64::from(f) * 256 + EXPOSURE_MATCH_LEVELS * 256 >= predicted_256
            && u64::from(f) * 256 <= predicted_256 + EXPOSURE_MATCH_LEVELS * 256
        {
            sum_f += u64::from(f);
            sum_b += u64::from(b);
            kept += 1;
        }
    }
    if kept == 0 {
        return Exposure::SAME;
    }
    Exposure {
        ratio_4096: ((sum_f * 4096 + sum_b / 2) / sum_b).min(u64::from(u32::MAX)) as u32,
        room_level: (sum_b / kept) as u32,
    }
}

/// A frame's exposure against the background's ([`exposure`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Exposure {
    /// The frame's light over the background's, in 4096ths.
    pub ratio_4096: u32,
    /// The mean grey level of the room's pixels it was measured on.
    pub room_level: u32,
}

impl Exposure {
    /// No change.
    pub const SAME: Exposure = Exposure { ratio_4096: 4096, room_level: 0 };

    /// How far (grey levels) the exposure moves the room's mean level.
    pub fn shift_levels(&self) -> f32 {
        (self.ratio_4096.abs_diff(4096) as f32) * (self.room_level as f32) / 4096.0
    }
}

/// `|frame − background|`, the background first moved by the camera's
/// shift since the still ([`camera_shift_px`]) and brought to the frame's
/// exposure ([`exposure`]) where the two differ by more than the noise: a
/// shift within the sensor's own noise is the noise, which the threshold is
/// set from; beyond it (a still taken at another exposure) the room would
/// turn to foreground. An error for `label` when the sizes differ.
pub fn matched_difference(
    frame: &GreyImage,
    background: &GreyImage,
    label: &str,
) -> Result<GreyImage, Error> {
    let shift = camera_shift_px(frame, background);
    let moved;
    let background = if shift == (0, 0) {
        background
    } else {
        moved = shifted(background, shift);
        &moved
    };
    let raw = difference(frame, background, label)?;
    let exposure = exposure(frame, background);
    let mut chosen = if exposure.ratio_4096 == 4096 {
        raw
    } else {
        let matched = difference(frame, &exposed(background, exposure.ratio_4096), label)?;
        if exposure.shift_levels() <= noise_sd(&matched) { raw } else { matched }
    };
    if shift != (0, 0) {
        blank_unseen(&mut chosen, shift);
    }
    Ok(chosen)
}

/// `difference` zeroed along the edges that a still moved by `shift` (see
/// [`shifted`]) does not show: those strips say nothing.
fn blank_unseen(difference: &mut GreyImage, (dx, dy): (i32, i32)) {
    let (w, h) = (difference.width_px as i32, difference.height_px as i32);
    for y in 0..h {
        for x in 0..w {
            if !(0..w).contains(&(x + dx)) || !(0..h).contains(&(y + dy)) {
                difference.pixels[(y * w + x) as usize] = 0;
            }
        }
    }
}

/// A pixel within this many grey levels of the background at the median's
/// exposure is the room (the noise of a camera and its codec, 1–4 levels,
/// three times over); farther, it is the actor or their shadow.
pub const EXPOSURE_MATCH_LEVELS: u64 = 8;

/// `background` as the camera would have seen it at `ratio_4096` / 4096 of
/// its exposure (see [`exposure`]), clipped at 255.
pub fn exposed(background: &GreyImage, ratio_4096: u32) -> GreyImage {
    let pixels = background
        .pixels
        .iter()
        .map(|&b| ((u64::from(b) * u64::from(ratio_4096) + 2048) >> 12).min(255) as u8)
        .collect();
    GreyImage { width_px: background.width_px, height_px: background.height_px, pixels }
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
            Threshold::FromNoise { .. } => self.level_at(noise_sd(difference)),
        }
    }

    /// The grey level for a difference image whose noise (see [`noise_sd`])
    /// is `noise_sd`, already measured.
    pub fn level_at(&self, noise_sd: f32) -> u8 {
        match *self {
            Threshold::Level(level) => level,
            Threshold::FromNoise { noise_sds, min_level } => {
                let level = libm::ceilf(noise_sds * noise_sd);
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
    fn a_frame_exposed_otherwise_is_matched_by_one_factor() {
        // A textured room of 40..=240, seen 10 % brighter, an actor of 0
        // over a third.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let room: Vec<u8> = (0..3000)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (40 + state % 201) as u8
            })
            .collect();
        let background = GreyImage::new(100, 30, room.clone(), "b").unwrap();
        let mut pixels: Vec<u8> = room.iter().map(|&b| ((b as f64 * 1.1).round().min(255.0)) as u8).collect();
        for p in pixels.iter_mut().take(1000) {
            *p = 0;
        }
        let frame = GreyImage::new(100, 30, pixels, "f").unwrap();
        let ratio = exposure(&frame, &background).ratio_4096;
        assert!((4480..=4530).contains(&ratio), "{ratio}");
        let matched = exposed(&background, ratio);
        let d = difference(&frame, &matched, "f").unwrap();
        // The room matches within a level or two (the clipped top aside).
        let room_off =
            d.pixels[1000..].iter().zip(&frame.pixels[1000..]).filter(|(d, f)| **f < 255 && **d > 2);
        assert_eq!(room_off.count(), 0);
        // The same exposure is no change at all.
        assert_eq!(exposure(&background, &background).ratio_4096, 4096);
        assert_eq!(matched_difference(&frame, &background, "f").unwrap(), d);
        // The same exposure through a sensor's noise (±3 levels): whatever
        // ratio the noise suggests is within it, and left to the threshold.
        let slightly: Vec<u8> = room
            .iter()
            .map(|&b| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (b as i64 + (state % 7) as i64 - 3) as u8
            })
            .collect();
        let slightly = GreyImage::new(100, 30, slightly, "s").unwrap();
        assert_eq!(
            matched_difference(&slightly, &background, "s").unwrap(),
            difference(&slightly, &background, "s").unwrap()
        );
        assert_eq!(exposed(&background, 4096), background);
    }

    #[test]
    fn a_camera_moved_since_its_still_is_found_by_its_shift() {
        // A room of diagonal stripes and squares; the frame sees it 3 px
        // right and 2 px down, with an actor over a fifth of it.
        let (w, h) = (80u32, 60u32);
        let room = |x: i32, y: i32| (60 + ((x / 3 + y / 5) % 4) * 40 + ((x * 7 + y * 13) % 11)) as u8;
        let background = GreyImage::new(
            w,
            h,
            (0..h as i32).flat_map(|y| (0..w as i32).map(move |x| room(x, y))).collect(),
            "b",
        )
        .unwrap();
        let mut frame: Vec<u8> =
            (0..h as i32).flat_map(|y| (0..w as i32).map(move |x| room(x - 3, y - 2))).collect();
        for y in 10..40 {
            for x in 30..50 {
                frame[y * w as usize + x] = 10;
            }
        }
        let frame = GreyImage::new(w, h, frame, "f").unwrap();
        assert_eq!(camera_shift_px(&frame, &background), (-3, -2));
        let moved = shifted(&background, (-3, -2));
        assert_eq!(moved.pixels[(20 * w + 60) as usize], room(57, 18));
        assert_eq!(camera_shift_px(&background, &background), (0, 0));
        // A portrait 1080×1920 room of 3-px blocks, sampled sparser.
        let block = |x: i32, y: i32| {
            let mut v =
                ((x.div_euclid(3) as u64) << 32 | y.div_euclid(3) as u32 as u64) ^ 0x9e37_79b9_7f4a_7c15;
            v ^= v << 13;
            v ^= v >> 7;
            v ^= v << 17;
            (40 + v % 180) as u8
        };
        let image = |dx: i32, dy: i32| {
            let pixels = (0..1920).flat_map(|y| (0..1080).map(move |x| block(x - dx, y - dy))).collect();
            GreyImage::new(1080, 1920, pixels, "portrait").unwrap()
        };
        assert_eq!(camera_shift_px(&image(2, -4), &image(0, 0)), (-2, 4));
        // Where the room matches once moved, it is no foreground.
        let d = matched_difference(&frame, &background, "f").unwrap();
        let off = (10..h as usize).flat_map(|y| (10..w as usize).map(move |x| (x, y)));
        let room_left = off.filter(|&(x, y)| !(30..50).contains(&x) || !(10..40).contains(&y));
        assert!(room_left.map(|(x, y)| d.pixels[y * w as usize + x]).all(|v| v == 0));
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
