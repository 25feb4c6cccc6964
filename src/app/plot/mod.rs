//! The app's plots as pure data: a figure is laid out here into a list of
//! shapes in pixel coordinates, which the browser merely paints (see
//! `web::canvas2d`). Keeping layout and hit-testing here lets them be tested
//! natively and keeps the wasm side thin.
//!
//! The figure is the paper's, live, in five panels:
//! - (a) the smoothed foot signal that pass 1 compares,
//! - (b) the foot heights before correction and (c) after it,
//! - (d) the hips' path on the floor seen from above, original and corrected,
//! - (e) the stance strip: which foot was held still in each frame, and why
//!   (or, for the contact method, which feet were on the floor).
//!
//! The time panels (a), (b), (c) and (e) share one time axis, numbered under
//! (e), so a single cursor lines up across them. Left is always
//! [`LEFT_COLOR`] and right [`RIGHT_COLOR`]; "before" is drawn ghosted or
//! grey, "after" solid.
//!
//! Drawing is split in two because a recording can have 100,000 frames: the
//! static part ([`draw_static`]) holds the long series, decimated to at most
//! two points per pixel column, and is meant to be painted once into an
//! offscreen canvas; the cursor ([`draw_cursor`]) is a handful of shapes
//! drawn over it each frame.

use glam::DVec3;

use crate::body::feet::Foot;

// --- What is plotted ---------------------------------------------------------

/// Why a frame's stance is what it is: which foot the method held still, and
/// which rule made it do so.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum StanceReason {
    /// Paper pass 1: the foot with the lower smoothed acceleration.
    Acceleration,
    /// Paper pass 2: the lower foot, where the heights differ by more than dyEps.
    Height,
    /// Both passes pinned this foot.
    Both,
    /// The contact method: this foot alone is on the floor.
    Contact,
}

/// One frame of the stance strip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Stance {
    /// No foot pinned (e.g. the paper method's zeroed tails).
    Free,
    Pinned(Foot, StanceReason),
    /// Neither foot on the floor (running, jumps).
    Flight,
    /// Both feet on the floor: the contact method's double support.
    Double,
}

impl Stance {
    /// True for the contact method's decisions that the paper method never
    /// makes: one foot alone on the floor, or both.
    pub const fn is_contact(self) -> bool {
        matches!(self, Stance::Pinned(_, StanceReason::Contact) | Stance::Double)
    }
}

/// Everything the plots show, frame by frame. Pairs are `[left, right]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlotData {
    pub fps: f64,
    /// (a) the signal that chose the planted foot, and its label with unit,
    /// e.g. "smoothed acceleration (g)".
    pub foot_signal: [Vec<f64>; 2],
    pub foot_signal_label: String,
    /// (b) foot heights before correction, cm.
    pub heights_before_cm: [Vec<f64>; 2],
    /// (c) foot heights after correction, cm.
    pub heights_after_cm: [Vec<f64>; 2],
    /// (d) hips on the floor, before and after (X/Z used; Y is up).
    pub hips_before_cm: Vec<DVec3>,
    pub hips_after_cm: Vec<DVec3>,
    /// (e) the stance strip.
    pub stance: Vec<Stance>,
}

impl PlotData {
    /// The number of frames the plots span: the length of the longest series.
    /// They normally all have one entry per frame; a shorter one is drawn as
    /// far as it goes.
    pub fn frame_count(&self) -> usize {
        let [a0, a1] = &self.foot_signal;
        let [b0, b1] = &self.heights_before_cm;
        let [c0, c1] = &self.heights_after_cm;
        [
            a0.len(),
            a1.len(),
            b0.len(),
            b1.len(),
            c0.len(),
            c1.len(),
            self.hips_before_cm.len(),
            self.hips_after_cm.len(),
            self.stance.len(),
        ]
        .into_iter()
        .max()
        .unwrap_or(0)
    }
}

// --- Shapes --------------------------------------------------------------------

/// An sRGB colour with straight (not premultiplied) alpha, each 0–255.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rgba(pub u8, pub u8, pub u8, pub u8);

impl Rgba {
    /// The same colour with alpha `alpha` (0–255).
    pub const fn with_alpha(self, alpha: u8) -> Rgba {
        Rgba(self.0, self.1, self.2, alpha)
    }

    /// The colour as a CSS string, `rgba(r,g,b,a)` with `a` from 0 to 1, as
    /// canvas fill and stroke styles take it.
    pub fn to_css(self) -> String {
        let Rgba(r, g, b, a) = self;
        // Three decimals tell all 256 alpha levels apart.
        format!("rgba({r},{g},{b},{:.3})", f32::from(a) / 255.0)
    }
}

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

/// The font family text is drawn in; the layout's text-width estimate assumes it.
pub const FONT_FAMILY: &str = "system-ui, sans-serif";
/// Dashed lines: this many pixels drawn, then this many left out.
pub const DASH_PX: [f32; 2] = [6.0, 4.0];

