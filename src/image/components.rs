//! The foreground's connected parts. A person is one connected blob of
//! foreground (with the shadow joined to their feet); someone else in the
//! room, apart from the actor, is another. Where the tracker has no idea
//! yet where the actor is, each large blob is a place to look.

use crate::image::grey::Mask;

/// One connected part of a mask (8-connected: a limb one pixel thin across
/// a diagonal is still one body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blob {
    /// How many pixels it has.
    pub area_px: usize,
    /// Its lowest row: where a standing person's feet are.
    pub bottom_row: u32,
    /// The middle of its pixels in that row (a column, px).
    pub bottom_column: f64,
}

/// The parts of `mask`, largest first (ties: the first found first, in
/// row-major order of their first pixel).
pub fn blobs(mask: &Mask) -> Vec<Blob> {
    let (w, h) = (mask.width_px as usize, mask.height_px as usize);
    let mut seen = vec![false; mask.on.len()];
    let mut stack: Vec<usize> = Vec::new();
    let mut found = Vec::new();
    for start in 0..mask.on.len() {
        if !mask.on[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut area_px = 0;
        let (mut bottom, mut columns): (usize, Vec<usize>) = (0, Vec::new());
        while let Some(i) = stack.pop() {
            area_px += 1;
            let (x, y) = (i % w, i / w);
            if y > bottom {
                (bottom, columns) = (y, Vec::new());
            }
            if y == bottom {
                columns.push(x);
            }
            for ny in y.saturating_sub(1)..(y + 2).min(h) {
                for nx in x.saturating_sub(1)..(x + 2).min(w) {
                    let j = ny * w + nx;
                    if mask.on[j] && !seen[j] {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        columns.sort_unstable();
        let bottom_column = columns.get(columns.len() / 2).copied().unwrap_or(0) as f64;
        found.push(Blob { area_px, bottom_row: bottom as u32, bottom_column });
    }
    // Stable: equal areas keep the order they were found in.
    found.sort_by_key(|b| std::cmp::Reverse(b.area_px));
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask(rows: &[&str]) -> Mask {
        let on = rows.iter().flat_map(|r| r.chars().map(|c| c == '#')).collect();
        Mask { width_px: rows[0].len() as u32, height_px: rows.len() as u32, on }
    }

    #[test]
    fn blobs_are_the_connected_parts_largest_first_with_their_feet() {
        let m = mask(&[
            "##.....#..", //
            ".#.....#..",
            "..#....##.",
            "..#.......",
            "....#.###.",
        ]);
        let found = blobs(&m);
        // The diagonal steps join the left part; the speck at (4, 4) is its own.
        assert_eq!(
            found,
            [
                Blob { area_px: 5, bottom_row: 3, bottom_column: 2.0 },
                Blob { area_px: 4, bottom_row: 2, bottom_column: 8.0 },
                Blob { area_px: 3, bottom_row: 4, bottom_column: 7.0 },
                Blob { area_px: 1, bottom_row: 4, bottom_column: 4.0 },
            ]
        );
        assert!(blobs(&mask(&["...", "..."])).is_empty());
    }
}
