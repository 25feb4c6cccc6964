//! Drawing each panel's static part: titles, legends, axes, grids and data.

use super::axes::{TimeAxis, TopView, ValueScale, multiples, nice_ticks, tick_budget, tick_label, x_ticks};
use super::decimate::{columns_in, path_shapes, series_shapes};
use super::figure::{Align, Figure, Rect, TextStyle};
use super::layout::{AXIS_ROW, HEADER, LEGEND_ROW, TICK_FONT};
use super::legend::{
    FEET_BEFORE_LEGEND, FEET_LEGEND, ITEM_GAP, LegendItem, PATH_LEGEND, STANCE_KINDS, draw_legend_item,
    flow_legend, legend_item_width, stance_color, stance_index, stance_legend,
};
use super::{Layout, Panel, PanelRects, PlotData, Stance, TextMeasure};
use crate::app::theme::{self, Rgba};
use crate::body::feet::PerFoot;

/// The panel's header: `legend` flush right (stopping `reserve_px` short of
/// the edge), and left of it the first of `titles` that fits.
fn draw_header(
    fig: &mut Figure,
    outer: Rect,
    (font_px, text): (f32, TextMeasure),
    titles: &[&str],
    legend: &[LegendItem],
    reserve_px: f32,
) {
    let y = outer.y + HEADER * font_px / 2.0;
    let mut right = outer.right() - reserve_px;
    for it in legend.iter().rev() {
        right -= legend_item_width(it, font_px, text);
        draw_legend_item(fig, it, right, y, font_px);
        right -= ITEM_GAP * font_px;
    }
    if let Some(title) = text.fit(titles, right - outer.x, font_px) {
        fig.text(outer.x, y, title, TextStyle::new(theme::TEXT, font_px, Align::Left));
    }
}

/// A vertical axis title, centred beside `plot` in the left margin of `outer`.
fn draw_y_title(
    fig: &mut Figure,
    outer: Rect,
    plot: Rect,
    (font_px, text): (f32, TextMeasure),
    titles: &[&str],
) {
    if let Some(title) = text.fit(titles, plot.h, font_px) {
        let style = TextStyle::new(theme::MUTED_TEXT, font_px, Align::Center).vertical();
        fig.text(outer.x + 0.7 * font_px, plot.y + plot.h / 2.0, title, style);
    }
}

/// How many ticks a vertical axis along `plot` takes: one per this many lines of tick labels.
const Y_TICK_SPACING: f32 = 2.4;

fn y_tick_budget(plot: Rect, font_px: f32) -> usize {
    tick_budget(plot.h, Y_TICK_SPACING * TICK_FONT * font_px)
}

/// Horizontal grid lines and numbered ticks at `ticks` (multiples of
/// `step`), placed by `y_of`.
fn draw_y_ticks(
    fig: &mut Figure,
    plot: Rect,
    font_px: f32,
    (ticks, step): (Vec<f64>, f64),
    y_of: impl Fn(f64) -> f32,
) {
    let tick_px = TICK_FONT * font_px;
    for v in ticks {
        let y = y_of(v);
        if y.is_finite() && y >= plot.y - 0.5 && y <= plot.bottom() + 0.5 {
            fig.segment((plot.x, y), (plot.right(), y), theme::PLOT_GRID, 1.0, false);
            let style = TextStyle::new(theme::MUTED_TEXT, tick_px, Align::Right);
            fig.text(plot.x - 0.35 * font_px, y, tick_label(v, step), style);
        }
    }
}

/// Vertical grid lines at the time ticks, so (a)–(c) can be read against the
/// numbers under (e).
fn draw_time_grid(fig: &mut Figure, plot: Rect, time: &TimeAxis, (font_px, text): (f32, TextMeasure)) {
    for (frame, _) in time.ticks(plot.w, font_px, text) {
        let x = time.x(plot, frame);
        fig.segment((x, plot.y), (x, plot.bottom()), theme::PLOT_GRID, 1.0, false);
    }
}

/// Numbered ticks under `plot` at `ticks` (position in px, label), and the
/// axis title centred below them.
fn draw_x_axis(fig: &mut Figure, plot: Rect, font_px: f32, ticks: &[(f32, String)], title: &str) {
    let tick_px = TICK_FONT * font_px;
    let label_y = plot.bottom() + AXIS_ROW * font_px / 2.0;
    for (x, label) in ticks {
        fig.segment((*x, plot.bottom()), (*x, plot.bottom() + 0.3 * font_px), theme::TICK, 1.0, false);
        fig.text(
            *x,
            label_y + 0.15 * font_px,
            label.clone(),
            TextStyle::new(theme::MUTED_TEXT, tick_px, Align::Center),
        );
    }
    let title_y = plot.bottom() + 1.5 * AXIS_ROW * font_px;
    fig.text(
        plot.x + plot.w / 2.0,
        title_y,
        title,
        TextStyle::new(theme::MUTED_TEXT, font_px, Align::Center),
    );
}

