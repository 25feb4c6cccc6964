//! An image shrunk by a factor in quarters (1, 1.25, 1.5, … times each
//! way): a take filmed at 1440×1080 is read at the pixel a 640×480 one
//! has only if 2.25 is a factor, and whole factors jump from 1 to 2 to 3
//! (a pixel twice, then three times, as large) where the measurement wants
//! one size of pixel at the body.
//!
//! Each shrunk pixel is the mean of the source pixels under its square,
//! each weighted by the area it covers there (area resampling, what a
//! sensor with larger pixels would have read), in integers: the same
//! bytes on every target.

/// How many times each way an image is shrunk, in quarters: 4 keeps it,
/// 8 halves it, 9 shrinks it 2.25 times. A pixel `x` of the shrunk image
/// spans `[x · q/4, (x + 1) · q/4)` of the source's pixel edges, its
/// centre at `(x + ½) · q/4 − ½` in the source; the columns and rows past
/// the last whole shrunk pixel are dropped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Shrink {
    quarters: u32,
}

impl Shrink {
    /// The image as it is.
    pub const NONE: Shrink = Shrink { quarters: 4 };

    /// The most it shrinks: 256 times each way (the resampler's sums,
    /// `q² · 255`, stay far inside a `u32`).
    pub const MAX_QUARTERS: u32 = 1024;

    /// `quarters / 4` times each way; `None` below 4 (that would enlarge)
    /// or above [`Shrink::MAX_QUARTERS`].
    pub fn from_quarters(quarters: u32) -> Option<Shrink> {
        (4..=Shrink::MAX_QUARTERS).contains(&quarters).then_some(Shrink { quarters })
    }

    /// `times` times each way (0 is taken as 1, more than 256 as 256).
    pub fn whole(times: u32) -> Shrink {
        Shrink { quarters: times.clamp(1, Shrink::MAX_QUARTERS / 4) * 4 }
    }

    /// The factor in quarters.
    pub fn quarters(self) -> u32 {
        self.quarters
    }

    /// How many times each way.
    pub fn factor(self) -> f64 {
        self.quarters as f64 / 4.0
    }

    /// Whether the image is kept as it is.
    pub fn is_none(self) -> bool {
        self.quarters == 4
    }

    /// A side of `length_px` source pixels, shrunk.
    pub fn length_px(self, length_px: u32) -> u32 {
        (length_px as u64 * 4 / self.quarters as u64) as u32
    }

    /// A source pixel coordinate (centres at whole numbers) in the shrunk
    /// image's.
    pub fn coordinate_px(self, source_px: f64) -> f64 {
        (source_px + 0.5) / self.factor() - 0.5
    }
}

/// Which source pixels a shrunk pixel covers along one axis, and by how
/// many quarters of a pixel each: `taps` weights a shrunk pixel, from
/// `first[x]` on.
pub(crate) struct Taps {
    pub first: Vec<usize>,
    /// `stride` weights a shrunk pixel (trailing zeros where it covers
    /// fewer); each pixel's sum to the factor's quarters.
    pub weights: Vec<u32>,
    pub stride: usize,
}

impl Taps {
    /// The taps of `shrink` over `length_px` source pixels.
    pub fn new(shrink: Shrink, length_px: u32) -> Taps {
        let q = shrink.quarters as usize;
        let count = shrink.length_px(length_px) as usize;
        // The most pixels a span of q quarters touches, over the places in
        // a pixel the spans start (x · q mod 4, repeating every 4 pixels):
        // q/4 at a whole factor, 6 at 5.5 times.
        let stride = (0..4).map(|x| ((x * q) % 4 + q).div_ceil(4)).max().unwrap_or(1);
        let mut first = Vec::with_capacity(count);
        let mut weights = vec![0u32; count * stride];
        for x in 0..count {
            let (start, end) = (x * q, (x + 1) * q);
            let source = start / 4;
            first.push(source);
            for (k, weight) in weights[x * stride..(x + 1) * stride].iter_mut().enumerate() {
                let (edge, next) = (4 * (source + k), 4 * (source + k + 1));
                *weight = next.min(end).saturating_sub(edge.max(start)) as u32;
            }
        }
        Taps { first, weights, stride }
    }

    /// The taps of shrunk pixel `x`: the first source pixel and the
    /// weights.
    pub fn of(&self, x: usize) -> (usize, &[u32]) {
        (self.first[x], &self.weights[x * self.stride..(x + 1) * self.stride])
    }
}

/// `pixels` (`width_px` wide) shrunk by `shrink`, area-weighted, rounded
/// half up: `(Σ w_x · w_y · v + q²/2) / q²` in integers. At a whole factor
/// it is the block mean.
pub(crate) fn area_resampled(
    pixels: &[u8],
    width_px: u32,
    height_px: u32,
    shrink: Shrink,
) -> (u32, u32, Vec<u8>) {
    let (columns, rows) = (Taps::new(shrink, width_px), Taps::new(shrink, height_px));
    let (out_w, out_h) = (columns.first.len(), rows.first.len());
    let q = shrink.quarters;
    let (area, half) = (q * q, q * q / 2);
    let w = width_px as usize;
    let mut out = Vec::with_capacity(out_w * out_h);
    // Down the columns first (a weighted sum of whole rows, which the
    // compiler vectorises), then along the one summed row; the sums run
    // `stride` zeros past the last column, so that every pixel's taps can
    // be read as a whole.
    let mut column_sums = vec![0u32; w + columns.stride];
    for y in 0..out_h {
        column_sums[..w].fill(0);
        let (first_row, row_weights) = rows.of(y);
        for (k, &weight_y) in row_weights.iter().enumerate().filter(|(_, w)| **w > 0) {
            let row = &pixels[(first_row + k) * w..(first_row + k + 1) * w];
            for (sum, &v) in column_sums.iter_mut().zip(row) {
                *sum += weight_y * v as u32;
            }
        }
        let mean = |sum: u32| ((sum + half) / area) as u8;
        match columns.stride {
            2 => along_row::<2>(&columns, &column_sums, mean, &mut out),
            3 => along_row::<3>(&columns, &column_sums, mean, &mut out),
            4 => along_row::<4>(&columns, &column_sums, mean, &mut out),
            5 => along_row::<5>(&columns, &column_sums, mean, &mut out),
            6 => along_row::<6>(&columns, &column_sums, mean, &mut out),
            7 => along_row::<7>(&columns, &column_sums, mean, &mut out),
            8 => along_row::<8>(&columns, &column_sums, mean, &mut out),
            _ => out.extend((0..out_w).map(|x| {
                let (first, weights) = columns.of(x);
                mean(weights.iter().zip(&column_sums[first..]).map(|(&a, &b)| a * b).sum())
            })),
        }
    }
    (out_w as u32, out_h as u32, out)
}

