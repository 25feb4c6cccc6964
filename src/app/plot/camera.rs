//! The camera panel's plots, laid out as shapes as the player's are: the
//! hips' track seen from above, the camera's confidence per frame (and,
//! with a truth, the track's error) with a cursor at the frame shown, and
//! the paper's candidates of the frame shown. Pixels of each plot's own
//! canvas; the text 10 px, as the panel's small print.

use crate::app::frame_report::Candidate;
use crate::app::plot::figure::{Align, Figure, Rect, Shape, TextStyle};
use crate::app::theme;
use crate::app::theme::Rgba;
use glam::DVec2;

const TEXT_PX: f32 = 10.0;
/// Text is placed by its middle; these plots give its baseline, which lies
/// this far below the middle of 10 px text.
const BASELINE_BELOW_MIDDLE_PX: f32 = 3.5;

fn label(figure: &mut Figure, x: f32, baseline_y: f32, text: impl Into<String>) {
    let style = TextStyle::new(theme::MUTED_TEXT, TEXT_PX, Align::Left);
    figure.text(x, baseline_y - BASELINE_BELOW_MIDDLE_PX, text, style);
}

fn background(width: f32, height: f32) -> Figure {
    let mut figure = Figure::new(width, height);
    figure.fill(Rect::new(0.0, 0.0, width, height), theme::CAMERA_PLOT_BACKGROUND);
    figure
}

/// A closed ring of `radius_px` about (x, y), as a polyline.
fn ring(x: f32, y: f32, radius_px: f32, color: Rgba, width_px: f32) -> Shape {
    let points = (0..=48)
        .map(|k| {
            let a = k as f32 / 48.0 * std::f32::consts::TAU;
            (x + radius_px * a.cos(), y + radius_px * a.sin())
        })
        .collect();
    Shape::Polyline { points, color, width_px, dashed: false }
}

/// The hips' path on the floor (x, z, cm) seen from above, x right and z
/// down, one scale for both, the path's box in the middle; its start
/// marked, a metre for scale.
pub fn top_view(width: f32, height: f32, path_cm: &[DVec2]) -> Figure {
    let mut figure = background(width, height);
    let Some(&start) = path_cm.first() else { return figure };
    let (lo, hi) = path_cm.iter().fold((start, start), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let size = (hi - lo).max(DVec2::splat(50.0));
    let scale = ((f64::from(width) - 20.0) / size.x).min((f64::from(height) - 30.0) / size.y);
    let centre = (lo + hi) / 2.0;
    let at = |p: DVec2| {
        let q = (p - centre) * scale;
        ((f64::from(width) / 2.0 + q.x) as f32, ((f64::from(height) - 10.0) / 2.0 + q.y) as f32)
    };
    let points = path_cm.iter().map(|&p| at(p)).collect();
    figure.shapes.push(Shape::Polyline { points, color: theme::CORRECTED, width_px: 2.0, dashed: false });
    let (sx, sz) = at(start);
    figure.fill(Rect::new(sx - 3.0, sz - 3.0, 6.0, 6.0), theme::MUTED_TEXT);
    let metre_px = (100.0 * scale) as f32;
    figure.fill(Rect::new(width - 10.0 - metre_px, height - 12.0, metre_px, 2.0), theme::MUTED_TEXT);
    label(&mut figure, width - 30.0, height - 16.0, "1 m");
    label(&mut figure, 10.0, height - 6.0, "the hips from above (■ start)");
    figure
}

/// The track's error against a truth, per frame (cm), and what it is named.
pub struct ErrorSeries<'a> {
    pub per_frame_cm: &'a [f64],
    pub truth_name: &'a str,
}

/// The series under the views: the camera's confidence per frame (0 to 1)
/// and, with a truth, the track's error (cm), over `frame_count` frames; a
/// cursor at `shown_frame`. Nothing but the background before a track.
pub fn frame_series(
    width: f32,
    height: f32,
    confidence: &[f64],
    errors: Option<ErrorSeries>,
    frame_count: usize,
    shown_frame: usize,
) -> Figure {
    let mut figure = background(width, height);
    if frame_count == 0 || confidence.is_empty() {
        return figure;
    }
    let rows = if errors.is_some() { 2.0 } else { 1.0 };
    let row = SeriesRow { width, row_height: (height - 10.0) / rows, frame_count };
    row.draw(&mut figure, 0.0, confidence, 1.0, theme::CONFIDENCE, "the camera's confidence per frame");
    if let Some(e) = errors {
        let largest = e.per_frame_cm.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let top = ((largest / 10.0).ceil() * 10.0).max(20.0);
        let name = format!("error against {} (cm)", e.truth_name);
        row.draw(&mut figure, 1.0, e.per_frame_cm, top, theme::TRACK_ERROR, &name);
    }
    let x = row.x(shown_frame);
    figure.segment((x, 5.0), (x, height - 5.0), theme::CORRECTED, 1.0, false);
    figure
}

