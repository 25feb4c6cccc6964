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
    /// The rows `prefix_top..prefix_top + prefix_rows` hold all the
    /// foreground and every distance outside it below the truncation; in
    /// every other row the truncated distance is the truncation itself and
    /// nothing is foreground, so a span there costs a multiplication (and,
    /// the truncation being an f32, exactly what a sum of its pixels would).
    prefix_top: usize,
    prefix_rows: usize,
    /// Per row of those, the prefix sums of the truncated distance outside
    /// the foreground: `outside_prefix[(y − prefix_top) * (w + 1) + x]` sums
    /// columns `0..x` of row `y`, so a span costs one subtraction.
    outside_prefix: Vec<f64>,
    /// Per row of those, the prefix counts of foreground pixels, likewise.
    foreground_prefix: Vec<u32>,
    truncation_px: f32,
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
        let near = |y: usize| {
            outside_distance.distance_px[y * w..(y + 1) * w].iter().any(|&d| d < truncation_px)
                || foreground.on[y * w..(y + 1) * w].iter().any(|&on| on)
        };
        let (prefix_top, prefix_rows) = match ((0..h).find(|&y| near(y)), (0..h).rev().find(|&y| near(y))) {
            (Some(top), Some(bottom)) => (top, bottom + 1 - top),
            _ => (0, 0),
        };
        let mut outside_prefix = vec![0.0; (w + 1) * prefix_rows];
        let mut foreground_prefix = vec![0u32; (w + 1) * prefix_rows];
        for k in 0..prefix_rows {
            let y = prefix_top + k;
            let (row, prefix) = (&outside_distance.distance_px[y * w..(y + 1) * w], k * (w + 1));
            for x in 0..w {
                outside_prefix[prefix + x + 1] =
                    outside_prefix[prefix + x] + row[x].min(truncation_px) as f64;
                foreground_prefix[prefix + x + 1] =
                    foreground_prefix[prefix + x] + foreground.on[y * w + x] as u32;
            }
        }
        FrameTerms {
            width_px: edge_distance.width_px,
            height_px: edge_distance.height_px,
            edge_distance_px: &edge_distance.distance_px,
            prefix_top,
            prefix_rows,
            outside_prefix,
            foreground_prefix,
            truncation_px,
        }
    }

    /// The index of row `row`'s prefix sums, `None` for a row beyond them.
    fn prefix_row(&self, row: u32) -> Option<usize> {
        let k = (row as usize).checked_sub(self.prefix_top)?;
        (k < self.prefix_rows).then(|| k * (self.width_px as usize + 1))
    }

    /// How `silhouette` fits; `None` when it covers no pixel of the image.
    pub fn fit(&self, silhouette: &Silhouette) -> Option<SilhouetteFit> {
        if silhouette.image_size.width_px != self.width_px
            || silhouette.image_size.height_px != self.height_px
        {
            return None;
        }
        let contour = silhouette.contour();
        if contour.is_empty() {
            return None;
        }
        let w = self.width_px as usize;
        let (mut chamfer, mut truncated, mut near) = (0.0f64, 0.0f64, 0usize);
        for [x, y] in &contour {
            let d = self.edge_distance_px[*y as usize * w + *x as usize];
            chamfer += d as f64;
            truncated += d.min(self.truncation_px) as f64;
            near += usize::from(d <= NEAR_EDGE_PX);
        }
        let mut outside = 0.0f64;
        for span in &silhouette.spans {
            outside += match self.prefix_row(span.row) {
                Some(row) => {
                    self.outside_prefix[row + span.end as usize]
                        - self.outside_prefix[row + span.start as usize]
                }
                None => (span.end - span.start) as f64 * self.truncation_px as f64,
            };
        }
        let (on_foreground, area) = self.foreground_under(silhouette);
        let n = contour.len() as f64;
        Some(SilhouetteFit {
            contour_px: contour.len(),
            chamfer_px: chamfer / n,
            truncated_chamfer_px: truncated / n,
            outside_px: outside / area.max(1) as f64,
            near_edge_share: near as f64 / n,
            on_foreground_share: on_foreground as f64 / area.max(1) as f64,
            uncovered_px: 0.0,
        })
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
        let fit = self.fit(silhouette)?;
        if widened.image_size != silhouette.image_size {
            return Some(fit);
        }
        let (inner_on, inner_area) = self.foreground_under(silhouette);
        let (outer_on, outer_area) = self.foreground_under(widened);
        let band_area = outer_area.saturating_sub(inner_area);
        let band_on = outer_on.saturating_sub(inner_on);
        let uncovered_px = if band_area == 0 { 0.0 } else { band_on as f64 / band_area as f64 * band_px };
        Some(SilhouetteFit { uncovered_px, ..fit })
    }

    /// The foreground pixels under `silhouette`, and its area (px).
    fn foreground_under(&self, silhouette: &Silhouette) -> (u64, u64) {
        let (mut on, mut area) = (0u64, 0u64);
        for span in &silhouette.spans {
            if let Some(row) = self.prefix_row(span.row) {
                on += (self.foreground_prefix[row + span.end as usize]
                    - self.foreground_prefix[row + span.start as usize]) as u64;
            }
            area += (span.end - span.start) as u64;
        }
        (on, area)
    }
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
