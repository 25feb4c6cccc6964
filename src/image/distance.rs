//! The exact Euclidean distance transform of Felzenszwalb & Huttenlocher
//! (*Distance Transforms of Sampled Functions*, 2012): for every pixel, the
//! distance to the nearest pixel that is on in a mask.
//!
//! Two one-dimensional passes: down the columns the distance to the nearest
//! on pixel is a count; along the rows, the squared distance is the lower
//! envelope of the parabolas `(x − p)² + column(p)²`. The envelope is built
//! in integers: where each parabola takes over is kept as the first whole
//! pixel where it is lowest (the form of Meijster et al., 2000, of the same
//! envelope), so the squared distances are exact and the same on every
//! target; only the final square root is floating point, and IEEE rounds it
//! correctly everywhere.

use crate::image::grey::PixelBox;
use crate::image::{DistanceImage, Mask};

/// The squared distance of a pixel with nothing on in its whole image.
pub const NONE: u32 = u32::MAX;

/// The squared Euclidean distance (px²) from every pixel to the nearest on
/// pixel of `mask` (0 on the mask itself), row-major; [`NONE`] everywhere
/// when nothing is on. Exact for images up to 32 768 px a side.
pub fn squared_distance_px2(mask: &Mask) -> Vec<u32> {
    let (w, h) = (mask.width_px as usize, mask.height_px as usize);
    // Down the columns, row by row so the memory is read in order: the
    // vertical distance to the nearest on pixel above, then below (each row
    // from its neighbour, loops the compiler vectorises).
    let mut column = vec![NONE; w * h];
    for y in 0..h {
        let (done, rest) = column.split_at_mut(y * w);
        let out = &mut rest[..w];
        let on = &mask.on[y * w..(y + 1) * w];
        if y == 0 {
            for (o, &on) in out.iter_mut().zip(on) {
                *o = if on { 0 } else { NONE };
            }
        } else {
            let above = &done[(y - 1) * w..];
            for ((o, &on), &a) in out.iter_mut().zip(on).zip(above) {
                *o = if on { 0 } else { a.saturating_add(1) };
            }
        }
    }
    for y in (0..h.saturating_sub(1)).rev() {
        let (head, below) = column.split_at_mut((y + 1) * w);
        for (o, &b) in head[y * w..].iter_mut().zip(&below[..w]) {
            *o = (*o).min(b.saturating_add(1));
        }
    }
    // Along the rows: the lower envelope of the columns' parabolas.
    let mut envelope = Envelope::with_capacity(w);
    let mut squared = column;
    for y in 0..h {
        envelope.row(&mut squared[y * w..(y + 1) * w]);
    }
    squared
}

/// The Euclidean distance (px) from every pixel to the nearest on pixel of
/// `mask`: the square root of [`squared_distance_px2`], `f32::INFINITY`
/// when nothing is on.
pub fn distance_to(mask: &Mask) -> DistanceImage {
    let squared = squared_distance_px2(mask);
    let (w, h) = (mask.width_px as u64, mask.height_px as u64);
    // Below 2²⁴ a squared distance is exact in f32, and the f32 root is then
    // the f64 root rounded to f32 (a root rounded twice through f64 is
    // rounded once): the fast, vectorised path gives the same bits.
    let distance_px = if (w - 1) * (w - 1) + (h - 1) * (h - 1) < (1 << 24) {
        squared.into_iter().map(|d2| if d2 == NONE { f32::INFINITY } else { (d2 as f32).sqrt() }).collect()
    } else {
        squared
            .into_iter()
            .map(|d2| if d2 == NONE { f32::INFINITY } else { libm::sqrt(d2 as f64) as f32 })
            .collect()
    };
    DistanceImage { width_px: mask.width_px, height_px: mask.height_px, distance_px }
}

/// `⌊num / den⌋` for `den > 0` and both below 2⁵³ in size: through an f64
/// division (several times faster than a 64-bit integer one, and the
/// envelope makes one per column), then corrected where the quotient was
/// truncated or rounded across a whole number, so it is exact.
fn floor_div(num: i64, den: i64) -> i64 {
    // Truncated, then moved to the floor: at most a step or two.
    let mut q = (num as f64 / den as f64) as i64;
    while q * den > num {
        q -= 1;
    }
    while (q + 1) * den <= num {
        q += 1;
    }
    q
}

