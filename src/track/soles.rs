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
//! time but biased; `depth` weighs the two. A foot is kept as a
//! [`SoleView`] (its sole and the foreground around it) and sighted from
//! wherever the final path puts the hips.

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

/// Whether `foot` is on the floor in `body` (posed as the suit says, the
/// floor at y = 0): its lowest point within [`PLANTED_CM`] of it.
pub fn is_planted(foot: &Foot, body: &PosedBody) -> bool {
    let lowest_cm = foot
        .spheres
        .iter()
        .filter_map(|&s| body.spheres.get(s))
        .map(|s| s.centre_cm.y - s.radius_cm)
        .fold(f64::INFINITY, f64::min);
    lowest_cm <= PLANTED_CM
}

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

/// One planted foot seen in a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoleSighting {
    /// The hips' floor position (x, z, cm) the foot implies along `along`.
    pub implied_hips_cm: DVec2,
    /// The camera's line of sight on the floor there (unit).
    pub along: DVec2,
    /// How uncertain the implied position is along it (cm, one σ): the
    /// edge's pixel through the floor's depth per image row there, and the
    /// pose's.
    pub sigma_cm: f64,
}

/// A sphere of a foot as its sole: under its centre on the floor, relative
/// to the hips' floor point (x, z, cm), and its radius (cm).
#[derive(Clone, Copy, Debug, PartialEq)]
struct SoleSphere {
    offset_cm: DVec2,
    radius_cm: f64,
}

/// One planted foot in one frame, kept so that it can be sighted from
/// wherever the path finally puts the hips: the foot's sole as the pose
/// has it, and the foreground's runs in the image columns around it. (A
/// sighting made where the forward filter stood, when that was 40 cm off,
/// would look for the sole in the wrong rows and confirm the error.)
#[derive(Clone, Debug, PartialEq)]
pub struct SoleView {
    /// The camera the foreground was seen through: the take's, or the
    /// smaller one of the working scale the frame was read at
    /// ([`crate::camera::Camera::shrunk`]).
    camera: Camera,
    sole: Vec<SoleSphere>,
    /// The first image column kept.
    first_column: i64,
    /// Per column kept, the foreground's runs of rows (first, last), top
    /// down, within the rows kept.
    runs: Vec<Vec<(i64, i64)>>,
}

/// The planted feet of `body` (posed at the floor's origin, as the suit
/// says) in `foreground`, with the hips near `hips_cm`: each foot's
/// [`SoleView`], with the columns and rows its sole's edge may be in
/// within twice [`REACH_CM`] along the line of sight. A foot whose window
/// also holds another part of the body (the other foot or leg striding
/// past, which could be lowest there) is left out.
pub fn view_soles(
    camera: &Camera,
    feet: &[Foot],
    body: &PosedBody,
    foreground: &Mask,
    hips_cm: DVec2,
) -> Vec<SoleView> {
    let discs = image_discs(camera, body, hips_cm);
    let mut views = Vec::new();
    for foot in feet.iter().filter(|f| is_planted(f, body)) {
        let sole: Vec<SoleSphere> = foot
            .spheres
            .iter()
            .filter_map(|&s| body.spheres.get(s))
            .map(|s| SoleSphere {
                offset_cm: DVec2::new(s.centre_cm.x, s.centre_cm.z),
                radius_cm: s.radius_cm,
            })
            .collect();
        let Some(edge) = sole_edge(camera, &sole, hips_cm) else { continue };
        let Some((top, bottom)) = edge.rows_reached(camera, REACH_CM) else { continue };
        let window = PixelWindow {
            left: edge.pixel.x - edge.half_width_px,
            right: edge.pixel.x + edge.half_width_px,
            top,
            bottom,
        };
        let leg = leg_spheres(foot, body);
        if discs.iter().any(|d| !leg.contains(&d.sphere) && window.meets(d)) {
            continue;
        }
        let Some((top, bottom)) = edge.rows_reached(camera, 2.0 * REACH_CM) else { continue };
        // The columns drift little as the hips move along the line of
        // sight; a margin of a few pixels covers it.
        let margin_px = 2.0 + 0.5 * edge.half_width_px;
        let first = (edge.pixel.x - edge.half_width_px - margin_px).floor() as i64;
        let last = (edge.pixel.x + edge.half_width_px + margin_px).ceil() as i64;
        let runs: Vec<Vec<(i64, i64)>> =
            (first..=last).map(|x| foreground_runs(foreground, x, top, bottom)).collect();
        // Nothing there (the foot hidden, or out of the image): not seen.
        if runs.iter().all(Vec::is_empty) {
            continue;
        }
        views.push(SoleView { camera: *camera, sole, first_column: first, runs });
    }
    views
}