/// One row of [`frame_series`].
struct SeriesRow {
    width: f32,
    row_height: f32,
    frame_count: usize,
}

impl SeriesRow {
    /// The x of frame `i`.
    fn x(&self, i: usize) -> f32 {
        40.0 + (i as f32 / (self.frame_count.max(2) - 1) as f32) * (self.width - 50.0)
    }

    /// `values` from 0 to `top` in row `row` (0 the first), framed, named.
    fn draw(&self, figure: &mut Figure, row: f32, values: &[f64], top: f64, color: Rgba, name: &str) {
        let (w, h) = (self.width, self.row_height);
        let y0 = 5.0 + row * h;
        let y = |v: f64| y0 + h - 14.0 - (v.min(top) / top) as f32 * (h - 20.0);
        let (left, top_y, right, bottom) = (40.0, y0 + 4.0, 40.0 + w - 50.0, y0 + h - 12.0);
        let frame = vec![(left, top_y), (right, top_y), (right, bottom), (left, bottom), (left, top_y)];
        figure.shapes.push(Shape::Polyline {
            points: frame,
            color: theme::CAMERA_PLOT_FRAME,
            width_px: 1.0,
            dashed: false,
        });
        let points = values.iter().enumerate().map(|(i, &v)| (self.x(i), y(v))).collect();
        figure.shapes.push(Shape::Polyline { points, color, width_px: 1.0, dashed: false });
        label(figure, 44.0, y0 + 16.0, name);
        label(figure, 4.0, y0 + 12.0, format_number(top));
        label(figure, 4.0, y0 + h - 12.0, "0");
    }
}

/// A whole number as JavaScript's `String` writes it.
fn format_number(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 { format!("{}", v as i64) } else { format!("{v}") }
}

/// The paper's candidates of frame `shown_frame` where they lie on the
/// floor around the last position (the first tried), seen from above as
/// the top view, coloured by energy (low [`theme::CONFIDENCE`], high
/// [`theme::TRACK_ERROR`]), the chosen one ringed.
pub fn candidates_view(
    width: f32,
    height: f32,
    tried: &[Candidate],
    chosen: Option<usize>,
    shown_frame: usize,
) -> Figure {
    let mut figure = background(width, height);
    let Some(first) = tried.first() else {
        label(&mut figure, 10.0, height / 2.0, "no candidates in this frame (no pose)");
        return figure;
    };
    let finite = tried.iter().map(|c| c.energy_px).filter(|e| e.is_finite());
    let (low, high) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), e| (l.min(e), h.max(e)));
    let origin = first.floor_cm;
    let reach = tried.iter().map(|c| (c.floor_cm - origin).abs().max_element()).fold(1.0, f64::max);
    let scale = ((f64::from(width.min(height - 40.0)) / 2.0 - 14.0) / reach) as f32;
    let (cx, cy) = (width / 2.0, (height - 40.0) / 2.0 + 8.0);
    for (k, c) in tried.iter().enumerate() {
        let d = c.floor_cm - origin;
        let (x, y) = (cx + d.x as f32 * scale, cy + d.y as f32 * scale);
        let color = energy_colour(c.energy_px, low, high);
        figure.shapes.push(Shape::Circle { x, y, radius_px: 6.0, color });
        if chosen == Some(k) {
            figure.shapes.push(ring(x, y, 10.0, theme::CORRECTED, 2.0));
        }
    }
    label(
        &mut figure,
        8.0,
        height - 24.0,
        format!("the paper's {} candidates, frame {shown_frame}", tried.len()),
    );
    let ten_cm_px = if scale > 0.0 { (10.0 * scale).round() } else { 0.0 };
    label(&mut figure, 8.0, height - 10.0, format!("energy {low:.2}–{high:.2} px; {ten_cm_px} px = 10 cm"));
    figure
}

