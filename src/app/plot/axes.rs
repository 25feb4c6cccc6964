//! The axes: how data maps to pixels (the shared time axis, a series panel's
//! value scale, the top view's floor), the data ranges they fit, and the
//! "nice" numbered ticks along them.

use glam::DVec3;

use super::figure::Rect;
use super::layout::TICK_FONT;
use super::{PlotData, TextMeasure};
use crate::body::feet::PerFoot;

/// Evenly spaced "nice" values in `lo..=hi`: the multiples of a step of 1, 2
/// or 5 × 10^k, the smallest such step giving at most `max_count` of them.
/// Returns the values and the step; no values for an empty or non-finite
/// range.
pub(super) fn nice_ticks(lo: f64, hi: f64, max_count: usize) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) || max_count < 2 {
        return (Vec::new(), 0.0);
    }
    // No step below span / max_count can do; try the nice steps upwards from
    // there (a step of span / (max_count - 1) always does, so few are tried).
    let mut magnitude = libm::pow(10.0, libm::log10(span / max_count as f64).floor());
    for _ in 0..4 {
        for step in [1.0, 2.0, 5.0].map(|m| m * magnitude) {
            match multiples(lo, hi, step, max_count) {
                Some(ticks) => return (ticks, step),
                None if step.is_finite() && step > 0.0 => {}
                None => return (Vec::new(), 0.0),
            }
        }
        magnitude *= 10.0;
    }
    (Vec::new(), 0.0)
}

/// The multiples of `step` in `lo..=hi`, or `None` when there are more than
/// `max_count` of them or `step` is not a positive finite number.
pub(super) fn multiples(lo: f64, hi: f64, step: f64, max_count: usize) -> Option<Vec<f64>> {
    if !(step.is_finite() && step > 0.0) {
        return None;
    }
    let (first, last) = ((lo / step).ceil(), (hi / step).floor());
    if !(first.is_finite() && last.is_finite()) {
        return None;
    }
    let count = if last < first { 0.0 } else { last - first + 1.0 };
    (count <= max_count as f64).then(|| (0..count as usize).map(|i| (first + i as f64) * step).collect())
}

/// `value` written with as many decimals as `step` needs, and never as "-0".
pub(super) fn tick_label(value: f64, step: f64) -> String {
    let decimals = (-libm::log10(step) - 1e-9).ceil().clamp(0.0, 12.0) as usize;
    let value = if value.abs() < step * 1e-6 { 0.0 } else { value };
    format!("{value:.decimals$}")
}

/// Nice ticks in `lo..=hi` along a horizontal axis drawn at `px_per_unit`,
/// as many as fit without their labels (measured by `text`) running into each
/// other.
pub(super) fn x_ticks(
    lo: f64,
    hi: f64,
    px_per_unit: f64,
    font_px: f32,
    text: TextMeasure,
) -> (Vec<f64>, f64) {
    let tick_px = TICK_FONT * font_px;
    let length_px = ((hi - lo) * px_per_unit) as f32;
    // Labels are a few characters wide: start from one per 3 font sizes and
    // thin out until the widest label, plus a gap, fits between ticks.
    let mut budget = tick_budget(length_px, 3.0 * font_px);
    loop {
        let (ticks, step) = nice_ticks(lo, hi, budget);
        let widest = ticks.iter().map(|t| text.width_px(&tick_label(*t, step), tick_px)).fold(0.0, f32::max);
        if widest + font_px <= (step * px_per_unit) as f32 || budget <= 2 {
            return (ticks, step);
        }
        budget -= 1;
    }
}

/// How many ticks fit along `length_px` if each needs `spacing_px`.
pub(super) fn tick_budget(length_px: f32, spacing_px: f32) -> usize {
    let n = (length_px / spacing_px).floor();
    if n.is_finite() && n >= 1.0 { (n as usize).saturating_add(1).min(50) } else { 2 }
}

/// The time panels' horizontal mapping, shared so that one cursor lines up
/// across them: frame 0 at the plot's left edge, the last frame at its right
/// edge (a single frame sits in the middle).
#[derive(Clone, Copy, Debug)]
pub(super) struct TimeAxis {
    pub(super) frames: usize,
    /// `None` when the frame rate is unusable: the axis then counts frames.
    pub(super) fps: Option<f64>,
}

impl TimeAxis {
    pub(super) fn new(data: &PlotData) -> TimeAxis {
        let fps = (data.fps.is_finite() && data.fps > 0.0).then_some(data.fps);
        TimeAxis { frames: data.frame_count(), fps }
    }

