//! Where the panels go on a canvas of a given size, and which panel a point
//! is in: (a) to (e) always, (f) with a camera take.

use super::figure::{Rect, rect};
use super::legend::{STANCE_LEGENDS, flow_legend};
use super::{PlotData, TextMeasure};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Panel {
    /// (a) the smoothed foot signal.
    FootSignal,
    /// (b) foot heights before correction.
    HeightsBefore,
    /// (c) foot heights after correction.
    HeightsAfter,
    /// (d) the hips' path on the floor, from above.
    TopView,
    /// (e) the stance strip.
    Stance,
    /// (f) with a camera take: its stated uncertainty per video frame, and
    /// its error against a truth. Laid out between (c) and (e).
    Camera,
}

impl Panel {
    /// All panels, (a) to (f).
    pub const ALL: [Panel; 6] = [
        Panel::FootSignal,
        Panel::HeightsBefore,
        Panel::HeightsAfter,
        Panel::TopView,
        Panel::Stance,
        Panel::Camera,
    ];

    /// 0 for (a) to 5 for (f).
    pub fn index(self) -> usize {
        match self {
            Panel::FootSignal => 0,
            Panel::HeightsBefore => 1,
            Panel::HeightsAfter => 2,
            Panel::TopView => 3,
            Panel::Stance => 4,
            Panel::Camera => 5,
        }
    }

    /// True for the panels plotted against time, which share the time axis.
    pub fn is_time(self) -> bool {
        self != Panel::TopView
    }
}

/// Where one panel sits: `outer` holds everything it draws (title, legend,
/// axis labels), `plot` is the data area inside it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PanelRects {
    pub outer: Rect,
    pub plot: Rect,
}

/// Where each panel sits on a canvas; see [`layout`].
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub width: f32,
    pub height: f32,
    /// Size of titles, legends and axis titles in pixels; tick labels are a
    /// little smaller. It follows the canvas size, so it also follows the
    /// device pixel ratio of a canvas sized in device pixels.
    pub font_px: f32,
    /// True when the top view (d) sits right of the time panels, false when
    /// it sits below them.
    pub side_by_side: bool,
    /// True when (f), the camera take's panel, is laid out.
    pub camera_shown: bool,
    panels: [PanelRects; 6],
}

impl Layout {
    /// The panels laid out: (a) to (e), and (f) with a camera take.
    pub fn shown(&self) -> impl Iterator<Item = Panel> + '_ {
        Panel::ALL.into_iter().filter(|&p| p != Panel::Camera || self.camera_shown)
    }

    /// The rectangles of `panel`.
    pub fn panel(&self, panel: Panel) -> PanelRects {
        self.panels[panel.index()]
    }

    /// The data area of `panel`.
    pub fn plot(&self, panel: Panel) -> Rect {
        self.panel(panel).plot
    }

    /// The data areas of (a) to (f) as `[x, y, w, h]` each, flattened (24
    /// numbers; (f) is all zero without a camera take), for JavaScript and
    /// browser tests.
    pub fn plot_rects_xywh(&self) -> Vec<f32> {
        self.panels.iter().flat_map(|p| [p.plot.x, p.plot.y, p.plot.w, p.plot.h]).collect()
    }
}

// Layout geometry, in units of the font size.
/// Space between the canvas edge and the panels.
const PAD: f32 = 0.6;
/// Space between panels.
const GAP: f32 = 0.8;
/// The title row on top of each panel.
pub(super) const HEADER: f32 = 1.5;
/// Left of a plot: the vertical axis title and the tick labels (about six
/// characters of tick font).
const MARGIN_LEFT: f32 = 4.9;
/// Right of a plot: room for half of the last x tick label.
const MARGIN_RIGHT: f32 = 1.2;
/// Under a plot with a numbered x axis: a row of tick labels, a row for the title.
pub(super) const AXIS_ROW: f32 = 1.4;
/// Height of the stance strip's bar.
const STRIP: f32 = 1.8;
/// One row of the stance legend.
pub(super) const LEGEND_ROW: f32 = 1.5;
/// Tick labels are this much smaller than the rest.
pub(super) const TICK_FONT: f32 = 0.9;
/// The top view goes beside the time panels when the canvas is at least this
/// many times wider than tall: then the time panels keep their width and the
/// top view gets the full height.
const SIDE_BY_SIDE_ASPECT: f32 = 1.15;

