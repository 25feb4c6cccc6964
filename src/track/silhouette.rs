//! The silhouette of a posed body in a camera's image: which pixels it
//! covers, its outer contour and its bounding box, computed on the CPU.
//!
//! How: a sphere's outline is the circle where the rays from the camera's
//! centre graze it; its points, projected, lie exactly on the sphere's image
//! (an ellipse, the conic of that cone of rays). A cone tangent to two
//! spheres is their convex hull, and a pinhole maps the convex hull of
//! points ahead of it to the convex hull of their images: the two ellipses
//! and, between them, the quadrilateral of their two common tangents. Those
//! tangents are the images of the two planes through the camera's centre
//! that touch both spheres, found in closed form (`bridges`), so a cone
//! costs four points, not a hull. Everything is computed in the *ideal*
//! image (normalised, undistorted), where these facts hold exactly; each
//! polygon is clipped there to the part of the plane the image can see, its
//! long edges split so the lens can bend them, and only then put through
//! the lens and the focal lengths, point by point, as
//! `Camera::point_in_image` does. Each polygon is filled with scanlines by
//! the pixel-centre rule, one column range per row, and the ranges of a
//! row are merged into its runs ([`Silhouette::spans`]): no pixel is
//! touched one by one (the trackers render many candidate positions per
//! frame).
//!
//! Outlines are sampled finely enough that the polygon stays within
//! 0.05 px of the true curve (points spaced by the projected size, the
//! polygon widened to straddle the curve rather than lie inside it).
//! Primitives that reach to within 1 cm of the camera's plane, or behind it,
//! are not drawn (they would cover the image, or the part of it that lies
//! ahead); [`Silhouette::skipped`] counts them.
//!
//! Only `+ − × ÷ √`, `ceil` and `libm`'s sine and cosine are used, all
//! exactly rounded or exact, so the mask is the same bytes on every target.

use glam::{DVec2, DVec3};

use crate::body::shape::PosedBody;
use crate::camera::{Camera, ImageSize};
use crate::image::PixelBox;

/// One run of covered pixels: columns `start..end` of image row `row`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Span {
    pub row: u32,
    pub start: u32,
    pub end: u32,
}

/// Pushes the columns of `span` that no span of `cover` (one row's, left
/// to right) covers.
fn uncovered(span: &Span, cover: &[Span], xs: &mut Vec<u32>) {
    let mut x = span.start;
    for c in cover {
        if c.end <= x {
            continue;
        }
        if c.start >= span.end {
            break;
        }
        xs.extend(x..c.start.max(x));
        x = x.max(c.end);
        if x >= span.end {
            return;
        }
    }
    xs.extend(x..span.end);
}

/// The pixels a body covers in one image.
#[derive(Clone, Debug, PartialEq)]
pub struct Silhouette {
    pub image_size: ImageSize,
    /// The covered pixels' bounding box (clipped to the image).
    pub bounds: PixelBox,
    /// The runs of covered pixels, row by row from the top, left to right,
    /// disjoint and not touching: what an energy sums over (with a per-row
    /// prefix sum of the image term, one subtraction per span).
    pub spans: Vec<Span>,
    /// Spheres and cones not drawn because they reach the camera's plane.
    pub skipped: usize,
}

impl Silhouette {
    /// Nothing covered, in an image of `image_size`.
    pub fn empty(image_size: ImageSize) -> Silhouette {
        Silhouette { image_size, bounds: PixelBox::default(), spans: Vec::new(), skipped: 0 }
    }

