//! Long series as few shapes: lines broken at gaps, and decimated so that a
//! 100,000-frame recording costs no more to paint than a short one.

use glam::DVec3;

use super::Shape;
use super::axes::{TimeAxis, TopView, ValueScale};
use super::figure::Rect;
use crate::app::theme::Rgba;

/// Builds polylines point by point, breaking them at gaps.
struct Trace {
    color: Rgba,
    width_px: f32,
    dashed: bool,
    current: Vec<(f32, f32)>,
    shapes: Vec<Shape>,
}

impl Trace {
    fn new(color: Rgba, width_px: f32, dashed: bool) -> Trace {
        Trace { color, width_px, dashed, current: Vec::new(), shapes: Vec::new() }
    }

    /// Extends the line to `p`, or ends it when `p` is `None` or not finite.
    fn push(&mut self, p: Option<(f32, f32)>) {
        match p {
            Some(p) if p.0.is_finite() && p.1.is_finite() => self.current.push(p),
            _ => self.end(),
        }
    }

    fn end(&mut self) {
        match self.current.len() {
            0 => {}
            // A lone sample between gaps would stroke nothing: show it as a dot.
            1 => {
                let (x, y) = self.current[0];
                self.shapes.push(Shape::Circle { x, y, radius_px: self.width_px, color: self.color });
                self.current.clear();
            }
            _ => self.shapes.push(Shape::Polyline {
                points: std::mem::take(&mut self.current),
                color: self.color,
                width_px: self.width_px,
                dashed: self.dashed,
            }),
        }
    }

    fn finish(mut self) -> Vec<Shape> {
        self.end();
        self.shapes
    }
}

/// The number of whole pixel columns across `w` pixels (at least 1, and
/// capped so an absurd canvas cannot exhaust memory).
pub(super) fn columns_in(w: f32) -> usize {
    let c = w.ceil();
    if c.is_finite() && c >= 1.0 { (c as usize).min(16_384) } else { 1 }
}

/// The series `values[frame]` drawn in `plot`, broken where values are not
/// finite. With more than two frames per pixel column, each column keeps only
/// its lowest and highest value, in frame order: at most two points per
/// column are drawn, and every spike stays visible.
pub(super) fn series_shapes(
    values: &[f64],
    time: &TimeAxis,
    plot: Rect,
    scale: ValueScale,
    color: Rgba,
) -> Vec<Shape> {
    let samples = values.iter().enumerate().map(|(f, &v)| (f as f64, v));
    placed_series_shapes(samples, values.len(), time, plot, scale, color)
}

/// As [`series_shapes`], each of the `len` samples `(frame, value)` at its
/// own (fractional, increasing) frame, such as a video's frames on a
/// recording's time axis. Samples outside the axis's frames are a gap.
pub(super) fn placed_series_shapes(
    samples: impl Iterator<Item = (f64, f64)>,
    len: usize,
    time: &TimeAxis,
    plot: Rect,
    scale: ValueScale,
    color: Rgba,
) -> Vec<Shape> {
    let last = time.frames.saturating_sub(1) as f64;
    let samples = samples.map(|(f, v)| (f, if (0.0..=last).contains(&f) { v } else { f64::NAN }));
    let mut trace = Trace::new(color, 1.5, false);
    let point = |f: f64, v: f64| (time.x(plot, f), scale.y(plot, v));
    let columns = columns_in(plot.w);
    if len <= 2 * columns {
        for (f, v) in samples {
            trace.push(v.is_finite().then(|| point(f, v)));
        }
        return trace.finish();
    }
    // (frame, value) of the lowest and the highest finite value in the column.
    type Extremes = Option<((f64, f64), (f64, f64))>;
    let emit = |trace: &mut Trace, extremes: Extremes| match extremes {
        // A column without a finite value is a gap.
        None => trace.push(None),
        Some((lo, hi)) => {
            let (first, second) = if lo.0 <= hi.0 { (lo, hi) } else { (hi, lo) };
            trace.push(Some(point(first.0, first.1)));
            if second.0 != first.0 {
                trace.push(Some(point(second.0, second.1)));
            }
        }
    };
    let mut column = None;
    let mut extremes: Extremes = None;
    for (f, v) in samples {
        let c = time.column(f, columns);
        if column != Some(c) {
            if column.is_some() {
                emit(&mut trace, extremes.take());
            }
            column = Some(c);
        }
        if v.is_finite() {
            extremes = Some(match extremes {
                None => ((f, v), (f, v)),
                Some((lo, hi)) => (if v < lo.1 { (f, v) } else { lo }, if v > hi.1 { (f, v) } else { hi }),
            });
        }
    }
    emit(&mut trace, extremes);
    trace.finish()
}

