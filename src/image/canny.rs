//! Canny's edge detector (1986) in integer arithmetic: Gaussian smoothing,
//! Sobel gradients, thinning to the gradient's ridge (non-maximum
//! suppression), and hysteresis between two thresholds.
//!
//! The thresholds are **step heights in grey levels**: an ideal straight
//! step of `high` levels between two flat regions is just an edge, one of
//! `low` levels just continues one. They are turned into gradient units
//! through the exact response of this smoothing and Sobel to such a step, so
//! that they keep their meaning whatever `sigma_px` is.

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
    // Along the rows; values up to 255 · 256.
    let mut across = vec![0u32; w * h];
    for y in 0..h {
        let row = &image.pixels[y * w..(y + 1) * w];
        let out = &mut across[y * w..(y + 1) * w];
        for (x, out) in out.iter_mut().enumerate() {
            let mut sum = half[0] * row[x] as u32;
            for (i, &weight) in half.iter().enumerate().skip(1) {
                let left = row[x.saturating_sub(i)] as u32;
                let right = row[(x + i).min(w - 1)] as u32;
                sum += weight * (left + right);
            }
            *out = sum;
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
    let Some((x0, y0, x1, y1)) = nonzero_box(image) else { return edges };
    let half = half_kernel(params.sigma_px);
    let reach = half.len() - 1 + 2;
    let (x0, y0) = (x0.saturating_sub(reach), y0.saturating_sub(reach));
    let (x1, y1) = ((x1 + reach).min(w - 1), (y1 + reach).min(h - 1));
    let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut pixels = Vec::with_capacity(bw * bh);
    for y in y0..=y1 {
        pixels.extend_from_slice(&image.pixels[y * w + x0..=y * w + x1]);
    }
    let cropped = GreyImage { width_px: bw as u32, height_px: bh as u32, pixels };
    let on = canny_whole(&cropped, &half, params);
    for (y, row) in (y0..=y1).zip(on.chunks_exact(bw)) {
        edges.on[y * w + x0..=y * w + x1].copy_from_slice(row);
    }
    edges
}

/// The smallest box `(x0, y0, x1, y1)` (inclusive) holding every non-zero
/// pixel; `None` for an image of zeros.
fn nonzero_box(image: &GreyImage) -> Option<(usize, usize, usize, usize)> {
    let w = image.width_px as usize;
    let mut found: Option<(usize, usize, usize, usize)> = None;
    for (y, row) in image.pixels.chunks_exact(w).enumerate() {
        let Some(first) = row.iter().position(|&p| p != 0) else { continue };
        let last = row.iter().rposition(|&p| p != 0).unwrap_or(first);
        found = Some(match found {
            None => (first, y, last, y),
            Some((x0, y0, x1, _)) => (x0.min(first), y0, x1.max(last), y),
        });
    }
    found
}

/// Canny over all of `image`, the border pixels repeated outwards.
fn canny_whole(image: &GreyImage, half: &[u32], params: &CannyParams) -> Vec<bool> {
    let (w, h) = (image.width_px as usize, image.height_px as usize);
    let s = smoothed(image, half);
    let at = |x: usize, y: usize| s[y * w + x] as i64;
    // Sobel; gradients below 2³⁰, squares below 2⁶¹.
    let mut gx = vec![0i32; w * h];
    let mut gy = vec![0i32; w * h];
    let mut magnitude = vec![0i64; w * h];
    for y in 0..h {
        let (up, down) = (y.saturating_sub(1), (y + 1).min(h - 1));
        for x in 0..w {
            let (left, right) = (x.saturating_sub(1), (x + 1).min(w - 1));
            let dx = (at(right, up) + 2 * at(right, y) + at(right, down))
                - (at(left, up) + 2 * at(left, y) + at(left, down));
            let dy = (at(left, down) + 2 * at(x, down) + at(right, down))
                - (at(left, up) + 2 * at(x, up) + at(right, up));
            let i = y * w + x;
            gx[i] = dx as i32;
            gy[i] = dy as i32;
            magnitude[i] = dx * dx + dy * dy;
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
            let m = magnitude[i];
            if m <= low {
                continue;
            }
            let (dx, dy) = (gx[i] as i64, gy[i] as i64);
            let (ax, ay) = (dx.abs(), dy.abs());
            let m_at = |ox: isize, oy: isize| {
                let (nx, ny) = (x as isize + ox, y as isize + oy);
                if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                    0
                } else {
                    magnitude[ny as usize * w + nx as usize]
                }
            };
            let (before, after) = if ay * 65536 <= TAN_22_5_Q16 * ax {
                (m_at(-1, 0), m_at(1, 0))
            } else if ax * 65536 <= TAN_22_5_Q16 * ay {
                (m_at(0, -1), m_at(0, 1))
            } else if (dx > 0) == (dy > 0) {
                (m_at(-1, -1), m_at(1, 1))
            } else {
                (m_at(1, -1), m_at(-1, 1))
            };
            if m > before && m >= after {
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