    /// The x of (possibly fractional) frame `frame` in `plot`.
    pub(super) fn x(&self, plot: Rect, frame: f64) -> f32 {
        if self.frames <= 1 {
            return plot.x + plot.w / 2.0;
        }
        plot.x + plot.w * (frame / (self.frames - 1) as f64) as f32
    }

    /// The frame whose x in `plot` is nearest to `x` (clamped to the plot).
    pub(super) fn frame_at(&self, plot: Rect, x: f32) -> usize {
        let u = (x - plot.x) / plot.w;
        if self.frames <= 1 || !u.is_finite() {
            return 0;
        }
        (f64::from(u.clamp(0.0, 1.0)) * (self.frames - 1) as f64).round() as usize
    }

    /// The pixel column (of `columns` across the plot) the (possibly
    /// fractional, not negative) frame `frame` falls in.
    pub(super) fn column(&self, frame: f64, columns: usize) -> usize {
        if self.frames <= 1 {
            return 0;
        }
        // f64: frames × columns overflows a 32-bit usize for long
        // recordings. Exact for whole frames: the product is a whole number
        // well below 2^53, and a correctly rounded quotient floors as the
        // integer division does.
        let c = (frame * columns as f64 / (self.frames - 1) as f64).floor();
        (c.max(0.0) as usize).min(columns.saturating_sub(1))
    }

    /// Tick positions (in frames) and labels (in seconds, or frames without a
    /// frame rate) for a plot `plot_w` pixels wide, labels measured by `text`.
    pub(super) fn ticks(&self, plot_w: f32, font_px: f32, text: TextMeasure) -> Vec<(f64, String)> {
        match self.frames {
            0 => Vec::new(),
            1 => vec![(0.0, "0".to_string())],
            n => {
                let frames_per_unit = self.fps.unwrap_or(1.0);
                let end = (n - 1) as f64 / frames_per_unit;
                let (ticks, step) = x_ticks(0.0, end, f64::from(plot_w) / end, font_px, text);
                ticks.into_iter().map(|t| (t * frames_per_unit, tick_label(t, step))).collect()
            }
        }
    }

    /// The axis title, with its unit.
    pub(super) fn title(&self) -> &'static str {
        if self.fps.is_some() { "time (s)" } else { "frame" }
    }
}

/// The vertical mapping of a series panel: `lo` at the plot's bottom, `hi` at its top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ValueScale {
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl ValueScale {
    /// The range of the finite values of both feet's `series`, widened by 5%
    /// of it on each side so lines clear the frame; a flat series gets ±5% of
    /// its value (at least ±0.5), no data 0–1.
    pub(super) fn of(series: &PerFoot<Vec<f64>>) -> ValueScale {
        let (lo, hi) = padded_range(finite_range(&[&series.left, &series.right]));
        ValueScale { lo, hi }
    }

    /// From 0 up to the largest finite value of `series`, widened by 5% so
    /// lines clear the frame: for distances, which start at none. 0–1
    /// without a positive value.
    pub(super) fn from_zero(series: &[&[f64]]) -> ValueScale {
        let hi = finite_range(series).map_or(0.0, |(_, hi)| hi);
        ValueScale { lo: 0.0, hi: if hi > 0.0 { 1.05 * hi } else { 1.0 } }
    }

    /// The y of `value` in `plot`.
    pub(super) fn y(self, plot: Rect, value: f64) -> f32 {
        // Halved so that even a range of ±1e308 does not overflow.
        let u = (value / 2.0 - self.lo / 2.0) / (self.hi / 2.0 - self.lo / 2.0);
        plot.bottom() - plot.h * u as f32
    }
}

/// The smallest and largest finite values of all `series`, or `None` when
/// there are none.
///
/// The cursor recomputes this over every series each frame, so it is written
/// to be fast: eight independent running minima and maxima (no dependency
/// chain through one accumulator, and a shape the optimiser vectorises), and
/// comparisons, which are false for NaN, instead of `f64::min`/`max`.
fn finite_range(series: &[&[f64]]) -> Option<(f64, f64)> {
    const LANES: usize = 8;
    let (mut lo, mut hi) = ([f64::INFINITY; LANES], [f64::NEG_INFINITY; LANES]);
    for values in series {
        let chunks = values.chunks_exact(LANES);
        for &v in chunks.remainder() {
            widen(&mut lo[0], &mut hi[0], v);
        }
        for chunk in chunks {
            for i in 0..LANES {
                let v = chunk[i];
                let finite = v.is_finite();
                lo[i] = if finite && v < lo[i] { v } else { lo[i] };
                hi[i] = if finite && v > hi[i] { v } else { hi[i] };
            }
        }
    }
    let lo = lo.into_iter().fold(f64::INFINITY, f64::min);
    let hi = hi.into_iter().fold(f64::NEG_INFINITY, f64::max);
    (lo <= hi).then_some((lo, hi))
}

