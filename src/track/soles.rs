//! Depth from the floor: where a planted foot's sole meets the floor in the
//! image fixes how far it is from the camera, whatever the body's girths.
//!
//! The silhouette barely sees depth: a body 20 cm farther is a body 3 %
//! smaller, which a model whose girths are a few percent off matches as
//! well, and a cast shadow or a second person beside the actor moves its
//! least by tens of centimetres along the camera's line of sight (the
//! `shadow` and `second_person` scenes: +23 and +31 cm, always farther).
//! A planted sole is on the floor, and the floor's ray through the image
//! row of its nearest edge says where: for a camera 1.5–2.5 m up looking at
//! a foot 3–6 m away, one image row is 2–4 cm of depth, where the
//! silhouette's energy changes by about 1 px over 20 cm.
//!
//! Each frame, for each foot the suit's pose has on the floor, the lowest
//! foreground row in the columns of its sole near where the track expects
//! it is a **sighting**: the hips' floor position that foot implies along
//! the line of sight. One sighting is rough — the suit's pose puts the
//! foot a few centimetres off the hips, the shoe is not the body model's
//! foot, the other foot or a shadow may be lowest — about 10 cm (one σ)
//! on the shared scenes, and nearly unbiased (medians of −5 to +5 cm). The
//! silhouette's error along the line of sight is the opposite: smooth in
//! time but biased. So once the track is smoothed, its offset along the
//! line of sight is estimated from the sightings as a slowly varying bias
//! (a running median over [`BIAS_WINDOW_S`], robust to the wrong
//! sightings) and taken off.

use glam::{DVec2, DVec3};

use crate::body::shape::{BodyShape, Part, PosedBody};
use crate::camera::Camera;
use crate::image::Mask;

/// A foot of a [`BodyShape`]: the indices of its spheres (the ankle, the
/// ball of the foot, the tip).
#[derive(Clone, Debug, PartialEq)]
pub struct Foot {
    pub spheres: Vec<usize>,
}

/// The feet of `shape`: each ankle's sphere with the foot spheres linked
/// to it (through the ball of the foot to the tip).
pub fn feet_of(shape: &BodyShape) -> Vec<Foot> {
    let is_foot = |i: usize| matches!(shape.spheres[i].part, Part::Toes | Part::ToeTip);
    let mut feet: Vec<Foot> = (0..shape.spheres.len())
        .filter(|&i| shape.spheres[i].part == Part::Ankle)
        .map(|i| Foot { spheres: vec![i] })
        .collect();
    for foot in &mut feet {
        // A foot is a short chain; follow the links until nothing is added.
        loop {
            let before = foot.spheres.len();
            for &(a, b) in &shape.links {
                for (from, to) in [(a, b), (b, a)] {
                    if foot.spheres.contains(&from) && !foot.spheres.contains(&to) && is_foot(to) {
                        foot.spheres.push(to);
                    }
                }
            }
            if foot.spheres.len() == before {
                break;
            }
        }
    }
    feet
}

/// A foot whose lowest point is within this of the floor (cm) is on it: the
/// contact method stands the suit's body with its supporting sole on the
/// floor, give or take the pose's noise of a few centimetres.
pub const PLANTED_CM: f64 = 3.0;

/// How far along the line of sight (cm) either side of where the track
/// expects the sole its edge is looked for: more than the silhouette's
/// worst bias (about 30 cm), less than a stride, so the other foot of a
/// walk is not taken for it.
pub const REACH_CM: f64 = 40.0;

/// How precisely a sole's edge is found in the mask (px, one σ): the
/// mask's edge lies within a pixel of the shoe's, give or take the blur
/// and the contact shadow under it.
pub const EDGE_SIGMA_PX: f64 = 1.5;

/// How far the suit's pose and the body model put a sole from where the
/// shoe's edge is (cm, one σ): the pose's angles move a planted foot a few
/// centimetres against the hips (docs/contact.md), and the model's foot is
/// not the actor's shoe.
pub const POSE_SIGMA_CM: f64 = 8.0;

/// The silhouette's bias along the line of sight is weighed against the
/// sightings as a slowly changing quantity: sightings count with a
/// Gaussian weight of this σ in time (s) — a stride or two, short against
/// how fast the bias changes as the body turns and moves off.
pub const BIAS_TIME_SIGMA_S: f64 = 0.5;

/// One foot's sightings in consecutive frames are one pose error seen
/// again: they count as one per this long (s), about a stance's length.
pub const STANCE_S: f64 = 0.3;

