//! How well a silhouette fits one frame, the two ways the trackers score it.
//!
//! - **The paper's Chamfer energy**: the mean, over the silhouette's
//!   contour pixels, of the distance to the video's nearest edge. Every
//!   contour pixel counts in full, so one far from any edge (a limb the suit
//!   puts a little wrong, an edge the codec smeared) weighs as much as the
//!   whole rest of the fit, and edges of clutter can pull the body aside.
//! - **The fused energy**: the same contour mean with each distance
//!   truncated at `truncation_px` (an outlier costs at most that), plus the
//!   mean over the silhouette's *area* of its truncated distance outside the
//!   foreground mask: a silhouette that slides off the actor onto the
//!   room's edges pays for every pixel it puts on the empty room. A cast
//!   shadow is foreground, so it costs nothing to cover and does not pull.
//!   Both terms are one-sided: a silhouette too *small* sits inside the
//!   actor, its contour on the clothes' and limbs' inner edges, and pays
//!   almost nothing — and along the camera's line of sight a body farther
//!   away is a body smaller. So the fused energy has a third term, the
//!   foreground the silhouette leaves **uncovered** in a band just outside
//!   it (`FrameTerms::fit_in_band`): what keeps the silhouette as large as
//!   the actor, and so at the actor's depth.

use glam::{DVec2, DVec3};

use crate::body::shape::PosedBody;
use crate::camera::Camera;
use crate::image::{DistanceImage, Mask};
use crate::track::silhouette::{Silhouette, SilhouetteRenderer};

/// The per-frame image terms, ready to be summed over many silhouettes.
/// They borrow the frame's edge distances, made once per frame and read at
/// every contour pixel of every silhouette tried.
#[derive(Clone, Debug)]
pub struct FrameTerms<'a> {
    width_px: u32,
    height_px: u32,
    /// Distance to the nearest edge (px), untruncated.
    edge_distance_px: &'a [f32],
    /// The rows `prefix_top..prefix_top + prefix_rows` and the columns
    /// `prefix_left..prefix_right` hold all the foreground and every
    /// distance outside it below the truncation; in every other pixel the
    /// truncated distance is the truncation itself and nothing is
    /// foreground, so a span there costs a multiplication. Exactly what a
    /// sum of its pixels would: each distance is 0 or an f32 of at least 1
    /// (a pixel's distance) and at most the truncation (a few hundred px at
    /// the most, under 2¹⁰), so a multiple of 2⁻²³; a row's sum (under 2¹⁴
    /// pixels) stays below 2²⁴, every partial sum exact in an f64, in any
    /// order.
    prefix_top: usize,
    prefix_rows: usize,
    prefix_left: usize,
    prefix_right: usize,
    /// Per row of those, the prefix sums of the truncated distance outside
    /// the foreground: `outside_prefix[(y − prefix_top) * (c + 1) + k]`
    /// sums columns `0..prefix_left + k` of row `y` (`c` columns kept), so
    /// a span costs one subtraction.
    outside_prefix: Vec<f64>,
    /// Per row of those, the prefix counts of foreground pixels, likewise.
    foreground_prefix: Vec<u32>,
    truncation_px: f32,
}

/// The pixels `from..to` of a frame, for those near the foreground: on it,
/// or less than `truncation_px` from it. Read a block of 16 at a time
/// without stopping (what vectorises), then pixel by pixel in the block
/// that has one.
struct NearScan<'s> {
    distance: &'s [f32],
    on: &'s [bool],
    truncation_px: f32,
    from: usize,
    to: usize,
}

impl NearScan<'_> {
    const BLOCK: usize = 16;

    fn near(&self, i: usize) -> bool {
        self.distance[i] < self.truncation_px || self.on[i]
    }

    fn block_has_one(&self, start: usize, end: usize) -> bool {
        let near = self.distance[start..end].iter().fold(false, |a, &d| a | (d < self.truncation_px));
        near | self.on[start..end].iter().fold(false, |a, &o| a | o)
    }

    fn any(&self) -> bool {
        self.first().is_some()
    }

    /// The first pixel near the foreground.
    fn first(&self) -> Option<usize> {
        let mut start = self.from;
        while start < self.to {
            let end = (start + Self::BLOCK).min(self.to);
            if self.block_has_one(start, end) {
                return (start..end).find(|&i| self.near(i));
            }
            start = end;
        }
        None
    }

    /// The last pixel near the foreground.
    fn last(&self) -> Option<usize> {
        let mut end = self.to;
        while end > self.from {
            let start = end.saturating_sub(Self::BLOCK).max(self.from);
            if self.block_has_one(start, end) {
                return (start..end).rev().find(|&i| self.near(i));
            }
            end = start;
        }
        None
    }
}