/// The corners (X and Z; Y is 0) of the floor area the points of `paths`
/// whose X and Z are both finite cover, or `None` when there are none. Fast
/// for the same reasons as [`finite_range`].
fn floor_range(paths: &[&Vec<DVec3>]) -> Option<(DVec3, DVec3)> {
    const LANES: usize = 4;
    let (mut lo_x, mut hi_x) = ([f64::INFINITY; LANES], [f64::NEG_INFINITY; LANES]);
    let (mut lo_z, mut hi_z) = ([f64::INFINITY; LANES], [f64::NEG_INFINITY; LANES]);
    for path in paths {
        let chunks = path.chunks_exact(LANES);
        let lanes =
            chunks.remainder().iter().map(|p| (0, p)).chain(chunks.flat_map(|c| c.iter().enumerate()));
        for (i, p) in lanes {
            let finite = p.x.is_finite() && p.z.is_finite();
            lo_x[i] = if finite && p.x < lo_x[i] { p.x } else { lo_x[i] };
            hi_x[i] = if finite && p.x > hi_x[i] { p.x } else { hi_x[i] };
            lo_z[i] = if finite && p.z < lo_z[i] { p.z } else { lo_z[i] };
            hi_z[i] = if finite && p.z > hi_z[i] { p.z } else { hi_z[i] };
        }
    }
    let min = |v: [f64; LANES]| v.into_iter().fold(f64::INFINITY, f64::min);
    let max = |v: [f64; LANES]| v.into_iter().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = (DVec3::new(min(lo_x), 0.0, min(lo_z)), DVec3::new(max(hi_x), 0.0, max(hi_z)));
    (lo.x <= hi.x).then_some((lo, hi))
}

/// Widens `lo..=hi` to take in `v` when `v` is finite.
fn widen(lo: &mut f64, hi: &mut f64, v: f64) {
    if v < *lo && v > f64::NEG_INFINITY {
        *lo = v;
    }
    if v > *hi && v < f64::INFINITY {
        *hi = v;
    }
}

/// See [`ValueScale::of`]; the result is finite with `lo < hi`.
fn padded_range(range: Option<(f64, f64)>) -> (f64, f64) {
    let Some((lo, hi)) = range else { return (0.0, 1.0) };
    let half_span = hi / 2.0 - lo / 2.0;
    let pad = if half_span > 0.0 { half_span * 0.1 } else { (lo.abs() * 0.05).max(0.5) };
    let (a, b) = (lo - pad, hi + pad);
    if a.is_finite() && b.is_finite() && a < b {
        (a, b)
    } else if lo < hi {
        (lo, hi)
    } else if (lo - 2.0 * pad).is_finite() {
        (lo - 2.0 * pad, hi)
    } else {
        (lo, hi + 2.0 * pad)
    }
}

/// The top view's mapping from the floor (X, Z in cm) to pixels: the same
/// scale on both axes, the data centred in the plot, X to the right and Z
/// down — the floor as seen from above with Y up (right-handed), so the path
/// is not mirrored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TopView {
    pub(super) center_x_cm: f64,
    pub(super) center_z_cm: f64,
    pub(super) px_per_cm: f64,
    pub(super) plot: Rect,
}

/// Half the smallest floor area the top view shows, so a hips path that
/// barely moves is not magnified into noise.
const TOP_VIEW_MIN_HALF_CM: f64 = 25.0;

impl TopView {
    /// Fits every finite point of the hips paths (the camera's too) in
    /// `plot`, with 6% to spare.
    pub(super) fn new(data: &PlotData, plot: Rect) -> TopView {
        let range = floor_range(&[&data.hips_before_cm, &data.hips_after_cm, &data.camera.hips_cm]);
        let center_half = |range: Option<(f64, f64)>| match range {
            // Halves: no overflow even for ±1e308.
            Some((lo, hi)) => {
                let half = ((hi / 2.0 - lo / 2.0) * 1.06).min(f64::MAX);
                (lo / 2.0 + hi / 2.0, half.max(TOP_VIEW_MIN_HALF_CM))
            }
            None => (0.0, TOP_VIEW_MIN_HALF_CM),
        };
        let (center_x_cm, half_x) = center_half(range.map(|(lo, hi)| (lo.x, hi.x)));
        let (center_z_cm, half_z) = center_half(range.map(|(lo, hi)| (lo.z, hi.z)));
        let px_per_cm = (f64::from(plot.w) / 2.0 / half_x).min(f64::from(plot.h) / 2.0 / half_z);
        TopView { center_x_cm, center_z_cm, px_per_cm, plot }
    }