/// A hips path in the top view. Points closer than a fraction of a pixel to
/// the last one drawn are skipped (doubling that distance until the path has
/// at most a few points per pixel of the plot's perimeter), so a 100,000-frame
/// path costs no more to paint than a short one. Non-finite points are skipped
/// and the path joined across them: a missing frame does not break a walk.
pub(super) fn path_shapes(
    points: &[DVec3],
    view: &TopView,
    color: Rgba,
    width_px: f32,
    dashed: bool,
) -> Vec<Shape> {
    let limit = 4 * (columns_in(view.plot.w) + columns_in(view.plot.h)) + 64;
    let mut min_step_px = 0.75f32;
    loop {
        let shapes = simplified_path(points, view, Trace::new(color, width_px, dashed), min_step_px);
        let count: usize = shapes.iter().map(point_count).sum();
        if count <= limit || min_step_px > 1e6 {
            return shapes;
        }
        min_step_px *= 2.0;
    }
}

fn simplified_path(points: &[DVec3], view: &TopView, mut trace: Trace, min_step_px: f32) -> Vec<Shape> {
    let mut last_kept: Option<(f32, f32)> = None;
    let mut skipped = None;
    for q in points.iter().filter_map(|p| view.px_of(*p)) {
        let far = last_kept.is_none_or(|k: (f32, f32)| (q.0 - k.0).hypot(q.1 - k.1) >= min_step_px);
        if far {
            trace.push(Some(q));
            last_kept = Some(q);
            skipped = None;
        } else {
            skipped = Some(q);
        }
    }
    // The path ends where the data ends, not at the last point kept.
    if skipped.is_some() {
        trace.push(skipped);
    }
    trace.finish()
}

fn point_count(shape: &Shape) -> usize {
    match shape {
        Shape::Polyline { points, .. } => points.len(),
        _ => 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::plot::testing::*;
    use crate::app::plot::*;
    use crate::app::theme;

    #[test]
    fn long_recordings_are_decimated() {
        let n = 100_000;
        let mut data = synthetic(n);
        // Noise at the frame rate, the worst case for a line, and some gaps.
        for (f, v) in data.foot_signal.left.iter_mut().enumerate() {
            *v += if f % 2 == 0 { 0.5 } else { -0.5 };
        }
        for f in (0..n).step_by(997) {
            data.heights_before_cm.right[f] = f64::NAN;
            data.hips_after_cm[f] = DVec3::NAN;
        }
        for (w, h) in [(400.0, 300.0), (1600.0, 500.0), (990.0, 1100.0)] {
            let l = layout(w, h, ESTIMATE);
            let fig = draw_static(&data, &l, ESTIMATE);
            assert!(all_finite(&fig));
            let points_in = |plot: Rect, colors: &[Rgba]| -> usize {
                fig.shapes
                    .iter()
                    .filter(|s| {
                        let (x, y) = anchor(s);
                        plot.contains(x, y)
                    })
                    .map(|s| match s {
                        Shape::Polyline { points, color, .. } if colors.contains(color) => points.len(),
                        Shape::Circle { color, .. } if colors.contains(color) => 1,
                        _ => 0,
                    })
                    .sum()
            };
            for p in [Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter] {
                let plot = l.plot(p);
                let colors = [
                    theme::FEET.left,
                    theme::FEET.right,
                    theme::FEET.left.with_alpha(theme::BEFORE_ALPHA),
                    theme::FEET.right.with_alpha(theme::BEFORE_ALPHA),
                ];
                let points = points_in(plot, &colors);
                let bound = 2 * 2 * (plot.w.ceil() as usize + 1);
                assert!(
                    points <= bound && points > plot.w as usize,
                    "{p:?} at {w}×{h}: {points} points, bound {bound}"
                );
            }
            let top = l.plot(Panel::TopView);
            let points = points_in(top, &[theme::ORIGINAL, theme::CORRECTED]);
            let bound = 2 * (4 * (top.w.ceil() + top.h.ceil()) as usize + 64);
            assert!(points <= bound, "top view at {w}×{h}: {points} points, bound {bound}");
            let runs = fig
                .shapes
                .iter()
                .filter(|s| matches!(s, Shape::Rect { y, .. } if *y == l.plot(Panel::Stance).y))
                .count();
            assert!(runs <= l.plot(Panel::Stance).w.ceil() as usize);
            // The whole figure stays small enough to paint in a few milliseconds.
            assert!(fig.shapes.len() < 2000, "{} shapes", fig.shapes.len());
        }
    }

    #[test]
    fn decimation_keeps_spikes() {
        let n = 50_000;
        let mut data = synthetic(n);
        data.foot_signal.right[31_234] = 40.0;
        let l = layout(400.0, 300.0, ESTIMATE);
        let fig = draw_static(&data, &l, ESTIMATE);
        let plot = l.plot(Panel::FootSignal);
        let top = fig
            .shapes
            .iter()
            .filter_map(|s| match s {
                // Not the legend's swatch: a line of the series.
                Shape::Polyline { points, color, .. } if *color == theme::FEET.right && points.len() > 2 => {
                    points.iter().map(|p| p.1).reduce(f32::min)
                }
                _ => None,
            })
            .reduce(f32::min)
            .expect("the right foot's line");
        assert!((top - (plot.y + plot.h * 0.05 / 1.1)).abs() < 1.0, "spike drawn at {top}, plot {plot:?}");
    }
}
