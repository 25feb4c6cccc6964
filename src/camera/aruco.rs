//! Finding a board's ArUco markers on their own, as OpenCV's `ArucoDetector`
//! does (feature `board`): the way in when the chessboard grid is not seen.
//!
//! A board lying 4–6 m away on a textured floor shows squares 10–20 px
//! across, foreshortened to a third of that in height; the ChESS corner
//! finder behind the grid search then sees the floor's grain as corners as
//! much as the board's, and finds no grid, while the markers, black
//! squares ringed by their white margin, still stand out. So, as OpenCV:
//! 1. the still thresholded against its local mean over windows of 3 to
//!    31 px (OpenCV's `adaptiveThreshWinSize` 3..31 step 4, constant 7):
//!    a small window keeps a thin white margin apart from the black squares
//!    beside it, a large one fills a large marker's bits;
//! 2. each dark connected region whose outline is a quadrilateral (its
//!    convex hull and the largest quadrilateral in it nearly the same area)
//!    with sides of at least 6 px (one per cell of a 4×4 marker and its
//!    border) is a candidate;
//! 3. a candidate's 6×6 cells are sampled through the quadrilateral's
//!    homography, split into dark and light by Otsu's rule, and kept when
//!    its border is dark and its 4×4 bits are one of the dictionary's codes
//!    within the error correction OpenCV allows (`errorCorrectionRate` 0.8
//!    of the dictionary's correction bits).

use calib_targets::aruco::Matcher;
use glam::DVec2;

use super::homography::{homography, map_point};

/// A grey image borrowed, sampled between pixel centres.
pub(super) struct Grey<'a> {
    pub width: usize,
    pub height: usize,
    pub pixels: &'a [u8],
}

impl Grey<'_> {
    /// Bilinear sample at `p` (pixel centres at whole numbers), clamped at
    /// the borders.
    pub fn at(&self, p: DVec2) -> f64 {
        let x = p.x.clamp(0.0, (self.width - 1) as f64);
        let y = p.y.clamp(0.0, (self.height - 1) as f64);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.width - 1), (y0 + 1).min(self.height - 1));
        let (fx, fy) = (x - x0 as f64, y - y0 as f64);
        let v = |x: usize, y: usize| self.pixels[y * self.width + x] as f64;
        (v(x0, y0) * (1.0 - fx) + v(x1, y0) * fx) * (1.0 - fy)
            + (v(x0, y1) * (1.0 - fx) + v(x1, y1) * fx) * fy
    }

    pub fn contains(&self, p: DVec2, margin: f64) -> bool {
        p.x >= margin
            && p.y >= margin
            && p.x <= self.width as f64 - 1.0 - margin
            && p.y <= self.height as f64 - 1.0 - margin
    }
}

/// One marker seen: its id and its corners in the image in the marker's
/// own order (top-left, top-right, bottom-right, bottom-left as printed,
/// OpenCV's order).
#[derive(Clone, Debug)]
pub(super) struct Marker {
    pub id: u32,
    pub corners: [DVec2; 4],
}

/// OpenCV's `adaptiveThreshConstant`: a pixel is dark when this much
/// darker than its window's mean, so flat floor is neither.
const THRESHOLD_CONSTANT: f64 = 7.0;

/// OpenCV's `polygonalApproxAccuracyRate` (the shared stills' detector
/// parameters): how far an outline may stray from its polygon, as a share
/// of the polygon's perimeter.
const POLYGON_ACCURACY: f64 = 0.06;

/// Every marker of `matcher`'s dictionary seen in `image` (`border_bits`
/// cells of black border around the code), once per threshold window it is
/// found at: the caller merges them.
pub(super) fn find_markers(image: &Grey, matcher: &Matcher, border_bits: usize) -> Vec<Marker> {
    let integral = Integral::new(image);
    let bits = matcher.dictionary().marker_size();
    let cells = bits + 2 * border_bits;
    let mut found = Vec::new();
    for window in (3..=31).step_by(4) {
        let dark = integral.dark(image, window);
        for region in regions(&dark, image.width, image.height) {
            let Some(quad) = quadrilateral(&region, cells as f64) else { continue };
            if let Some(marker) = decode(image, matcher, quad, bits, border_bits) {
                found.push(marker);
            }
        }
    }
    found
}

/// Sums of the image over rectangles in constant time.
struct Integral {
    width: usize,
    height: usize,
    /// `(width + 1) × (height + 1)`, row major, zero first row and column.
    sums: Vec<u64>,
}

impl Integral {
    fn new(image: &Grey) -> Self {
        let (w, h) = (image.width, image.height);
        let mut sums = vec![0u64; (w + 1) * (h + 1)];
        for y in 0..h {
            let mut row = 0u64;
            for x in 0..w {
                row += image.pixels[y * w + x] as u64;
                sums[(y + 1) * (w + 1) + x + 1] = sums[y * (w + 1) + x + 1] + row;
            }
        }
        Self { width: w, height: h, sums }
    }

