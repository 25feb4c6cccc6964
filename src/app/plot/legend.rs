//! Legends: the swatches and words that say which colour is what, laid out
//! in the header of a panel or, for the stance strip, in rows under it.

use super::figure::{Align, Figure, Rect, TextStyle};
use super::{Stance, StanceReason, TextMeasure};
use crate::app::theme::{self, Rgba};
use crate::body::feet::{Foot, PerFoot};

// --- The stance strip's colours -------------------------------------------------

/// The stance categories: the paper method's in [`STANCE_LEGEND`] order, then
/// the contact method's. [`stance_color`] gives the kinds of each method's
/// legend distinct colours.
pub(super) const STANCE_KINDS: [Stance; 11] = [
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
pub(super) const fn stance_color(stance: Stance) -> Rgba {
    use StanceReason::*;
    match stance {
        Stance::Pinned(foot, Acceleration) => of_foot(foot, theme::FEET_LIGHT),
        Stance::Pinned(foot, Height | Contact) => of_foot(foot, theme::FEET),
        Stance::Pinned(foot, Both) => of_foot(foot, theme::FEET_DARK),
        Stance::Free => theme::NO_FOOT_PINNED,
        Stance::Flight => theme::FLIGHT,
        Stance::Double => theme::DOUBLE_SUPPORT,
    }
}

/// `colors[foot]`, in a `const fn`.
const fn of_foot(foot: Foot, colors: PerFoot<Rgba>) -> Rgba {
    match foot {
        Foot::Left => colors.left,
        Foot::Right => colors.right,
    }
}

/// The position of `stance` in [`STANCE_KINDS`].
pub(super) fn stance_index(stance: Stance) -> usize {
    STANCE_KINDS.iter().position(|&k| k == stance).unwrap_or(0)
}

// --- Legends -------------------------------------------------------------------

/// What a legend item shows before its text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Swatch {
    /// A group label: text only.
    Label,
    /// A short stroke of a line's colour, dashed or not.
    Line(Rgba, bool),
    /// A filled square.
    Block(Rgba),
}

/// A swatch and what it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LegendItem {
    pub(super) swatch: Swatch,
    pub(super) text: &'static str,
}

const fn item(swatch: Swatch, text: &'static str) -> LegendItem {
    LegendItem { swatch, text }
}

pub(super) const FEET_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(theme::FEET.left, false), "left foot"),
    item(Swatch::Line(theme::FEET.right, false), "right foot"),
];
pub(super) const FEET_BEFORE_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(theme::FEET.left.with_alpha(theme::BEFORE_ALPHA), false), "left foot"),
    item(Swatch::Line(theme::FEET.right.with_alpha(theme::BEFORE_ALPHA), false), "right foot"),
];
pub(super) const PATH_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(theme::ORIGINAL, true), "original"),
    item(Swatch::Line(theme::CORRECTED, false), "corrected"),
];
/// (d) with a camera take: the suit's own path, the inertial estimate (the
/// method's correction) and the camera's track.
pub(super) const CAMERA_PATH_LEGEND: [LegendItem; 3] = [
    item(Swatch::Line(theme::ORIGINAL, true), "suit"),
    item(Swatch::Line(theme::CORRECTED, false), "inertial"),
    item(Swatch::Line(theme::CAMERA, false), "camera"),
];
/// (f): the camera track's stated uncertainty, and its error against a truth.
pub(super) const CAMERA_SERIES_LEGEND: [LegendItem; 2] = [
    item(Swatch::Line(theme::CAMERA, false), "uncertainty (1σ)"),
    item(Swatch::Line(theme::TRACK_ERROR, false), "error"),
];
/// The paper method's stance legend in groups that are kept on one row when
/// they fit.
pub(super) const STANCE_LEGEND: [&[LegendItem]; 3] = [
    &[
        item(Swatch::Label, "left:"),
        item(
            Swatch::Block(stance_color(Stance::Pinned(Foot::Left, StanceReason::Acceleration))),
            "acceleration",
        ),
        item(Swatch::Block(stance_color(Stance::Pinned(Foot::Left, StanceReason::Height))), "height"),
        item(Swatch::Block(stance_color(Stance::Pinned(Foot::Left, StanceReason::Both))), "both"),
    ],
    &[
        item(Swatch::Label, "right:"),
        item(
            Swatch::Block(stance_color(Stance::Pinned(Foot::Right, StanceReason::Acceleration))),
            "acceleration",
        ),
        item(Swatch::Block(stance_color(Stance::Pinned(Foot::Right, StanceReason::Height))), "height"),
        item(Swatch::Block(stance_color(Stance::Pinned(Foot::Right, StanceReason::Both))), "both"),
    ],
    &[
        item(Swatch::Block(stance_color(Stance::Free)), "none pinned"),
        item(Swatch::Block(stance_color(Stance::Flight)), "flight"),
    ],
];
/// The contact method's stance legend, grouped as [`STANCE_LEGEND`].
pub(super) const CONTACT_LEGEND: [&[LegendItem]; 2] = [
    &[
        item(Swatch::Block(stance_color(STANCE_KINDS[8])), "left foot"),
        item(Swatch::Block(stance_color(STANCE_KINDS[9])), "right foot"),
    ],
    &[
        item(Swatch::Block(stance_color(STANCE_KINDS[10])), "both feet"),
        item(Swatch::Block(stance_color(STANCE_KINDS[7])), "flight"),
    ],
];
/// Every legend (e) may draw. [`layout`](super::layout()) leaves room for the tallest, so the
/// panels do not move with the data.
pub(super) const STANCE_LEGENDS: [&[&[LegendItem]]; 2] = [&STANCE_LEGEND, &CONTACT_LEGEND];

