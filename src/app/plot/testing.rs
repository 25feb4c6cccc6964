//! What the plot tests share: canvas sizes, data to draw, and ways to find
//! shapes in a figure.

use glam::DVec3;

use super::legend::STANCE_KINDS;
use super::{CameraSeries, Figure, PlotData, Rect, Shape, Stance, StanceReason, TextMeasure};
use crate::body::feet::{Foot, PerFoot};

/// The text measure of every test: the fixed estimate.
pub(super) const ESTIMATE: TextMeasure = TextMeasure::Estimate;

/// Sizes of plot canvases the app meets: the tests' 400 × 300, the page's
/// column at 1× and 2×, a wide embed, a phone.
pub(super) const SIZES: [(f32, f32); 7] = [
    (400.0, 300.0),
    (495.0, 550.0),
    (990.0, 1100.0),
    (1600.0, 500.0),
    (390.0, 600.0),
    (800.0, 800.0),
    (2400.0, 1300.0),
];

/// `n` frames of plausible data: alternating steps, and hips along a
/// spiral (so no two frames share a floor point).
pub(super) fn synthetic(n: usize) -> PlotData {
    let t = |f: usize| f as f64 / 100.0;
    let wave = |f: usize, phase: f64| (t(f) * 3.0 + phase).sin();
    // The right foot steps half a cycle after the left.
    let phase = |foot: Foot| if foot == Foot::Left { 0.0 } else { 3.0 };
    let spiral = |f: usize, r0: f64| {
        let a = t(f) * 0.8;
        DVec3::new((r0 + 20.0 * a) * a.cos(), 90.0, (r0 + 20.0 * a) * a.sin())
    };
    let step = |f: usize, foot: Foot| 5.0 + 8.0 * wave(f, phase(foot)).max(0.0);
    PlotData {
        fps: 100.0,
        foot_signal: PerFoot::from_fn(|foot| (0..n).map(|f| 1.0 + 0.3 * wave(f, phase(foot))).collect()),
        foot_signal_label: "smoothed acceleration (g)".to_string(),
        heights_before_cm: PerFoot::from_fn(|foot| (0..n).map(|f| step(f, foot) + t(f)).collect()),
        heights_after_cm: PerFoot::from_fn(|foot| (0..n).map(|f| step(f, foot)).collect()),
        hips_before_cm: (0..n).map(|f| spiral(f, 40.0) + DVec3::new(t(f) * 10.0, 0.0, 0.0)).collect(),
        hips_after_cm: (0..n).map(|f| spiral(f, 30.0)).collect(),
        stance: (0..n)
            .map(|f| match (f / 37) % 9 {
                8 => Stance::Flight,
                k => STANCE_KINDS[k % 7],
            })
            .collect(),
        camera: CameraSeries::default(),
    }
}

/// `data` with a camera take: its path 4 m beside the corrected one, and a
/// video at 3/5 of the recording's rate whose uncertainty and error rise
/// and fall.
pub(super) fn with_camera(mut data: PlotData) -> PlotData {
    let n = data.hips_after_cm.len();
    let hips_cm = data.hips_after_cm.iter().map(|p| *p + DVec3::new(400.0, 0.0, 0.0)).collect();
    let video_frames = n * 3 / 5;
    let recording_time_s: Vec<f64> = (0..video_frames).map(|i| i as f64 * 5.0 / 3.0 / data.fps).collect();
    let uncertainty_cm = recording_time_s.iter().map(|t| 3.0 + 2.0 * (t * 2.5).sin()).collect();
    let error_cm = recording_time_s.iter().map(|t| 4.0 + 3.0 * (t * 4.0).cos()).collect();
    data.camera = CameraSeries {
        hips_cm,
        recording_time_s,
        uncertainty_cm,
        error_cm,
        truth_name: "walk.truth.csv".into(),
    };
    data
}

/// [`synthetic`] with a camera take ([`with_camera`]).
pub(super) fn synthetic_with_camera(n: usize) -> PlotData {
    with_camera(synthetic(n))
}

/// `n` frames of [`synthetic`] data whose stances are the contact method's.
pub(super) fn synthetic_contact(n: usize) -> PlotData {
    let kinds = [
        Stance::Pinned(Foot::Left, StanceReason::Contact),
        Stance::Double,
        Stance::Pinned(Foot::Right, StanceReason::Contact),
        Stance::Double,
        Stance::Flight,
    ];
    PlotData { stance: (0..n).map(|f| kinds[(f / 37) % kinds.len()]).collect(), ..synthetic(n) }
}

pub(super) fn demo_data() -> PlotData {
    let session =
        crate::app::session::Session::open(crate::synth::demo::demo().recording(), Default::default())
            .expect("the demo opens");
    session.plot_data
}

/// A point that says where a shape is.
pub(super) fn anchor(shape: &Shape) -> (f32, f32) {
    match shape {
        Shape::Polyline { points, .. } => points.first().copied().unwrap_or((f32::NAN, f32::NAN)),
        Shape::Rect { x, y, w, h, .. } => (x + w / 2.0, y + h / 2.0),
        Shape::Text { x, y, .. } | Shape::Circle { x, y, .. } => (*x, *y),
    }
}

pub(super) fn all_finite(fig: &Figure) -> bool {
    fig.shapes.iter().all(|s| match s {
        Shape::Polyline { points, width_px, .. } => {
            width_px.is_finite() && points.iter().all(|p| p.0.is_finite() && p.1.is_finite())
        }
        Shape::Rect { x, y, w, h, .. } => [x, y, w, h].iter().all(|v| v.is_finite()),
        Shape::Text { x, y, size_px, .. } => [x, y, size_px].iter().all(|v| v.is_finite()),
        Shape::Circle { x, y, radius_px, .. } => [x, y, radius_px].iter().all(|v| v.is_finite()),
    })
}

/// The x of the cursor line in `panel`'s plot.
pub(super) fn cursor_x(fig: &Figure, plot: Rect) -> Option<f32> {
    fig.shapes.iter().find_map(|s| match s {
        Shape::Polyline { points, .. } if points.len() == 2 && points[0].0 == points[1].0 => {
            plot.contains(points[0].0, points[0].1).then_some(points[0].0)
        }
        _ => None,
    })
}

/// The texts drawn inside `r`.
pub(super) fn texts_in(fig: &Figure, r: Rect) -> Vec<&str> {
    fig.shapes
        .iter()
        .filter_map(|s| match s {
            Shape::Text { x, y, text, .. } if r.contains(*x, *y) => Some(text.as_str()),
            _ => None,
        })
        .collect()
}