/// What a series panel shows.
struct SeriesPanel<'a> {
    panel: Panel,
    series: &'a PerFoot<Vec<f64>>,
    colors: PerFoot<Rgba>,
    titles: &'a [&'a str],
    y_titles: &'a [&'a str],
    legend: &'a [LegendItem],
}

fn draw_series_panel(fig: &mut Figure, layout: &Layout, time: &TimeAxis, p: &SeriesPanel, text: TextMeasure) {
    let f = layout.font_px;
    let PanelRects { outer, plot } = layout.panel(p.panel);
    fig.fill(plot, theme::PLOT_BACKGROUND);
    let scale = ValueScale::of(p.series);
    draw_time_grid(fig, plot, time, (f, text));
    draw_y_ticks(fig, plot, f, nice_ticks(scale.lo, scale.hi, y_tick_budget(plot, f)), |v| scale.y(plot, v));
    draw_y_title(fig, outer, plot, (f, text), p.y_titles);
    for (foot, values) in p.series.iter() {
        fig.shapes.extend(series_shapes(values, time, plot, scale, p.colors[foot]));
    }
    draw_header(fig, outer, (f, text), p.titles, p.legend, 0.0);
    if time.frames == 0 {
        let style = TextStyle::new(theme::MUTED_TEXT, f, Align::Center);
        let (cx, cy) = plot.center();
        fig.text(cx, cy, text.fit(&["no data"], plot.w, f).unwrap_or_default(), style);
    }
}

fn draw_top_view(fig: &mut Figure, layout: &Layout, data: &PlotData, text: TextMeasure) {
    let f = layout.font_px;
    let PanelRects { outer, plot } = layout.panel(Panel::TopView);
    fig.fill(plot, theme::PLOT_BACKGROUND);
    let view = TopView::new(data, plot);
    let (cx, cy) = plot.center();
    // One step for both axes, the coarser of what each has room for, so the
    // grid is square like the floor it measures; unless that leaves an axis
    // with fewer than three numbers (a long, narrow path), then each its own.
    let ((x_lo, x_hi), (z_lo, z_hi)) = (view.visible_x_cm(), view.visible_z_cm());
    let (x_own, z_own) =
        (x_ticks(x_lo, x_hi, view.px_per_cm, f, text), nice_ticks(z_lo, z_hi, y_tick_budget(plot, f)));
    let common = x_own.1.max(z_own.1);
    let (x_ticks_cm, z_ticks_cm) =
        match (multiples(x_lo, x_hi, common, 50), multiples(z_lo, z_hi, common, 50)) {
            (Some(x), Some(z)) if x.len() >= 3 && z.len() >= 3 => ((x, common), (z, common)),
            _ => (x_own, z_own),
        };
    // Z grid and numbers, left.
    let z_to_px = |z: f64| cy + ((z - view.center_z_cm) * view.px_per_cm) as f32;
    draw_y_ticks(fig, plot, f, z_ticks_cm, z_to_px);
    draw_y_title(fig, outer, plot, (f, text), &["z (cm)", "z"]);
    // X grid and numbers, below.
    let mut labelled = Vec::new();
    let (x_ticks_cm, x_step) = x_ticks_cm;
    for x_cm in x_ticks_cm {
        let x = cx + ((x_cm - view.center_x_cm) * view.px_per_cm) as f32;
        if x.is_finite() {
            fig.segment((x, plot.y), (x, plot.bottom()), theme::PLOT_GRID, 1.0, false);
            labelled.push((x, tick_label(x_cm, x_step)));
        }
    }
    draw_x_axis(fig, plot, f, &labelled, "x (cm)");
    fig.shapes.extend(path_shapes(&data.hips_before_cm, &view, theme::ORIGINAL, 1.5, true));
    fig.shapes.extend(path_shapes(&data.hips_after_cm, &view, theme::CORRECTED, 2.0, false));
    let titles =
        ["(d) hips path on the floor, seen from above", "(d) hips path, from above", "(d) hips path", "(d)"];
    draw_header(fig, outer, (f, text), &titles, &PATH_LEGEND, 0.0);
}