impl SoleView {
    /// Where this foot puts the hips along the line of sight when they are
    /// near `hips_cm`: the median over the sole's columns of the lowest
    /// foreground row within [`REACH_CM`] of where its edge would be;
    /// `None` when fewer than half its columns have foreground there or
    /// the columns were not kept.
    pub fn sight(&self, hips_cm: DVec2) -> Option<SoleSighting> {
        let camera = &self.camera;
        let edge = sole_edge(camera, &self.sole, hips_cm)?;
        let (top, bottom) = edge.rows_reached(camera, REACH_CM)?;
        let first = (edge.pixel.x - edge.half_width_px).round() as i64;
        let last = (edge.pixel.x + edge.half_width_px).round() as i64;
        let mut lows: Vec<i64> = Vec::new();
        for x in first..=last {
            let runs = usize::try_from(x - self.first_column).ok().and_then(|c| self.runs.get(c))?;
            let lowest = runs
                .iter()
                .filter(|(a, b)| (*a as f64) <= bottom && (*b as f64) >= top)
                .map(|(_, b)| (*b).min(bottom.floor() as i64))
                .max();
            lows.extend(lowest);
        }
        let columns = (last - first + 1).max(1) as usize;
        if lows.is_empty() || 2 * lows.len() < columns {
            return None;
        }
        lows.sort_unstable();
        // The last foreground pixel's centre is on the sole and the edge
        // falls before the next one's, half a row lower on average; but a
        // blurred step of high contrast crosses the foreground's threshold
        // early, outside the edge, by about as much. The row itself it is.
        let row = lows[lows.len() / 2] as f64;
        // Foreground down to the image's last row is a body the frame cuts
        // off, not a sole on the floor.
        if row + 1.0 >= f64::from(camera.image_size.height_px) {
            return None;
        }
        let seen = camera.floor_point(DVec2::new(edge.pixel.x, row))?;
        let next_row = camera.floor_point(DVec2::new(edge.pixel.x, row + 1.0))?;
        let seen_cm = DVec2::new(seen.x, seen.z);
        let shift_cm = (seen_cm - edge.floor_cm).dot(edge.along);
        let cm_per_row = (DVec2::new(next_row.x, next_row.z) - seen_cm).length();
        let edge_cm = EDGE_SIGMA_PX * cm_per_row;
        Some(SoleSighting {
            implied_hips_cm: hips_cm + edge.along * shift_cm,
            along: edge.along,
            // Not `hypot`: the CLI's and the browser's libraries differ in
            // its last bit; a square root does not.
            sigma_cm: (edge_cm * edge_cm + POSE_SIGMA_CM * POSE_SIGMA_CM).sqrt(),
        })
    }
}