    /// Whether pixel `(x, y)` is covered.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        let first = self.spans.partition_point(|s| (s.row, s.end) <= (y, x));
        self.spans.get(first).is_some_and(|s| s.row == y && s.start <= x)
    }

    /// The number of covered pixels.
    pub fn area_px(&self) -> usize {
        self.spans.iter().map(|s| (s.end - s.start) as usize).sum()
    }

    /// The outer contour: covered pixels with a 4-neighbour that is not
    /// covered, in raster order, as `[x, y]`. A neighbour off the image
    /// does not count: where the image cuts the body, the cut is no edge.
    pub fn contour(&self) -> Vec<[u32; 2]> {
        let mut out = Vec::new();
        self.visit_contour(|x, y| out.push([x, y]));
        out
    }

    /// Calls `visit(x, y)` on each pixel of [`Silhouette::contour`], in its
    /// order, without collecting them (an energy reads each once).
    pub fn visit_contour(&self, mut visit: impl FnMut(u32, u32)) {
        // From the spans alone: a span's pixels on the contour are its ends
        // and what the rows above and below leave uncovered of it, found by
        // interval arithmetic — a few steps a span, not a test a pixel.
        let (image_w, image_h) = (self.image_size.width_px, self.image_size.height_px);
        let mut rows: Vec<(u32, usize, usize)> = Vec::new();
        for (i, span) in self.spans.iter().enumerate() {
            match rows.last_mut() {
                Some((row, _, end)) if *row == span.row => *end = i + 1,
                _ => rows.push((span.row, i, i + 1)),
            }
        }
        let empty: &[Span] = &[];
        // The spans of image row `y` next to row entry `r` (`None` off the
        // image: a neighbour there does not count).
        let neighbour = |r: Option<usize>, y: Option<u32>| -> Option<&[Span]> {
            let y = y.filter(|&y| y < image_h)?;
            Some(match r.and_then(|r| rows.get(r)) {
                Some(&(row, from, to)) if row == y => &self.spans[from..to],
                _ => empty,
            })
        };
        let mut xs: Vec<u32> = Vec::new();
        for (r, &(y, from, to)) in rows.iter().enumerate() {
            let up = neighbour(r.checked_sub(1), y.checked_sub(1));
            let down = neighbour(Some(r + 1), Some(y + 1));
            for span in &self.spans[from..to] {
                xs.clear();
                if span.start > 0 {
                    xs.push(span.start);
                }
                if span.end < image_w {
                    xs.push(span.end - 1);
                }
                for cover in [up, down].into_iter().flatten() {
                    uncovered(span, cover, &mut xs);
                }
                xs.sort_unstable();
                xs.dedup();
                for &x in &xs {
                    visit(x, y);
                }
            }
        }
    }

    /// The mask over the whole image, row by row (1 covered, 0 not).
    pub fn image_mask(&self) -> Vec<u8> {
        let (w, h) = (self.image_size.width_px as usize, self.image_size.height_px as usize);
        let mut image = vec![0u8; w * h];
        for span in &self.spans {
            let row = span.row as usize * w;
            image[row + span.start as usize..row + span.end as usize].fill(1);
        }
        image
    }
}

/// Nothing closer to the camera's plane than this (cm) is drawn, as
/// `Camera::point_in_image` projects nothing closer.
const NEAREST_DEPTH_CM: f64 = 1.0;
/// The largest distance (px) between the sampled outline and the true one.
const OUTLINE_TOLERANCE_PX: f64 = 0.05;
/// Polygon edges longer than this (px) are split before the lens bends them.
const LONGEST_EDGE_PX: f64 = 8.0;
/// Outlines are sampled with one of these point counts.
const OUTLINE_POINTS: [usize; 6] = [8, 16, 32, 64, 128, 256];

/// Renders silhouettes for one camera, keeping its scratch buffers from one
/// render to the next.
#[derive(Clone, Debug)]
pub struct SilhouetteRenderer {
    camera: Camera,
    /// The box of the ideal image plane outside which nothing reaches the
    /// image: the undistorted image border's bounds, with a margin.
    ideal_min: DVec2,
    ideal_max: DVec2,
    focal_px: f64,
    lens_bends: bool,
    /// Unit circles of each of [`OUTLINE_POINTS`] points, and how much each
    /// is widened to straddle the curve: 2 / (1 + cos(π/n)).
    circles: Vec<(Vec<DVec2>, f64)>,
    /// Each sphere's centre (camera cm) and radius, when ahead of the camera.
    visible: Vec<Option<(DVec3, f64)>>,
    /// The pixel polygons to fill: ranges of `polygon_points`.
    polygons: Vec<(usize, usize)>,
    polygon_points: Vec<DVec2>,
    clip: Vec<DVec2>,
    clip_spare: Vec<DVec2>,
    /// Per row of the polygons' box, the leftmost and the rightmost
    /// crossing of the polygon being filled (apart, so that a row's two
    /// updates are two vector instructions for several rows).
    row_lows: Vec<f64>,
    row_highs: Vec<f64>,
    /// Per row of the polygons' box, the union of the column ranges the
    /// polygons drawn so far cover there, as runs ([`add_range`]).
    row_ranges: Vec<Vec<(u32, u32)>>,
}

