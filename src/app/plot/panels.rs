//! Drawing each panel's static part: titles, legends, axes, grids and data.

use super::axes::{TimeAxis, TopView, ValueScale, multiples, nice_ticks, tick_budget, tick_label, x_ticks};
use super::decimate::{columns_in, path_shapes, placed_series_shapes, series_shapes};
use super::figure::{Align, Figure, Rect, TextStyle};
use super::layout::{AXIS_ROW, HEADER, LEGEND_ROW, TICK_FONT};
use super::legend::{
    CAMERA_PATH_LEGEND, CAMERA_SERIES_LEGEND, FEET_BEFORE_LEGEND, FEET_LEGEND, ITEM_GAP, LegendItem,
    PATH_LEGEND, STANCE_KINDS, draw_legend_item, flow_legend, legend_item_width, stance_color, stance_index,
    stance_legend,
};
use super::{CameraSeries, Layout, Panel, PanelRects, PlotData, Stance, TextMeasure};
use crate::app::theme::{self, Rgba};
use crate::body::feet::PerFoot;

/// The panel's header: `legend` flush right (stopping `reserve_px` short of
/// the edge), and left of it the first of `titles` that fits. Where none
/// fits beside the whole legend, its first items make room: the panel's
/// name comes first.
fn draw_header(
    fig: &mut Figure,
    outer: Rect,
    (font_px, text): (f32, TextMeasure),
    titles: &[&str],
    legend: &[LegendItem],
    reserve_px: f32,
) {
    let y = outer.y + HEADER * font_px / 2.0;
    let legend_left = |items: &[LegendItem]| {
        let widths: f32 =
            items.iter().map(|it| legend_item_width(it, font_px, text) + ITEM_GAP * font_px).sum();
        outer.right() - reserve_px - widths
    };
    let shortest = titles.last().map_or(0.0, |t| text.width_px(t, font_px));
    let shown = (0..=legend.len())
        .find(|&first| shortest <= legend_left(&legend[first..]) - outer.x)
        .map_or(&legend[legend.len()..], |first| &legend[first..]);
    let mut right = outer.right() - reserve_px;
    for it in shown.iter().rev() {
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
    // The camera's path on top: with a take, it is the result shown.
    fig.shapes.extend(path_shapes(&data.camera.hips_cm, &view, theme::CAMERA, 2.0, false));
    let titles =
        ["(d) hips path on the floor, seen from above", "(d) hips path, from above", "(d) hips path", "(d)"];
    let legend: &[LegendItem] =
        if data.camera.hips_cm.is_empty() { &PATH_LEGEND } else { &CAMERA_PATH_LEGEND };
    draw_header(fig, outer, (f, text), &titles, legend, 0.0);
}

/// The scale of (f): from no distance to the largest uncertainty or error.
pub(super) fn camera_scale(camera: &CameraSeries) -> ValueScale {
    ValueScale::from_zero(&[&camera.uncertainty_cm, &camera.error_cm])
}

/// Where video frame `i` of a camera take sits on the time axis: the
/// recording's (fractional) frame it was read at.
pub(super) fn video_frame_at(camera: &CameraSeries, time: &TimeAxis, i: usize) -> f64 {
    camera.recording_time_s[i] * time.fps.unwrap_or(1.0)
}

/// (f): the camera track's stated uncertainty per video frame and, with a
/// truth, its error against it, both in cm on the recording's time axis.
fn draw_camera_panel(fig: &mut Figure, layout: &Layout, time: &TimeAxis, data: &PlotData, text: TextMeasure) {
    let f = layout.font_px;
    let camera = &data.camera;
    let PanelRects { outer, plot } = layout.panel(Panel::Camera);
    fig.fill(plot, theme::PLOT_BACKGROUND);
    let scale = camera_scale(camera);
    draw_time_grid(fig, plot, time, (f, text));
    draw_y_ticks(fig, plot, f, nice_ticks(scale.lo, scale.hi, y_tick_budget(plot, f)), |v| scale.y(plot, v));
    draw_y_title(fig, outer, plot, (f, text), &["distance (cm)", "cm"]);
    let fps = time.fps.unwrap_or(1.0);
    for (values, color) in [(&camera.uncertainty_cm, theme::CAMERA), (&camera.error_cm, theme::TRACK_ERROR)] {
        let samples = camera.recording_time_s.iter().zip(values).map(|(t, &v)| (t * fps, v));
        fig.shapes.extend(placed_series_shapes(samples, values.len(), time, plot, scale, color));
    }
    let (legend, titles): (&[LegendItem], Vec<String>) = if camera.error_cm.is_empty() {
        let titles = ["(f) camera track: its stated uncertainty", "(f) camera: uncertainty", "(f)"];
        (&CAMERA_SERIES_LEGEND[..1], titles.map(String::from).to_vec())
    } else {
        let long =
            format!("(f) camera track: its stated uncertainty and its error against {}", camera.truth_name);
        let short = format!("(f) camera: uncertainty, error against {}", camera.truth_name);
        let titles = [long, short, "(f) camera: uncertainty, error".into(), "(f)".into()];
        (&CAMERA_SERIES_LEGEND[..], titles.to_vec())
    };
    let titles: Vec<&str> = titles.iter().map(String::as_str).collect();
    draw_header(fig, outer, (f, text), &titles, legend, 0.0);
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
        let c = time.column(f as f64, columns);
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
/// axes with numbered ticks, grids, and the data of every panel laid out. Long
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
    if layout.camera_shown {
        draw_camera_panel(&mut fig, layout, &time, data, text);
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
        for (data, (w, h)) in
            [demo_data(), with_camera(demo_data())].iter().flat_map(|d| SIZES.map(|s| (d, s)))
        {
            let l = layout_for(data, w, h, ESTIMATE);
            let fig = draw_static(data, &l, ESTIMATE);
            assert!(all_finite(&fig));
            for p in l.shown() {
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
            let letters: &[&str] = if data.camera.is_shown() {
                &["(a)", "(b)", "(c)", "(d)", "(e)", "(f)"]
            } else {
                &["(a)", "(b)", "(c)", "(d)", "(e)"]
            };
            for letter in letters {
                assert!(
                    fig.shapes
                        .iter()
                        .any(|s| matches!(s, Shape::Text { text, .. } if text.starts_with(letter))),
                    "{letter} at {w}×{h}"
                );
            }
            let cursor = draw_cursor(data, 300, &l, ESTIMATE);
            assert!(all_finite(&cursor));
            let lines = cursor.shapes.iter().filter(|s| matches!(s, Shape::Polyline { .. })).count();
            let dots = cursor.shapes.iter().filter(|s| matches!(s, Shape::Circle { .. })).count();
            if data.camera.is_shown() {
                assert_eq!(lines, 5, "a cursor line on (a), (b), (c), (f) and (e)");
                assert_eq!(
                    dots,
                    2 * (6 + 3 + 2),
                    "haloed dots: a foot in (a)-(c), a path in (d), a series in (f)"
                );
            } else {
                assert_eq!(lines, 4, "a cursor line on (a), (b), (c) and (e)");
                assert_eq!(dots, 2 * (6 + 2), "a haloed dot per foot in (a)-(c) and per path in (d)");
            }
        }
    }

    #[test]
    fn a_camera_take_draws_its_path_beside_the_others_in_d() {
        // The camera's path 4 m beside the inertial one, so (d) must widen
        // to hold it.
        let data = synthetic_with_camera(400);
        for (w, h) in SIZES {
            let l = layout_for(&data, w, h, ESTIMATE);
            let plot = l.plot(Panel::TopView);
            let fig = draw_static(&data, &l, ESTIMATE);
            let camera_lines: Vec<&Vec<(f32, f32)>> = fig
                .shapes
                .iter()
                .filter_map(|s| match s {
                    // Not the legend's swatch, a line of two points.
                    Shape::Polyline { points, color, .. }
                        if *color == theme::CAMERA
                            && points.len() > 2
                            && l.panel(Panel::TopView).outer.contains(points[0].0, points[0].1) =>
                    {
                        Some(points)
                    }
                    _ => None,
                })
                .collect();
            let points = camera_lines.iter().map(|p| p.len()).sum::<usize>();
            assert!(points > 10, "{w}×{h}: the camera path has {points} points");
            assert!(camera_lines.iter().flat_map(|p| p.iter()).all(|&(x, y)| plot.contains(x, y)));
            // The page's sizes name all three; the tests' 400 × 300 only
            // has room for the panel's name and the result shown.
            let words: &[&str] = if w >= 495.0 { &["suit", "inertial", "camera"] } else { &["camera"] };
            for word in words {
                assert!(
                    texts_in(&fig, l.panel(Panel::TopView).outer).contains(word),
                    "{w}×{h}: no {word:?} in (d)'s legend"
                );
            }
            // The cursor's dot on the camera path, where the take has it.
            let frame = 250;
            let cursor = draw_cursor(&data, frame, &l, ESTIMATE);
            let dot = cursor.shapes.iter().find_map(|s| match s {
                Shape::Circle { x, y, color, .. } if *color == theme::CAMERA && plot.contains(*x, *y) => {
                    Some((*x, *y))
                }
                _ => None,
            });
            let expected = TopView::new(&data, plot).px_of(data.camera.hips_cm[frame]);
            assert_eq!(dot, expected, "{w}×{h}: the dot on the camera path at frame {frame}");
        }
        // Without a take, (d) is as before: two paths, no camera.
        let fig = draw_static(&synthetic(400), &layout(1600.0, 500.0, ESTIMATE), ESTIMATE);
        assert!(
            !fig.shapes.iter().any(|s| matches!(s, Shape::Polyline { color, .. } if *color == theme::CAMERA))
        );
    }

    #[test]
    fn a_camera_take_plots_its_uncertainty_and_error_per_video_frame_in_f() {
        let data = synthetic_with_camera(400);
        let time = TimeAxis::new(&data);
        let video_frames = data.camera.recording_time_s.len();
        for (w, h) in SIZES {
            let l = layout_for(&data, w, h, ESTIMATE);
            let PanelRects { outer, plot } = l.panel(Panel::Camera);
            let fig = draw_static(&data, &l, ESTIMATE);
            for color in [theme::CAMERA, theme::TRACK_ERROR] {
                let points: Vec<(f32, f32)> = fig
                    .shapes
                    .iter()
                    .filter_map(|s| match s {
                        Shape::Polyline { points, color: c, .. } if *c == color && points.len() > 2 => {
                            Some(points)
                        }
                        _ => None,
                    })
                    .flatten()
                    .copied()
                    .filter(|&(x, y)| outer.contains(x, y))
                    .collect();
                // Each video frame at the recording frame it was read at:
                // the first at the axis's start, the last 3/5 along it.
                assert!(points.len() >= video_frames.min(2 * columns_in(plot.w)) / 2, "{w}×{h}: {color:?}");
                assert!(points.iter().all(|&(x, y)| plot.contains(x, y)), "{w}×{h}: {color:?} outside (f)");
                let last_at = video_frame_at(&data.camera, &time, video_frames - 1);
                assert!((points[0].0 - plot.x).abs() < 1e-3, "{w}×{h}");
                assert!((points[points.len() - 1].0 - time.x(plot, last_at)).abs() < 1e-3, "{w}×{h}");
            }
            let texts = texts_in(&fig, outer);
            assert!(texts.iter().any(|t| t.starts_with("(f)")), "{w}×{h}: {texts:?}");
            // A click in (f) seeks the recording frame under it.
            let x = time.x(plot, 120.0);
            assert_eq!(frame_at(&data, &l, x, plot.y + plot.h / 2.0), Some(120), "{w}×{h}");
        }
        let l = layout_for(&data, 2400.0, 1300.0, ESTIMATE);
        let fig = draw_static(&data, &l, ESTIMATE);
        let texts = texts_in(&fig, l.panel(Panel::Camera).outer);
        assert!(texts.iter().any(|t| t.contains("walk.truth.csv")), "the truth named: {texts:?}");
        assert!(texts.contains(&"uncertainty (1σ)") && texts.contains(&"error"), "{texts:?}");
        // Without a truth, the uncertainty alone.
        let mut no_truth = data.clone();
        (no_truth.camera.error_cm, no_truth.camera.truth_name) = (Vec::new(), String::new());
        let fig = draw_static(&no_truth, &l, ESTIMATE);
        assert!(
            !fig.shapes
                .iter()
                .any(|s| matches!(s, Shape::Polyline { color, .. } if *color == theme::TRACK_ERROR))
        );
        assert!(!texts_in(&fig, l.panel(Panel::Camera).outer).contains(&"error"));
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