/// Column `x`'s runs of foreground rows (first, last) between rows `top`
/// and `bottom`, top down; none off the image.
fn foreground_runs(mask: &Mask, x: i64, top: f64, bottom: f64) -> Vec<(i64, i64)> {
    let (w, h) = (mask.width_px as i64, mask.height_px as i64);
    if x < 0 || x >= w {
        return Vec::new();
    }
    let (top, bottom) = ((top.floor() as i64).max(0), (bottom.ceil() as i64).min(h - 1));
    let mut runs = Vec::new();
    let mut start: Option<i64> = None;
    for y in top..=bottom {
        match (mask.on[(y * w + x) as usize], start) {
            (true, None) => start = Some(y),
            (false, Some(a)) => {
                runs.push((a, y - 1));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(a) = start {
        runs.push((a, bottom));
    }
    runs
}

/// A round patch of the body's image: a sphere's, or a point of a cone
/// between two (then `sphere` is the cone's end nearer that point).
struct ImageDisc {
    centre_px: DVec2,
    radius_px: f64,
    sphere: usize,
}

/// The body's spheres, and three points along each cone, as discs in the
/// image with the hips at `hips_cm`. A cone's points belong to both its
/// spheres' ends: each is listed once under either end, so that a leg's
/// own cones are known by their spheres.
fn image_discs(camera: &Camera, body: &PosedBody, hips_cm: DVec2) -> Vec<ImageDisc> {
    let shift = DVec3::new(hips_cm.x, 0.0, hips_cm.y);
    let disc = |centre_cm: DVec3, radius_cm: f64, sphere: usize| {
        let at = centre_cm + shift;
        let depth_cm = camera.point_in_camera(at).z;
        let centre_px = camera.point_in_image(at)?;
        (depth_cm > 0.0).then(|| ImageDisc {
            centre_px,
            radius_px: camera.intrinsics.fx_px * radius_cm / depth_cm,
            sphere,
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
    /// The image rows (top, bottom) of the floor `reach_cm` farther and
    /// nearer along the line of sight.
    fn rows_reached(&self, camera: &Camera, reach_cm: f64) -> Option<(f64, f64)> {
        let at = |d: f64| {
            let p = self.floor_cm + self.along * d;
            camera.point_in_image(DVec3::new(p.x, 0.0, p.y)).map(|px| px.y)
        };
        let (far, near) = (at(reach_cm)?, at(-reach_cm)?);
        Some((far.min(near), far.max(near)))
    }
}

/// The edge nearest the camera of `sole` with the hips at `hips_cm`: of the
/// floor points nearest the camera under each of its spheres, the one
/// lowest in the image.
fn sole_edge(camera: &Camera, sole: &[SoleSphere], hips_cm: DVec2) -> Option<SoleEdge> {
    let mut best: Option<SoleEdge> = None;
    for sphere in sole {
        let under = sphere.offset_cm + hips_cm;
        let along = camera.line_of_sight_on_floor(under);
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::body::shape::{Anchor, ShapeSphere, Sphere};

    /// A camera 150 cm up at (0, 150, −500) looking along +z, tilted down
    /// 20°, 640×480, f = 500 px.
    pub(crate) fn camera() -> Camera {
        let tilt = 20f64.to_radians();
        let (s, c) = tilt.sin_cos();
        // Camera axes in the world: x right, y down, z forward.
        let right = DVec3::X;
        let forward = DVec3::new(0.0, -s, c);
        let down = DVec3::new(0.0, -c, -s);
        Camera {
            image_size: crate::camera::ImageSize { width_px: 640, height_px: 480 },
            intrinsics: crate::camera::Intrinsics { fx_px: 500.0, fy_px: 500.0, cx_px: 319.5, cy_px: 239.5 },
            distortion: crate::camera::Distortion::default(),
            camera_from_world: glam::DAffine3::from_mat3_translation(
                glam::DMat3::from_cols(right, down, forward),
                DVec3::new(0.0, 150.0, -500.0),
            )
            .inverse(),
        }
    }

    /// A body of one planted foot: an ankle sphere 8 cm up and a toe sphere
    /// on the floor, `toe_offset_cm` from the hips' floor point.
    pub(crate) fn one_foot(toe_offset_cm: DVec2) -> (Vec<Foot>, PosedBody) {
        let body = PosedBody {
            spheres: vec![
                Sphere {
                    centre_cm: DVec3::new(toe_offset_cm.x, 8.0, toe_offset_cm.y - 15.0),
                    radius_cm: 5.0,
                },
                Sphere { centre_cm: DVec3::new(toe_offset_cm.x, 4.0, toe_offset_cm.y), radius_cm: 4.0 },
            ],
            cones: vec![(0, 1)],
        };
        (vec![Foot { spheres: vec![0, 1] }], body)
    }

    /// The foreground of a foot whose sole covers the floor within `radius`
    /// of each of `soles_cm` (floor points, cm), as `camera` sees it.
    pub(crate) fn mask_of_soles(camera: &Camera, soles_cm: &[(DVec2, f64)]) -> Mask {
        let (w, h) = (camera.image_size.width_px, camera.image_size.height_px);
        let mut on = vec![false; (w * h) as usize];
        for y in 0..h {
            for x in 0..w {
                let Some(p) = camera.floor_point(DVec2::new(x as f64, y as f64)) else { continue };
                let p = DVec2::new(p.x, p.z);
                on[(y * w + x) as usize] = soles_cm.iter().any(|(c, r)| p.distance(*c) <= *r);
            }
        }
        Mask { width_px: w, height_px: h, on }
    }

    /// The foreground of `body`'s soles (each sphere's disc on the floor)
    /// with the hips at `hips_cm`.
    pub(crate) fn mask_of_body_soles(camera: &Camera, body: &PosedBody, hips_cm: DVec2) -> Mask {
        let soles: Vec<(DVec2, f64)> = body
            .spheres
            .iter()
            .map(|s| (DVec2::new(s.centre_cm.x, s.centre_cm.z) + hips_cm, s.radius_cm))
            .collect();
        mask_of_soles(camera, &soles)
    }

    #[test]
    fn a_shape_s_feet_are_its_ankles_with_their_toes() {
        let sphere = |joint, part| ShapeSphere { anchor: Anchor::Joint(joint), radius_cm: 5.0, part };
        let shape = BodyShape {
            spheres: vec![
                sphere(0, Part::Pelvis),
                sphere(1, Part::Knee),
                sphere(2, Part::Ankle),
                sphere(3, Part::Toes),
                sphere(4, Part::ToeTip),
                sphere(5, Part::Knee),
                sphere(6, Part::Ankle),
                sphere(7, Part::Toes),
            ],
            links: vec![(0, 1), (1, 2), (2, 3), (3, 4), (0, 5), (5, 6), (6, 7)],
            stature_cm: 170.0,
            joint_count: 8,
        };
        let feet = feet_of(&shape);
        assert_eq!(feet, [Foot { spheres: vec![2, 3, 4] }, Foot { spheres: vec![6, 7] }]);
    }

    #[test]
    fn a_planted_sole_puts_the_hips_where_it_is_from_a_track_30_cm_off() {
        let camera = camera();
        let toe = DVec2::new(10.0, 20.0);
        let (feet, body) = one_foot(toe);
        // The hips truly at (0, 0), 5 m from the camera: the sole is there
        // in the image.
        let truth = DVec2::new(0.0, 0.0);
        let mask = mask_of_body_soles(&camera, &body, truth);
        // The track 30 cm too far along the line of sight.
        let off = truth + DVec2::new(0.0, 30.0);
        let views = view_soles(&camera, &feet, &body, &mask, off);
        assert_eq!(views.len(), 1);
        let sighting = views[0].sight(off).unwrap();
        let along_error = (sighting.implied_hips_cm - truth).dot(sighting.along);
        // Within the floor's depth of one image row (3.3 cm here): the
        // mask's pixel centres sample the edge.
        assert!(along_error.abs() < 3.5, "{sighting:?}");
        assert!(sighting.sigma_cm > POSE_SIGMA_CM && sighting.sigma_cm < 10.0, "{sighting:?}");
        // A foot in the air is not sighted.
        let lifted = PosedBody {
            spheres: body
                .spheres
                .iter()
                .map(|s| Sphere { centre_cm: s.centre_cm + DVec3::Y * 20.0, ..*s })
                .collect(),
            ..body.clone()
        };
        assert!(view_soles(&camera, &feet, &lifted, &mask, off).is_empty());
    }
}