/// Lays (a) to (e) out on a `width` × `height` pixel canvas, with text
/// measured by `text`: the plots of a recording without a camera take.
pub fn layout(width: f32, height: f32, text: TextMeasure) -> Layout {
    layout_panels(width, height, false, text)
}

/// Lays out the panels `data` fills: (f) too when it holds a camera take.
pub fn layout_for(data: &PlotData, width: f32, height: f32, text: TextMeasure) -> Layout {
    layout_panels(width, height, data.camera.has_video_frames(), text)
}

/// Lays the panels out on a `width` × `height` pixel canvas, with text
/// measured by `text`, (f) among them when `camera_shown`.
///
/// The time panels (a), (b), (c), (f) and (e) are stacked in one column with
/// their plot areas aligned, so that they share a time axis (numbered under
/// (e)), and the top view (d) goes beside them when the canvas is wide
/// ([`Layout::side_by_side`]), as square as the height allows but at most 45%
/// of the width, or below them when it is not, taking up to 36% of the
/// height. The stance bar and all the text have fixed sizes in units of
/// [`Layout::font_px`], which follows the canvas size; (a), (b), (c) and (f)
/// share what height is left equally.
///
/// Sizes that are not finite or below 1 are taken as 1; on a canvas too small
/// for the margins, plot areas shrink to zero size rather than go negative.
fn layout_panels(width: f32, height: f32, camera_shown: bool, text: TextMeasure) -> Layout {
    let sane = |v: f32| if v.is_finite() && v >= 1.0 { v } else { 1.0 };
    let (width, height) = (sane(width), sane(height));
    let f = (width / 44.0).min(height / 40.0).clamp(9.0, 24.0);
    let inner = rect(PAD * f, PAD * f, width - 2.0 * PAD * f, height - 2.0 * PAD * f);
    let gap = GAP * f;
    let side_by_side = width >= SIDE_BY_SIDE_ASPECT * height;
    let (time_column, top) = if side_by_side {
        let square_plot = inner.h - (HEADER + 2.0 * AXIS_ROW) * f;
        let w = (square_plot + (MARGIN_LEFT + MARGIN_RIGHT) * f).min(0.45 * (inner.w - gap)).max(0.0);
        (rect(inner.x, inner.y, inner.w - gap - w, inner.h), rect(inner.right() - w, inner.y, w, inner.h))
    } else {
        let square_plot = inner.w - (MARGIN_LEFT + MARGIN_RIGHT) * f;
        let h = (square_plot + (HEADER + 2.0 * AXIS_ROW) * f).min(0.36 * (inner.h - gap)).max(0.0);
        (rect(inner.x, inner.y, inner.w, inner.h - gap - h), rect(inner.x, inner.bottom() - h, inner.w, h))
    };

    let mut panels = [PanelRects::default(); 6];
    let plot_in = |outer: Rect, below: f32| {
        rect(
            outer.x + MARGIN_LEFT * f,
            outer.y + HEADER * f,
            outer.w - (MARGIN_LEFT + MARGIN_RIGHT) * f,
            outer.h - HEADER * f - below,
        )
    };
    let legend_rows =
        STANCE_LEGENDS.iter().map(|legend| flow_legend(legend, time_column.w, f, text).1).max().unwrap_or(0);
    let stance_h = (HEADER + STRIP + 2.0 * AXIS_ROW + LEGEND_ROW * legend_rows as f32) * f;
    let series: &[Panel] = if camera_shown {
        &[Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter, Panel::Camera]
    } else {
        &[Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter]
    };
    let n = series.len() as f32;
    let series_plot_h = ((time_column.h - stance_h - n * gap - n * HEADER * f) / n).max(0.0);
    let mut y = time_column.y;
    for &panel in series {
        let outer = rect(time_column.x, y, time_column.w, HEADER * f + series_plot_h);
        panels[panel.index()] = PanelRects { outer, plot: plot_in(outer, 0.0) };
        y = outer.bottom() + gap;
    }
    // On a canvas too short for everything, the strip is cut at the bottom.
    let outer = rect(time_column.x, y, time_column.w, stance_h.min(time_column.bottom() - y));
    let plot = rect(
        outer.x + MARGIN_LEFT * f,
        outer.y + HEADER * f,
        outer.w - (MARGIN_LEFT + MARGIN_RIGHT) * f,
        STRIP * f,
    );
    panels[Panel::Stance.index()] = PanelRects { outer, plot };
    panels[Panel::TopView.index()] = PanelRects { outer: top, plot: plot_in(top, 2.0 * AXIS_ROW * f) };
    Layout { width, height, font_px: f, side_by_side, camera_shown, panels }
}