/// A silhouette's fit, its parts kept apart for the confidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SilhouetteFit {
    /// Contour pixels.
    pub contour_px: usize,
    /// The paper's energy: the mean untruncated edge distance (px).
    pub chamfer_px: f64,
    /// The mean edge distance, each truncated (px).
    pub truncated_chamfer_px: f64,
    /// The mean truncated distance outside the foreground over the area (px).
    pub outside_px: f64,
    /// The share of contour pixels within `NEAR_EDGE_PX` of an edge.
    pub near_edge_share: f64,
    /// The share of the silhouette's area on the foreground.
    pub on_foreground_share: f64,
    /// The share of a band just outside the silhouette that is foreground,
    /// times the band's width (px): about how far the actor reaches beyond
    /// the silhouette. 0 when fitted without a band ([`FrameTerms::fit`]).
    pub uncovered_px: f64,
}

/// A contour pixel this close to an edge (px) is on it, give or take the
/// edge detector's and the rasteriser's pixel.
pub const NEAR_EDGE_PX: f32 = 2.0;

impl<'a> FrameTerms<'a> {
    /// The terms of a frame whose edges are `edge_distance` away and whose
    /// foreground is `foreground` (with `outside_distance` its distance
    /// transform), distances truncated at `truncation_px` for the fused
    /// energy.
    pub fn new(
        edge_distance: &'a DistanceImage,
        outside_distance: &DistanceImage,
        foreground: &Mask,
        truncation_px: f32,
    ) -> FrameTerms<'a> {
        let (w, h) = (edge_distance.width_px as usize, edge_distance.height_px as usize);
        let (distance, on) = (&outside_distance.distance_px[..], &foreground.on[..]);
        let near_in = |from: usize, to: usize| NearScan { distance, on, truncation_px, from, to };
        let near = |y: usize| near_in(y * w, (y + 1) * w).any();
        let (prefix_top, prefix_rows) = match ((0..h).find(|&y| near(y)), (0..h).rev().find(|&y| near(y))) {
            (Some(top), Some(bottom)) => (top, bottom + 1 - top),
            _ => (0, 0),
        };
        let (mut prefix_left, mut prefix_right) = (w, 0);
        for y in prefix_top..prefix_top + prefix_rows {
            let row = y * w;
            if let Some(i) = near_in(row, row + prefix_left).first() {
                prefix_left = i - row;
            }
            let from = row + prefix_right.max(prefix_left);
            if let Some(i) = near_in(from, row + w).last() {
                prefix_right = i - row + 1;
            }
        }
        let prefix_right = prefix_right.max(prefix_left).min(w);
        let prefix_left = prefix_left.min(prefix_right);
        let columns = prefix_right - prefix_left;
        let mut outside_prefix = Vec::with_capacity((columns + 1) * prefix_rows);
        let mut foreground_prefix = Vec::with_capacity((columns + 1) * prefix_rows);
        let before = prefix_left as f64 * truncation_px as f64;
        for y in prefix_top..prefix_top + prefix_rows {
            let (from, to) = (y * w + prefix_left, y * w + prefix_right);
            let (mut outside_sum, mut foreground_count) = (before, 0u32);
            outside_prefix.push(outside_sum);
            foreground_prefix.push(foreground_count);
            for (&d, &on) in distance[from..to].iter().zip(&on[from..to]) {
                outside_sum += d.min(truncation_px) as f64;
                foreground_count += u32::from(on);
                outside_prefix.push(outside_sum);
                foreground_prefix.push(foreground_count);
            }
        }
        FrameTerms {
            width_px: edge_distance.width_px,
            height_px: edge_distance.height_px,
            edge_distance_px: &edge_distance.distance_px,
            prefix_top,
            prefix_rows,
            prefix_left,
            prefix_right,
            outside_prefix,
            foreground_prefix,
            truncation_px,
        }
    }

    /// The index of row `row`'s prefix sums, `None` for a row beyond them.
    fn prefix_row(&self, row: u32) -> Option<usize> {
        let k = (row as usize).checked_sub(self.prefix_top)?;
        (k < self.prefix_rows).then(|| k * (self.prefix_right - self.prefix_left + 1))
    }

    /// Of the row whose prefix sums start at `row` ([`FrameTerms::prefix_row`]),
    /// the truncated distance outside the foreground summed over columns
    /// `0..x`, and the foreground pixels there.
    fn sums_to(&self, row: usize, x: u32) -> (f64, u32) {
        let (x, left, right) = (x as usize, self.prefix_left, self.prefix_right);
        let truncation = self.truncation_px as f64;
        if x <= left {
            (x as f64 * truncation, 0)
        } else if x < right {
            (self.outside_prefix[row + x - left], self.foreground_prefix[row + x - left])
        } else {
            let last = row + right - left;
            (self.outside_prefix[last] + (x - right) as f64 * truncation, self.foreground_prefix[last])
        }
    }

    /// How `silhouette` fits; `None` when it covers no pixel of the image.
    pub fn fit(&self, silhouette: &Silhouette) -> Option<SilhouetteFit> {
        self.fit_and_sums(silhouette).map(|(fit, _)| fit)
    }

    /// [`FrameTerms::fit`], and the sums over the silhouette's spans it
    /// was made from.
    fn fit_and_sums(&self, silhouette: &Silhouette) -> Option<(SilhouetteFit, SpanSums)> {
        if silhouette.image_size.width_px != self.width_px
            || silhouette.image_size.height_px != self.height_px
        {
            return None;
        }
        let w = self.width_px as usize;
        let (mut chamfer, mut truncated, mut near, mut contour_px) = (0.0f64, 0.0f64, 0usize, 0usize);
        silhouette.visit_contour(|x, y| {
            let d = self.edge_distance_px[y as usize * w + x as usize];
            chamfer += d as f64;
            truncated += d.min(self.truncation_px) as f64;
            near += usize::from(d <= NEAR_EDGE_PX);
            contour_px += 1;
        });
        if contour_px == 0 {
            return None;
        }
        let sums = self.span_sums(silhouette);
        let area = sums.area.max(1) as f64;
        let n = contour_px as f64;
        let fit = SilhouetteFit {
            contour_px,
            chamfer_px: chamfer / n,
            truncated_chamfer_px: truncated / n,
            outside_px: sums.outside_px / area,
            near_edge_share: near as f64 / n,
            on_foreground_share: sums.on_foreground as f64 / area,
            uncovered_px: 0.0,
        };
        Some((fit, sums))
    }

    /// How `silhouette` fits, with the foreground it leaves uncovered in the
    /// band out to `widened` (the same body's silhouette with `band_px`
    /// more all round it, [`crate::body::shape::BodyShape::widened`]): the
    /// band's foreground share times `band_px`. A silhouette the actor's
    /// size leaves its band on the empty room (0); one `e` px too small all
    /// round leaves about `e / band_px` of it on the actor (`e` px).
    pub fn fit_in_band(
        &self,
        silhouette: &Silhouette,
        widened: &Silhouette,
        band_px: f64,
    ) -> Option<SilhouetteFit> {
        let (fit, inner) = self.fit_and_sums(silhouette)?;
        if widened.image_size != silhouette.image_size {
            return Some(fit);
        }
        let outer = self.span_sums(widened);
        let band_area = outer.area.saturating_sub(inner.area);
        let band_on = outer.on_foreground.saturating_sub(inner.on_foreground);
        let uncovered_px = if band_area == 0 { 0.0 } else { band_on as f64 / band_area as f64 * band_px };
        Some(SilhouetteFit { uncovered_px, ..fit })
    }

    /// The sums over `silhouette`'s spans, one subtraction of prefix sums
    /// a span.
    fn span_sums(&self, silhouette: &Silhouette) -> SpanSums {
        let mut sums = SpanSums { outside_px: 0.0, on_foreground: 0, area: 0 };
        for span in &silhouette.spans {
            match self.prefix_row(span.row) {
                Some(row) => {
                    let ((end_sum, end_on), (start_sum, start_on)) =
                        (self.sums_to(row, span.end), self.sums_to(row, span.start));
                    sums.outside_px += end_sum - start_sum;
                    sums.on_foreground += (end_on - start_on) as u64;
                }
                None => sums.outside_px += (span.end - span.start) as f64 * self.truncation_px as f64,
            }
            sums.area += (span.end - span.start) as u64;
        }
        sums
    }
}