/// One shrunk row from `column_sums` (the row's columns summed down), for
/// taps `N` wide: fixed-size, so that each pixel's sum is unrolled.
fn along_row<const N: usize>(
    columns: &Taps,
    column_sums: &[u32],
    mean: impl Fn(u32) -> u8,
    out: &mut Vec<u8>,
) {
    let taps = columns.first.iter().zip(columns.weights.chunks_exact(N));
    out.extend(taps.map(|(&first, weights)| {
        let (sums, weights) = (&column_sums[first..][..N], &weights[..N]);
        mean((0..N).map(|k| weights[k] * sums[k]).sum())
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_taps_cover_each_shrunk_pixel_with_its_quarters() {
        // 2.25 times over 9 pixels: 4 shrunk pixels, spans [0, 9), [9, 18),
        // [18, 27), [27, 36) in quarters.
        let taps = Taps::new(Shrink::from_quarters(9).unwrap(), 9);
        assert_eq!(taps.first, [0, 2, 4, 6]);
        assert_eq!(taps.stride, 3);
        assert_eq!(taps.of(0).1, [4, 4, 1]);
        assert_eq!(taps.of(1).1, [3, 4, 2]);
        assert_eq!(taps.of(2).1, [2, 4, 3]);
        assert_eq!(taps.of(3).1, [1, 4, 4]);
        for x in 0..4 {
            assert_eq!(taps.of(x).1.iter().sum::<u32>(), 9);
        }
    }

    #[test]
    fn a_whole_factor_gives_the_block_means() {
        let (w, h) = (13u32, 11u32);
        let pixels: Vec<u8> = (0..w * h).map(|i| (i * 37 % 256) as u8).collect();
        for times in 2..=4u32 {
            let s = times as usize;
            let (out_w, out_h, out) = area_resampled(&pixels, w, h, Shrink::whole(times));
            assert_eq!((out_w, out_h), (w / times, h / times));
            for y in 0..out_h as usize {
                for x in 0..out_w as usize {
                    let sum: u32 = (0..s)
                        .flat_map(|dy| (0..s).map(move |dx| (dx, dy)))
                        .map(|(dx, dy)| pixels[(y * s + dy) * w as usize + x * s + dx] as u32)
                        .sum();
                    let mean = (sum + (s * s / 2) as u32) / (s * s) as u32;
                    assert_eq!(out[y * out_w as usize + x] as u32, mean, "{times}× at ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn every_factor_is_the_area_weighted_mean_pixel_by_pixel() {
        // Against the definition, one shrunk pixel at a time: the source
        // pixels' overlaps with its square, in quarters each way.
        let (w, h) = (37u32, 29u32);
        let pixels: Vec<u8> = (0..w * h).map(|i| (i * 97 % 251) as u8).collect();
        let overlap =
            |a: u32, q: u32, i: u32| ((a + 1) * q).min(4 * i + 4).saturating_sub((a * q).max(4 * i));
        for q in 5..=40 {
            let shrink = Shrink::from_quarters(q).unwrap();
            let (out_w, out_h, out) = area_resampled(&pixels, w, h, shrink);
            assert_eq!((out_w, out_h), (w * 4 / q, h * 4 / q));
            for (y, x) in (0..out_h).flat_map(|y| (0..out_w).map(move |x| (y, x))) {
                let sum: u32 = (0..h)
                    .flat_map(|j| (0..w).map(move |i| (j, i)))
                    .map(|(j, i)| overlap(x, q, i) * overlap(y, q, j) * pixels[(j * w + i) as usize] as u32)
                    .sum();
                let expected = (sum + q * q / 2) / (q * q);
                assert_eq!(out[(y * out_w + x) as usize] as u32, expected, "{q} quarters at ({x}, {y})");
            }
        }
    }

    #[test]
    fn an_edge_shrunk_by_a_quarter_step_is_weighted_by_area() {
        // A step from 0 to 200 between columns 1 and 2, shrunk 1.25 times:
        // the first shrunk pixel covers columns 0 and a quarter of 1 (all
        // 0), the second three quarters of 1 and half of 2.
        let pixels: Vec<u8> = [0u8, 0, 200, 200, 200].repeat(5);
        let (out_w, out_h, out) = area_resampled(&pixels, 5, 5, Shrink::from_quarters(5).unwrap());
        assert_eq!((out_w, out_h), (4, 4));
        // Pixel 1 spans quarters [5, 10): 3 of column 1 (0) and 2 of
        // column 2 (200): 400 / 5 = 80, in every row.
        assert_eq!(out[0], 0);
        assert_eq!(out[1], 80);
        assert_eq!(out[2], 200);
    }
}
