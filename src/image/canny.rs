//! Canny's edge detector (1986) in integer arithmetic: Gaussian smoothing,
//! Sobel gradients, thinning to the gradient's ridge (non-maximum
//! suppression), and hysteresis between two thresholds.
//!
//! The thresholds are **step heights in grey levels**: an ideal straight
//! step of `high` levels between two flat regions is just an edge, one of
//! `low` levels just continues one. They are turned into gradient units
//! through the exact response of this smoothing and Sobel to such a step, so
//! that they keep their meaning whatever `sigma_px` is.

use crate::image::grey::PixelBox;
use crate::image::{GreyImage, Mask};

/// Canny's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CannyParams {
    /// The Gaussian's standard deviation (px); below 0.1 no smoothing.
    pub sigma_px: f32,
    /// Hysteresis: a step of more than `low_step` levels continues an edge...
    pub low_step: f32,
    /// ...and one of more than `high_step` levels starts one.
    pub high_step: f32,
}

/// The smoothing kernel's weights, `radius + 1` of them from the centre
/// out, integers summing (both sides) to [`KERNEL_SUM`].
const KERNEL_SUM: u32 = 256;

/// The tangent of 22.5° in 1/65536: the border between a gradient counted
/// as horizontal (or vertical) and one counted as diagonal.
const TAN_22_5_Q16: i64 = 27146;

/// The half kernel of a Gaussian of `sigma_px`, sampled at whole pixels out
/// to 3σ and rounded to integers summing to [`KERNEL_SUM`] (the centre takes
/// the rounding). `libm::exp`, so every target rounds the same.
fn half_kernel(sigma_px: f32) -> Vec<u32> {
    // NaN too: no smoothing.
    if sigma_px.is_nan() || sigma_px < 0.1 {
        return vec![KERNEL_SUM];
    }
    let sigma = sigma_px as f64;
    let radius = libm::ceil(3.0 * sigma).max(1.0) as usize;
    let raw: Vec<f64> = (0..=radius).map(|i| libm::exp(-((i * i) as f64) / (2.0 * sigma * sigma))).collect();
    let total = raw[0] + 2.0 * raw[1..].iter().sum::<f64>();
    let mut half: Vec<u32> = raw.iter().map(|&w| libm::round(w / total * KERNEL_SUM as f64) as u32).collect();
    let sides: u32 = 2 * half[1..].iter().sum::<u32>();
    half[0] = KERNEL_SUM.saturating_sub(sides);
    // Trailing zero weights only cost time.
    while half.len() > 1 && half[half.len() - 1] == 0 {
        half.pop();
    }
    half
}

/// `image` smoothed by the separable Gaussian, each value 65 536 times the
/// grey level (the two passes' weights multiplied), the border pixels
/// repeated outwards.
fn smoothed(image: &GreyImage, half: &[u32]) -> Vec<u32> {
    let (w, h) = (image.width_px as usize, image.height_px as usize);
    let r = half.len() - 1;
    // Along the rows, each row first copied between r repeats of its end
    // pixels so the taps need no bounds; values up to 255 · 256.
    let mut across = vec![0u32; w * h];
    let mut padded = vec![0u32; w + 2 * r];
    for y in 0..h {
        let row = &image.pixels[y * w..(y + 1) * w];
        for (p, &v) in padded[r..r + w].iter_mut().zip(row) {
            *p = v as u32;
        }
        let (first, last) = (row[0] as u32, row[w - 1] as u32);
        padded[..r].fill(first);
        padded[r + w..].fill(last);
        let out = &mut across[y * w..(y + 1) * w];
        for (o, &c) in out.iter_mut().zip(&padded[r..r + w]) {
            *o = half[0] * c;
        }
        for (i, &weight) in half.iter().enumerate().skip(1) {
            let (left, right) = (&padded[r - i..r - i + w], &padded[r + i..r + i + w]);
            for ((o, &a), &b) in out.iter_mut().zip(left).zip(right) {
                *o += weight * (a + b);
            }
        }
    }
    if r == 0 {
        return across.iter().map(|&v| v * KERNEL_SUM).collect();
    }
    // Down the columns, a row at a time; values up to 255 · 65 536 < 2³².
    let mut both = vec![0u32; w * h];
    for y in 0..h {
        let out = &mut both[y * w..(y + 1) * w];
        let centre = &across[y * w..(y + 1) * w];
        for (o, &c) in out.iter_mut().zip(centre) {
            *o = half[0] * c;
        }
        for (i, &weight) in half.iter().enumerate().skip(1) {
            let above = &across[y.saturating_sub(i) * w..][..w];
            let below = &across[(y + i).min(h - 1) * w..][..w];
            for ((o, &a), &b) in out.iter_mut().zip(above).zip(below) {
                *o += weight * (a + b);
            }
        }
    }
    both
}