/// What a silhouette's spans cover in one frame's terms.
struct SpanSums {
    /// The truncated distance outside the foreground, summed (px).
    outside_px: f64,
    /// The foreground pixels covered.
    on_foreground: u64,
    /// The pixels covered.
    area: u64,
}

/// One frame's body as the fused energy scores it: posed, widened by the
/// band (`BodyShape::widened`), and the band's width in pixels at the
/// body's distance (0: no band).
pub struct BandedBody {
    pub body: PosedBody,
    pub widened: PosedBody,
    pub band_px: f64,
}

/// Scores a body's silhouette at floor positions in one frame's terms: a
/// renderer and its two silhouettes, kept from one position to the next.
pub struct Scorer {
    renderer: SilhouetteRenderer,
    silhouette: Silhouette,
    /// The widened body's silhouette, for the band.
    band_silhouette: Silhouette,
}

impl Scorer {
    pub fn new(camera: &Camera) -> Scorer {
        Scorer {
            renderer: SilhouetteRenderer::new(camera),
            silhouette: Silhouette::empty(camera.image_size),
            band_silhouette: Silhouette::empty(camera.image_size),
        }
    }

    /// The fit of `body` at `floor_cm` with its band (none when the band is
    /// 0 px wide: then the widened body is not drawn at all).
    pub fn banded_fit(
        &mut self,
        terms: &FrameTerms,
        body: &BandedBody,
        floor_cm: DVec2,
    ) -> Option<SilhouetteFit> {
        let shift = DVec3::new(floor_cm.x, 0.0, floor_cm.y);
        self.renderer.render_into(&body.body, shift, &mut self.silhouette);
        if body.band_px <= 0.0 {
            return terms.fit(&self.silhouette);
        }
        self.renderer.render_into(&body.widened, shift, &mut self.band_silhouette);
        terms.fit_in_band(&self.silhouette, &self.band_silhouette, body.band_px)
    }

