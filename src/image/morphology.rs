//! Opening and closing of masks by a square (the pixels within `radius_px`
//! in x and in y): an opening removes the specks the sensor's noise leaves
//! above the threshold, a closing fills the thin gaps where the actor
//! happens to match the room behind (dark trousers across a dark skirting
//! board).
//!
//! The work is done on bytes (0 or 1 per pixel) eight at a time in a `u64`:
//! `|` and `&` of such words are the pixels' own, and a shift by one pixel is
//! a load one byte further. Eight times fewer operations where the compiler
//! cannot vectorise (wasm without SIMD), and no `unsafe`.

use crate::image::Mask;
use crate::image::grey::PixelBox;

/// On where any pixel within `radius_px` (Chebyshev) is on; the outside of
/// the image counts as off.
pub fn dilate(mask: &Mask, radius_px: u32) -> Mask {
    from_bytes(
        mask,
        &spread(&to_bytes(mask), mask.width_px as usize, mask.height_px as usize, radius_px, Op::Any),
    )
}

/// On where every pixel within `radius_px` (Chebyshev) is on; the outside of
/// the image counts as on, so that an actor cut by the image's border is not
/// eaten from that side.
pub fn erode(mask: &Mask, radius_px: u32) -> Mask {
    from_bytes(
        mask,
        &spread(&to_bytes(mask), mask.width_px as usize, mask.height_px as usize, radius_px, Op::All),
    )
}

/// Erosion then dilation: what is narrower than `2 · radius_px + 1` goes.
pub fn open(mask: &Mask, radius_px: u32) -> Mask {
    open_close(mask, radius_px, 0)
}

/// Dilation then erosion: gaps narrower than `2 · radius_px + 1` close.
pub fn close(mask: &Mask, radius_px: u32) -> Mask {
    open_close(mask, 0, radius_px)
}