/// The legend and titles (longest first) of (e) for `stance`: the contact
/// method's when any frame has one of its decisions, else the paper's.
pub(super) fn stance_legend(
    stance: &[Stance],
) -> (&'static [&'static [LegendItem]], &'static [&'static str]) {
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
pub(super) const ITEM_GAP: f32 = 0.9;

/// The width in pixels of `item`, swatch and text, at `font_px`.
pub(super) fn legend_item_width(item: &LegendItem, font_px: f32, text: TextMeasure) -> f32 {
    let swatch = match item.swatch {
        Swatch::Label => 0.0,
        Swatch::Line(..) => (SWATCH_LINE + SWATCH_GAP) * font_px,
        Swatch::Block(_) => (SWATCH_BLOCK + SWATCH_GAP) * font_px,
    };
    swatch + text.width_px(item.text, font_px)
}

/// Where each legend item goes when `groups` of items flow left to right in
/// rows of `width_px`: `(x offset, row)` per item, in order, and the number of
/// rows. A group starts a new row rather than be split, unless it is wider
/// than a row; a group label never ends a row.
pub(super) fn flow_legend(
    groups: &[&[LegendItem]],
    width_px: f32,
    font_px: f32,
    text: TextMeasure,
) -> (Vec<(f32, usize)>, usize) {
    let gap = ITEM_GAP * font_px;
    let mut placed = Vec::new();
    let (mut x, mut row) = (0.0f32, 0usize);
    for group in groups {
        let group_w = group.iter().map(|it| legend_item_width(it, font_px, text) + gap).sum::<f32>() - gap;
        if x > 0.0 && x + group_w > width_px {
            row += 1;
            x = 0.0;
        }
        for (i, it) in group.iter().enumerate() {
            let w = legend_item_width(it, font_px, text);
            let needed = match (it.swatch, group.get(i + 1)) {
                (Swatch::Label, Some(next)) => w + gap + legend_item_width(next, font_px, text),
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
pub(super) fn draw_legend_item(fig: &mut Figure, it: &LegendItem, x: f32, y: f32, font_px: f32) {
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
    let color = if it.swatch == Swatch::Label { theme::MUTED_TEXT } else { theme::TEXT };
    fig.text(text_x, y, it.text, TextStyle::new(color, font_px, Align::Left));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::plot::layout::AXIS_ROW;
    use crate::app::plot::testing::*;
    use crate::app::plot::*;

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
        assert_eq!(stance_color(Stance::Pinned(Foot::Left, StanceReason::Contact)), theme::FEET.left);
        assert_eq!(stance_color(Stance::Pinned(Foot::Right, StanceReason::Contact)), theme::FEET.right);
        let double = stance_color(Stance::Double);
        assert_ne!(double, theme::CORRECTED);
        for k in STANCE_KINDS.into_iter().filter(|k| *k != Stance::Double) {
            assert_ne!(stance_color(k), double, "{k:?}");
        }
    }

    #[test]
    fn contact_stances_draw_the_contact_legend() {
        let contact = synthetic_contact(1000);
        let paper = synthetic(1000);
        for (w, h) in SIZES {
            let l = layout(w, h, ESTIMATE);
            let PanelRects { outer, plot } = l.panel(Panel::Stance);
            let fig = draw_static(&contact, &l, ESTIMATE);
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
            let fig = draw_static(&paper, &l, ESTIMATE);
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
        let l = layout(2400.0, 1300.0, ESTIMATE);
        let outer = l.panel(Panel::Stance).outer;
        let contact_texts = draw_static(&contact, &l, ESTIMATE);
        assert!(texts_in(&contact_texts, outer).contains(&"(e) stance: which feet are on the floor"));
        let paper_texts = draw_static(&paper, &l, ESTIMATE);
        assert!(texts_in(&paper_texts, outer).contains(&"(e) stance: which foot is pinned, and why"));
    }
}