impl SilhouetteRenderer {
    pub fn new(camera: &Camera) -> SilhouetteRenderer {
        let (w, h) = (camera.image_size.width_px as f64, camera.image_size.height_px as f64);
        // Where the image's border comes from in the ideal plane.
        let mut ideal_min = DVec2::splat(f64::INFINITY);
        let mut ideal_max = DVec2::splat(f64::NEG_INFINITY);
        const STEPS: usize = 32;
        for i in 0..=STEPS {
            let t = i as f64 / STEPS as f64;
            let (x, y) = (-0.5 + t * w, -0.5 + t * h);
            for pixel in
                [DVec2::new(x, -0.5), DVec2::new(x, h - 0.5), DVec2::new(-0.5, y), DVec2::new(w - 0.5, y)]
            {
                let ideal = camera.distortion.undistort(camera.intrinsics.normalised(pixel));
                if ideal.is_finite() {
                    ideal_min = ideal_min.min(ideal);
                    ideal_max = ideal_max.max(ideal);
                }
            }
        }
        if !(ideal_min.is_finite() && ideal_max.is_finite()) {
            ideal_min = DVec2::ZERO;
            ideal_max = DVec2::ZERO;
        }
        let margin = (ideal_max - ideal_min) * 0.05;
        let circles = OUTLINE_POINTS
            .iter()
            .map(|&n| {
                let points = (0..n)
                    .map(|i| {
                        let a = std::f64::consts::TAU * i as f64 / n as f64;
                        DVec2::new(libm::cos(a), libm::sin(a))
                    })
                    .collect();
                (points, 2.0 / (1.0 + libm::cos(std::f64::consts::PI / n as f64)))
            })
            .collect();
        SilhouetteRenderer {
            camera: *camera,
            ideal_min: ideal_min - margin,
            ideal_max: ideal_max + margin,
            focal_px: camera.intrinsics.fx_px.abs().max(camera.intrinsics.fy_px.abs()),
            lens_bends: camera.distortion != crate::camera::Distortion::default(),
            circles,
            visible: Vec::new(),
            polygons: Vec::new(),
            polygon_points: Vec::new(),
            clip: Vec::new(),
            clip_spare: Vec::new(),
            row_lows: Vec::new(),
            row_highs: Vec::new(),
            row_ranges: Vec::new(),
        }
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The silhouette of `body` moved by `shift_cm`.
    pub fn render(&mut self, body: &PosedBody, shift_cm: DVec3) -> Silhouette {
        let mut out = Silhouette::empty(self.camera.image_size);
        self.render_into(body, shift_cm, &mut out);
        out
    }

    /// As [`SilhouetteRenderer::render`], into `out`, reusing its
    /// allocations.
    pub fn render_into(&mut self, body: &PosedBody, shift_cm: DVec3, out: &mut Silhouette) {
        out.image_size = self.camera.image_size;
        out.skipped = 0;
        self.visible.clear();
        self.polygons.clear();
        self.polygon_points.clear();
        for sphere in &body.spheres {
            let centre = self.camera.point_in_camera(sphere.centre_cm + shift_cm);
            let radius = sphere.radius_cm;
            // The widened outline reaches a little beyond the sphere.
            let ahead = centre.is_finite() && radius >= 0.0 && centre.z - 1.1 * radius > NEAREST_DEPTH_CM;
            if ahead {
                self.outline(centre, radius);
                self.add_polygon();
                self.visible.push(Some((centre, radius)));
            } else {
                out.skipped += 1;
                self.visible.push(None);
            }
        }
        for &(a, b) in &body.cones {
            let (Some(Some(a)), Some(Some(b))) = (self.visible.get(a), self.visible.get(b)) else {
                out.skipped += 1;
                continue;
            };
            if let Some(quad) = bridges(*a, *b) {
                self.clip.clear();
                self.clip.extend(quad.iter().map(|p| DVec2::new(p.x / p.z, p.y / p.z)));
                self.add_polygon();
            }
        }
        self.fill(out);
    }

    /// The sampled outline of the sphere at `centre` (camera cm, ahead of
    /// the camera) of `radius_cm`, in the ideal image, into `clip`.
    fn outline(&mut self, centre: DVec3, radius_cm: f64) {
        let distance2 = centre.length_squared();
        let k = radius_cm * radius_cm / distance2;
        // The circle of grazing rays: its centre and radius.
        let middle = centre * (1.0 - k);
        let rim = radius_cm * (1.0 - k).sqrt();
        // Its image's radius in pixels, about: the sphere's angular radius,
        // stretched off the optical axis as the ellipse is.
        let ideal_centre = DVec2::new(centre.x, centre.y) / centre.z;
        let radius_px = self.focal_px * radius_cm / (distance2 - radius_cm * radius_cm).sqrt()
            * (1.0 + ideal_centre.length_squared());
        // A chord of a circle of radius ρ over angle 2π/n sags ρ(1 − cos(π/n))
        // ≈ ρπ²/2n²; the widened polygon halves that error.
        let wanted = std::f64::consts::PI * (radius_px / (4.0 * OUTLINE_TOLERANCE_PX)).sqrt();
        let which =
            OUTLINE_POINTS.iter().position(|&n| n as f64 >= wanted).unwrap_or(OUTLINE_POINTS.len() - 1);
        // Widened so that the vertices lie as far outside the circle as the
        // edges' middles lie inside.
        let (circle, widen) = &self.circles[which];
        let widened = rim * widen;
        let (u, v) = centre.normalize().any_orthonormal_pair();
        self.clip.clear();
        for c in circle {
            let p = middle + (u * c.x + v * c.y) * widened;
            self.clip.push(DVec2::new(p.x / p.z, p.y / p.z));
        }
    }

    /// Clips the convex polygon in `clip` (ideal image) to what the image
    /// sees, splits its long edges, and stores it in pixels.
    fn add_polygon(&mut self) {
        let (lo, hi) = (self.ideal_min, self.ideal_max);
        let (mut low, mut high) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in &self.clip {
            low = low.min(*p);
            high = high.max(*p);
        }
        if !(high.x >= lo.x && high.y >= lo.y && low.x <= hi.x && low.y <= hi.y) {
            return; // wholly off the image (or NaN)
        }
        if !(low.x >= lo.x && low.y >= lo.y && high.x <= hi.x && high.y <= hi.y) {
            // Sutherland–Hodgman against the four sides of the box.
            for (axis, bound, keep_below) in
                [(0, lo.x, false), (0, hi.x, true), (1, lo.y, false), (1, hi.y, true)]
            {
                clip_half_plane(&self.clip, axis, bound, keep_below, &mut self.clip_spare);
                std::mem::swap(&mut self.clip, &mut self.clip_spare);
                if self.clip.is_empty() {
                    return;
                }
            }
        }
        let start = self.polygon_points.len();
        let longest_ideal = LONGEST_EDGE_PX / self.focal_px;
        let count = self.clip.len();
        self.polygon_points.reserve(count);
        for i in 0..count {
            let p = self.clip[i];
            self.polygon_points.push(self.pixel(p));
            if self.lens_bends {
                let q = self.clip[(i + 1) % count];
                // Most edges (all of a sphere's) are far shorter than the
                // longest kept: those skip the square root and the ceiling.
                if (q - p).length_squared() < 0.81 * longest_ideal * longest_ideal {
                    continue;
                }
                let pieces = ceil((q - p).length() / longest_ideal);
                if pieces > 1 {
                    let pieces = pieces.min(256) as usize;
                    for k in 1..pieces {
                        let t = k as f64 / pieces as f64;
                        self.polygon_points.push(self.pixel(p + (q - p) * t));
                    }
                }
            }
        }
        self.polygons.push((start, self.polygon_points.len()));
    }

    /// The pixel of an ideal image point, through the lens.
    fn pixel(&self, ideal: DVec2) -> DVec2 {
        self.camera.intrinsics.pixel(self.camera.distortion.distort(ideal))
    }

    /// Fills the stored polygons into `out`'s spans: each polygon's column
    /// range per row, merged per row where they overlap or touch (what
    /// filling a mask and reading its runs would give, without touching
    /// every pixel).
    fn fill(&mut self, out: &mut Silhouette) {
        let (w, h) = (self.camera.image_size.width_px, self.camera.image_size.height_px);
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for p in &self.polygon_points {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        // Pixel u is covered when its centre is: lo ≤ u < hi.
        let first =
            |v: f64, size: u32| if v.is_finite() { v.ceil().clamp(0.0, size as f64) as u32 } else { 0 };
        let bounds = PixelBox {
            left: first(lo.x, w),
            top: first(lo.y, h),
            right: first(hi.x, w),
            bottom: first(hi.y, h),
        };
        let bounds = if bounds.is_empty() { PixelBox::default() } else { bounds };
        let bh = bounds.height() as usize;
        self.row_lows.clear();
        self.row_lows.resize(bh, f64::INFINITY);
        self.row_highs.clear();
        self.row_highs.resize(bh, f64::NEG_INFINITY);
        if self.row_ranges.len() < bh {
            self.row_ranges.resize_with(bh, Vec::new);
        }
        for &(start, end) in &self.polygons {
            let rows = (&mut self.row_lows[..], &mut self.row_highs[..]);
            fill_convex(&self.polygon_points[start..end], bounds, rows, &mut self.row_ranges);
        }
        merge_spans(&mut self.row_ranges[..bh], bounds.top, out);
    }
}

/// `out`'s spans and tight bounds from each row's runs (`row_ranges[k]`
/// those of image row `top + k`, kept by [`add_range`]; emptied here).
fn merge_spans(row_ranges: &mut [Vec<(u32, u32)>], top: u32, out: &mut Silhouette) {
    out.spans.clear();
    let (mut left, mut right) = (u32::MAX, 0);
    for (ranges, row) in row_ranges.iter_mut().zip(top..) {
        let (Some(first), Some(last)) = (ranges.first(), ranges.last()) else { continue };
        (left, right) = (left.min(first.0), right.max(last.1));
        out.spans.extend(ranges.drain(..).map(|(start, end)| Span { row, start, end }));
    }
    out.bounds = match (out.spans.first(), out.spans.last()) {
        (Some(first), Some(last)) => PixelBox { left, top: first.row, right, bottom: last.row + 1 },
        _ => PixelBox::default(),
    };
}

/// Adds columns `start..end` to `ranges`, one row's union so far: left to
/// right, disjoint and not touching. A range that overlaps or touches some
/// of them becomes one with them, so the union is kept as it grows (a row
/// holds a few runs; the ranges drawn on it, many more).
fn add_range(ranges: &mut Vec<(u32, u32)>, start: u32, end: u32) {
    // The first run that reaches the new range (or lies past it) ...
    let first = ranges.iter().position(|r| r.1 >= start).unwrap_or(ranges.len());
    // ... and the runs from there that start before its end: all one now.
    let mut merged = (start, end);
    let mut past = first;
    while let Some(&(s, e)) = ranges.get(past).filter(|r| r.0 <= end) {
        merged = (merged.0.min(s), merged.1.max(e));
        past += 1;
    }
    if past == first {
        ranges.insert(first, merged);
    } else {
        ranges[first] = merged;
        ranges.drain(first + 1..past);
    }
}

/// The pixels whose centres lie in the convex polygon `points` (pixels),
/// as a column range per row added to `row_ranges` (row `bounds.top + k`
/// at `k`, [`add_range`]); `(lows, highs)` is scratch of `bounds.height()`
/// entries each, left as `∞` and `−∞`. Each edge gives the crossing of every row it spans,
/// `top ≤ v < bottom` (so a row through a vertex is counted once), and each
/// row covers from its leftmost to its rightmost crossing, `left ≤ u < right`.
fn fill_convex(
    points: &[DVec2],
    bounds: PixelBox,
    (lows, highs): (&mut [f64], &mut [f64]),
    row_ranges: &mut [Vec<(u32, u32)>],
) {
    let (top, bottom) = (i64::from(bounds.top), i64::from(bounds.bottom));
    let mut used = (usize::MAX, 0);
    let Some(&last) = points.last() else { return };
    // Each edge from the one before it to it; a vertex's row ceiling is
    // computed once, not once per edge (the rows are order-free).
    let (mut p, mut p_row) = (last, ceil(last.y));
    for &q in points {
        let q_row = ceil(q.y);
        let ((a, a_row), (b, b_row)) =
            if p.y < q.y { ((p, p_row), (q, q_row)) } else { ((q, q_row), (p, p_row)) };
        let flat = p.y == q.y;
        (p, p_row) = (q, q_row);
        if flat {
            continue;
        }
        let first = a_row.max(top);
        let end = b_row.min(bottom);
        if first >= end {
            continue;
        }
        let slope = (b.x - a.x) / (b.y - a.y);
        // Within the bounds: 0 ≤ first − top < end − top ≤ their height.
        let (r0, r1) = ((first - top) as usize, (end - top) as usize);
        used = (used.0.min(r0), used.1.max(r1));
        // The row numbers as i32 (within the image), whose conversion to
        // f64 has a vector instruction: the loop runs two rows at a time.
        let first = first as i32;
        for (k, (low, high)) in lows[r0..r1].iter_mut().zip(&mut highs[r0..r1]).enumerate() {
            let x = a.x + (f64::from(first + k as i32) - a.y) * slope;
            // As `min` and `max` (a NaN crossing changes nothing; the
            // rows are never NaN), without their NaN handling: one
            // instruction each here and in wasm.
            *low = if x < *low { x } else { *low };
            *high = if x > *high { x } else { *high };
        }
    }
    if used.0 >= used.1 {
        return;
    }
    let (left, right) = (f64::from(bounds.left), f64::from(bounds.right));
    let used = used.0..used.1;
    let rows = lows[used.clone()].iter_mut().zip(&mut highs[used.clone()]);
    for ((low, high), ranges) in rows.zip(&mut row_ranges[used]) {
        let (x0, x1) = (*low, *high);
        (*low, *high) = (f64::INFINITY, f64::NEG_INFINITY);
        // Clamped to the bounds, whole numbers, before the ceiling: the
        // same columns as clamping after it, and within u32 (the rows are
        // never NaN; an untouched row, (∞, −∞), clamps to an empty range).
        let start = ceil_within_u32(clamp(x0, left, right));
        let end = ceil_within_u32(clamp(x1, left, right));
        if start < end {
            add_range(ranges, start, end);
        }
    }
}

/// `x` within `low ≤ high`, as comparisons (no NaN handling: `x` is no NaN).
fn clamp(x: f64, low: f64, high: f64) -> f64 {
    if x < low {
        low
    } else if x > high {
        high
    } else {
        x
    }
}

/// [`ceil`] of an `x` in `0 ≤ x ≤ u32::MAX` (no saturation to check).
fn ceil_within_u32(x: f64) -> u32 {
    let toward_zero = x as u32;
    toward_zero + u32::from((toward_zero as f64) < x)
}

/// The least whole number not below `x`: exact, so the same on every
/// target (`f64::ceil` is a library call on x86-64 without SSE 4.1, and
/// this is the hot loop). Saturates beyond `i64`'s range (an infinity
/// included); NaN gives 0.
fn ceil(x: f64) -> i64 {
    let toward_zero = x as i64;
    toward_zero.saturating_add(i64::from((toward_zero as f64) < x))
}

/// The part of the polygon `points` on one side of the line `p[axis] = bound`
/// (below it when `keep_below`), into `out`.
fn clip_half_plane(points: &[DVec2], axis: usize, bound: f64, keep_below: bool, out: &mut Vec<DVec2>) {
    out.clear();
    let inside = |p: DVec2| if keep_below { p[axis] <= bound } else { p[axis] >= bound };
    for (i, &p) in points.iter().enumerate() {
        let q = points[(i + 1) % points.len()];
        let (p_in, q_in) = (inside(p), inside(q));
        if p_in {
            out.push(p);
        }
        if p_in != q_in {
            let t = (bound - p[axis]) / (q[axis] - p[axis]);
            let mut cut = p + (q - p) * t;
            cut[axis] = bound;
            out.push(cut);
        }
    }
}

/// The cone between two spheres (camera cm, centre and radius), seen from
/// the camera: the quadrilateral of the points where the two planes through
/// the camera's centre that touch both spheres on the same side touch them.
/// The cone's image is the two spheres' images and this quadrilateral
/// between them (its sides are the images' common tangents). `None` when
/// there is no such plane: one sphere's image holds the other's, and the
/// cone shows nothing more.
///
/// A plane `n·x = 0` (`|n| = 1`) touches sphere `i` on its `+n` side where
/// `n·c_i = r_i`. Writing `n = α c₁ + β c₂ + γ (c₁ × c₂)`, the two touching
/// conditions fix α and β; `|n| = 1` gives `γ = ±√((1 − |α c₁ + β c₂|²) /
/// |c₁ × c₂|²)`, one sign per side; the touching points are `c_i − r_i n`.
fn bridges((c1, r1): (DVec3, f64), (c2, r2): (DVec3, f64)) -> Option<[DVec3; 4]> {
    let (a11, a12, a22) = (c1.length_squared(), c1.dot(c2), c2.length_squared());
    // |c₁ × c₂|² = a11·a22 − a12²: zero when the camera sees along the bone.
    let det = a11 * a22 - a12 * a12;
    if det.is_nan() || det <= 1e-12 * a11 * a22 {
        return None;
    }
    let alpha = (r1 * a22 - r2 * a12) / det;
    let beta = (r2 * a11 - r1 * a12) / det;
    let m = c1 * alpha + c2 * beta;
    let gamma2 = (1.0 - m.length_squared()) / det;
    if gamma2.is_nan() || gamma2 <= 0.0 {
        return None;
    }
    let across = c1.cross(c2) * gamma2.sqrt();
    let (n_plus, n_minus) = (m + across, m - across);
    Some([c1 - n_plus * r1, c2 - n_plus * r2, c2 - n_minus * r2, c1 - n_minus * r1])
}

/// The silhouette of `body` moved by `shift_cm` in `camera`'s image (a
/// renderer made for one call; keep a [`SilhouetteRenderer`] to render many).
pub fn silhouette(camera: &Camera, body: &PosedBody, shift_cm: DVec3) -> Silhouette {
    SilhouetteRenderer::new(camera).render(body, shift_cm)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ranges added in any order, overlapping, touching or apart, leave the
    /// runs a row of pixels covered by any of them has.
    #[test]
    fn a_rows_runs_are_the_union_of_its_ranges() {
        let mut state = 12345u64;
        let mut next = |n: u32| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 33) % u64::from(n)) as u32
        };
        for _ in 0..2000 {
            let (mut runs, mut covered) = (Vec::new(), [false; 40]);
            for _ in 0..next(8) {
                let start = next(38);
                let end = start + 1 + next(40 - start - 1);
                add_range(&mut runs, start, end);
                covered[start as usize..end as usize].fill(true);
            }
            let mut expected = Vec::new();
            for (x, &on) in covered.iter().enumerate() {
                match expected.last_mut() {
                    Some((_, end)) if on && *end == x as u32 => *end += 1,
                    _ if on => expected.push((x as u32, x as u32 + 1)),
                    _ => {}
                }
            }
            assert_eq!(runs, expected);
        }
    }
}