/// An opening by `open_px` then a closing by `close_px` (0: none).
///
/// Only the opening's erosion looks at the whole image: what survives it is
/// the actor (the specks are gone), and the three passes after it change
/// nothing beyond `open_px + 2 · close_px` of that, so they work on that box
/// alone (the extra `close_px` keeps the box's own border, where its outside
/// would count as on for the closing's erosion, clear of anything on).
pub fn open_close(mask: &Mask, open_px: u32, close_px: u32) -> Mask {
    let (w, h) = (mask.width_px as usize, mask.height_px as usize);
    let mut bytes = to_bytes(mask);
    if open_px > 0 {
        bytes = spread(&bytes, w, h, open_px, Op::All);
    }
    let mut out = Mask::empty(mask.width_px, mask.height_px);
    let Some(on) = PixelBox::around(&bytes, w, |&b| b != 0) else { return out };
    let b = on.grown((open_px + 2 * close_px) as usize, w, h);
    let (bw, bh) = (b.width() as usize, b.height() as usize);
    let mut inner = b.crop(&bytes, w);
    for (radius, op) in [(open_px, Op::Any), (close_px, Op::Any), (close_px, Op::All)] {
        if radius > 0 {
            inner = spread(&inner, bw, bh, radius, op);
        }
    }
    for (row, inner) in b.rows(w).zip(inner.chunks_exact(bw)) {
        for (o, &i) in out.on[row].iter_mut().zip(inner) {
            *o = i != 0;
        }
    }
    out
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Op {
    /// Dilation: `|`, the outside off.
    Any,
    /// Erosion: `&`, the outside on.
    All,
}

impl Op {
    fn apply(self, a: u64, b: u64) -> u64 {
        match self {
            Op::Any => a | b,
            Op::All => a & b,
        }
    }

    /// The byte the outside of the image counts as.
    fn outside(self) -> u8 {
        match self {
            Op::Any => 0,
            Op::All => 1,
        }
    }
}

fn to_bytes(mask: &Mask) -> Vec<u8> {
    mask.on.iter().map(|&on| on as u8).collect()
}

fn from_bytes(size: &Mask, bytes: &[u8]) -> Mask {
    Mask { width_px: size.width_px, height_px: size.height_px, on: bytes.iter().map(|&b| b != 0).collect() }
}

fn load(bytes: &[u8], at: usize) -> u64 {
    let mut word = [0u8; 8];
    word.copy_from_slice(&bytes[at..at + 8]);
    u64::from_le_bytes(word)
}

/// Every pixel of `bytes` (`w × h`) combined by `op` with its neighbours
/// within `radius_px` across, then with the rows within `radius_px` above
/// and below.
fn spread(bytes: &[u8], w: usize, h: usize, radius_px: u32, op: Op) -> Vec<u8> {
    let r = (radius_px as usize).min(w.max(h));
    // Across: each row copied between `r` outside bytes (and slack to a
    // whole word), then combined with itself shifted by −r..=r bytes.
    let words = w.div_ceil(8);
    let mut padded = vec![op.outside(); r + 8 * words + r];
    let mut across = vec![0u8; 8 * words * h];
    for y in 0..h {
        padded[r..r + w].copy_from_slice(&bytes[y * w..(y + 1) * w]);
        let out = &mut across[y * 8 * words..(y + 1) * 8 * words];
        for k in 0..words {
            let mut word = load(&padded, 8 * k + r);
            for shift in 0..r {
                word = op.apply(
                    word,
                    op.apply(load(&padded, 8 * k + shift), load(&padded, 8 * k + r + 1 + shift)),
                );
            }
            out[8 * k..8 * k + 8].copy_from_slice(&word.to_le_bytes());
        }
    }
    // Down: each row combined with the rows within r, word by word (the
    // rows outside the image are left out: "off" for `|`, "on" for `&`).
    let mut result = vec![0u8; w * h];
    let stride = 8 * words;
    for y in 0..h {
        let (top, bottom) = (y.saturating_sub(r), (y + r).min(h - 1));
        let out = &mut result[y * w..(y + 1) * w];
        for k in 0..words {
            let mut word = load(&across, y * stride + 8 * k);
            for other in top..=bottom {
                word = op.apply(word, load(&across, other * stride + 8 * k));
            }
            let bytes = word.to_le_bytes();
            let n = (w - 8 * k).min(8);
            out[8 * k..8 * k + n].copy_from_slice(&bytes[..n]);
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask(rows: &[&str]) -> Mask {
        let on: Vec<bool> = rows.iter().flat_map(|r| r.chars().map(|c| c == '#')).collect();
        Mask { width_px: rows[0].len() as u32, height_px: rows.len() as u32, on }
    }

    /// Dilation (`any`) or erosion by trying every pixel of the square.
    fn naive(mask: &Mask, r: i64, any: bool) -> Mask {
        let (w, h) = (mask.width_px as i64, mask.height_px as i64);
        let on = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let mut near = (-r..=r).flat_map(|dy| (-r..=r).map(move |dx| (x + dx, y + dy)));
                let at = |(nx, ny): (i64, i64)| {
                    if nx < 0 || ny < 0 || nx >= w || ny >= h {
                        !any
                    } else {
                        mask.on[(ny * w + nx) as usize]
                    }
                };
                if any { near.any(at) } else { near.all(at) }
            })
            .collect();
        Mask { width_px: mask.width_px, height_px: mask.height_px, on }
    }

    /// A `w × h` mask with about `percent` % on, from the xorshift `state`.
    fn random_mask(state: &mut u64, w: u32, h: u32, percent: u64) -> Mask {
        let on = (0..w * h)
            .map(|_| {
                *state ^= *state << 13;
                *state ^= *state >> 7;
                *state ^= *state << 17;
                *state % 100 < percent
            })
            .collect();
        Mask { width_px: w, height_px: h, on }
    }

    #[test]
    fn the_word_at_a_time_passes_are_the_naive_ones() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for case in 0..200u32 {
            let (w, h) = (1 + case % 23, 1 + (case / 3) % 11);
            let mask = random_mask(&mut state, w, h, 20 + (case as u64 % 60));
            for r in 1..=3 {
                assert_eq!(dilate(&mask, r), naive(&mask, r as i64, true), "case {case} ({w}×{h}), r = {r}");
                assert_eq!(erode(&mask, r), naive(&mask, r as i64, false), "case {case} ({w}×{h}), r = {r}");
            }
        }
    }

    #[test]
    fn opening_and_closing_in_a_box_are_the_passes_over_the_whole() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for case in 0..300u32 {
            let (w, h) = (1 + case % 37, 1 + (case / 5) % 29);
            let mask = random_mask(&mut state, w, h, 5 + (case as u64 % 70));
            for (open_px, close_px) in [(1, 2), (0, 1), (2, 0), (1, 1), (0, 0)] {
                let whole = erode(&dilate(&dilate(&erode(&mask, open_px), open_px), close_px), close_px);
                assert_eq!(
                    open_close(&mask, open_px, close_px),
                    whole,
                    "case {case}: {w}×{h}, {open_px} {close_px}"
                );
            }
        }
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