/// The panel whose area (title and labels included) holds (`x`, `y`).
pub fn panel_at(layout: &Layout, x: f32, y: f32) -> Option<Panel> {
    layout.shown().find(|&p| layout.panel(p).outer.contains(x, y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::plot::testing::*;
    use crate::app::plot::*;

    #[test]
    fn panels_fit_the_canvas_and_do_not_overlap() {
        for (w, h) in SIZES {
            for data in [synthetic(100), synthetic_with_camera(100)] {
                let l = layout_for(&data, w, h, ESTIMATE);
                assert_eq!(l.shown().count(), if data.camera.is_shown() { 6 } else { 5 });
                for p in l.shown() {
                    let PanelRects { outer, plot } = l.panel(p);
                    let inside = |r: Rect, within: Rect| {
                        r.x >= within.x - 1e-3
                            && r.y >= within.y - 1e-3
                            && r.right() <= within.right() + 1e-3
                            && r.bottom() <= within.bottom() + 1e-3
                    };
                    assert!(inside(outer, Rect::new(0.0, 0.0, w, h)), "{p:?} {outer:?} outside {w}×{h}");
                    assert!(inside(plot, outer), "{p:?} plot {plot:?} outside {outer:?} at {w}×{h}");
                    assert!(plot.w > 50.0 && plot.h > 10.0, "{p:?} plot {plot:?} too small at {w}×{h}");
                    for q in l.shown().filter(|&q| q != p) {
                        assert!(!outer.overlaps(l.panel(q).outer), "{p:?} overlaps {q:?} at {w}×{h}");
                    }
                }
                // The time panels' plots line up, so one cursor crosses them all.
                let a = l.plot(Panel::FootSignal);
                for p in l.shown().filter(|p| p.is_time()) {
                    assert_eq!((l.plot(p).x, l.plot(p).w), (a.x, a.w));
                }
                assert_eq!(l.plot_rects_xywh().len(), 24);
            }
            // (f) between (c) and (e), and nowhere without a take.
            let l = layout_for(&synthetic_with_camera(100), w, h, ESTIMATE);
            let (c, f, e) = (l.plot(Panel::HeightsAfter), l.plot(Panel::Camera), l.plot(Panel::Stance));
            assert!(c.bottom() < f.y && f.bottom() < e.y, "{w}×{h}");
            let l = layout(w, h, ESTIMATE);
            let f = l.panel(Panel::Camera).outer;
            assert_eq!(panel_at(&l, f.x, f.y), panel_at(&l, f.x, f.y).filter(|&p| p != Panel::Camera));
        }
        assert!(layout(1600.0, 500.0, ESTIMATE).side_by_side);
        assert!(!layout(495.0, 550.0, ESTIMATE).side_by_side);
    }

    #[test]
    fn degenerate_canvas_sizes_give_finite_non_negative_rectangles() {
        for (w, h) in
            [(0.0, 0.0), (1.0, 1.0), (f32::NAN, 300.0), (-5.0, f32::INFINITY), (30.0, 20.0), (1e9, 3.0)]
        {
            let l = layout(w, h, ESTIMATE);
            for p in Panel::ALL {
                for r in [l.panel(p).outer, l.plot(p)] {
                    assert!([r.x, r.y, r.w, r.h].iter().all(|v| v.is_finite()), "{w}×{h}: {r:?}");
                    assert!(r.w >= 0.0 && r.h >= 0.0, "{w}×{h}: {r:?}");
                }
            }
            let data = synthetic(50);
            assert!(all_finite(&draw(&data, 10, &l, ESTIMATE)));
            let _ = frame_at(&data, &l, 0.5, 0.5);
        }
    }
}
