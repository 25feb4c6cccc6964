//! Paints a [`Figure`] on a canvas 2D context, and measures its text there.
//! All layout, scaling and decimation happened in [`crate::app::plot`]; this
//! only turns shapes into canvas calls, so it stays too thin to need tests of
//! its own.

use wasm_bindgen::JsValue;
use web_sys::CanvasRenderingContext2d;

use crate::app::plot::{Align, DASH_PX, FONT_FAMILY, Figure, Shape};

/// The canvas font of text at `size_px`.
fn font(size_px: f32) -> String {
    format!("{size_px}px {FONT_FAMILY}")
}

/// Text widths as [`paint`] draws text on `ctx`: the returned function gives
/// the width in pixels of `text` at `size_px`, from `measureText`, for
/// [`TextMeasure::With`](crate::app::plot::TextMeasure::With). It sets `ctx`'s font; where the canvas cannot
/// measure, it falls back to
/// [`TextMeasure::Estimate`](crate::app::plot::TextMeasure::Estimate).
#[cfg(feature = "web-player")]
pub fn measure_text(ctx: &CanvasRenderingContext2d) -> impl Fn(&str, f32) -> f32 + '_ {
    let font_size_px = std::cell::Cell::new(f32::NAN);
    move |text: &str, size_px: f32| {
        // Setting the font parses CSS; the layout measures runs of one size.
        if size_px != font_size_px.get() {
            ctx.set_font(&font(size_px));
            font_size_px.set(size_px);
        }
        match ctx.measure_text(text) {
            Ok(metrics) => metrics.width() as f32,
            Err(_) => crate::app::plot::TextMeasure::Estimate.width_px(text, size_px),
        }
    }
}

/// Paints every shape of `figure`, in order, onto `ctx`, and nothing else: it
/// neither clears the canvas nor paints a background. Leaves the line dash
/// solid; other context state (styles, font, alignment) is left as the last
/// shape set it.
pub fn paint(ctx: &CanvasRenderingContext2d, figure: &Figure) {
    let solid = js_sys::Array::new();
    let dashed = js_sys::Array::new();
    for length in DASH_PX {
        dashed.push(&JsValue::from_f64(f64::from(length)));
    }
    // Round joins keep min/max-decimated series from sprouting miter spikes.
    ctx.set_line_join("round");
    ctx.set_text_baseline("middle");
    let mut dash_on = false;
    // Setting the same font string for every label costs a CSS parse each
    // time; remember the last one.
    let mut font_size_px = f32::NAN;
    for shape in &figure.shapes {
        match shape {
            Shape::Polyline { points, color, width_px, dashed: want_dash } => {
                let Some((&(x0, y0), rest)) = points.split_first() else { continue };
                if *want_dash != dash_on {
                    // Only fails for non-finite lengths, which DASH_PX has not.
                    let _ = ctx.set_line_dash(if *want_dash { &dashed } else { &solid });
                    dash_on = *want_dash;
                }
                ctx.set_stroke_style_str(&color.to_css());
                ctx.set_line_width(f64::from(*width_px));
                ctx.begin_path();
                ctx.move_to(f64::from(x0), f64::from(y0));
                for &(x, y) in rest {
                    ctx.line_to(f64::from(x), f64::from(y));
                }
                ctx.stroke();
            }
            Shape::Rect { x, y, w, h, color } => {
                ctx.set_fill_style_str(&color.to_css());
                ctx.fill_rect(f64::from(*x), f64::from(*y), f64::from(*w), f64::from(*h));
            }
            Shape::Text { x, y, text, color, size_px, align, vertical } => {
                if *size_px != font_size_px {
                    ctx.set_font(&font(*size_px));
                    font_size_px = *size_px;
                }
                ctx.set_text_align(match align {
                    Align::Left => "left",
                    Align::Center => "center",
                    Align::Right => "right",
                });
                ctx.set_fill_style_str(&color.to_css());
                let (x, y) = (f64::from(*x), f64::from(*y));
                if *vertical {
                    // A quarter turn anticlockwise about (x, y): reads bottom to top.
                    ctx.save();
                    let turned = ctx.translate(x, y).and_then(|_| ctx.rotate(-std::f64::consts::FRAC_PI_2));
                    if turned.is_ok() {
                        let _ = ctx.fill_text(text, 0.0, 0.0);
                    }
                    ctx.restore();
                } else {
                    // Fails only for non-finite coordinates, which draw nothing anyway.
                    let _ = ctx.fill_text(text, x, y);
                }
            }
            Shape::Circle { x, y, radius_px, color } => {
                ctx.set_fill_style_str(&color.to_css());
                ctx.begin_path();
                let drawn =
                    ctx.arc(f64::from(*x), f64::from(*y), f64::from(*radius_px), 0.0, std::f64::consts::TAU);
                // `arc` rejects a negative radius; then there is nothing to fill.
                if drawn.is_ok() {
                    ctx.fill();
                }
            }
        }
    }
    if dash_on {
        let _ = ctx.set_line_dash(&solid);
    }
}