/// The stance bar: one colour per pixel column, the stance most frames in
/// that column have (or, where frames are sparser than pixels, the stance of
/// the frame nearest to the column), merged into runs.
fn draw_stance_bar(fig: &mut Figure, plot: Rect, time: &TimeAxis, stance: &[Stance]) {
    if stance.is_empty() || plot.w.is_nan() || plot.w <= 0.0 {
        return;
    }
    let columns = columns_in(plot.w);
    let mut kinds: Vec<Option<usize>> = vec![None; columns];
    let mut counts = [0u32; STANCE_KINDS.len()];
    let mut column = None;
    let majority = |counts: &[u32; STANCE_KINDS.len()]| {
        let (kind, &count) = counts.iter().enumerate().max_by_key(|(i, c)| (**c, std::cmp::Reverse(*i)))?;
        (count > 0).then_some(kind)
    };
    for (f, s) in stance.iter().enumerate() {
        let c = time.column(f, columns);
        if column != Some(c) {
            if let Some(prev) = column {
                kinds[prev] = majority(&counts);
            }
            counts = [0; STANCE_KINDS.len()];
            column = Some(c);
        }
        counts[stance_index(*s)] += 1;
    }
    if let Some(prev) = column {
        kinds[prev] = majority(&counts);
    }
    let column_w = plot.w / columns as f32;
    if time.frames > 1 {
        for (c, kind) in kinds.iter_mut().enumerate() {
            if kind.is_none() {
                let nearest = time.frame_at(plot, plot.x + (c as f32 + 0.5) * column_w);
                *kind = stance.get(nearest).map(|s| stance_index(*s));
            }
        }
    } else {
        kinds.fill(stance.first().map(|s| stance_index(*s)));
    }
    // Merge equal neighbours into one rectangle each.
    let mut start = 0;
    for c in 1..=columns {
        if c == columns || kinds[c] != kinds[start] {
            if let Some(kind) = kinds[start] {
                let x0 = plot.x + start as f32 * column_w;
                let x1 = plot.x + c as f32 * column_w;
                fig.fill(Rect::new(x0, plot.y, x1 - x0, plot.h), stance_color(STANCE_KINDS[kind]));
            }
            start = c;
        }
    }
}

/// The part of the (e) header the cursor read-out may use: the title stays left of it.
pub(super) fn readout_reserve_px(outer: Rect) -> f32 {
    0.5 * outer.w
}

fn draw_stance_panel(
    fig: &mut Figure,
    layout: &Layout,
    time: &TimeAxis,
    stance: &[Stance],
    text: TextMeasure,
) {
    let f = layout.font_px;
    let PanelRects { outer, plot } = layout.panel(Panel::Stance);
    fig.fill(plot, theme::PLOT_BACKGROUND);
    draw_stance_bar(fig, plot, time, stance);
    let ticks: Vec<(f32, String)> =
        time.ticks(plot.w, f, text).into_iter().map(|(frame, label)| (time.x(plot, frame), label)).collect();
    draw_x_axis(fig, plot, f, &ticks, time.title());
    let (legend, titles) = stance_legend(stance);
    let (placed, _) = flow_legend(legend, outer.w, f, text);
    let legend_top = plot.bottom() + 2.0 * AXIS_ROW * f;
    for (it, (dx, row)) in legend.iter().copied().flatten().zip(placed) {
        let y = legend_top + (row as f32 + 0.5) * LEGEND_ROW * f;
        draw_legend_item(fig, it, outer.x + dx, y, f);
    }
    draw_header(fig, outer, (f, text), titles, &[], readout_reserve_px(outer));
}

