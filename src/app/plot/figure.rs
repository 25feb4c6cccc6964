//! The figure as shapes to paint, and the rectangles that place them.

use crate::app::theme::Rgba;

/// Horizontal placement of a [`Shape::Text`] relative to its `x`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// `x` is the left edge.
    Left,
    /// `x` is the centre.
    Center,
    /// `x` is the right edge.
    Right,
}

/// The font family text is drawn in, and measured in (see [`super::TextMeasure`]).
pub const FONT_FAMILY: &str = "system-ui, sans-serif";
/// Dashed lines: this many pixels drawn, then this many left out.
pub const DASH_PX: [f32; 2] = [6.0, 4.0];

/// One thing to paint, in the figure's pixels (see the [module docs](super)).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Straight segments through `points`, stroked `width_px` wide with round
    /// joins, dashed by [`DASH_PX`] when `dashed`.
    Polyline { points: Vec<(f32, f32)>, color: Rgba, width_px: f32, dashed: bool },
    /// A filled rectangle with its top-left corner at (`x`, `y`).
    Rect { x: f32, y: f32, w: f32, h: f32, color: Rgba },
    /// One line of text in [`FONT_FAMILY`] at `size_px`. `y` is the vertical
    /// middle of the line and `x` is placed by `align`. `vertical` text is
    /// turned a quarter turn anticlockwise about (`x`, `y`), reading bottom to
    /// top, as y-axis titles are.
    Text { x: f32, y: f32, text: String, color: Rgba, size_px: f32, align: Align, vertical: bool },
    /// A filled circle centred on (`x`, `y`).
    Circle { x: f32, y: f32, radius_px: f32, color: Rgba },
}

/// Shapes to paint in order (later ones over earlier ones) on a canvas of
/// `width` × `height` pixels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Figure {
    pub width: f32,
    pub height: f32,
    pub shapes: Vec<Shape>,
}

impl Figure {
    pub fn new(width: f32, height: f32) -> Figure {
        Figure { width, height, shapes: Vec::new() }
    }

    /// Appends `other`'s shapes, to be painted over these.
    pub fn extend(&mut self, other: Figure) {
        self.shapes.extend(other.shapes);
    }

    pub(super) fn fill(&mut self, r: Rect, color: Rgba) {
        if r.w > 0.0 && r.h > 0.0 {
            self.shapes.push(Shape::Rect { x: r.x, y: r.y, w: r.w, h: r.h, color });
        }
    }

    pub(super) fn segment(
        &mut self,
        from: (f32, f32),
        to: (f32, f32),
        color: Rgba,
        width_px: f32,
        dashed: bool,
    ) {
        self.shapes.push(Shape::Polyline { points: vec![from, to], color, width_px, dashed });
    }

    pub(super) fn text(&mut self, x: f32, y: f32, text: impl Into<String>, style: TextStyle) {
        let text = text.into();
        if !text.is_empty() {
            self.shapes.push(Shape::Text {
                x,
                y,
                text,
                color: style.color,
                size_px: style.size_px,
                align: style.align,
                vertical: style.vertical,
            });
        }
    }
}

/// How a [`Shape::Text`] is drawn.
#[derive(Clone, Copy)]
pub(super) struct TextStyle {
    color: Rgba,
    size_px: f32,
    align: Align,
    vertical: bool,
}

impl TextStyle {
    pub(super) fn new(color: Rgba, size_px: f32, align: Align) -> TextStyle {
        TextStyle { color, size_px, align, vertical: false }
    }

    /// Turned a quarter turn anticlockwise, as y-axis titles are.
    pub(super) fn vertical(self) -> TextStyle {
        TextStyle { vertical: true, ..self }
    }
}

/// A rectangle: top-left corner (`x`, `y`), size `w` × `h`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rect {
    pub x: f32,
    pub y: f32,
    pub w: f32,
    pub h: f32,
}

impl Rect {
    pub const fn new(x: f32, y: f32, w: f32, h: f32) -> Rect {
        Rect { x, y, w, h }
    }

    pub fn right(self) -> f32 {
        self.x + self.w
    }

    pub fn bottom(self) -> f32 {
        self.y + self.h
    }

    pub fn center(self) -> (f32, f32) {
        (self.x + self.w / 2.0, self.y + self.h / 2.0)
    }

    /// True when (`x`, `y`) is inside or on the edge.
    pub fn contains(self, x: f32, y: f32) -> bool {
        x >= self.x && x <= self.right() && y >= self.y && y <= self.bottom()
    }

    /// True when the two share a region of positive area.
    pub fn overlaps(self, other: Rect) -> bool {
        self.x < other.right() && other.x < self.right() && self.y < other.bottom() && other.y < self.bottom()
    }
}

/// A rectangle whose negative sizes (when the canvas is too small for the
/// margins) are clamped to 0.
pub(super) fn rect(x: f32, y: f32, w: f32, h: f32) -> Rect {
    Rect::new(x, y, w.max(0.0), h.max(0.0))
}