/// One thing to paint. Coordinates are canvas pixels, origin top left, y down.
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

    fn fill(&mut self, r: Rect, color: Rgba) {
        if r.w > 0.0 && r.h > 0.0 {
            self.shapes.push(Shape::Rect { x: r.x, y: r.y, w: r.w, h: r.h, color });
        }
    }

    fn segment(&mut self, from: (f32, f32), to: (f32, f32), color: Rgba, width_px: f32, dashed: bool) {
        self.shapes.push(Shape::Polyline { points: vec![from, to], color, width_px, dashed });
    }

    fn text(&mut self, x: f32, y: f32, text: impl Into<String>, style: TextStyle) {
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

#[derive(Clone, Copy)]
struct TextStyle {
    color: Rgba,
    size_px: f32,
    align: Align,
    vertical: bool,
}

impl TextStyle {
    fn new(color: Rgba, size_px: f32, align: Align) -> TextStyle {
        TextStyle { color, size_px, align, vertical: false }
    }

    fn vertical(self) -> TextStyle {
        TextStyle { vertical: true, ..self }
    }
}

// --- Colours -------------------------------------------------------------------

/// The left foot, in every panel (the 3D view marks it alike).
pub const LEFT_COLOR: Rgba = Rgba(255, 99, 92, 255);
/// The right foot, in every panel.
pub const RIGHT_COLOR: Rgba = Rgba(72, 200, 120, 255);
/// "Before correction" series are drawn in their colour at this alpha.
pub const GHOST_ALPHA: u8 = 115;
/// The original (uncorrected) hips path.
pub const ORIGINAL_COLOR: Rgba = Rgba(160, 166, 178, 200);
/// The corrected hips path (the 3D view's corrected trail).
pub const CORRECTED_COLOR: Rgba = Rgba(255, 200, 40, 255);
/// The time cursor.
pub const CURSOR_COLOR: Rgba = Rgba(255, 255, 255, 220);

const TEXT_COLOR: Rgba = Rgba(230, 230, 234, 255);
const MUTED_COLOR: Rgba = Rgba(154, 160, 170, 255);
const GRID_COLOR: Rgba = Rgba(255, 255, 255, 26);
const TICK_COLOR: Rgba = Rgba(154, 160, 170, 160);
/// A faint wash behind each plot area, so empty plots still show where they are.
const PLOT_BACKGROUND: Rgba = Rgba(255, 255, 255, 9);
/// A dark ring under cursor dots, so they stand out on any line.
const HALO_COLOR: Rgba = Rgba(0, 0, 0, 170);

/// The stance categories: the paper method's in [`STANCE_LEGEND`] order, then
/// the contact method's. [`stance_color`] gives the kinds of each method's
/// legend distinct colours.
const STANCE_KINDS: [Stance; 11] = [
    Stance::Pinned(Foot::Left, StanceReason::Acceleration),
    Stance::Pinned(Foot::Left, StanceReason::Height),
    Stance::Pinned(Foot::Left, StanceReason::Both),
    Stance::Pinned(Foot::Right, StanceReason::Acceleration),
    Stance::Pinned(Foot::Right, StanceReason::Height),
    Stance::Pinned(Foot::Right, StanceReason::Both),
    Stance::Free,
    Stance::Flight,
    Stance::Pinned(Foot::Left, StanceReason::Contact),
    Stance::Pinned(Foot::Right, StanceReason::Contact),
    Stance::Double,
];

/// The colour of a stance in the strip (e). Each foot keeps its hue, from
/// light (pinned by acceleration only) through its own colour (by height
/// only) to dark (both passes agree); no foot pinned is grey, flight violet.
/// The contact method's single support is the foot's own colour (as the
/// paper's "height" is: the two methods never share a strip), its double
/// support a light warm grey.
pub const fn stance_color(stance: Stance) -> Rgba {
    match stance {
        Stance::Pinned(Foot::Left, StanceReason::Acceleration) => Rgba(255, 176, 168, 255),
        Stance::Pinned(Foot::Left, StanceReason::Height) => LEFT_COLOR,
        Stance::Pinned(Foot::Left, StanceReason::Both) => Rgba(186, 38, 46, 255),
        Stance::Pinned(Foot::Right, StanceReason::Acceleration) => Rgba(166, 232, 190, 255),
        Stance::Pinned(Foot::Right, StanceReason::Height) => RIGHT_COLOR,
        Stance::Pinned(Foot::Right, StanceReason::Both) => Rgba(22, 128, 68, 255),
        Stance::Free => Rgba(88, 93, 104, 255),
        Stance::Flight => Rgba(164, 124, 255, 255),
        Stance::Pinned(Foot::Left, StanceReason::Contact) => LEFT_COLOR,
        Stance::Pinned(Foot::Right, StanceReason::Contact) => RIGHT_COLOR,
        Stance::Double => Rgba(226, 221, 204, 255),
    }
}

fn stance_index(stance: Stance) -> usize {
    STANCE_KINDS.iter().position(|&k| k == stance).unwrap_or(0)
}

// --- Legends -------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq)]
enum Swatch {
    /// A group label: text only.
    Label,
    /// A short stroke of a line's colour, dashed or not.
    Line(Rgba, bool),
    /// A filled square.
    Block(Rgba),
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct LegendItem {
    swatch: Swatch,
    text: &'static str,
}

const fn item(swatch: Swatch, text: &'static str) -> LegendItem {
    LegendItem { swatch, text }
}

const FEET_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(LEFT_COLOR, false), "left foot"),
    item(Swatch::Line(RIGHT_COLOR, false), "right foot"),
];
const FEET_BEFORE_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(LEFT_COLOR.with_alpha(GHOST_ALPHA), false), "left foot"),
    item(Swatch::Line(RIGHT_COLOR.with_alpha(GHOST_ALPHA), false), "right foot"),
];
const PATH_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(ORIGINAL_COLOR, true), "original"),
    item(Swatch::Line(CORRECTED_COLOR, false), "corrected"),
];
/// The paper method's stance legend in groups that are kept on one row when
/// they fit.
const STANCE_LEGEND: [&[LegendItem]; 3] = [
    &[
        item(Swatch::Label, "left:"),
        item(Swatch::Block(stance_color(STANCE_KINDS[0])), "acceleration"),
        item(Swatch::Block(stance_color(STANCE_KINDS[1])), "height"),
        item(Swatch::Block(stance_color(STANCE_KINDS[2])), "both"),
    ],
    &[
        item(Swatch::Label, "right:"),
        item(Swatch::Block(stance_color(STANCE_KINDS[3])), "acceleration"),
        item(Swatch::Block(stance_color(STANCE_KINDS[4])), "height"),
        item(Swatch::Block(stance_color(STANCE_KINDS[5])), "both"),
    ],
    &[
        item(Swatch::Block(stance_color(STANCE_KINDS[6])), "none pinned"),
        item(Swatch::Block(stance_color(STANCE_KINDS[7])), "flight"),
    ],
];
/// The contact method's stance legend, grouped as [`STANCE_LEGEND`].
const CONTACT_LEGEND: [&[LegendItem]; 2] = [
    &[
        item(Swatch::Block(stance_color(STANCE_KINDS[8])), "left foot"),
        item(Swatch::Block(stance_color(STANCE_KINDS[9])), "right foot"),
    ],
    &[
        item(Swatch::Block(stance_color(STANCE_KINDS[10])), "both feet"),
        item(Swatch::Block(stance_color(STANCE_KINDS[7])), "flight"),
    ],
];
/// Every legend (e) may draw. [`layout`] leaves room for the tallest, so the
/// panels do not move with the data.
const STANCE_LEGENDS: [&[&[LegendItem]]; 2] = [&STANCE_LEGEND, &CONTACT_LEGEND];

/// The legend and titles (longest first) of (e) for `stance`: the contact
/// method's when any frame has one of its decisions, else the paper's.
fn stance_legend(stance: &[Stance]) -> (&'static [&'static [LegendItem]], &'static [&'static str]) {
    if stance.iter().any(|s| s.is_contact()) {
        (
            &CONTACT_LEGEND,
            &["(e) stance: which feet are on the floor", "(e) feet on the floor", "(e) feet", "(e)"],
        )
    } else {
        (
            &STANCE_LEGEND,
            &[
                "(e) stance: which foot is pinned, and why",
                "(e) pinned foot, and why",
                "(e) pinned foot",
                "(e)",
            ],
        )
    }
}

// Legend geometry, in units of the font size.
const SWATCH_LINE: f32 = 1.4;
const SWATCH_BLOCK: f32 = 0.8;
const SWATCH_GAP: f32 = 0.3;
const ITEM_GAP: f32 = 0.9;

fn legend_item_width(item: &LegendItem, font_px: f32) -> f32 {
    let swatch = match item.swatch {
        Swatch::Label => 0.0,
        Swatch::Line(..) => (SWATCH_LINE + SWATCH_GAP) * font_px,
        Swatch::Block(_) => (SWATCH_BLOCK + SWATCH_GAP) * font_px,
    };
    swatch + text_width_px(item.text, font_px)
}

/// Where each legend item goes when `groups` of items flow left to right in
/// rows of `width_px`: `(x offset, row)` per item, in order, and the number of
/// rows. A group starts a new row rather than be split, unless it is wider
/// than a row; a group label never ends a row.
fn flow_legend(groups: &[&[LegendItem]], width_px: f32, font_px: f32) -> (Vec<(f32, usize)>, usize) {
    let gap = ITEM_GAP * font_px;
    let mut placed = Vec::new();
    let (mut x, mut row) = (0.0f32, 0usize);
    for group in groups {
        let group_w = group.iter().map(|it| legend_item_width(it, font_px) + gap).sum::<f32>() - gap;
        if x > 0.0 && x + group_w > width_px {
            row += 1;
            x = 0.0;
        }
        for (i, it) in group.iter().enumerate() {
            let w = legend_item_width(it, font_px);
            let needed = match (it.swatch, group.get(i + 1)) {
                (Swatch::Label, Some(next)) => w + gap + legend_item_width(next, font_px),
                _ => w,
            };
            if x > 0.0 && x + needed > width_px {
                row += 1;
                x = 0.0;
            }
            placed.push((x, row));
            x += w + gap;
        }
    }
    let rows = if placed.is_empty() { 0 } else { row + 1 };
    (placed, rows)
}