/// Everything that does not move with the time cursor: titles, legends,
/// axes with numbered ticks, grids, and the data of all five panels. Long
/// series are decimated (see `series_shapes`, `path_shapes` and
/// `draw_stance_bar`), so the figure stays a few thousand points whatever
/// the recording's length; it is meant to be painted once per recording,
/// settings or size and kept (e.g. in an offscreen canvas). Text is measured
/// by `text`, as it was for `layout`.
pub fn draw_static(data: &PlotData, layout: &Layout, text: TextMeasure) -> Figure {
    let mut fig = Figure::new(layout.width, layout.height);
    let time = TimeAxis::new(data);
    let label = data.foot_signal_label.trim();
    let label = if label.is_empty() { "foot signal" } else { label };
    let signal_title = format!("(a) foot signal: {label}");
    let unit = label.find('(').and_then(|i| label[i..].find(')').map(|j| &label[i..=i + j]));
    let short_label = unit.map_or("signal".to_string(), |u| format!("signal {u}"));
    let unit = unit.unwrap_or("signal");
    let panels = [
        SeriesPanel {
            panel: Panel::FootSignal,
            series: &data.foot_signal,
            colors: theme::FEET,
            titles: &[&signal_title, "(a) foot signal", "(a) signal", "(a)"],
            y_titles: &[label, &short_label, unit],
            legend: &FEET_LEGEND,
        },
        SeriesPanel {
            panel: Panel::HeightsBefore,
            series: &data.heights_before_cm,
            colors: theme::FEET.map(|c| c.with_alpha(theme::BEFORE_ALPHA)),
            titles: &["(b) foot heights before correction", "(b) heights before", "(b) before", "(b)"],
            y_titles: &["height (cm)", "cm"],
            legend: &FEET_BEFORE_LEGEND,
        },
        SeriesPanel {
            panel: Panel::HeightsAfter,
            series: &data.heights_after_cm,
            colors: theme::FEET,
            titles: &["(c) foot heights after correction", "(c) heights after", "(c) after", "(c)"],
            y_titles: &["height (cm)", "cm"],
            legend: &FEET_LEGEND,
        },
    ];
    for p in &panels {
        draw_series_panel(&mut fig, layout, &time, p, text);
    }
    draw_top_view(&mut fig, layout, data, text);
    draw_stance_panel(&mut fig, layout, &time, &data.stance, text);
    fig
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::plot::testing::*;
    use crate::app::plot::*;

    #[test]
    fn every_panel_draws_the_demo() {
        let data = demo_data();
        for (w, h) in SIZES {
            let l = layout(w, h, ESTIMATE);
            let fig = draw_static(&data, &l, ESTIMATE);
            assert!(all_finite(&fig));
            for p in Panel::ALL {
                let PanelRects { outer, plot } = l.panel(p);
                let in_outer = fig.shapes.iter().filter(|s| {
                    let (x, y) = anchor(s);
                    outer.contains(x, y)
                });
                assert!(in_outer.count() >= 5, "{p:?} at {w}×{h} draws little");
                let texts = fig
                    .shapes
                    .iter()
                    .filter(|s| matches!(s, Shape::Text { x, y, .. } if outer.contains(*x, *y)))
                    .count();
                assert!(texts >= 3, "{p:?} at {w}×{h} has {texts} texts");
                // Data inside the plot: long polylines, or the stance bar's runs.
                let data_shapes = fig
                    .shapes
                    .iter()
                    .filter(|s| match s {
                        Shape::Polyline { points, .. } => {
                            points.len() > 10 && points.iter().all(|&(x, y)| plot.contains(x, y))
                        }
                        Shape::Rect { x, y, color, .. } => {
                            plot.contains(*x, *y) && STANCE_KINDS.iter().any(|k| stance_color(*k) == *color)
                        }
                        _ => false,
                    })
                    .count();
                // The demo's original hips barely leave their spot, so (d) may show
                // only the corrected path as a line.
                let expected = match p {
                    Panel::Stance => 5,
                    Panel::TopView => 1,
                    _ => 2,
                };
                assert!(data_shapes >= expected, "{p:?} at {w}×{h}: {data_shapes} data shapes");
            }
            // Titles say which panel is which.
            for letter in ["(a)", "(b)", "(c)", "(d)", "(e)"] {
                assert!(
                    fig.shapes
                        .iter()
                        .any(|s| matches!(s, Shape::Text { text, .. } if text.starts_with(letter)))
                );
            }
            let cursor = draw_cursor(&data, 300, &l, ESTIMATE);
            assert!(all_finite(&cursor));
            let lines = cursor.shapes.iter().filter(|s| matches!(s, Shape::Polyline { .. })).count();
            let dots = cursor.shapes.iter().filter(|s| matches!(s, Shape::Circle { .. })).count();
            assert_eq!(lines, 4, "a cursor line on (a), (b), (c) and (e)");
            assert_eq!(dots, 2 * (6 + 2), "a haloed dot per foot in (a)-(c) and per path in (d)");
        }
    }

    #[test]
    fn axes_have_units() {
        let fig = draw_static(&synthetic(1000), &layout(1600.0, 500.0, ESTIMATE), ESTIMATE);
        let has = |t: &str| fig.shapes.iter().any(|s| matches!(s, Shape::Text { text, .. } if text == t));
        for title in ["time (s)", "height (cm)", "x (cm)", "z (cm)"] {
            assert!(has(title), "no axis title {title:?}");
        }
        // The signal's axis title is its label, or as much of it as fits, unit included.
        let signal_axis = fig.shapes.iter().any(|s| {
            matches!(s, Shape::Text { text, vertical: true, .. } if text.ends_with("(g)") && text.len() > 3)
        });
        assert!(signal_axis, "no unit on the signal axis");
        // 1000 frames at 100 fps: 0 to 9.99 s.
        assert!(has("0") && has("8"));
    }
}