/// The squared gradient magnitude that an ideal step of `step` grey levels
/// makes at its edge: the smoothed step rises by `(w₀ + w₁)/256` of it
/// between the two pixels either side of the edge, and Sobel's `[1 2 1]`
/// across and `[−1 0 1]` along make 4 times that difference.
fn squared_response(step: f32, half: &[u32]) -> i64 {
    let rise = (half[0] + half.get(1).copied().unwrap_or(0)) as f64 * KERNEL_SUM as f64;
    let g = 4.0 * rise * step.max(0.0) as f64;
    // Steps of at most 255 levels: below 2⁵³, exact as an i64.
    (g * g).min(i64::MAX as f64 / 2.0) as i64
}

/// Canny's edges of `image`: one pixel wide, where the smoothed image's
/// gradient is a local maximum across the edge, above `high_step` or
/// joined (8-connected) to such a pixel through pixels above `low_step`.
///
/// Only the box around the image's non-zero pixels is worked on (a
/// thresholded difference is zero but for the actor): beyond the smoothing's
/// reach plus two pixels the gradient is zero, so the edges are the same as
/// over the whole image.
pub fn canny(image: &GreyImage, params: &CannyParams) -> Mask {
    let (w, h) = (image.width_px as usize, image.height_px as usize);
    let mut edges = Mask::empty(image.width_px, image.height_px);
    let Some(nonzero) = PixelBox::around(&image.pixels, w, |&p| p != 0) else { return edges };
    let half = half_kernel(params.sigma_px);
    let b = nonzero.grown(half.len() - 1 + 2, w, h);
    let cropped = GreyImage { width_px: b.width(), height_px: b.height(), pixels: b.crop(&image.pixels, w) };
    let on = canny_whole(&cropped, &half, params);
    for (row, inner) in b.rows(w).zip(on.chunks_exact(b.width() as usize)) {
        edges.on[row].copy_from_slice(inner);
    }
    edges
}