/// Draws one legend item with its left edge at `x`, centred on `y`.
fn draw_legend_item(fig: &mut Figure, it: &LegendItem, x: f32, y: f32, font_px: f32) {
    let text_x = match it.swatch {
        Swatch::Label => x,
        Swatch::Line(color, dashed) => {
            // Short dashes, so a dashed swatch shows at least one gap.
            let w = SWATCH_LINE * font_px;
            if dashed {
                let dash = w / 3.0;
                fig.segment((x, y), (x + dash, y), color, 2.0, false);
                fig.segment((x + 2.0 * dash, y), (x + w, y), color, 2.0, false);
            } else {
                fig.segment((x, y), (x + w, y), color, 2.0, false);
            }
            x + (SWATCH_LINE + SWATCH_GAP) * font_px
        }
        Swatch::Block(color) => {
            let s = SWATCH_BLOCK * font_px;
            fig.fill(Rect::new(x, y - s / 2.0, s, s), color);
            x + (SWATCH_BLOCK + SWATCH_GAP) * font_px
        }
    };
    let color = if it.swatch == Swatch::Label { MUTED_COLOR } else { TEXT_COLOR };
    fig.text(text_x, y, it.text, TextStyle::new(color, font_px, Align::Left));
}

// --- Text ------------------------------------------------------------------------

/// Average glyph width of [`FONT_FAMILY`] as a fraction of the font size.
/// Canvas text can only be measured in the browser, so the layout estimates;
/// this errs wide for lower-case text, so estimated text rarely overflows.
const CHAR_WIDTH: f32 = 0.56;

/// Estimated width in pixels of `text` at `size_px`.
fn text_width_px(text: &str, size_px: f32) -> f32 {
    text.chars().count() as f32 * CHAR_WIDTH * size_px
}

/// The first of `candidates` (longest first) whose estimated width fits in
/// `max_px`; failing all, the last cut short with an ellipsis; `None` when not
/// even one character and the ellipsis fit.
fn fit_text(candidates: &[&str], max_px: f32, size_px: f32) -> Option<String> {
    if let Some(c) = candidates.iter().find(|c| text_width_px(c, size_px) <= max_px) {
        return Some(c.to_string());
    }
    let last = candidates.last()?;
    let chars = (max_px / (CHAR_WIDTH * size_px)).floor();
    if chars.is_nan() || chars < 2.0 {
        return None;
    }
    let mut cut: String = last.chars().take(chars as usize - 1).collect();
    cut.push('…');
    Some(cut)
}

// --- Layout --------------------------------------------------------------------

/// A rectangle in canvas pixels: top-left corner (`x`, `y`), size `w` × `h`.
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
fn rect(x: f32, y: f32, w: f32, h: f32) -> Rect {
    Rect::new(x, y, w.max(0.0), h.max(0.0))
}

/// The five panels, in the paper's order (a)–(e).
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
}

impl Panel {
    /// All panels, (a) to (e).
    pub const ALL: [Panel; 5] =
        [Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter, Panel::TopView, Panel::Stance];

