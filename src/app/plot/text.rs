//! Measuring text. Only the browser knows how wide its font draws a string,
//! so everything that fits text takes a [`TextMeasure`]: the page passes its
//! canvas's `measureText`, native tests a fixed estimate.

/// Average glyph width of [`FONT_FAMILY`](super::FONT_FAMILY) as a fraction of the font size, for
/// [`TextMeasure::Estimate`]. It errs wide for lower-case text, so estimated
/// text rarely overflows.
const CHAR_WIDTH: f32 = 0.56;

/// How wide a line of text in [`FONT_FAMILY`](super::FONT_FAMILY) is drawn.
#[derive(Clone, Copy)]
pub enum TextMeasure<'a> {
    /// `CHAR_WIDTH` × the font size per character: the same everywhere, for
    /// native tests and wherever no canvas is at hand.
    Estimate,
    /// `width_px(text, size_px)` is the width in pixels of `text` at
    /// `size_px`, e.g. from a canvas's `measureText` in that font.
    With(&'a dyn Fn(&str, f32) -> f32),
}

impl TextMeasure<'_> {
    /// The width in pixels of `text` at `size_px`.
    pub fn width_px(self, text: &str, size_px: f32) -> f32 {
        match self {
            TextMeasure::Estimate => text.chars().count() as f32 * CHAR_WIDTH * size_px,
            TextMeasure::With(width_px) => width_px(text, size_px),
        }
    }

    /// The first of `candidates` (longest first) at most `max_px` wide;
    /// failing all, the longest start of the last one that fits with an
    /// ellipsis after it; `None` when not even one character and the ellipsis
    /// fit.
    pub(super) fn fit(self, candidates: &[&str], max_px: f32, size_px: f32) -> Option<String> {
        if let Some(c) = candidates.iter().find(|c| self.width_px(c, size_px) <= max_px) {
            return Some(c.to_string());
        }
        let last = candidates.last()?;
        // Every start of `last` of at least one character, longest first.
        let ends = last.char_indices().rev().map(|(end, _)| end).filter(|&end| end > 0);
        let mut cuts = ends.map(|end| format!("{}…", &last[..end]));
        // Not `!(width > max_px)`: a cut that cannot be measured (NaN) does not fit.
        cuts.find(|cut| self.width_px(cut, size_px) <= max_px)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_fitted_or_cut() {
        let fit = |candidates: &[&str], max_px| TextMeasure::Estimate.fit(candidates, max_px, 10.0);
        assert_eq!(fit(&["a long title", "short"], 60.0).as_deref(), Some("short"));
        assert_eq!(fit(&["abcdefghij"], 30.0).as_deref(), Some("abcd…"));
        assert_eq!(fit(&["abc"], 5.0), None);
        // A measure that is not the estimate: every character 2 px at any size.
        let narrow = |text: &str, _: f32| 2.0 * text.chars().count() as f32;
        let narrow = TextMeasure::With(&narrow);
        assert_eq!(narrow.fit(&["abcdefghij"], 8.0, 10.0).as_deref(), Some("abc…"));
        assert_eq!(narrow.fit(&["abcdefghij", "x"], 20.0, 10.0).as_deref(), Some("abcdefghij"));
        let unmeasurable = |_: &str, _: f32| f32::NAN;
        assert_eq!(TextMeasure::With(&unmeasurable).fit(&["abc"], 100.0, 10.0), None);
    }
}