    /// Whether each pixel is darker than the mean of the `window`-wide
    /// square about it (clipped at the borders) by the threshold constant.
    fn dark(&self, image: &Grey, window: usize) -> Vec<bool> {
        let (w, h) = (self.width, self.height);
        let half = window / 2;
        let mut dark = vec![false; w * h];
        for y in 0..h {
            let (y0, y1) = (y.saturating_sub(half), (y + half + 1).min(h));
            for x in 0..w {
                let (x0, x1) = (x.saturating_sub(half), (x + half + 1).min(w));
                let at = |x: usize, y: usize| self.sums[y * (w + 1) + x];
                let sum = at(x1, y1) + at(x0, y0) - at(x0, y1) - at(x1, y0);
                let mean = sum as f64 / ((x1 - x0) * (y1 - y0)) as f64;
                dark[y * w + x] = (image.pixels[y * w + x] as f64) < mean - THRESHOLD_CONSTANT;
            }
        }
        dark
    }
}

/// The boundary pixels of each 8-connected dark region (a region's inside
/// does not shape its outline), for regions of at least 8 pixels.
fn regions(dark: &[bool], width: usize, height: usize) -> Vec<Vec<(usize, usize)>> {
    let mut label = vec![false; dark.len()];
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for start in 0..dark.len() {
        if !dark[start] || label[start] {
            continue;
        }
        label[start] = true;
        stack.push(start);
        let mut boundary = Vec::new();
        let mut size = 0usize;
        while let Some(i) = stack.pop() {
            size += 1;
            let (x, y) = (i % width, i / width);
            let mut inner = true;
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    if dx == 0 && dy == 0 {
                        continue;
                    }
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                        inner = false;
                        continue;
                    }
                    let n = ny as usize * width + nx as usize;
                    if !dark[n] {
                        inner = false;
                    } else if !label[n] {
                        label[n] = true;
                        stack.push(n);
                    }
                }
            }
            if !inner {
                boundary.push((x, y));
            }
        }
        if size >= 8 {
            out.push(boundary);
        }
    }
    out
}

/// The region's outline as a quadrilateral (corners in the image's
/// clockwise order as seen, the first of the four by nothing in
/// particular), when it is one: the largest quadrilateral on its convex
/// hull holds the hull but for OpenCV's tolerance, and each side is at
/// least `cells` px.
fn quadrilateral(boundary: &[(usize, usize)], cells: f64) -> Option<[DVec2; 4]> {
    // Only each row's leftmost and rightmost pixels can be on the hull;
    // their outer corners, so that a region's outline is its edge.
    let top = boundary.iter().map(|p| p.1).min()?;
    let bottom = boundary.iter().map(|p| p.1).max()?;
    let mut rows = vec![(usize::MAX, 0usize); bottom - top + 1];
    for &(x, y) in boundary {
        let row = &mut rows[y - top];
        *row = (row.0.min(x), row.1.max(x));
    }
    let mut points: Vec<DVec2> = Vec::with_capacity(4 * rows.len());
    for (dy, &(left, right)) in rows.iter().enumerate() {
        let y = (top + dy) as f64;
        for x in [left as f64 - 0.5, right as f64 + 0.5] {
            points.push(DVec2::new(x, y - 0.5));
            points.push(DVec2::new(x, y + 0.5));
        }
    }
    let hull = convex_hull(&mut points);
    if hull.len() < 4 {
        return None;
    }
    let hull_area = polygon_area(&hull);
    // A marker needs a pixel a cell at least.
    if hull_area < cells * cells {
        return None;
    }
    // The largest quadrilateral on the hull's vertices: over each diagonal,
    // the vertex farthest on either side (a foreshortened marker's longest
    // chord may be a side, not a diagonal, so every pair is tried).
    let mut best: Option<(f64, [DVec2; 4])> = None;
    for i in 0..hull.len() {
        for j in i + 2..hull.len() {
            let (a, c) = (hull[i], hull[j]);
            let side = |p: &&DVec2| (c - a).perp_dot(**p - a);
            let (Some(b), Some(d)) = (
                hull.iter().min_by(|p, q| side(p).total_cmp(&side(q))),
                hull.iter().max_by(|p, q| side(p).total_cmp(&side(q))),
            ) else {
                continue;
            };
            // Positive orientation in pixel coordinates (y down) is
            // clockwise as seen: the printed marker's corner order.
            let quad = [a, *b, c, *d];
            let area = polygon_area(&quad);
            if side(&b) < 0.0 && side(&d) > 0.0 && best.is_none_or(|(most, _)| area > most) {
                best = Some((area, quad));
            }
        }
    }
    let (_, quad) = best?;
    // The hull within OpenCV's polygon approximation tolerance of the
    // quadrilateral (`polygonalApproxAccuracyRate` 0.06 of the outline's
    // length): blur rounds a small marker's corners, and the pixels'
    // staircase adds a pixel.
    let perimeter: f64 = (0..4).map(|k| (quad[k] - quad[(k + 1) % 4]).length()).sum();
    let outside = |p: DVec2| {
        (0..4)
            .map(|k| {
                let edge = quad[(k + 1) % 4] - quad[k];
                -edge.perp_dot(p - quad[k]) / edge.length()
            })
            .fold(0.0f64, f64::max)
    };
    if hull.iter().any(|p| outside(*p) > POLYGON_ACCURACY * perimeter) {
        return None;
    }
    let shortest = (0..4).map(|k| (quad[k] - quad[(k + 1) % 4]).length()).fold(f64::INFINITY, f64::min);
    (shortest >= cells).then_some(quad)
}

