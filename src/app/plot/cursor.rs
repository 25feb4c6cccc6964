//! The time cursor drawn over the static figure each frame, and the reverse:
//! the frame a click on the plots seeks to.

use super::axes::{TimeAxis, TopView, ValueScale};
use super::figure::{Align, Figure, Shape, TextStyle};
use super::layout::HEADER;
use super::panels::{camera_scale, draw_static, readout_reserve_px, video_frame_at};
use super::{Layout, Panel, PlotData, Stance, StanceReason, TextMeasure, panel_at};
use crate::app::theme::{self, Rgba};
use crate::body::feet::Foot;

/// What the read-out says about a stance: a sentence, and a few words.
fn stance_words(stance: Stance) -> (&'static str, &'static str) {
    use StanceReason::*;
    match stance {
        Stance::Free => ("no foot pinned", "none pinned"),
        Stance::Flight => ("flight, no foot down", "flight"),
        Stance::Pinned(Foot::Left, Acceleration) => {
            ("left foot pinned: calmer (acceleration)", "left, acceleration")
        }
        Stance::Pinned(Foot::Left, Height) => ("left foot pinned: lower (height)", "left, height"),
        Stance::Pinned(Foot::Left, Both) => ("left foot pinned: calmer and lower", "left, both"),
        Stance::Pinned(Foot::Right, Acceleration) => {
            ("right foot pinned: calmer (acceleration)", "right, acceleration")
        }
        Stance::Pinned(Foot::Right, Height) => ("right foot pinned: lower (height)", "right, height"),
        Stance::Pinned(Foot::Right, Both) => ("right foot pinned: calmer and lower", "right, both"),
        Stance::Pinned(Foot::Left, Contact) => ("left foot on the floor", "left foot"),
        Stance::Pinned(Foot::Right, Contact) => ("right foot on the floor", "right foot"),
        Stance::Double => ("both feet on the floor", "both feet"),
    }
}

/// A dot with a dark halo, so it shows over lines of its own colour.
fn dot(fig: &mut Figure, (x, y): (f32, f32), radius_px: f32, color: Rgba) {
    fig.shapes.push(Shape::Circle { x, y, radius_px: radius_px + 1.5, color: theme::HALO });
    fig.shapes.push(Shape::Circle { x, y, radius_px, color });
}

/// The time cursor at `frame` (clamped to the last frame): a vertical line
/// across the plots of (a), (b), (c) and (e), a dot on each foot's value in
/// (a)–(c), a dot on both hips paths in (d), and in the header of (e) the
/// time and the stance of that frame in words. Empty for empty data.
///
/// It recomputes the panels' scales, O(frames): about a millisecond for
/// 100,000 frames (natively), most of it reading the hips paths. The read-out
/// is fitted to its room by `text`.
pub fn draw_cursor(data: &PlotData, frame: usize, layout: &Layout, text: TextMeasure) -> Figure {
    let mut fig = Figure::new(layout.width, layout.height);
    let time = TimeAxis::new(data);
    if time.frames == 0 {
        return fig;
    }
    let frame = frame.min(time.frames - 1);
    let f = layout.font_px;
    for panel in layout.shown().filter(|p| p.is_time()) {
        let plot = layout.plot(panel);
        let x = time.x(plot, frame as f64);
        fig.segment((x, plot.y), (x, plot.bottom()), theme::CURSOR, 1.0, false);
    }
    for (panel, series) in [
        (Panel::FootSignal, &data.foot_signal),
        (Panel::HeightsBefore, &data.heights_before_cm),
        (Panel::HeightsAfter, &data.heights_after_cm),
    ] {
        let plot = layout.plot(panel);
        let scale = ValueScale::of(series);
        for (foot, values) in series.iter() {
            if let Some(&v) = values.get(frame).filter(|v| v.is_finite()) {
                dot(&mut fig, (time.x(plot, frame as f64), scale.y(plot, v)), 0.28 * f, theme::FEET[foot]);
            }
        }
    }
    if layout.camera_shown {
        camera_dots(&mut fig, data, frame, layout, &time);
    }
    let view = TopView::new(data, layout.plot(Panel::TopView));
    for (path, color) in [
        (&data.hips_before_cm, theme::ORIGINAL.with_alpha(255)),
        (&data.hips_after_cm, theme::CORRECTED),
        (&data.camera.hips_cm, theme::CAMERA),
    ] {
        if let Some(p) = path.get(frame).and_then(|p| view.px_of(*p)) {
            dot(&mut fig, p, 0.35 * f, color);
        }
    }
    // The read-out: when, and what the method decided then.
    let when = match time.fps {
        Some(fps) => format!("{:.2} s", frame as f64 / fps),
        None => format!("frame {frame}"),
    };
    let (long, short) = data.stance.get(frame).map_or(("", ""), |s| stance_words(*s));
    let candidates = if long.is_empty() {
        vec![format!("{when}, frame {frame}"), when.clone()]
    } else {
        vec![
            format!("{when}, frame {frame}: {long}"),
            format!("{when}: {long}"),
            format!("{when}: {short}"),
            when,
        ]
    };
    let candidates: Vec<&str> = candidates.iter().map(String::as_str).collect();
    let outer = layout.panel(Panel::Stance).outer;
    if let Some(readout) = text.fit(&candidates, readout_reserve_px(outer), f) {
        let style = TextStyle::new(theme::TEXT, f, Align::Right);
        fig.text(outer.right(), outer.y + HEADER * f / 2.0, readout, style);
    }
    fig
}