    /// The fit of `body` alone at `floor_cm` (no band).
    pub fn plain_fit(
        &mut self,
        terms: &FrameTerms,
        body: &PosedBody,
        floor_cm: DVec2,
    ) -> Option<SilhouetteFit> {
        self.renderer.render_into(body, DVec3::new(floor_cm.x, 0.0, floor_cm.y), &mut self.silhouette);
        terms.fit(&self.silhouette)
    }
}

impl SilhouetteFit {
    /// The fused energy (px): the truncated contour distance, plus the area
    /// off the foreground weighed by `mask_weight`, plus the uncovered band
    /// weighed by `uncovered_weight`.
    pub fn fused_energy(&self, mask_weight: f64, uncovered_weight: f64) -> f64 {
        self.truncated_chamfer_px + mask_weight * self.outside_px + uncovered_weight * self.uncovered_px
    }

    /// How far the fit can be trusted, 0 to 1: the geometric mean of the
    /// contour's share on edges and the area's share on the foreground.
    pub fn confidence(&self) -> f64 {
        (self.near_edge_share * self.on_foreground_share).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::ImageSize;
    use crate::image::PixelBox;
    use crate::track::silhouette::Span;

    /// Spans reaching past the columns and rows the prefix sums keep, on
    /// either side, sum to what their pixels one by one do, to the bit.
    #[test]
    fn spans_beyond_the_kept_pixels_sum_as_their_pixels_do() {
        let (w, h) = (12u32, 5u32);
        let truncation_px = 2.5f32;
        // Near the foreground (columns 4–7 of rows 1–3) the distances are
        // below the truncation; elsewhere above it.
        let distance_px: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                if (4..8).contains(&x) && (1..4).contains(&y) {
                    [0.0, 1.0, 2f32.sqrt(), 5f32.sqrt()][x as usize % 4]
                } else {
                    7.0
                }
            })
            .collect();
        let on: Vec<bool> = (0..w * h).map(|i| distance_px[i as usize] == 0.0).collect();
        let outside = DistanceImage { width_px: w, height_px: h, distance_px };
        let foreground = Mask { width_px: w, height_px: h, on };
        let terms = FrameTerms::new(&outside, &outside, &foreground, truncation_px);
        let spans = vec![
            Span { row: 0, start: 1, end: 11 },
            Span { row: 1, start: 0, end: 5 },
            Span { row: 1, start: 6, end: 12 },
            Span { row: 2, start: 2, end: 9 },
            Span { row: 3, start: 5, end: 7 },
            Span { row: 4, start: 3, end: 10 },
        ];
        let silhouette = Silhouette {
            image_size: ImageSize { width_px: w, height_px: h },
            bounds: PixelBox { left: 0, top: 0, right: w, bottom: h },
            spans: spans.clone(),
            skipped: 0,
        };
        let fit = terms.fit(&silhouette).unwrap();
        let (mut sum, mut area, mut on) = (0.0f64, 0usize, 0usize);
        for span in &spans {
            for x in span.start..span.end {
                let i = (span.row * w + x) as usize;
                sum += outside.distance_px[i].min(truncation_px) as f64;
                on += usize::from(foreground.on[i]);
                area += 1;
            }
        }
        assert_eq!(fit.outside_px.to_bits(), (sum / area as f64).to_bits());
        assert_eq!(fit.on_foreground_share, on as f64 / area as f64);
    }
}