/// [`distance_to`] capped at `max_px` (nothing on at all: `max_px`
/// everywhere), the same values as `distance_to(mask).truncated(max_px)`
/// but computed on the box round the on pixels grown by `max_px` only:
/// every on pixel is inside it, so the distances there are exact, and
/// every pixel outside is farther than `max_px` from all of them. For an
/// actor a fifth of the frame wide and a cap of tens of pixels, a few times
/// less work.
pub fn distance_to_truncated(mask: &Mask, max_px: f32) -> DistanceImage {
    let (w, h) = (mask.width_px as usize, mask.height_px as usize);
    let max_px = if max_px.is_nan() { 0.0 } else { max_px.max(0.0) };
    let mut out = DistanceImage {
        width_px: mask.width_px,
        height_px: mask.height_px,
        distance_px: vec![max_px; w * h],
    };
    let Some(on_box) = PixelBox::around(&mask.on, w, |&on| on) else { return out };
    let b = on_box.grown(libm::ceilf(max_px).min((w + h) as f32) as usize, w, h);
    let inner = Mask { width_px: b.width(), height_px: b.height(), on: b.crop(&mask.on, w) };
    let inner = distance_to(&inner);
    for (row, inner) in b.rows(w).zip(inner.distance_px.chunks_exact(b.width() as usize)) {
        for (o, &d) in out.distance_px[row].iter_mut().zip(inner) {
            *o = d.min(max_px);
        }
    }
    out
}

/// The working memory of one row's envelope, kept across rows.
struct Envelope {
    /// The columns whose parabolas make the envelope, left to right.
    apex: Vec<i64>,
    /// Their squared column distances.
    apex_height: Vec<i64>,
    /// The first pixel where each is the lowest.
    start: Vec<i64>,
}

impl Envelope {
    fn with_capacity(n: usize) -> Self {
        Envelope {
            apex: Vec::with_capacity(n),
            apex_height: Vec::with_capacity(n),
            start: Vec::with_capacity(n),
        }
    }

    /// Replaces each column distance `c(q)` of `row` ([`NONE`] where the
    /// column has nothing on) by `min_p (q − p)² + c(p)²`.
    fn row(&mut self, row: &mut [u32]) {
        let n = row.len() as i64;
        self.apex.clear();
        self.apex_height.clear();
        self.start.clear();
        for (u, &c) in row.iter().enumerate() {
            if c == NONE {
                continue;
            }
            let (u, g) = (u as i64, c as i64 * c as i64);
            // Drop the parabolas the new one is below at their first pixel:
            // it is then below them on all the rest of their stretch.
            while let (Some(&v), Some(&gv), Some(&t)) =
                (self.apex.last(), self.apex_height.last(), self.start.last())
            {
                if (t - v) * (t - v) + gv > (t - u) * (t - u) + g {
                    self.apex.pop();
                    self.apex_height.pop();
                    self.start.pop();
                } else {
                    break;
                }
            }
            let start = match (self.apex.last(), self.apex_height.last()) {
                // The first pixel past where the two parabolas cross.
                (Some(&v), Some(&gv)) => 1 + floor_div(u * u - v * v + g - gv, 2 * (u - v)),
                _ => 0,
            };
            if start < n {
                self.apex.push(u);
                self.apex_height.push(g);
                self.start.push(start);
            }
        }
        if self.apex.is_empty() {
            row.fill(NONE);
            return;
        }
        for k in 0..self.apex.len() {
            let (p, g) = (self.apex[k], self.apex_height[k]);
            let (start, end) = (self.start[k], self.start.get(k + 1).copied().unwrap_or(n));
            // In u32: a squared distance within the image fits.
            let (offset, g) = ((start - p) as i32, g as u32);
            for (i, out) in row[start as usize..end as usize].iter_mut().enumerate() {
                let dx = offset + i as i32;
                *out = (dx * dx) as u32 + g;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_floor_division_is_exact_where_f64_rounds() {
        for (num, den) in [(7, 2), (-7, 2), (6, 3), (-6, 3), (0, 5), (-1, 4)] {
            assert_eq!(floor_div(num, den), i64::div_euclid(num, den), "{num}/{den}");
        }
        // Just below a whole number, where the f64 quotient rounds up to it.
        let den = (1i64 << 26) + 1;
        let num = 3 * den - 1;
        assert_eq!(floor_div(num, den), 2);
    }

    #[test]
    fn one_point_gives_the_euclidean_distance_and_none_gives_infinity() {
        let mut mask = Mask::empty(7, 5);
        mask.on[2 * 7 + 3] = true;
        let d = distance_to(&mask);
        assert_eq!(d.at(3, 2), 0.0);
        assert_eq!(d.at(6, 2), 3.0);
        assert_eq!(d.at(0, 0), 13f32.sqrt());
        let none = distance_to(&Mask::empty(3, 2));
        assert!(none.distance_px.iter().all(|d| d.is_infinite()));
    }
}