/// A candidate's colour: from [`theme::CONFIDENCE`] at the lowest energy to
/// [`theme::TRACK_ERROR`] at the highest; [`theme::NO_ENERGY`] where none.
fn energy_colour(energy_px: f64, low: f64, high: f64) -> Rgba {
    if !energy_px.is_finite() {
        return theme::NO_ENERGY;
    }
    let t = if high > low { (energy_px - low) / (high - low) } else { 0.0 };
    let (a, b) = (theme::CONFIDENCE, theme::TRACK_ERROR);
    let mix = |from: u8, to: u8| (f64::from(from) + (f64::from(to) - f64::from(from)) * t).round() as u8;
    Rgba(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2), 255)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polylines(f: &Figure) -> Vec<&Vec<(f32, f32)>> {
        f.shapes
            .iter()
            .filter_map(|s| if let Shape::Polyline { points, .. } = s { Some(points) } else { None })
            .collect()
    }

    fn texts(f: &Figure) -> Vec<&str> {
        f.shapes
            .iter()
            .filter_map(|s| if let Shape::Text { text, .. } = s { Some(text.as_str()) } else { None })
            .collect()
    }

    #[test]
    fn the_top_view_centres_the_path_at_one_scale() {
        let path = [DVec2::new(0.0, 0.0), DVec2::new(200.0, 0.0), DVec2::new(200.0, 100.0)];
        let f = top_view(320.0, 240.0, &path);
        let line = polylines(&f)[0];
        // The box 200 × 100 cm: 300 px across for 200 cm.
        assert_eq!(line[0], (10.0, 115.0 - 75.0));
        assert_eq!(line[1], (310.0, 40.0));
        assert_eq!(line[2], (310.0, 190.0));
        assert!(texts(&f).contains(&"1 m"));
        assert_eq!(top_view(320.0, 240.0, &[]).shapes.len(), 1, "the background alone");
    }

    #[test]
    fn the_series_scale_errors_to_a_round_top_and_mark_the_frame_shown() {
        let errors = [5.0, 33.0, 12.0];
        let f = frame_series(
            960.0,
            180.0,
            &[1.0, 0.5, 0.0],
            Some(ErrorSeries { per_frame_cm: &errors, truth_name: "walk.truth.csv" }),
            3,
            1,
        );
        let t = texts(&f);
        assert!(t.contains(&"40"), "33 cm rounds up to a top of 40: {t:?}");
        assert!(t.contains(&"error against walk.truth.csv (cm)"));
        let cursor = polylines(&f).last().map(|l| l[0]);
        assert_eq!(cursor, Some((40.0 + 0.5 * 910.0, 5.0)));
        // Confidence 1 at the row's top, 0 at its bottom.
        let confidence = polylines(&f)[1];
        assert_eq!(confidence[0].1, 5.0 + 85.0 - 14.0 - 65.0);
        assert_eq!(confidence[2].1, 5.0 + 85.0 - 14.0);
        assert_eq!(frame_series(960.0, 180.0, &[], None, 3, 0).shapes.len(), 1);
    }

    #[test]
    fn candidates_are_coloured_by_energy_and_the_chosen_ringed() {
        let c = |x: f64, e: f64| Candidate { floor_cm: DVec2::new(x, 0.0), energy_px: e };
        let f = candidates_view(240.0, 240.0, &[c(0.0, 2.0), c(10.0, 4.0), c(-10.0, f64::NAN)], Some(1), 7);
        let colours: Vec<Rgba> = f
            .shapes
            .iter()
            .filter_map(|s| if let Shape::Circle { color, .. } = s { Some(*color) } else { None })
            .collect();
        assert_eq!(colours, [theme::CONFIDENCE, theme::TRACK_ERROR, theme::NO_ENERGY]);
        assert_eq!(polylines(&f).len(), 1, "one ring");
        assert!(texts(&f).contains(&"the paper's 3 candidates, frame 7"));
        assert!(texts(&f)[1].starts_with("energy 2.00–4.00 px; 86 px = 10 cm"), "{:?}", texts(&f));
        assert_eq!(
            texts(&candidates_view(240.0, 240.0, &[], None, 0)),
            ["no candidates in this frame (no pose)"]
        );
    }
}