/// How far the silhouette's least may be off along the line of sight
/// before any sighting (cm, one σ): 10–30 cm on the shared scenes
/// (docs/track.md). A correction is the sightings' estimate shrunk towards
/// none by how much more uncertain it is than that.
pub const PRIOR_BIAS_SIGMA_CM: f64 = 20.0;

/// One planted foot seen in a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoleSighting {
    /// The hips' floor position (x, z, cm) the foot implies along `along`,
    /// from the track's position when it was seen.
    pub implied_hips_cm: DVec2,
    /// The camera's line of sight on the floor there (unit).
    pub along: DVec2,
    /// How uncertain the implied position is along it (cm, one σ): the
    /// edge's pixel through the floor's depth per image row there, and the
    /// pose's.
    pub sigma_cm: f64,
}

/// The planted feet of `body` (posed at the floor's origin, as the suit
/// says) seen in `foreground` with the hips at `hips_cm`: where the lowest
/// foreground row in each sole's columns puts the hips along the camera's
/// line of sight. A foot whose columns hold the other foot's sole too, or
/// no foreground, is not sighted.
pub fn sight_soles(
    camera: &Camera,
    feet: &[Foot],
    body: &PosedBody,
    foreground: &Mask,
    hips_cm: DVec2,
) -> Vec<SoleSighting> {
    let centre = camera.center_in_world();
    let soles: Vec<Option<SoleEdge>> = feet
        .iter()
        .map(|foot| sole_edge(camera, foot, body, hips_cm, DVec2::new(centre.x, centre.z)))
        .collect();
    let discs = image_discs(camera, body, hips_cm);
    let leg_of: Vec<Vec<usize>> = feet.iter().map(|f| leg_spheres(f, body)).collect();
    let mut sightings = Vec::new();
    for (k, (foot, sole)) in feet.iter().zip(&soles).enumerate() {
        let Some(sole) = sole else { continue };
        let lowest_cm = foot
            .spheres
            .iter()
            .filter_map(|&s| body.spheres.get(s))
            .map(|s| s.centre_cm.y - s.radius_cm)
            .fold(f64::INFINITY, f64::min);
        if lowest_cm > PLANTED_CM {
            continue;
        }
        let rows = sole.rows_reached(camera);
        let Some((top, bottom)) = rows else { continue };
        // Whatever else of the body the model puts in front of the floor
        // there (the other foot or leg striding past) could be lowest: the
        // foot is not sighted.
        let window = PixelWindow {
            left: sole.pixel.x - sole.half_width_px,
            right: sole.pixel.x + sole.half_width_px,
            top,
            bottom,
        };
        if discs.iter().any(|d| !leg_of[k].contains(&d.sphere_a) && window.meets(d)) {
            continue;
        }
        let Some(row) = lowest_foreground_row(foreground, sole.pixel.x, sole.half_width_px, top, bottom)
        else {
            continue;
        };
        let Some(seen) = camera.floor_point(DVec2::new(sole.pixel.x, row)) else { continue };
        let Some(next_row) = camera.floor_point(DVec2::new(sole.pixel.x, row + 1.0)) else { continue };
        let seen_cm = DVec2::new(seen.x, seen.z);
        let shift_cm = (seen_cm - sole.floor_cm).dot(sole.along);
        let cm_per_row = (DVec2::new(next_row.x, next_row.z) - seen_cm).length();
        let sigma_cm = (EDGE_SIGMA_PX * cm_per_row).hypot(POSE_SIGMA_CM);
        sightings.push(SoleSighting {
            implied_hips_cm: hips_cm + sole.along * shift_cm,
            along: sole.along,
            sigma_cm,
        });
    }
    sightings
}

/// A round patch of the body's image: a sphere's, or a point of a cone
/// between two (then `sphere_a` is the cone's end nearer the hips' side
/// of the list, `sphere_b` the other).
struct ImageDisc {
    centre_px: DVec2,
    radius_px: f64,
    sphere_a: usize,
}