/// In (f), a dot on the uncertainty and the error of the video frame read
/// nearest to recording frame `frame`.
fn camera_dots(fig: &mut Figure, data: &PlotData, frame: usize, layout: &Layout, time: &TimeAxis) {
    let camera = &data.camera;
    let plot = layout.plot(Panel::Camera);
    let at = |i: usize| video_frame_at(camera, time, i);
    let count = camera.recording_time_s.len();
    // The first video frame at or after `frame`: their instants increase
    // (Session::set_camera_take).
    let fps = time.fps.unwrap_or(1.0);
    let next = camera.recording_time_s.partition_point(|&t| t * fps < frame as f64);
    let nearest = [next.checked_sub(1), (next < count).then_some(next)]
        .into_iter()
        .flatten()
        .min_by(|&a, &b| (at(a) - frame as f64).abs().total_cmp(&(at(b) - frame as f64).abs()));
    // None where the video does not film the recording (within a frame).
    let video_frame = camera.recording_time_s.windows(2).map(|w| w[1] - w[0]).next().unwrap_or(0.0) * fps;
    let Some(i) = nearest.filter(|&i| {
        let at_frame = at(i);
        (at_frame - frame as f64).abs() <= video_frame.max(1.0)
            && at_frame >= 0.0
            && at_frame <= (time.frames - 1) as f64
    }) else {
        return;
    };
    let scale = camera_scale(camera);
    for (values, color) in [(&camera.uncertainty_cm, theme::CAMERA), (&camera.error_cm, theme::TRACK_ERROR)] {
        if let Some(&v) = values.get(i).filter(|v| v.is_finite()) {
            dot(fig, (time.x(plot, at(i)), scale.y(plot, v)), 0.28 * layout.font_px, color);
        }
    }
}

/// The whole figure at `frame`: [`draw_static`] with [`draw_cursor`] over it.
pub fn draw(data: &PlotData, frame: usize, layout: &Layout, text: TextMeasure) -> Figure {
    let mut fig = draw_static(data, layout, text);
    fig.extend(draw_cursor(data, frame, layout, text));
    fig
}

/// Where the camera take's path in (d) is drawn at recording frame `frame`
/// (canvas pixels); `None` without a take, or where that frame has no point.
pub fn camera_path_px(data: &PlotData, layout: &Layout, frame: usize) -> Option<(f32, f32)> {
    TopView::new(data, layout.plot(Panel::TopView)).px_of(*data.camera.hips_cm.get(frame)?)
}