    /// 0 for (a) to 4 for (e).
    pub fn index(self) -> usize {
        match self {
            Panel::FootSignal => 0,
            Panel::HeightsBefore => 1,
            Panel::HeightsAfter => 2,
            Panel::TopView => 3,
            Panel::Stance => 4,
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
    panels: [PanelRects; 5],
}

impl Layout {
    /// The rectangles of `panel`.
    pub fn panel(&self, panel: Panel) -> PanelRects {
        self.panels[panel.index()]
    }

    /// The data area of `panel`.
    pub fn plot(&self, panel: Panel) -> Rect {
        self.panel(panel).plot
    }

    /// The data areas of (a) to (e) as `[x, y, w, h]` each, flattened (20
    /// numbers), for JavaScript and browser tests.
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
const HEADER: f32 = 1.5;
/// Left of a plot: the vertical axis title and the tick labels (about six
/// characters of tick font).
const MARGIN_LEFT: f32 = 4.9;
/// Right of a plot: room for half of the last x tick label.
const MARGIN_RIGHT: f32 = 1.2;
/// Under a plot with a numbered x axis: a row of tick labels, a row for the title.
const AXIS_ROW: f32 = 1.4;
/// Height of the stance strip's bar.
const STRIP: f32 = 1.8;
/// One row of the stance legend.
const LEGEND_ROW: f32 = 1.5;
/// Tick labels are this much smaller than the rest.
const TICK_FONT: f32 = 0.9;
/// The top view goes beside the time panels when the canvas is at least this
/// many times wider than tall: then the time panels keep their width and the
/// top view gets the full height.
const SIDE_BY_SIDE_ASPECT: f32 = 1.15;

/// Lays the five panels out on a `width` × `height` pixel canvas.
///
/// The time panels (a), (b), (c) and (e) are stacked in one column with their
/// plot areas aligned, so that they share a time axis (numbered under (e)),
/// and the top view (d) goes beside them when the canvas is wide
/// ([`Layout::side_by_side`]), as square as the height allows but at most 45%
/// of the width, or below them when it is not, taking up to 36% of the
/// height. The stance bar and all the text have fixed sizes in units of
/// [`Layout::font_px`], which follows the canvas size; (a), (b) and (c) share
/// what height is left equally.
///
/// Sizes that are not finite or below 1 are taken as 1; on a canvas too small
/// for the margins, plot areas shrink to zero size rather than go negative.
pub fn layout(width: f32, height: f32) -> Layout {
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

    let mut panels = [PanelRects::default(); 5];
    let plot_in = |outer: Rect, below: f32| {
        rect(
            outer.x + MARGIN_LEFT * f,
            outer.y + HEADER * f,
            outer.w - (MARGIN_LEFT + MARGIN_RIGHT) * f,
            outer.h - HEADER * f - below,
        )
    };
    let legend_rows =
        STANCE_LEGENDS.iter().map(|legend| flow_legend(legend, time_column.w, f).1).max().unwrap_or(0);
    let stance_h = (HEADER + STRIP + 2.0 * AXIS_ROW + LEGEND_ROW * legend_rows as f32) * f;
    let series_plot_h = ((time_column.h - stance_h - 3.0 * gap - 3.0 * HEADER * f) / 3.0).max(0.0);
    let mut y = time_column.y;
    for panel in [Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter] {
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
    Layout { width, height, font_px: f, side_by_side, panels }
}

/// The panel whose area (title and labels included) holds (`x`, `y`).
pub fn panel_at(layout: &Layout, x: f32, y: f32) -> Option<Panel> {
    Panel::ALL.into_iter().find(|&p| layout.panel(p).outer.contains(x, y))
}

// --- Axes ------------------------------------------------------------------------

/// Evenly spaced "nice" values in `lo..=hi`: the multiples of a step of 1, 2
/// or 5 × 10^k, the smallest such step giving at most `max_count` of them.
/// Returns the values and the step; no values for an empty or non-finite
/// range.
fn nice_ticks(lo: f64, hi: f64, max_count: usize) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) || max_count < 2 {
        return (Vec::new(), 0.0);
    }
    // No step below span / max_count can do; try the nice steps upwards from
    // there (a step of span / (max_count - 1) always does, so few are tried).
    let mut magnitude = 10f64.powf((span / max_count as f64).log10().floor());
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
fn multiples(lo: f64, hi: f64, step: f64, max_count: usize) -> Option<Vec<f64>> {
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
fn tick_label(value: f64, step: f64) -> String {
    let decimals = (-step.log10() - 1e-9).ceil().clamp(0.0, 12.0) as usize;
    let value = if value.abs() < step * 1e-6 { 0.0 } else { value };
    format!("{value:.decimals$}")
}

/// Nice ticks in `lo..=hi` along a horizontal axis drawn at `px_per_unit`,
/// as many as fit without their labels running into each other.
fn x_ticks(lo: f64, hi: f64, px_per_unit: f64, font_px: f32) -> (Vec<f64>, f64) {
    let tick_px = TICK_FONT * font_px;
    let length_px = ((hi - lo) * px_per_unit) as f32;
    // Labels are a few characters wide: start from one per 3 font sizes and
    // thin out until the widest label, plus a gap, fits between ticks.
    let mut budget = tick_budget(length_px, 3.0 * font_px);
    loop {
        let (ticks, step) = nice_ticks(lo, hi, budget);
        let widest = ticks.iter().map(|t| text_width_px(&tick_label(*t, step), tick_px)).fold(0.0, f32::max);
        if widest + font_px <= (step * px_per_unit) as f32 || budget <= 2 {
            return (ticks, step);
        }
        budget -= 1;
    }
}

/// How many ticks fit along `length_px` if each needs `spacing_px`.
fn tick_budget(length_px: f32, spacing_px: f32) -> usize {
    let n = (length_px / spacing_px).floor();
    if n.is_finite() && n >= 1.0 { (n as usize).saturating_add(1).min(50) } else { 2 }
}

/// The time panels' horizontal mapping, shared so that one cursor lines up
/// across them: frame 0 at the plot's left edge, the last frame at its right
/// edge (a single frame sits in the middle).
#[derive(Clone, Copy, Debug)]
struct TimeAxis {
    frames: usize,
    /// `None` when the frame rate is unusable: the axis then counts frames.
    fps: Option<f64>,
}

impl TimeAxis {
    fn new(data: &PlotData) -> TimeAxis {
        let fps = (data.fps.is_finite() && data.fps > 0.0).then_some(data.fps);
        TimeAxis { frames: data.frame_count(), fps }
    }

    /// The x of (possibly fractional) frame `frame` in `plot`.
    fn x(&self, plot: Rect, frame: f64) -> f32 {
        if self.frames <= 1 {
            return plot.x + plot.w / 2.0;
        }
        plot.x + plot.w * (frame / (self.frames - 1) as f64) as f32
    }

    /// The frame whose x in `plot` is nearest to `x` (clamped to the plot).
    fn frame_at(&self, plot: Rect, x: f32) -> usize {
        let u = (x - plot.x) / plot.w;
        if self.frames <= 1 || !u.is_finite() {
            return 0;
        }
        (f64::from(u.clamp(0.0, 1.0)) * (self.frames - 1) as f64).round() as usize
    }

    /// The pixel column (of `columns` across the plot) frame `frame` falls in.
    fn column(&self, frame: usize, columns: usize) -> usize {
        if self.frames <= 1 {
            return 0;
        }
        // u64: frames × columns overflows a 32-bit usize for long recordings.
        let c = frame as u64 * columns as u64 / (self.frames - 1) as u64;
        (c as usize).min(columns.saturating_sub(1))
    }

    /// Tick positions (in frames) and labels (in seconds, or frames without a
    /// frame rate) for a plot `plot_w` pixels wide.
    fn ticks(&self, plot_w: f32, font_px: f32) -> Vec<(f64, String)> {
        match self.frames {
            0 => Vec::new(),
            1 => vec![(0.0, "0".to_string())],
            n => {
                let frames_per_unit = self.fps.unwrap_or(1.0);
                let end = (n - 1) as f64 / frames_per_unit;
                let (ticks, step) = x_ticks(0.0, end, f64::from(plot_w) / end, font_px);
                ticks.into_iter().map(|t| (t * frames_per_unit, tick_label(t, step))).collect()
            }
        }
    }

    fn title(&self) -> &'static str {
        if self.fps.is_some() { "time (s)" } else { "frame" }
    }
}

/// The vertical mapping of a series panel: `lo` at the plot's bottom, `hi` at its top.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ValueScale {
    lo: f64,
    hi: f64,
}

impl ValueScale {
    /// The range of the finite values of `series`, widened by 5% of it on
    /// each side so lines clear the frame; a flat series gets ±5% of its value
    /// (at least ±0.5), no data 0–1.
    fn of(series: &[Vec<f64>]) -> ValueScale {
        let (lo, hi) = padded_range(finite_range(series));
        ValueScale { lo, hi }
    }

    fn y(self, plot: Rect, value: f64) -> f32 {
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
fn finite_range(series: &[Vec<f64>]) -> Option<(f64, f64)> {
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
struct TopView {
    center_x_cm: f64,
    center_z_cm: f64,
    px_per_cm: f64,
    plot: Rect,
}

/// Half the smallest floor area the top view shows, so a hips path that
/// barely moves is not magnified into noise.
const TOP_VIEW_MIN_HALF_CM: f64 = 25.0;

impl TopView {
    /// Fits every finite point of both hips paths in `plot`, with 6% to spare.
    fn new(data: &PlotData, plot: Rect) -> TopView {
        let range = floor_range(&[&data.hips_before_cm, &data.hips_after_cm]);
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
    fn px_of(&self, p: DVec3) -> Option<(f32, f32)> {
        let (cx, cy) = self.plot.center();
        let x = cx + ((p.x - self.center_x_cm) * self.px_per_cm) as f32;
        let y = cy + ((p.z - self.center_z_cm) * self.px_per_cm) as f32;
        (x.is_finite() && y.is_finite()).then_some((x, y))
    }

    /// The X range (cm) visible across the plot.
    fn visible_x_cm(&self) -> (f64, f64) {
        let half = f64::from(self.plot.w) / 2.0 / self.px_per_cm;
        (self.center_x_cm - half, self.center_x_cm + half)
    }

    /// The Z range (cm) visible down the plot.
    fn visible_z_cm(&self) -> (f64, f64) {
        let half = f64::from(self.plot.h) / 2.0 / self.px_per_cm;
        (self.center_z_cm - half, self.center_z_cm + half)
    }
}

// --- Lines -----------------------------------------------------------------------

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
fn columns_in(w: f32) -> usize {
    let c = w.ceil();
    if c.is_finite() && c >= 1.0 { (c as usize).min(16_384) } else { 1 }
}

/// The series `values[frame]` drawn in `plot`, broken where values are not
/// finite. With more than two frames per pixel column, each column keeps only
/// its lowest and highest value, in frame order: at most two points per
/// column are drawn, and every spike stays visible.
fn series_shapes(values: &[f64], time: &TimeAxis, plot: Rect, scale: ValueScale, color: Rgba) -> Vec<Shape> {
    let mut trace = Trace::new(color, 1.5, false);
    let point = |f: usize, v: f64| (time.x(plot, f as f64), scale.y(plot, v));
    let columns = columns_in(plot.w);
    if values.len() <= 2 * columns {
        for (f, &v) in values.iter().enumerate() {
            trace.push(v.is_finite().then(|| point(f, v)));
        }
        return trace.finish();
    }
    // (frame, value) of the lowest and the highest finite value in the column.
    type Extremes = Option<((usize, f64), (usize, f64))>;
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
    for (f, &v) in values.iter().enumerate() {
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
fn path_shapes(points: &[DVec3], view: &TopView, color: Rgba, width_px: f32, dashed: bool) -> Vec<Shape> {
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

// --- Panels ----------------------------------------------------------------------

/// The panel's header: `legend` flush right (stopping `reserve_px` short of
/// the edge), and left of it the first of `titles` that fits.
fn draw_header(
    fig: &mut Figure,
    outer: Rect,
    font_px: f32,
    titles: &[&str],
    legend: &[LegendItem],
    reserve_px: f32,
) {
    let y = outer.y + HEADER * font_px / 2.0;
    let mut right = outer.right() - reserve_px;
    for it in legend.iter().rev() {
        right -= legend_item_width(it, font_px);
        draw_legend_item(fig, it, right, y, font_px);
        right -= ITEM_GAP * font_px;
    }
    if let Some(title) = fit_text(titles, right - outer.x, font_px) {
        fig.text(outer.x, y, title, TextStyle::new(TEXT_COLOR, font_px, Align::Left));
    }
}

/// A vertical axis title, centred beside `plot` in the left margin of `outer`.
fn draw_y_title(fig: &mut Figure, outer: Rect, plot: Rect, font_px: f32, titles: &[&str]) {
    if let Some(title) = fit_text(titles, plot.h, font_px) {
        let style = TextStyle::new(MUTED_COLOR, font_px, Align::Center).vertical();
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
            fig.segment((plot.x, y), (plot.right(), y), GRID_COLOR, 1.0, false);
            let style = TextStyle::new(MUTED_COLOR, tick_px, Align::Right);
            fig.text(plot.x - 0.35 * font_px, y, tick_label(v, step), style);
        }
    }
}

/// Vertical grid lines at the time ticks, so (a)–(c) can be read against the
/// numbers under (e).
fn draw_time_grid(fig: &mut Figure, plot: Rect, time: &TimeAxis, font_px: f32) {
    for (frame, _) in time.ticks(plot.w, font_px) {
        let x = time.x(plot, frame);
        fig.segment((x, plot.y), (x, plot.bottom()), GRID_COLOR, 1.0, false);
    }
}

/// Numbered ticks under `plot` at `ticks` (position in px, label), and the
/// axis title centred below them.
fn draw_x_axis(fig: &mut Figure, plot: Rect, font_px: f32, ticks: &[(f32, String)], title: &str) {
    let tick_px = TICK_FONT * font_px;
    let label_y = plot.bottom() + AXIS_ROW * font_px / 2.0;
    for (x, label) in ticks {
        fig.segment((*x, plot.bottom()), (*x, plot.bottom() + 0.3 * font_px), TICK_COLOR, 1.0, false);
        fig.text(
            *x,
            label_y + 0.15 * font_px,
            label.clone(),
            TextStyle::new(MUTED_COLOR, tick_px, Align::Center),
        );
    }
    let title_y = plot.bottom() + 1.5 * AXIS_ROW * font_px;
    fig.text(plot.x + plot.w / 2.0, title_y, title, TextStyle::new(MUTED_COLOR, font_px, Align::Center));
}

/// What a series panel shows.
struct SeriesPanel<'a> {
    panel: Panel,
    series: &'a [Vec<f64>; 2],
    colors: [Rgba; 2],
    titles: &'a [&'a str],
    y_titles: &'a [&'a str],
    legend: &'a [LegendItem],
}

fn draw_series_panel(fig: &mut Figure, layout: &Layout, time: &TimeAxis, p: &SeriesPanel) {
    let f = layout.font_px;
    let PanelRects { outer, plot } = layout.panel(p.panel);
    fig.fill(plot, PLOT_BACKGROUND);
    let scale = ValueScale::of(p.series);
    draw_time_grid(fig, plot, time, f);
    draw_y_ticks(fig, plot, f, nice_ticks(scale.lo, scale.hi, y_tick_budget(plot, f)), |v| scale.y(plot, v));
    draw_y_title(fig, outer, plot, f, p.y_titles);
    for (values, color) in p.series.iter().zip(p.colors) {
        fig.shapes.extend(series_shapes(values, time, plot, scale, color));
    }
    draw_header(fig, outer, f, p.titles, p.legend, 0.0);
    if time.frames == 0 {
        let style = TextStyle::new(MUTED_COLOR, f, Align::Center);
        let (cx, cy) = plot.center();
        fig.text(cx, cy, fit_text(&["no data"], plot.w, f).unwrap_or_default(), style);
    }
}

fn draw_top_view(fig: &mut Figure, layout: &Layout, data: &PlotData) {
    let f = layout.font_px;
    let PanelRects { outer, plot } = layout.panel(Panel::TopView);
    fig.fill(plot, PLOT_BACKGROUND);
    let view = TopView::new(data, plot);
    let (cx, cy) = plot.center();
    // One step for both axes, the coarser of what each has room for, so the
    // grid is square like the floor it measures; unless that leaves an axis
    // with fewer than three numbers (a long, narrow path), then each its own.
    let ((x_lo, x_hi), (z_lo, z_hi)) = (view.visible_x_cm(), view.visible_z_cm());
    let (x_own, z_own) =
        (x_ticks(x_lo, x_hi, view.px_per_cm, f), nice_ticks(z_lo, z_hi, y_tick_budget(plot, f)));
    let common = x_own.1.max(z_own.1);
    let (x_ticks_cm, z_ticks_cm) =
        match (multiples(x_lo, x_hi, common, 50), multiples(z_lo, z_hi, common, 50)) {
            (Some(x), Some(z)) if x.len() >= 3 && z.len() >= 3 => ((x, common), (z, common)),
            _ => (x_own, z_own),
        };
    // Z grid and numbers, left.
    let z_to_px = |z: f64| cy + ((z - view.center_z_cm) * view.px_per_cm) as f32;
    draw_y_ticks(fig, plot, f, z_ticks_cm, z_to_px);
    draw_y_title(fig, outer, plot, f, &["z (cm)", "z"]);
    // X grid and numbers, below.
    let mut labelled = Vec::new();
    let (x_ticks_cm, x_step) = x_ticks_cm;
    for x_cm in x_ticks_cm {
        let x = cx + ((x_cm - view.center_x_cm) * view.px_per_cm) as f32;
        if x.is_finite() {
            fig.segment((x, plot.y), (x, plot.bottom()), GRID_COLOR, 1.0, false);
            labelled.push((x, tick_label(x_cm, x_step)));
        }
    }
    draw_x_axis(fig, plot, f, &labelled, "x (cm)");
    fig.shapes.extend(path_shapes(&data.hips_before_cm, &view, ORIGINAL_COLOR, 1.5, true));
    fig.shapes.extend(path_shapes(&data.hips_after_cm, &view, CORRECTED_COLOR, 2.0, false));
    let titles =
        ["(d) hips path on the floor, seen from above", "(d) hips path, from above", "(d) hips path", "(d)"];
    draw_header(fig, outer, f, &titles, &PATH_LEGEND, 0.0);
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
fn readout_reserve_px(outer: Rect) -> f32 {
    0.5 * outer.w
}

fn draw_stance_panel(fig: &mut Figure, layout: &Layout, time: &TimeAxis, stance: &[Stance]) {
    let f = layout.font_px;
    let PanelRects { outer, plot } = layout.panel(Panel::Stance);
    fig.fill(plot, PLOT_BACKGROUND);
    draw_stance_bar(fig, plot, time, stance);
    let ticks: Vec<(f32, String)> =
        time.ticks(plot.w, f).into_iter().map(|(frame, label)| (time.x(plot, frame), label)).collect();
    draw_x_axis(fig, plot, f, &ticks, time.title());
    let (legend, titles) = stance_legend(stance);
    let (placed, _) = flow_legend(legend, outer.w, f);
    let legend_top = plot.bottom() + 2.0 * AXIS_ROW * f;
    for (it, (dx, row)) in legend.iter().copied().flatten().zip(placed) {
        let y = legend_top + (row as f32 + 0.5) * LEGEND_ROW * f;
        draw_legend_item(fig, it, outer.x + dx, y, f);
    }
    draw_header(fig, outer, f, titles, &[], readout_reserve_px(outer));
}

/// Everything that does not move with the time cursor: titles, legends,
/// axes with numbered ticks, grids, and the data of all five panels. Long
/// series are decimated (see [`series_shapes`], [`path_shapes`] and
/// [`draw_stance_bar`]), so the figure stays a few thousand points whatever
/// the recording's length; it is meant to be painted once per recording,
/// settings or size and kept (e.g. in an offscreen canvas).
pub fn draw_static(data: &PlotData, layout: &Layout) -> Figure {
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
            colors: [LEFT_COLOR, RIGHT_COLOR],
            titles: &[&signal_title, "(a) foot signal", "(a) signal", "(a)"],
            y_titles: &[label, &short_label, unit],
            legend: &FEET_LEGEND,
        },
        SeriesPanel {
            panel: Panel::HeightsBefore,
            series: &data.heights_before_cm,
            colors: [LEFT_COLOR.with_alpha(GHOST_ALPHA), RIGHT_COLOR.with_alpha(GHOST_ALPHA)],
            titles: &["(b) foot heights before correction", "(b) heights before", "(b) before", "(b)"],
            y_titles: &["height (cm)", "cm"],
            legend: &FEET_BEFORE_LEGEND,
        },
        SeriesPanel {
            panel: Panel::HeightsAfter,
            series: &data.heights_after_cm,
            colors: [LEFT_COLOR, RIGHT_COLOR],
            titles: &["(c) foot heights after correction", "(c) heights after", "(c) after", "(c)"],
            y_titles: &["height (cm)", "cm"],
            legend: &FEET_LEGEND,
        },
    ];
    for p in &panels {
        draw_series_panel(&mut fig, layout, &time, p);
    }
    draw_top_view(&mut fig, layout, data);
    draw_stance_panel(&mut fig, layout, &time, &data.stance);
    fig
}

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
    fig.shapes.push(Shape::Circle { x, y, radius_px: radius_px + 1.5, color: HALO_COLOR });
    fig.shapes.push(Shape::Circle { x, y, radius_px, color });
}

/// The time cursor at `frame` (clamped to the last frame): a vertical line
/// across the plots of (a), (b), (c) and (e), a dot on each foot's value in
/// (a)–(c), a dot on both hips paths in (d), and in the header of (e) the
/// time and the stance of that frame in words. Empty for empty data.
///
/// It recomputes the panels' scales, O(frames): about a millisecond for
/// 100,000 frames (natively), most of it reading the hips paths.
pub fn draw_cursor(data: &PlotData, frame: usize, layout: &Layout) -> Figure {
    let mut fig = Figure::new(layout.width, layout.height);
    let time = TimeAxis::new(data);
    if time.frames == 0 {
        return fig;
    }
    let frame = frame.min(time.frames - 1);
    let f = layout.font_px;
    for panel in [Panel::FootSignal, Panel::HeightsBefore, Panel::HeightsAfter, Panel::Stance] {
        let plot = layout.plot(panel);
        let x = time.x(plot, frame as f64);
        fig.segment((x, plot.y), (x, plot.bottom()), CURSOR_COLOR, 1.0, false);
    }
    for (panel, series) in [
        (Panel::FootSignal, &data.foot_signal),
        (Panel::HeightsBefore, &data.heights_before_cm),
        (Panel::HeightsAfter, &data.heights_after_cm),
    ] {
        let plot = layout.plot(panel);
        let scale = ValueScale::of(series);
        for (values, color) in series.iter().zip([LEFT_COLOR, RIGHT_COLOR]) {
            if let Some(&v) = values.get(frame).filter(|v| v.is_finite()) {
                dot(&mut fig, (time.x(plot, frame as f64), scale.y(plot, v)), 0.28 * f, color);
            }
        }
    }
    let view = TopView::new(data, layout.plot(Panel::TopView));
    for (path, color) in
        [(&data.hips_before_cm, ORIGINAL_COLOR.with_alpha(255)), (&data.hips_after_cm, CORRECTED_COLOR)]
    {
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
    if let Some(text) = fit_text(&candidates, readout_reserve_px(outer), f) {
        let style = TextStyle::new(TEXT_COLOR, f, Align::Right);
        fig.text(outer.right(), outer.y + HEADER * f / 2.0, text, style);
    }
    fig
}

/// The whole figure at `frame`: [`draw_static`] with [`draw_cursor`] over it.
pub fn draw(data: &PlotData, frame: usize, layout: &Layout) -> Figure {
    let mut fig = draw_static(data, layout);
    fig.extend(draw_cursor(data, frame, layout));
    fig
}

/// The frame to seek to for a click or drag at (`x`, `y`) canvas pixels: in a
/// time panel (anywhere in its area, titles included), the frame under `x`,
/// clamped to the plot's ends; in the top view, the frame whose corrected
/// hips point, or failing that original one, is drawn nearest to the click.
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
    // Corrected first, and only a strictly nearer original point wins, so
    // ties go to the corrected path, the one the user is inspecting.
    for path in [&data.hips_after_cm, &data.hips_before_cm] {
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

    /// Sizes of plot canvases the app meets: the tests' 400 × 300, the page's
    /// column at 1× and 2×, a wide embed, a phone.
    const SIZES: [(f32, f32); 7] = [
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
    fn synthetic(n: usize) -> PlotData {
        let t = |f: usize| f as f64 / 100.0;
        let wave = |f: usize, phase: f64| (t(f) * 3.0 + phase).sin();
        let spiral = |f: usize, r0: f64| {
            let a = t(f) * 0.8;
            DVec3::new((r0 + 20.0 * a) * a.cos(), 90.0, (r0 + 20.0 * a) * a.sin())
        };
        PlotData {
            fps: 100.0,
            foot_signal: [
                (0..n).map(|f| 1.0 + 0.3 * wave(f, 0.0)).collect(),
                (0..n).map(|f| 1.0 + 0.3 * wave(f, 3.0)).collect(),
            ],
            foot_signal_label: "smoothed acceleration (g)".to_string(),
            heights_before_cm: [
                (0..n).map(|f| 5.0 + 8.0 * wave(f, 0.0).max(0.0) + t(f)).collect(),
                (0..n).map(|f| 5.0 + 8.0 * wave(f, 3.0).max(0.0) + t(f)).collect(),
            ],
            heights_after_cm: [
                (0..n).map(|f| 5.0 + 8.0 * wave(f, 0.0).max(0.0)).collect(),
                (0..n).map(|f| 5.0 + 8.0 * wave(f, 3.0).max(0.0)).collect(),
            ],
            hips_before_cm: (0..n).map(|f| spiral(f, 40.0) + DVec3::new(t(f) * 10.0, 0.0, 0.0)).collect(),
            hips_after_cm: (0..n).map(|f| spiral(f, 30.0)).collect(),
            stance: (0..n)
                .map(|f| match (f / 37) % 9 {
                    8 => Stance::Flight,
                    k => STANCE_KINDS[k % 7],
                })
                .collect(),
        }
    }

    fn demo_data() -> PlotData {
        let session =
            crate::app::session::Session::open(crate::synth::demo::demo().recording(), Default::default())
                .expect("the demo opens");
        session.plot_data
    }

    /// A point that says where a shape is.
    fn anchor(shape: &Shape) -> (f32, f32) {
        match shape {
            Shape::Polyline { points, .. } => points.first().copied().unwrap_or((f32::NAN, f32::NAN)),
            Shape::Rect { x, y, w, h, .. } => (x + w / 2.0, y + h / 2.0),
            Shape::Text { x, y, .. } | Shape::Circle { x, y, .. } => (*x, *y),
        }
    }

    fn all_finite(fig: &Figure) -> bool {
        fig.shapes.iter().all(|s| match s {
            Shape::Polyline { points, width_px, .. } => {
                width_px.is_finite() && points.iter().all(|p| p.0.is_finite() && p.1.is_finite())
            }
            Shape::Rect { x, y, w, h, .. } => [x, y, w, h].iter().all(|v| v.is_finite()),
            Shape::Text { x, y, size_px, .. } => [x, y, size_px].iter().all(|v| v.is_finite()),
            Shape::Circle { x, y, radius_px, .. } => [x, y, radius_px].iter().all(|v| v.is_finite()),
        })
    }

    #[test]
    fn panels_fit_the_canvas_and_do_not_overlap() {
        for (w, h) in SIZES {
            let l = layout(w, h);
            for p in Panel::ALL {
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
                for q in Panel::ALL.into_iter().filter(|&q| q != p) {
                    assert!(!outer.overlaps(l.panel(q).outer), "{p:?} overlaps {q:?} at {w}×{h}");
                }
            }
            // The time panels' plots line up, so one cursor crosses them all.
            let a = l.plot(Panel::FootSignal);
            for p in [Panel::HeightsBefore, Panel::HeightsAfter, Panel::Stance] {
                assert_eq!((l.plot(p).x, l.plot(p).w), (a.x, a.w));
            }
            assert_eq!(l.plot_rects_xywh().len(), 20);
        }
        assert!(layout(1600.0, 500.0).side_by_side);
        assert!(!layout(495.0, 550.0).side_by_side);
    }

    #[test]
    fn degenerate_canvas_sizes_give_finite_non_negative_rectangles() {
        for (w, h) in
            [(0.0, 0.0), (1.0, 1.0), (f32::NAN, 300.0), (-5.0, f32::INFINITY), (30.0, 20.0), (1e9, 3.0)]
        {
            let l = layout(w, h);
            for p in Panel::ALL {
                for r in [l.panel(p).outer, l.plot(p)] {
                    assert!([r.x, r.y, r.w, r.h].iter().all(|v| v.is_finite()), "{w}×{h}: {r:?}");
                    assert!(r.w >= 0.0 && r.h >= 0.0, "{w}×{h}: {r:?}");
                }
            }
            let data = synthetic(50);
            assert!(all_finite(&draw(&data, 10, &l)));
            let _ = frame_at(&data, &l, 0.5, 0.5);
        }
    }

    #[test]
    fn every_panel_draws_the_demo() {
        let data = demo_data();
        for (w, h) in SIZES {
            let l = layout(w, h);
            let fig = draw_static(&data, &l);
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
            let cursor = draw_cursor(&data, 300, &l);
            assert!(all_finite(&cursor));
            let lines = cursor.shapes.iter().filter(|s| matches!(s, Shape::Polyline { .. })).count();
            let dots = cursor.shapes.iter().filter(|s| matches!(s, Shape::Circle { .. })).count();
            assert_eq!(lines, 4, "a cursor line on (a), (b), (c) and (e)");
            assert_eq!(dots, 2 * (6 + 2), "a haloed dot per foot in (a)-(c) and per path in (d)");
        }
    }

    #[test]
    fn axes_have_units() {
        let fig = draw_static(&synthetic(1000), &layout(1600.0, 500.0));
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

    /// The x of the cursor line in `panel`'s plot.
    fn cursor_x(fig: &Figure, plot: Rect) -> Option<f32> {
        fig.shapes.iter().find_map(|s| match s {
            Shape::Polyline { points, .. } if points.len() == 2 && points[0].0 == points[1].0 => {
                plot.contains(points[0].0, points[0].1).then_some(points[0].0)
            }
            _ => None,
        })
    }

    #[test]
    fn clicking_the_cursor_seeks_to_its_frame() {
        for n in [2, 7, 1000, 100_000] {
            let data = synthetic(n);
            for (w, h) in SIZES {
                let l = layout(w, h);
                for frame in [0, 1, n / 3, n / 2, n - 2, n - 1] {
                    let cursor = draw_cursor(&data, frame, &l);
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
        let l = layout(400.0, 300.0);
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
            let l = layout(w, h);
            let view = TopView::new(&data, l.plot(Panel::TopView));
            for frame in [0, 57, 200, 399] {
                let cursor = draw_cursor(&data, frame, &l);
                let (x, y) = cursor
                    .shapes
                    .iter()
                    .find_map(|s| match s {
                        Shape::Circle { x, y, color, .. } if *color == CORRECTED_COLOR => Some((*x, *y)),
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
    fn long_recordings_are_decimated() {
        let n = 100_000;
        let mut data = synthetic(n);
        // Noise at the frame rate, the worst case for a line, and some gaps.
        for (f, v) in data.foot_signal[0].iter_mut().enumerate() {
            *v += if f % 2 == 0 { 0.5 } else { -0.5 };
        }
        for f in (0..n).step_by(997) {
            data.heights_before_cm[1][f] = f64::NAN;
            data.hips_after_cm[f] = DVec3::NAN;
        }
        for (w, h) in [(400.0, 300.0), (1600.0, 500.0), (990.0, 1100.0)] {
            let l = layout(w, h);
            let fig = draw_static(&data, &l);
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
                    LEFT_COLOR,
                    RIGHT_COLOR,
                    LEFT_COLOR.with_alpha(GHOST_ALPHA),
                    RIGHT_COLOR.with_alpha(GHOST_ALPHA),
                ];
                let points = points_in(plot, &colors);
                let bound = 2 * 2 * (plot.w.ceil() as usize + 1);
                assert!(
                    points <= bound && points > plot.w as usize,
                    "{p:?} at {w}×{h}: {points} points, bound {bound}"
                );
            }
            let top = l.plot(Panel::TopView);
            let points = points_in(top, &[ORIGINAL_COLOR, CORRECTED_COLOR]);
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
        data.foot_signal[1][31_234] = 40.0;
        let l = layout(400.0, 300.0);
        let fig = draw_static(&data, &l);
        let plot = l.plot(Panel::FootSignal);
        let top = fig
            .shapes
            .iter()
            .filter_map(|s| match s {
                // Not the legend's swatch: a line of the series.
                Shape::Polyline { points, color, .. } if *color == RIGHT_COLOR && points.len() > 2 => {
                    points.iter().map(|p| p.1).reduce(f32::min)
                }
                _ => None,
            })
            .reduce(f32::min)
            .expect("the right foot's line");
        assert!((top - (plot.y + plot.h * 0.05 / 1.1)).abs() < 1.0, "spike drawn at {top}, plot {plot:?}");
    }

    #[test]
    fn empty_nan_and_one_frame_data_do_not_panic() {
        let one = PlotData {
            fps: 100.0,
            foot_signal: [vec![1.0], vec![2.0]],
            heights_before_cm: [vec![3.0], vec![4.0]],
            heights_after_cm: [vec![0.0], vec![0.0]],
            hips_before_cm: vec![DVec3::new(1.0, 2.0, 3.0)],
            hips_after_cm: vec![DVec3::ZERO],
            stance: vec![Stance::Free],
            ..Default::default()
        };
        let nan = PlotData {
            fps: f64::NAN,
            foot_signal: [vec![f64::NAN; 5], vec![f64::INFINITY; 5]],
            heights_before_cm: [vec![f64::MAX, -f64::MAX], vec![]],
            heights_after_cm: [vec![1e-320, 0.0], vec![f64::NEG_INFINITY]],
            hips_before_cm: vec![DVec3::NAN; 3],
            hips_after_cm: vec![DVec3::splat(f64::MAX), DVec3::splat(-f64::MAX)],
            stance: vec![Stance::Flight],
            ..Default::default()
        };
        let mut mismatched = synthetic(300);
        mismatched.fps = 0.0;
        mismatched.stance.truncate(10);
        mismatched.foot_signal[1].clear();
        mismatched.hips_before_cm.truncate(1);
        for data in [PlotData::default(), one, nan, mismatched] {
            for (w, h) in [(400.0, 300.0), (1600.0, 500.0), (5.0, 5.0)] {
                let l = layout(w, h);
                for frame in [0, 1, 4, usize::MAX] {
                    let fig = draw(&data, frame, &l);
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
        assert!(draw_cursor(&PlotData::default(), 0, &layout(400.0, 300.0)).shapes.is_empty());
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
            let l = layout(w, h);
            let fig = draw_static(&data, &l);
            let points: Vec<(f32, f32)> = fig
                .shapes
                .iter()
                .filter_map(|s| match s {
                    // Not the legend's swatch: the path.
                    Shape::Polyline { points, color, .. }
                        if *color == CORRECTED_COLOR && points.len() > 2 =>
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
    fn text_is_fitted_or_cut() {
        assert_eq!(fit_text(&["a long title", "short"], 60.0, 10.0).as_deref(), Some("short"));
        assert_eq!(fit_text(&["abcdefghij"], 30.0, 10.0).as_deref(), Some("abcd…"));
        assert_eq!(fit_text(&["abc"], 5.0, 10.0), None);
        assert_eq!(Rgba(255, 99, 92, 255).to_css(), "rgba(255,99,92,1.000)");
        assert_eq!(Rgba(0, 0, 0, 0).to_css(), "rgba(0,0,0,0.000)");
    }

    /// The stance kinds `legend` names, by their swatches.
    fn kinds_in(legend: &[&[LegendItem]]) -> Vec<Stance> {
        let colors: Vec<Swatch> = legend.iter().copied().flatten().map(|it| it.swatch).collect();
        let paper = std::ptr::eq(legend, &STANCE_LEGEND[..]);
        STANCE_KINDS
            .iter()
            .copied()
            .filter(|k| k.is_contact() != paper || *k == Stance::Flight)
            .filter(|k| colors.contains(&Swatch::Block(stance_color(*k))))
            .collect()
    }

    #[test]
    fn the_stance_legend_names_every_colour_once() {
        // Each legend's kinds have distinct colours, and every kind is in one.
        for legend in STANCE_LEGENDS {
            let kinds = kinds_in(legend);
            let colors: Vec<Rgba> = kinds.iter().map(|k| stance_color(*k)).collect();
            for (i, c) in colors.iter().enumerate() {
                assert!(!colors[..i].contains(c), "two stances share {c:?}");
            }
            let blocks = legend.iter().copied().flatten().filter(|it| matches!(it.swatch, Swatch::Block(_)));
            assert_eq!(blocks.count(), kinds.len(), "{kinds:?}");
        }
        let paper = kinds_in(&STANCE_LEGEND);
        let contact = kinds_in(&CONTACT_LEGEND);
        for k in STANCE_KINDS {
            assert!(paper.contains(&k) || contact.contains(&k), "{k:?} is in no legend");
            assert!(!k.is_contact() || !paper.contains(&k), "{k:?} in the paper legend");
        }
        assert_eq!(contact.len(), 4);
        // The contact method's feet are the feet's own colours; double
        // support is none of the strip's other colours, nor the corrected trail's.
        assert_eq!(stance_color(Stance::Pinned(Foot::Left, StanceReason::Contact)), LEFT_COLOR);
        assert_eq!(stance_color(Stance::Pinned(Foot::Right, StanceReason::Contact)), RIGHT_COLOR);
        let double = stance_color(Stance::Double);
        assert_ne!(double, CORRECTED_COLOR);
        for k in STANCE_KINDS.into_iter().filter(|k| *k != Stance::Double) {
            assert_ne!(stance_color(k), double, "{k:?}");
        }
    }

    /// `n` frames of [`synthetic`] data whose stances are the contact method's.
    fn synthetic_contact(n: usize) -> PlotData {
        let kinds = [
            Stance::Pinned(Foot::Left, StanceReason::Contact),
            Stance::Double,
            Stance::Pinned(Foot::Right, StanceReason::Contact),
            Stance::Double,
            Stance::Flight,
        ];
        PlotData { stance: (0..n).map(|f| kinds[(f / 37) % kinds.len()]).collect(), ..synthetic(n) }
    }

    /// The texts drawn inside `r`.
    fn texts_in(fig: &Figure, r: Rect) -> Vec<&str> {
        fig.shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Text { x, y, text, .. } if r.contains(*x, *y) => Some(text.as_str()),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn contact_stances_draw_the_contact_legend() {
        let contact = synthetic_contact(1000);
        let paper = synthetic(1000);
        for (w, h) in SIZES {
            let l = layout(w, h);
            let PanelRects { outer, plot } = l.panel(Panel::Stance);
            let fig = draw_static(&contact, &l);
            assert!(all_finite(&fig));
            let texts = texts_in(&fig, outer);
            for t in ["left foot", "right foot", "both feet", "flight"] {
                assert!(texts.contains(&t), "no {t:?} in (e) at {w}×{h}: {texts:?}");
            }
            for t in ["acceleration", "height", "both", "none pinned", "left:", "right:"] {
                assert!(!texts.contains(&t), "paper legend's {t:?} in (e) at {w}×{h}");
            }
            let title = texts.iter().find(|t| t.starts_with("(e)")).expect("a title");
            assert!(!title.contains("pinned"), "{title:?}");
            // The strip shows each of the contact method's colours.
            for k in kinds_in(&CONTACT_LEGEND) {
                let color = stance_color(k);
                let shown = fig.shapes.iter().any(
                    |s| matches!(s, Shape::Rect { x, y, color: c, .. } if *c == color && plot.contains(*x, *y)),
                );
                assert!(shown, "{k:?} not in the strip at {w}×{h}");
            }
            // The legend stays inside (e), under the strip and its axis.
            for s in &fig.shapes {
                let (x, y) = anchor(s);
                if outer.contains(x, y) && y > plot.bottom() + 2.0 * AXIS_ROW * l.font_px {
                    assert!(y <= outer.bottom(), "{s:?} below (e) at {w}×{h}");
                }
            }

            // Paper data still draws the paper legend and title.
            let fig = draw_static(&paper, &l);
            let texts = texts_in(&fig, outer);
            for t in ["left:", "right:", "acceleration", "height", "none pinned", "flight"] {
                assert!(texts.contains(&t), "no {t:?} in (e) at {w}×{h}: {texts:?}");
            }
            for t in ["left foot", "right foot", "both feet"] {
                assert!(!texts.contains(&t), "contact legend's {t:?} in (e) at {w}×{h}");
            }
            assert!(texts.iter().any(|t| t.starts_with("(e)")));
        }
        // At a roomy size, the titles say which method's strip it is.
        let l = layout(2400.0, 1300.0);
        let outer = l.panel(Panel::Stance).outer;
        let contact_texts = draw_static(&contact, &l);
        assert!(texts_in(&contact_texts, outer).contains(&"(e) stance: which feet are on the floor"));
        let paper_texts = draw_static(&paper, &l);
        assert!(texts_in(&paper_texts, outer).contains(&"(e) stance: which foot is pinned, and why"));
    }

    #[test]
    fn the_cursor_reads_out_contact_stances() {
        let data = synthetic_contact(1000);
        let l = layout(2400.0, 1300.0);
        let outer = l.panel(Panel::Stance).outer;
        for (frame, words) in [
            (0, "left foot on the floor"),
            (40, "both feet on the floor"),
            (80, "right foot on the floor"),
            (150, "flight"),
        ] {
            let cursor = draw_cursor(&data, frame, &l);
            let texts = texts_in(&cursor, outer);
            assert!(texts.iter().any(|t| t.contains(words)), "frame {frame}: {texts:?}");
        }
        for k in STANCE_KINDS {
            let (long, short) = stance_words(k);
            assert!(!long.is_empty() && !short.is_empty() && short.len() <= long.len(), "{k:?}");
        }
        // Clicking the contact strip seeks as the paper one does.
        let cursor = draw_cursor(&data, 500, &l);
        let plot = l.plot(Panel::Stance);
        let x = cursor_x(&cursor, plot).expect("a cursor line");
        assert!(frame_at(&data, &l, x, plot.center().1).is_some_and(|f| f.abs_diff(500) <= 1));
    }
}
