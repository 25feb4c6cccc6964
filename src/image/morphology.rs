//! Opening and closing of masks by a square (the pixels within `radius_px`
//! in x and in y): an opening removes the specks the sensor's noise leaves
//! above the threshold, a closing fills the thin gaps where the actor
//! happens to match the room behind (dark trousers across a dark skirting
//! board). Each pass combines shifted rows, then rows above and below, with
//! `|` or `&`: loops the compiler vectorises, for the small radii used.

use crate::image::Mask;

/// On where any pixel within `radius_px` (Chebyshev) is on; the outside of
/// the image counts as off.
pub fn dilate(mask: &Mask, radius_px: u32) -> Mask {
    spread(mask, radius_px, |a, b| a | b)
}

/// On where every pixel within `radius_px` (Chebyshev) is on; the outside of
/// the image counts as on, so that an actor cut by the image's border is not
/// eaten from that side.
pub fn erode(mask: &Mask, radius_px: u32) -> Mask {
    spread(mask, radius_px, |a, b| a & b)
}

/// Erosion then dilation: what is narrower than `2 · radius_px + 1` goes.
pub fn open(mask: &Mask, radius_px: u32) -> Mask {
    dilate(&erode(mask, radius_px), radius_px)
}

/// Dilation then erosion: gaps narrower than `2 · radius_px + 1` close.
pub fn close(mask: &Mask, radius_px: u32) -> Mask {
    erode(&dilate(mask, radius_px), radius_px)
}

/// Every pixel combined by `op` with its neighbours within `radius_px`
/// across, then with the rows within `radius_px` above and below; the
/// pixels outside the image left out (which is "off" for `|`, "on" for `&`).
fn spread(mask: &Mask, radius_px: u32, op: impl Fn(bool, bool) -> bool) -> Mask {
    let (w, h) = (mask.width_px as usize, mask.height_px as usize);
    let r = (radius_px as usize).min(w.max(h));
    let mut across = mask.on.clone();
    for y in 0..h {
        let row = &mask.on[y * w..(y + 1) * w];
        let out = &mut across[y * w..(y + 1) * w];
        for shift in 1..=r.min(w - 1) {
            for (o, &right) in out[..w - shift].iter_mut().zip(&row[shift..]) {
                *o = op(*o, right);
            }
            for (o, &left) in out[shift..].iter_mut().zip(&row[..w - shift]) {
                *o = op(*o, left);
            }
        }
    }
    let mut on = across.clone();
    for y in 0..h {
        let out = &mut on[y * w..(y + 1) * w];
        for other in y.saturating_sub(r)..(y + r + 1).min(h) {
            if other != y {
                for (o, &a) in out.iter_mut().zip(&across[other * w..(other + 1) * w]) {
                    *o = op(*o, a);
                }
            }
        }
    }
    Mask { width_px: mask.width_px, height_px: mask.height_px, on }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask(rows: &[&str]) -> Mask {
        let on: Vec<bool> = rows.iter().flat_map(|r| r.chars().map(|c| c == '#')).collect();
        Mask { width_px: rows[0].len() as u32, height_px: rows.len() as u32, on }
    }

    #[test]
    fn dilation_and_erosion_by_a_square() {
        let dot = mask(&[".....", ".....", "..#..", ".....", "....."]);
        assert_eq!(dilate(&dot, 1), mask(&[".....", ".###.", ".###.", ".###.", "....."]));
        assert_eq!(erode(&dilate(&dot, 1), 1), dot);
        // The border counts as on for erosion.
        let edge = mask(&["##...", "##...", "##..."]);
        assert_eq!(erode(&edge, 1), mask(&["#....", "#....", "#...."]));
    }

    #[test]
    fn opening_removes_specks_and_closing_fills_gaps() {
        let noisy = mask(&["........", ".#......", "..####..", "..####..", "......#.", "........"]);
        assert_eq!(open(&noisy, 1), Mask::empty(8, 6), "a band two pixels high goes with the specks");
        let cut = mask(&["..####..", "..####..", "..####..", "........", "..####..", "..####..", "..####.."]);
        let closed = close(&cut, 1);
        assert_eq!(
            closed,
            mask(&["..####..", "..####..", "..####..", "..####..", "..####..", "..####..", "..####.."])
        );
        assert_eq!(open(&closed, 1), closed, "a body 4 wide survives the opening");
    }
}