/// The frame to seek to for a click or drag at (`x`, `y`) canvas pixels: in a
/// time panel (anywhere in its area, titles included), the frame under `x`,
/// clamped to the plot's ends; in the top view, the frame whose hips point
/// is drawn nearest to the click (the camera's, the corrected or the
/// original path's, in that order on a tie).
/// `None` outside the panels and for empty data.
pub fn frame_at(data: &PlotData, layout: &Layout, x: f32, y: f32) -> Option<usize> {
    let time = TimeAxis::new(data);
    if time.frames == 0 {
        return None;
    }
    let panel = panel_at(layout, x, y)?;
    if panel.is_time() {
        return Some(time.frame_at(layout.plot(panel), x));
    }
    let view = TopView::new(data, layout.plot(Panel::TopView));
    let mut best: Option<(f32, usize)> = None;
    // The result shown first (a camera take's track, else the corrected
    // path), and only a strictly nearer point of another wins, so ties go
    // to the path the user is inspecting.
    for path in [&data.camera.hips_cm, &data.hips_after_cm, &data.hips_before_cm] {
        for (f, p) in path.iter().enumerate() {
            if let Some((px, py)) = view.px_of(*p) {
                let d = (px - x).powi(2) + (py - y).powi(2);
                if d.is_finite() && best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, f));
                }
            }
        }
    }
    best.map(|(_, f)| f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::plot::legend::STANCE_KINDS;
    use crate::app::plot::testing::*;
    use crate::app::plot::*;
    use crate::body::feet::PerFoot;
    use glam::DVec3;

    #[test]
    fn clicking_the_cursor_seeks_to_its_frame() {
        for n in [2, 7, 1000, 100_000] {
            let data = synthetic(n);
            for (w, h) in SIZES {
                let l = layout(w, h, ESTIMATE);
                for frame in [0, 1, n / 3, n / 2, n - 2, n - 1] {
                    let cursor = draw_cursor(&data, frame, &l, ESTIMATE);
                    for p in [Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter, Panel::Stance] {
                        let plot = l.plot(p);
                        let x = cursor_x(&cursor, plot).expect("a cursor line");
                        let (_, y) = plot.center();
                        let found = frame_at(&data, &l, x, y).expect("a frame");
                        assert!(
                            found.abs_diff(frame) <= 1,
                            "{p:?}, {n} frames at {w}×{h}: {frame} → {found}"
                        );
                    }
                }
            }
        }
        // Outside every panel: nothing; empty data: nothing.
        let l = layout(400.0, 300.0, ESTIMATE);
        assert_eq!(frame_at(&synthetic(10), &l, -10.0, -10.0), None);
        assert_eq!(frame_at(&synthetic(10), &l, f32::NAN, 100.0), None);
        assert_eq!(frame_at(&PlotData::default(), &l, 100.0, 100.0), None);
        // The middle of (b) is the middle of the recording (the browser test clicks there).
        let data = synthetic(1001);
        let (x, y) = l.plot(Panel::HeightsBefore).center();
        assert_eq!(frame_at(&data, &l, x, y), Some(500));
    }

    #[test]
    fn clicking_a_hips_dot_in_the_top_view_seeks_there() {
        let data = synthetic(400);
        for (w, h) in SIZES {
            let l = layout(w, h, ESTIMATE);
            let view = TopView::new(&data, l.plot(Panel::TopView));
            for frame in [0, 57, 200, 399] {
                let cursor = draw_cursor(&data, frame, &l, ESTIMATE);
                let (x, y) = cursor
                    .shapes
                    .iter()
                    .find_map(|s| match s {
                        Shape::Circle { x, y, color, .. } if *color == theme::CORRECTED => Some((*x, *y)),
                        _ => None,
                    })
                    .expect("a corrected dot");
                let found = frame_at(&data, &l, x, y).expect("a frame");
                let (fx, fy) = view.px_of(data.hips_after_cm[found]).expect("finite");
                let off = (fx - x).hypot(fy - y);
                assert!(
                    found.abs_diff(frame) <= 1 || off < 1e-3,
                    "{w}×{h}: {frame} → {found} ({off} px off)"
                );
            }
        }
    }

    #[test]
    fn clicking_the_camera_path_in_the_top_view_seeks_there() {
        let data = synthetic_with_camera(400);
        for (w, h) in SIZES {
            let l = layout_for(&data, w, h, ESTIMATE);
            for frame in [0, 57, 200, 399] {
                let (x, y) = camera_path_px(&data, &l, frame).expect("drawn");
                let found = frame_at(&data, &l, x, y).expect("a frame");
                assert!(found.abs_diff(frame) <= 1, "{w}×{h}: {frame} → {found}");
            }
        }
        assert_eq!(camera_path_px(&synthetic(400), &layout(800.0, 800.0, ESTIMATE), 10), None);
    }

    #[test]
    fn empty_nan_and_one_frame_data_do_not_panic() {
        let one = PlotData {
            fps: 100.0,
            foot_signal: PerFoot::new(vec![1.0], vec![2.0]),
            heights_before_cm: PerFoot::new(vec![3.0], vec![4.0]),
            heights_after_cm: PerFoot::new(vec![0.0], vec![0.0]),
            hips_before_cm: vec![DVec3::new(1.0, 2.0, 3.0)],
            hips_after_cm: vec![DVec3::ZERO],
            stance: vec![Stance::Free],
            ..Default::default()
        };
        let nan = PlotData {
            fps: f64::NAN,
            foot_signal: PerFoot::new(vec![f64::NAN; 5], vec![f64::INFINITY; 5]),
            heights_before_cm: PerFoot::new(vec![f64::MAX, -f64::MAX], vec![]),
            heights_after_cm: PerFoot::new(vec![1e-320, 0.0], vec![f64::NEG_INFINITY]),
            hips_before_cm: vec![DVec3::NAN; 3],
            hips_after_cm: vec![DVec3::splat(f64::MAX), DVec3::splat(-f64::MAX)],
            stance: vec![Stance::Flight],
            ..Default::default()
        };
        let mut mismatched = synthetic(300);
        mismatched.fps = 0.0;
        mismatched.stance.truncate(10);
        mismatched.foot_signal.right.clear();
        mismatched.hips_before_cm.truncate(1);
        for data in [PlotData::default(), one, nan, mismatched] {
            for (w, h) in [(400.0, 300.0), (1600.0, 500.0), (5.0, 5.0)] {
                let l = layout(w, h, ESTIMATE);
                for frame in [0, 1, 4, usize::MAX] {
                    let fig = draw(&data, frame, &l, ESTIMATE);
                    assert!(all_finite(&fig), "{data:?}");
                }
                for (x, y) in
                    [(0.0, 0.0), (200.0, 150.0), (w / 2.0, h - 5.0), (f32::NAN, f32::NAN), (1e30, -1e30)]
                {
                    let found = frame_at(&data, &l, x, y);
                    assert!(found.is_none_or(|f| f < data.frame_count().max(1)));
                }
            }
        }
        assert!(
            draw_cursor(&PlotData::default(), 0, &layout(400.0, 300.0, ESTIMATE), ESTIMATE).shapes.is_empty()
        );
    }

    #[test]
    fn the_cursor_reads_out_contact_stances() {
        let data = synthetic_contact(1000);
        let l = layout(2400.0, 1300.0, ESTIMATE);
        let outer = l.panel(Panel::Stance).outer;
        for (frame, words) in [
            (0, "left foot on the floor"),
            (40, "both feet on the floor"),
            (80, "right foot on the floor"),
            (150, "flight"),
        ] {
            let cursor = draw_cursor(&data, frame, &l, ESTIMATE);
            let texts = texts_in(&cursor, outer);
            assert!(texts.iter().any(|t| t.contains(words)), "frame {frame}: {texts:?}");
        }
        for k in STANCE_KINDS {
            let (long, short) = stance_words(k);
            assert!(!long.is_empty() && !short.is_empty() && short.len() <= long.len(), "{k:?}");
        }
        // Clicking the contact strip seeks as the paper one does.
        let cursor = draw_cursor(&data, 500, &l, ESTIMATE);
        let plot = l.plot(Panel::Stance);
        let x = cursor_x(&cursor, plot).expect("a cursor line");
        assert!(frame_at(&data, &l, x, plot.center().1).is_some_and(|f| f.abs_diff(500) <= 1));
    }
}