/// The body's spheres, and three points along each cone, as discs in the
/// image with the hips at `hips_cm`. A cone's points belong to both its
/// spheres' ends: each is listed once under either end, so that a leg's
/// own cones are known by their spheres.
fn image_discs(camera: &Camera, body: &PosedBody, hips_cm: DVec2) -> Vec<ImageDisc> {
    let shift = DVec3::new(hips_cm.x, 0.0, hips_cm.y);
    let disc = |centre_cm: DVec3, radius_cm: f64, sphere_a: usize| {
        let at = centre_cm + shift;
        let depth_cm = camera.point_in_camera(at).z;
        let centre_px = camera.point_in_image(at)?;
        (depth_cm > 0.0).then(|| ImageDisc {
            centre_px,
            radius_px: camera.intrinsics.fx_px * radius_cm / depth_cm,
            sphere_a,
        })
    };
    let mut discs: Vec<ImageDisc> =
        body.spheres.iter().enumerate().filter_map(|(i, s)| disc(s.centre_cm, s.radius_cm, i)).collect();
    for &(a, b) in &body.cones {
        let (Some(sa), Some(sb)) = (body.spheres.get(a), body.spheres.get(b)) else { continue };
        for t in [0.25, 0.5, 0.75] {
            let centre = sa.centre_cm.lerp(sb.centre_cm, t);
            let radius = sa.radius_cm + (sb.radius_cm - sa.radius_cm) * t;
            // A cone of the leg belongs to the leg whichever end is listed.
            discs.extend(disc(centre, radius, if t < 0.5 { a } else { b }));
        }
    }
    discs
}

/// The spheres of `foot`'s own leg, whose image may fill the columns above
/// its sole: the foot's, and the knee (and any sphere) linked to them.
fn leg_spheres(foot: &Foot, body: &PosedBody) -> Vec<usize> {
    let mut leg = foot.spheres.clone();
    for &(a, b) in &body.cones {
        for (from, to) in [(a, b), (b, a)] {
            if foot.spheres.contains(&from) && !leg.contains(&to) {
                leg.push(to);
            }
        }
    }
    leg
}

/// The columns and rows a sole's edge is looked for in (px).
struct PixelWindow {
    left: f64,
    right: f64,
    top: f64,
    bottom: f64,
}

impl PixelWindow {
    /// Whether `disc` reaches into the window.
    fn meets(&self, disc: &ImageDisc) -> bool {
        let nearest = DVec2::new(
            disc.centre_px.x.clamp(self.left, self.right),
            disc.centre_px.y.clamp(self.top, self.bottom),
        );
        nearest.distance(disc.centre_px) < disc.radius_px
    }
}

/// The edge of a sole nearest the camera, where the track expects it.
struct SoleEdge {
    /// On the floor (x, z, cm).
    floor_cm: DVec2,
    /// In the image (px).
    pixel: DVec2,
    /// The line of sight through it on the floor (unit).
    along: DVec2,
    /// Half the sole's width in the image (px, at least 2).
    half_width_px: f64,
}

impl SoleEdge {
    /// The image rows (top, bottom) of the floor [`REACH_CM`] farther and
    /// nearer along the line of sight.
    fn rows_reached(&self, camera: &Camera) -> Option<(f64, f64)> {
        let at = |d: f64| {
            let p = self.floor_cm + self.along * d;
            camera.point_in_image(DVec3::new(p.x, 0.0, p.y)).map(|px| px.y)
        };
        let (far, near) = (at(REACH_CM)?, at(-REACH_CM)?);
        Some((far.min(near), far.max(near)))
    }
}

/// The edge of `foot`'s sole nearest the camera (standing below the camera
/// at `camera_floor_cm`) with the hips at `hips_cm`: of the floor points
/// nearest the camera under each of the foot's spheres, the one lowest in
/// the image.
fn sole_edge(
    camera: &Camera,
    foot: &Foot,
    body: &PosedBody,
    hips_cm: DVec2,
    camera_floor_cm: DVec2,
) -> Option<SoleEdge> {
    let mut best: Option<SoleEdge> = None;
    for sphere in foot.spheres.iter().filter_map(|&s| body.spheres.get(s)) {
        let under = DVec2::new(sphere.centre_cm.x, sphere.centre_cm.z) + hips_cm;
        let along = (under - camera_floor_cm).normalize_or_zero();
        if along == DVec2::ZERO {
            continue;
        }
        let floor_cm = under - along * sphere.radius_cm;
        let at = DVec3::new(floor_cm.x, 0.0, floor_cm.y);
        let Some(pixel) = camera.point_in_image(at) else { continue };
        let depth_cm = camera.point_in_camera(at).z;
        if depth_cm <= 0.0 || best.as_ref().is_some_and(|b| b.pixel.y >= pixel.y) {
            continue;
        }
        let half_width_px = (camera.intrinsics.fx_px * sphere.radius_cm / depth_cm).max(2.0);
        best = Some(SoleEdge { floor_cm, pixel, along, half_width_px });
    }
    best
}