/// Andrew's monotone chain; positively oriented, `points` reordered.
fn convex_hull(points: &mut [DVec2]) -> Vec<DVec2> {
    points.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
    let mut hull: Vec<DVec2> = Vec::with_capacity(points.len() + 1);
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    for pass in 0..2 {
        let floor = hull.len();
        let ordered: Box<dyn Iterator<Item = &DVec2>> =
            if pass == 0 { Box::new(points.iter()) } else { Box::new(points.iter().rev()) };
        for &p in ordered {
            while hull.len() >= floor + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Signed area, positive for a positively oriented polygon.
fn polygon_area(polygon: &[DVec2]) -> f64 {
    let n = polygon.len();
    0.5 * (0..n).map(|i| polygon[i].perp_dot(polygon[(i + 1) % n])).sum::<f64>()
}

/// The marker whose cells `quad` outlines, if its border is dark and its
/// bits are a code of the dictionary.
fn decode(image: &Grey, matcher: &Matcher, quad: [DVec2; 4], bits: usize, border: usize) -> Option<Marker> {
    let cells = bits + 2 * border;
    let n = cells as f64;
    let unit = [DVec2::ZERO, DVec2::new(n, 0.0), DVec2::new(n, n), DVec2::new(0.0, n)];
    let h = homography(&unit, &quad)?;
    // Each cell's middle half (OpenCV ignores a quarter cell at each edge),
    // 3×3 samples.
    let mut means = Vec::with_capacity(cells * cells);
    for cy in 0..cells {
        for cx in 0..cells {
            let mut sum = 0.0;
            for (sx, sy) in [-0.25, 0.0, 0.25].into_iter().flat_map(|a| [(a, -0.25), (a, 0.0), (a, 0.25)]) {
                let p = DVec2::new(cx as f64 + 0.5 + sx, cy as f64 + 0.5 + sy);
                sum += image.at(map_point(&h, p)?);
            }
            means.push(sum / 9.0);
        }
    }
    let cut = otsu(&means)?;
    let is_border =
        |cx: usize, cy: usize| cx < border || cy < border || cx >= cells - border || cy >= cells - border;
    let mut border_light = 0usize;
    let mut border_count = 0usize;
    let mut code = 0u64;
    for cy in 0..cells {
        for cx in 0..cells {
            let black = means[cy * cells + cx] < cut;
            if is_border(cx, cy) {
                border_count += 1;
                border_light += usize::from(!black);
            } else if black {
                code |= 1 << ((cy - border) * bits + (cx - border));
            }
        }
    }
    // A border cell or two may catch a neighbour's edge when the quad is a
    // pixel off; more and this is not a marker's frame.
    if border_light * 8 > border_count {
        return None;
    }
    let found = matcher.match_code(code)?;
    // `code == rotate(dictionary code, rotation)`: the printed top-left
    // corner is the quad's corner `rotation`.
    let r = found.rotation as usize;
    let corners = [0, 1, 2, 3].map(|m| quad[(m + r) % 4]);
    Some(Marker { id: found.id, corners })
}

/// Otsu's split of `values` into dark and light (the threshold), or `None`
/// when they hold too little contrast to split (OpenCV's `minOtsuStdDev`,
/// 5 grey levels).
fn otsu(values: &[f64]) -> Option<f64> {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    if variance.sqrt() < 5.0 {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let total: f64 = sorted.iter().sum();
    let (mut best, mut cut, mut below) = (f64::NEG_INFINITY, mean, 0.0);
    for k in 1..sorted.len() {
        below += sorted[k - 1];
        let (w0, w1) = (k as f64, n - k as f64);
        let between = w0 * w1 * (below / w0 - (total - below) / w1).powi(2);
        if between > best {
            best = between;
            cut = 0.5 * (sorted[k - 1] + sorted[k]);
        }
    }
    Some(cut)
}