    /// Where `p` is drawn, or `None` when it is not finite there.
    pub(super) fn px_of(&self, p: DVec3) -> Option<(f32, f32)> {
        let (cx, cy) = self.plot.center();
        let x = cx + ((p.x - self.center_x_cm) * self.px_per_cm) as f32;
        let y = cy + ((p.z - self.center_z_cm) * self.px_per_cm) as f32;
        (x.is_finite() && y.is_finite()).then_some((x, y))
    }

    /// The X range (cm) visible across the plot.
    pub(super) fn visible_x_cm(&self) -> (f64, f64) {
        let half = f64::from(self.plot.w) / 2.0 / self.px_per_cm;
        (self.center_x_cm - half, self.center_x_cm + half)
    }

    /// The Z range (cm) visible down the plot.
    pub(super) fn visible_z_cm(&self) -> (f64, f64) {
        let half = f64::from(self.plot.h) / 2.0 / self.px_per_cm;
        (self.center_z_cm - half, self.center_z_cm + half)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::plot::testing::*;
    use crate::app::plot::*;
    use crate::app::theme;

    #[test]
    fn ticks_are_nice() {
        let (ticks, step) = nice_ticks(0.0, 26.9, 6);
        assert_eq!(step, 5.0);
        assert_eq!(ticks, [0.0, 5.0, 10.0, 15.0, 20.0, 25.0]);
        let (ticks, step) = nice_ticks(-0.37, 0.52, 10);
        assert_eq!(step, 0.1);
        let labels: Vec<String> = ticks.iter().map(|t| tick_label(*t, step)).collect();
        assert_eq!(labels, ["-0.3", "-0.2", "-0.1", "0.0", "0.1", "0.2", "0.3", "0.4", "0.5"]);
        assert_eq!(nice_ticks(3.0, 1480.0, 4).1, 500.0);
        assert_eq!(tick_label(1e-17, 0.2), "0.0");
        assert_eq!(tick_label(-1e-17, 2.0), "0");
        assert_eq!(tick_label(0.05, 0.05), "0.05");
        for (lo, hi) in [(0.0, 0.0), (1.0, f64::NAN), (-f64::MAX, f64::MAX), (1e300, 1e300 * (1.0 + 1e-15))] {
            assert!(nice_ticks(lo, hi, 6).0.len() <= 7);
        }
    }

    #[test]
    fn the_top_view_keeps_equal_scale() {
        // An ellipse 300 cm across X and 100 cm across Z.
        let n = 720;
        let ellipse: Vec<DVec3> = (0..n)
            .map(|f| {
                let a = f as f64 / n as f64 * std::f64::consts::TAU;
                DVec3::new(500.0 + 150.0 * a.cos(), 90.0, -200.0 + 50.0 * a.sin())
            })
            .collect();
        let data = PlotData {
            fps: 100.0,
            hips_after_cm: ellipse.clone(),
            hips_before_cm: ellipse,
            ..Default::default()
        };
        for (w, h) in SIZES {
            let l = layout(w, h, ESTIMATE);
            let fig = draw_static(&data, &l, ESTIMATE);
            let points: Vec<(f32, f32)> = fig
                .shapes
                .iter()
                .filter_map(|s| match s {
                    // Not the legend's swatch: the path.
                    Shape::Polyline { points, color, .. }
                        if *color == theme::CORRECTED && points.len() > 2 =>
                    {
                        Some(points.clone())
                    }
                    _ => None,
                })
                .flatten()
                .collect();
            let (x0, x1) = points.iter().fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (y0, y1) = points.iter().fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
            let (x_scale, y_scale) = ((x1 - x0) / 300.0, (y1 - y0) / 100.0);
            assert!((x_scale / y_scale - 1.0).abs() < 0.02, "{w}×{h}: {x_scale} vs {y_scale} px/cm");
            // It fills the plot in the tighter direction.
            let plot = l.plot(Panel::TopView);
            assert!((x1 - x0) / plot.w > 0.9 || (y1 - y0) / plot.h > 0.9, "{w}×{h}: small");
            // Seen from above: +Z is down the screen.
            let view = TopView::new(&data, plot);
            let near = view.px_of(DVec3::new(500.0, 0.0, -250.0)).expect("finite");
            let far = view.px_of(DVec3::new(500.0, 0.0, -150.0)).expect("finite");
            assert!(far.1 > near.1);
        }
    }
}