/// The median over the columns within `half_width_px` of `x_px` of each
/// column's lowest foreground row between rows `top` and `bottom`; `None`
/// when fewer than half the columns have any.
fn lowest_foreground_row(mask: &Mask, x_px: f64, half_width_px: f64, top: f64, bottom: f64) -> Option<f64> {
    let (w, h) = (mask.width_px as i64, mask.height_px as i64);
    let (first, last) = ((x_px - half_width_px).round() as i64, (x_px + half_width_px).round() as i64);
    let (top, bottom) = ((top.floor() as i64).max(0), (bottom.ceil() as i64).min(h - 1));
    let mut lows: Vec<i64> = Vec::new();
    let mut columns = 0usize;
    for x in first.max(0)..=last.min(w - 1) {
        columns += 1;
        if let Some(y) = (top..=bottom).rev().find(|&y| mask.on[(y * w + x) as usize]) {
            lows.push(y);
        }
    }
    if lows.is_empty() || 2 * lows.len() < columns {
        return None;
    }
    lows.sort_unstable();
    Some(lows[lows.len() / 2] as f64)
}

/// `track` (floor positions per frame, cm) moved along the camera's lines
/// of sight by the bias its sightings show. Per frame, each sighting's
/// offset (how far beyond the track it puts the hips) weighs by its
/// precision and by a Gaussian of [`BIAS_TIME_SIGMA_S`] in time; the
/// weighted median finds the bulk, the weighted mean of the offsets within
/// 2.5 σ of it estimates the bias, which is shrunk towards none by its
/// uncertainty against [`PRIOR_BIAS_SIGMA_CM`] (one foot's sightings within
/// [`STANCE_S`] counting as one). `sightings` are (frame index into
/// `track`, sighting); frames are `dt_s` apart; the camera stands above
/// `camera_floor_cm`. Returns each frame's correction and its uncertainty
/// (cm along the line of sight, one σ).
pub fn correct_depth(
    track: &mut [DVec2],
    sightings: &[(usize, SoleSighting)],
    dt_s: f64,
    camera_floor_cm: DVec2,
) -> Vec<(f64, f64)> {
    let n = track.len();
    let offsets: Vec<(usize, f64, f64)> = sightings
        .iter()
        .filter(|(i, _)| *i < n)
        .map(|&(i, s)| (i, (s.implied_hips_cm - track[i]).dot(s.along), s.sigma_cm))
        .collect();
    let reach = (4.0 * BIAS_TIME_SIGMA_S / dt_s).ceil() as usize;
    let per_stance = (STANCE_S / dt_s).max(1.0);
    let prior = PRIOR_BIAS_SIGMA_CM * PRIOR_BIAS_SIGMA_CM;
    let mut corrections = Vec::with_capacity(n);
    for (i, p) in track.iter_mut().enumerate() {
        let near: Vec<(f64, f64, f64)> = offsets
            .iter()
            .filter(|(j, _, _)| j.abs_diff(i) <= reach)
            .map(|&(j, offset, sigma)| {
                let t = j.abs_diff(i) as f64 * dt_s / BIAS_TIME_SIGMA_S;
                (offset, (-0.5 * t * t).exp() / (sigma * sigma), sigma)
            })
            .collect();
        let Some(bulk) = weighted_median(&near) else {
            corrections.push((0.0, PRIOR_BIAS_SIGMA_CM));
            continue;
        };
        let kept: Vec<&(f64, f64, f64)> =
            near.iter().filter(|(o, _, s)| (o - bulk).abs() <= 2.5 * s).collect();
        let weight: f64 = kept.iter().map(|k| k.1).sum();
        if weight <= 0.0 {
            corrections.push((0.0, PRIOR_BIAS_SIGMA_CM));
            continue;
        }
        let estimate = kept.iter().map(|k| k.0 * k.1).sum::<f64>() / weight;
        // Sightings within a stance share their error: the information is
        // the weight over how many frames a stance spans.
        let variance = per_stance / weight;
        let gain = prior / (prior + variance);
        let correction = gain * estimate;
        *p += (*p - camera_floor_cm).normalize_or_zero() * correction;
        corrections.push((correction, (gain * variance).sqrt()));
    }
    corrections
}

/// The weighted median of `(value, weight, _)`; `None` without weight.
fn weighted_median(values: &[(f64, f64, f64)]) -> Option<f64> {
    let total: f64 = values.iter().map(|v| v.1).sum();
    if total <= 0.0 || !total.is_finite() {
        return None;
    }
    let mut sorted: Vec<(f64, f64)> = values.iter().map(|v| (v.0, v.1)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut running = 0.0;
    for (value, weight) in sorted {
        running += weight;
        if running >= 0.5 * total {
            return Some(value);
        }
    }
    None
}