/// Canny over all of `image`, the border pixels repeated outwards.
fn canny_whole(image: &GreyImage, half: &[u32], params: &CannyParams) -> Vec<bool> {
    let (w, h) = (image.width_px as usize, image.height_px as usize);
    let s = smoothed(image, half);
    // Sobel, as its two separable halves a row at a time: `across` is the
    // column sum [1 2 1] and `down` the column difference [−1 0 1] of the
    // smoothed rows above and below; gradients below 2³⁰.
    // The magnitudes (squared, below 2⁶¹) sit in a frame one pixel wider on
    // every side, zero, so that thinning looks at neighbours without bounds.
    let pw = w + 2;
    let mut gx = vec![0i32; w * h];
    let mut gy = vec![0i32; w * h];
    let mut magnitude = vec![0i64; pw * (h + 2)];
    let mut across = vec![0i32; w];
    let mut down = vec![0i32; w];
    for y in 0..h {
        let (up, below) = (&s[y.saturating_sub(1) * w..][..w], &s[(y + 1).min(h - 1) * w..][..w]);
        let centre = &s[y * w..(y + 1) * w];
        for (((a, d), (&u, &c)), &b) in
            across.iter_mut().zip(down.iter_mut()).zip(up.iter().zip(centre)).zip(below)
        {
            *a = (u + 2 * c + b) as i32;
            *d = b as i32 - u as i32;
        }
        for x in 0..w {
            let (left, right) = (x.saturating_sub(1), (x + 1).min(w - 1));
            let dx = across[right] - across[left];
            let dy = down[left] + 2 * down[x] + down[right];
            let i = y * w + x;
            gx[i] = dx;
            gy[i] = dy;
            magnitude[(y + 1) * pw + x + 1] = dx as i64 * dx as i64 + dy as i64 * dy as i64;
        }
    }
    let low = squared_response(params.low_step, half);
    let high = squared_response(params.high_step, half);
    // Thinning: keep a pixel whose magnitude is a maximum along its
    // gradient's direction (quantised to 45°), ties going to the pixel
    // before, as OpenCV does, so a plateau keeps one pixel.
    const NOT: u8 = 0;
    const WEAK: u8 = 1;
    const STRONG: u8 = 2;
    let mut class = vec![NOT; w * h];
    let mut stack = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let at = (y + 1) * pw + x + 1;
            let m = magnitude[at];
            if m <= low {
                continue;
            }
            let (dx, dy) = (gx[i] as i64, gy[i] as i64);
            let (ax, ay) = (dx.abs(), dy.abs());
            // The neighbours before and after along the gradient.
            let (before, after) = if ay * 65536 <= TAN_22_5_Q16 * ax {
                (at - 1, at + 1)
            } else if ax * 65536 <= TAN_22_5_Q16 * ay {
                (at - pw, at + pw)
            } else if (dx > 0) == (dy > 0) {
                (at - pw - 1, at + pw + 1)
            } else {
                (at - pw + 1, at + pw - 1)
            };
            if m > magnitude[before] && m >= magnitude[after] {
                if m > high {
                    class[i] = STRONG;
                    stack.push(i);
                } else {
                    class[i] = WEAK;
                }
            }
        }
    }
    // Hysteresis: grow the strong pixels through the weak ones.
    while let Some(i) = stack.pop() {
        let (x, y) = (i % w, i / w);
        for ny in y.saturating_sub(1)..=(y + 1).min(h - 1) {
            for nx in x.saturating_sub(1)..=(x + 1).min(w - 1) {
                let n = ny * w + nx;
                if class[n] == WEAK {
                    class[n] = STRONG;
                    stack.push(n);
                }
            }
        }
    }
    class.iter().map(|&c| c == STRONG).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(low_step: f32, high_step: f32) -> CannyParams {
        CannyParams { sigma_px: 1.0, low_step, high_step }
    }

    #[test]
    fn the_kernel_sums_to_its_scale_and_falls_off() {
        for sigma in [0.0, 0.5, 1.0, 1.4, 3.0] {
            let half = half_kernel(sigma);
            assert_eq!(half[0] + 2 * half[1..].iter().sum::<u32>(), KERNEL_SUM, "σ = {sigma}");
            assert!(half.windows(2).all(|p| p[0] >= p[1]), "σ = {sigma}: {half:?}");
        }
        assert_eq!(half_kernel(f32::NAN), vec![KERNEL_SUM]);
    }

    /// A disc of `level` on 0.
    fn disc(size: u32, radius: f64, level: u8) -> GreyImage {
        let c = (size as f64 - 1.0) / 2.0;
        let pixels = (0..size * size)
            .map(|i| {
                let (x, y) = ((i % size) as f64 - c, (i / size) as f64 - c);
                if x * x + y * y <= radius * radius { level } else { 0 }
            })
            .collect();
        GreyImage::new(size, size, pixels, "disc").unwrap()
    }

    #[test]
    fn a_disc_has_one_closed_thin_outline_at_its_border() {
        let image = disc(41, 12.0, 40);
        let edges = canny(&image, &params(10.0, 20.0));
        let c = 20.0;
        let mut count = 0;
        for y in 0..41 {
            for x in 0..41 {
                if edges.at(x, y) {
                    count += 1;
                    let r = ((x as f64 - c).powi(2) + (y as f64 - c).powi(2)).sqrt();
                    assert!((r - 12.0).abs() <= 1.5, "an edge at ({x}, {y}), r = {r}");
                }
            }
        }
        // A one-pixel-wide ring of radius 12 has about 2π·12 ≈ 75 pixels
        // (8-connected, fewer): not a band two or three pixels wide.
        assert!((55..=100).contains(&count), "{count} edge pixels");
    }

    #[test]
    fn a_step_below_the_thresholds_is_no_edge_and_flat_is_nothing() {
        let image = disc(41, 12.0, 40);
        assert_eq!(canny(&image, &params(41.0, 50.0)).count(), 0, "a step of 40 is below 41");
        assert!(canny(&image, &params(30.0, 39.0)).count() > 0, "a step of 40 is above 39");
        assert_eq!(canny(&GreyImage::filled(9, 9, 77), &params(0.0, 0.0)).count(), 0);
        // One pixel wide or high is an image too.
        assert_eq!(
            canny(&GreyImage::new(5, 1, vec![0, 0, 90, 90, 90], "row").unwrap(), &params(5.0, 10.0)).count(),
            1
        );
    }
}
