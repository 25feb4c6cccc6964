//! The body model's silhouette (`track::silhouette`) against a brute-force
//! ray test through every pixel centre, the brute force itself against a
//! sphere's analytic image (a conic), and the true pose of the shared
//! optical scenes against the actor in their videos.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::Path;
use std::process::Command;

use embusen::body::shape::{BodyShape, Part, PosedBody, Sphere};
use embusen::camera::{Camera, Distortion, ImageSize, Intrinsics};
use embusen::synth::rng::XorShift64;
use embusen::track::silhouette::{Silhouette, SilhouetteRenderer, silhouette};
use glam::{DAffine3, DMat3, DVec2, DVec3};

/// A camera at `eye` looking at `target`, the world's +Y up in the image.
fn look_at(eye: DVec3, target: DVec3, size: ImageSize, focal_px: f64, distortion: Distortion) -> Camera {
    let forward = (target - eye).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let down = forward.cross(right);
    let world_from_camera = DAffine3::from_mat3_translation(DMat3::from_cols(right, down, forward), eye);
    Camera {
        image_size: size,
        intrinsics: Intrinsics {
            fx_px: focal_px,
            fy_px: focal_px * 1.002,
            cx_px: (size.width_px as f64 - 1.0) / 2.0 + 1.3,
            cy_px: (size.height_px as f64 - 1.0) / 2.0 - 0.8,
        },
        distortion,
        camera_from_world: world_from_camera.inverse(),
    }
}

const VGA: ImageSize = ImageSize { width_px: 640, height_px: 480 };

fn barrel() -> Distortion {
    Distortion { k1: -0.08, k2: 0.03, p1: -0.0004, p2: 0.0003, k3: 0.0 }
}

/// The mask of pixels whose centre's ray (the lens undone) meets a sphere
/// or the convex hull of a linked pair: the union of the balls centred on
/// the segment between their centres, the radius running linearly.
fn brute_force(camera: &Camera, body: &PosedBody) -> Vec<u8> {
    let spheres: Vec<(DVec3, f64)> =
        body.spheres.iter().map(|s| (camera.point_in_camera(s.centre_cm), s.radius_cm)).collect();
    let (w, h) = (camera.image_size.width_px, camera.image_size.height_px);
    let mut mask = vec![0u8; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let d = camera.ray_in_camera(DVec2::new(x as f64, y as f64));
            // The part of a point off the ray, and its distance along it.
            let off = |p: DVec3| p - d * p.dot(d);
            let hit_sphere = spheres.iter().any(|&(c, r)| c.dot(d) > 0.0 && off(c).length() <= r);
            let hit_cone = || {
                body.cones.iter().any(|&(a, b)| {
                    let ((ca, ra), (cb, rb)) = (spheres[a], spheres[b]);
                    // Far from the pair's bounding sphere: no need to search.
                    let bound = 0.5 * ca.distance(cb) + ra.max(rb);
                    if off(0.5 * (ca + cb)).length() > bound {
                        return false;
                    }
                    // g(s) = |off(c(s))| − r(s) is convex: golden-section search.
                    let g = |s: f64| off(ca.lerp(cb, s)).length() - (ra + (rb - ra) * s);
                    let (mut lo, mut hi) = (0.0, 1.0);
                    let ratio = 0.5 * (5f64.sqrt() - 1.0);
                    for _ in 0..60 {
                        let (m1, m2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
                        if g(m1) < g(m2) { hi = m2 } else { lo = m1 }
                    }
                    g(0.5 * (lo + hi)) <= 0.0
                })
            };
            if hit_sphere || hit_cone() {
                mask[(y * w + x) as usize] = 1;
            }
        }
    }
    mask
}

/// Intersection over union of two image masks.
fn iou(a: &[u8], b: &[u8]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x != 0 && **y != 0).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x != 0 || **y != 0).count();
    if either == 0 { 1.0 } else { both as f64 / either as f64 }
}

#[test]
fn the_brute_force_draws_a_spheres_analytic_ellipse() {
    // A pinhole (no lens), the sphere well off the optical axis so that its
    // image is a long ellipse.
    let camera = look_at(
        DVec3::new(0.0, 150.0, 500.0),
        DVec3::new(0.0, 100.0, 0.0),
        VGA,
        480.0,
        Distortion::default(),
    );
    let centre = camera.world_from_camera().transform_point3(DVec3::new(160.0, -90.0, 420.0));
    let body = PosedBody { spheres: vec![Sphere { centre_cm: centre, radius_cm: 30.0 }], cones: Vec::new() };
    // The cone of rays grazing the sphere, in pixels: the pixel (u, v) sees
    // it when its ray d = K⁻¹(u, v, 1) has (d·c)² ≥ |d|²(|c|² − r²), d·c > 0.
    let c = camera.point_in_camera(centre);
    let k = camera.intrinsics;
    let mut conic = vec![0u8; 640 * 480];
    for v in 0..480 {
        for u in 0..640 {
            let d = DVec3::new((u as f64 - k.cx_px) / k.fx_px, (v as f64 - k.cy_px) / k.fy_px, 1.0);
            let along = d.dot(c);
            if along > 0.0 && along * along >= d.length_squared() * (c.length_squared() - 30.0 * 30.0) {
                conic[v * 640 + u] = 1;
            }
        }
    }
    let area: usize = conic.iter().map(|&m| m as usize).sum();
    assert!(area > 3000, "the ellipse covers {area} px");
    let brute = brute_force(&camera, &body);
    let differ = brute.iter().zip(&conic).filter(|(a, b)| a != b).count();
    assert!(differ <= 2, "the brute force and the conic differ on {differ} of {area} px");
    let fast = silhouette(&camera, &body, DVec3::ZERO).image_mask();
    let differ = fast.iter().zip(&conic).filter(|(a, b)| a != b).count();
    let overlap = iou(&fast, &conic);
    eprintln!("one sphere: {area} px, the silhouette differs on {differ} px, IoU {overlap:.5}");
    assert!(overlap >= 0.995, "IoU {overlap}");
}

/// The demo's skeleton and default body, and `count` random frames of it
/// placed at random on the floor, seen by `camera`.
fn demo_bodies(count: usize, seed: u64) -> Vec<PosedBody> {
    let recording = embusen::synth::demo::demo().recording();
    let shape =
        BodyShape::standard(&recording.joint_names, &recording.parents, recording.poses.frame(0)).unwrap();
    let mut rng = XorShift64(seed);
    (0..count)
        .map(|_| {
            let frame = ((rng.symmetric() + 1.0) * 0.5 * (recording.frame_count() - 1) as f64) as usize;
            let hips = recording.poses.at(frame, 0);
            let shift = DVec3::new(rng.symmetric() * 80.0 - hips.x, 0.0, rng.symmetric() * 80.0 - hips.z);
            shape.pose(recording.poses.frame(frame), shift).unwrap()
        })
        .collect()
}

#[test]
fn silhouettes_match_the_brute_force_on_random_poses() {
    let mut rng = XorShift64(0x5eed_0b0d);
    for (i, body) in demo_bodies(4, 17).iter().enumerate() {
        // From all round, 3.5–6 m away, 1–2.2 m up, through a barrel lens.
        let angle = std::f64::consts::PI * rng.symmetric();
        let distance = 475.0 + 125.0 * rng.symmetric();
        let eye = DVec3::new(
            distance * libm::cos(angle),
            160.0 + 60.0 * rng.symmetric(),
            distance * libm::sin(angle),
        );
        let target = DVec3::new(40.0 * rng.symmetric(), 90.0, 40.0 * rng.symmetric());
        let camera = look_at(eye, target, VGA, 480.0, barrel());
        let fast = silhouette(&camera, body, DVec3::ZERO);
        assert_eq!(fast.skipped, 0);
        let brute = brute_force(&camera, body);
        let overlap = iou(&fast.image_mask(), &brute);
        let area: usize = brute.iter().map(|&m| m as usize).sum();
        eprintln!(
            "pose {i}: {area} px, {} px tall, IoU with the brute force {overlap:.4}",
            fast.bounds.height()
        );
        assert!(overlap >= 0.98, "pose {i}: IoU {overlap}");
    }
}

#[test]
fn spans_contour_and_bounds_agree_with_the_mask() {
    let body = &demo_bodies(1, 3)[0];
    let camera = look_at(DVec3::new(300.0, 150.0, 400.0), DVec3::new(0.0, 90.0, 0.0), VGA, 480.0, barrel());
    let s = silhouette(&camera, body, DVec3::ZERO);
    let image = s.image_mask();
    let (w, h) = (640usize, 480usize);
    // The spans are the mask, each row's runs disjoint and in order.
    let mut from_spans = vec![0u8; w * h];
    let mut last = (0u32, 0u32);
    for span in &s.spans {
        assert!(span.start < span.end && (span.row, span.start) >= last, "{span:?} after {last:?}");
        last = (span.row, span.end + 1);
        from_spans[span.row as usize * w + span.start as usize..span.row as usize * w + span.end as usize]
            .fill(1);
    }
    assert_eq!(from_spans, image);
    assert_eq!(s.area_px(), image.iter().filter(|&&m| m != 0).count());
    // The box is tight: each of its sides touches the mask.
    let b = s.bounds;
    let covered = |x: u32, y: u32| image[y as usize * w + x as usize] != 0;
    assert!(
        (b.top..b.bottom).any(|y| covered(b.left, y)) && (b.top..b.bottom).any(|y| covered(b.right - 1, y))
    );
    assert!(
        (b.left..b.right).any(|x| covered(x, b.top)) && (b.left..b.right).any(|x| covered(x, b.bottom - 1))
    );
    assert!(image.iter().enumerate().all(|(i, &m)| m == 0 || s.contains((i % w) as u32, (i / w) as u32)));
    let expected = contour_of_mask(&image, w, h);
    assert_eq!(s.contour(), expected);
    assert!(expected.len() > 100);
    // Cut by the image's edges (left, top, bottom): the cut is no contour.
    for shift in [DVec3::new(-290.0, 0.0, 140.0), DVec3::new(0.0, 190.0, 0.0), DVec3::new(0.0, -200.0, 0.0)] {
        let cut = silhouette(&camera, body, shift);
        let b = cut.bounds;
        assert!(b.left == 0 || b.top == 0 || b.bottom == 480, "{shift}: {b:?} is not cut");
        let expected = contour_of_mask(&cut.image_mask(), w, h);
        assert!(expected.len() > 20, "{shift}");
        assert_eq!(cut.contour(), expected, "{shift}");
    }
}

/// The contour by brute force: covered pixels with an uncovered 4-neighbour
/// in the image, in raster order.
fn contour_of_mask(image: &[u8], w: usize, h: usize) -> Vec<[u32; 2]> {
    let mut expected = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let at = |x: usize, y: usize| image[y * w + x] != 0;
            if at(x, y)
                && ((x > 0 && !at(x - 1, y))
                    || (x + 1 < w && !at(x + 1, y))
                    || (y > 0 && !at(x, y - 1))
                    || (y + 1 < h && !at(x, y + 1)))
            {
                expected.push([x as u32, y as u32]);
            }
        }
    }
    expected
}

#[test]
fn a_shift_moves_the_body_and_a_renderer_repeats_itself() {
    let body = &demo_bodies(1, 5)[0];
    let camera = look_at(DVec3::new(0.0, 150.0, 500.0), DVec3::new(0.0, 90.0, 0.0), VGA, 480.0, barrel());
    let mut renderer = SilhouetteRenderer::new(&camera);
    let shift = DVec3::new(12.5, 0.0, -7.0);
    let a = renderer.render(body, shift);
    let b = renderer.render(&body.translated(shift), DVec3::ZERO);
    let c = silhouette(&camera, body, shift);
    assert_eq!(a, c);
    // Moving the body first or in the renderer adds the same numbers in
    // another order: the masks may differ by a rounding on an edge.
    let differ = a.image_mask().iter().zip(b.image_mask()).filter(|(x, y)| **x != *y).count();
    assert!(differ <= 2, "{differ} px differ");
    let mut reused = Silhouette::empty(camera.image_size);
    for _ in 0..3 {
        renderer.render_into(body, shift, &mut reused);
        assert_eq!(reused, a);
    }
}

#[test]
fn what_reaches_the_camera_is_not_drawn() {
    let camera = look_at(DVec3::ZERO, DVec3::new(0.0, 0.0, -100.0), VGA, 480.0, barrel());
    let sphere = |z: f64| Sphere { centre_cm: DVec3::new(10.0, 0.0, z), radius_cm: 10.0 };
    // Ahead; straddling the camera's plane; behind, linked to the first.
    let body = PosedBody { spheres: vec![sphere(-200.0), sphere(-5.0), sphere(100.0)], cones: vec![(0, 2)] };
    let s = silhouette(&camera, &body, DVec3::ZERO);
    assert_eq!(s.skipped, 3, "two spheres and the cone");
    let alone =
        silhouette(&camera, &PosedBody { spheres: vec![sphere(-200.0)], cones: Vec::new() }, DVec3::ZERO);
    assert_eq!((&s.spans, s.bounds), (&alone.spans, alone.bounds));
    assert!(alone.area_px() > 100);
    // Off the image: nothing covered, nothing skipped, no contour.
    let s = silhouette(&camera, &body, DVec3::new(1000.0, 0.0, 0.0));
    assert_eq!((s.area_px(), s.skipped, s.bounds.is_empty(), s.contour().len()), (0, 3, true, 0));
}

#[test]
fn the_shared_skeletons_get_whole_bodies() {
    let Some(dir) = common::data_dir() else { return };
    // Bandai's optical skeleton (a floor root, end sites on their joints)
    // and the karate files' Motion Shadow one (Z up, head and foot ends).
    for file in ["optical/walk.truth.bvh", "karate/heian_shodan.bvh", "karate/empi_right.bvh"] {
        let recording = common::open(&dir, file);
        let shape = BodyShape::standard(&recording.joint_names, &recording.parents, recording.poses.frame(0))
            .unwrap();
        let count = |part: Part| shape.spheres.iter().filter(|s| s.part == part).count();
        eprintln!(
            "{file}: stature {:.1} cm, {} spheres, {} cones",
            shape.stature_cm,
            shape.spheres.len(),
            shape.links.len()
        );
        assert!((150.0..190.0).contains(&shape.stature_cm), "{file}: stature {}", shape.stature_cm);
        for (part, wanted) in [
            (Part::Pelvis, 1),
            (Part::Skull, 1),
            (Part::Hip, 2),
            (Part::Knee, 2),
            (Part::Ankle, 2),
            (Part::Shoulder, 2),
            (Part::Elbow, 2),
            (Part::Wrist, 2),
            (Part::Palm, 2),
            (Part::Other, 0),
        ] {
            assert_eq!(count(part), wanted, "{file}: {part:?}");
        }
        assert!(count(Part::Trunk) >= 2, "{file}: the spine");
        // `empi_right.bvh` ends its legs at the ankles: no foot to extend.
        assert_eq!(count(Part::ToeTip), if file.contains("empi") { 0 } else { 2 }, "{file}: toe tips");
        // One tree of cones over all spheres, none at the floor's root.
        assert_eq!(shape.links.len(), shape.spheres.len() - 1, "{file}");
        // No sphere hangs far below the lowest joint (the sole is a few cm
        // under the ankle and toes).
        let up = |p: DVec3| if recording.up_axis_is_z() { p.z } else { p.y };
        for f in (0..recording.frame_count()).step_by(25) {
            let frame = recording.poses.frame(f);
            let lowest_joint = frame.iter().map(|&p| up(p)).fold(f64::INFINITY, f64::min);
            let body = shape.pose(frame, DVec3::ZERO).unwrap();
            let lowest =
                body.spheres.iter().map(|s| up(s.centre_cm) - s.radius_cm).fold(f64::INFINITY, f64::min);
            assert!(
                lowest > lowest_joint - 6.0,
                "{file} frame {f}: {lowest} cm, the lowest joint {lowest_joint}"
            );
        }
    }
}

/// Frames `every`th of a video or image, decoded by ffmpeg as RGB, `size`
/// each; `None` (said) without ffmpeg.
fn decode_rgb(path: &Path, every: usize, size: ImageSize) -> Option<Vec<Vec<u8>>> {
    let select = format!("select=not(mod(n\\,{every}))");
    let output = match Command::new("ffmpeg")
        .args(["-v", "error", "-i"])
        .arg(path)
        .args(["-vf", &select, "-vsync", "0", "-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
        .output()
    {
        Ok(output) => output,
        Err(e) => {
            if std::env::var("CI").is_ok_and(|ci| ci == "true") {
                panic!("ffmpeg: {e}: CI=true needs ffmpeg");
            }
            eprintln!("SKIPPED: ffmpeg: {e}");
            return None;
        }
    };
    assert!(output.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&output.stderr));
    let frame = (size.width_px * size.height_px * 3) as usize;
    Some(output.stdout.chunks_exact(frame).map(<[u8]>::to_vec).collect())
}

/// The actor in a frame: pixels whose colour differs from the empty room's
/// by more than `threshold` in some channel (the actor's cast shadow too).
fn foreground(frame: &[u8], background: &[u8], threshold: u8) -> Vec<u8> {
    frame
        .chunks_exact(3)
        .zip(background.chunks_exact(3))
        .map(|(a, b)| u8::from(a.iter().zip(b).any(|(x, y)| x.abs_diff(*y) > threshold)))
        .collect()
}

#[test]
fn the_true_pose_covers_the_actor_in_the_shared_scenes() {
    let Some(dir) = common::data_dir() else { return };
    let optical = dir.join("optical");
    let every = 15;
    let mut means = Vec::new();
    for scene in ["walk", "walk_turns", "run", "slash"] {
        let file = format!("{scene}.camera.json");
        let camera =
            Camera::from_json(&std::fs::read_to_string(optical.join(&file)).unwrap(), &file).unwrap();
        let truth = common::open(&dir, &format!("optical/{scene}.truth.bvh"));
        let shape = BodyShape::standard(&truth.joint_names, &truth.parents, truth.poses.frame(0)).unwrap();
        let Some(frames) = decode_rgb(&optical.join(format!("{scene}.mp4")), every, camera.image_size) else {
            return;
        };
        let background =
            decode_rgb(&optical.join(format!("{scene}.background.png")), 1, camera.image_size).unwrap();
        let mut renderer = SilhouetteRenderer::new(&camera);
        let mut ious = Vec::new();
        // The share of the silhouette on the actor, and of the actor (its
        // shadow with it) in the silhouette, summed over frames.
        let (mut covered, mut found) = (0.0, 0.0);
        for (k, frame) in frames.iter().enumerate() {
            let f = k * every;
            if f >= truth.frame_count() {
                break;
            }
            let body = shape.pose(truth.poses.frame(f), DVec3::ZERO).unwrap();
            let mask = renderer.render(&body, DVec3::ZERO).image_mask();
            let actor = foreground(frame, &background[0], 30);
            ious.push(iou(&mask, &actor));
            let both = mask.iter().zip(&actor).filter(|(a, b)| **a != 0 && **b != 0).count() as f64;
            covered += both / mask.iter().filter(|&&m| m != 0).count() as f64;
            found += both / actor.iter().filter(|&&m| m != 0).count() as f64;
        }
        ious.sort_by(f64::total_cmp);
        let mean = ious.iter().sum::<f64>() / ious.len() as f64;
        eprintln!(
            "{scene}: IoU of the default body with the foreground over {} frames: mean {mean:.3}, min {:.3}, \
             max {:.3}; on the actor {:.3}, of the actor {:.3}",
            ious.len(),
            ious[0],
            ious[ious.len() - 1],
            covered / ious.len() as f64,
            found / ious.len() as f64,
        );
        means.push((mean, covered / ious.len() as f64));
    }
    // The body is not the renderer's (on purpose), and the shadow counts as
    // foreground: guards below what it scores (0.68–0.78, 0.88–0.97).
    assert!(
        means.iter().all(|&(iou, on)| iou > 0.6 && on > 0.8),
        "mean IoUs, shares on the actor: {means:?}"
    );
}

/// A VGA camera of 500 px focal length 4 m in front of the world's origin,
/// at 1 m up, looking at the point 1 m above it.
fn four_metres_away() -> Camera {
    look_at(DVec3::new(0.0, 100.0, -400.0), DVec3::new(0.0, 100.0, 0.0), VGA, 500.0, Distortion::default())
}

/// The fused energy's band term (`FrameTerms::fit_in_band`): a body the
/// actor's size leaves its band on the empty room; one too small leaves it
/// partly on the actor, about by how much it falls short in pixels.
#[test]
fn the_band_term_sees_a_body_too_small_for_the_actor() {
    use embusen::image::Mask;
    use embusen::image::distance::distance_to;
    use embusen::track::energy::FrameTerms;
    let camera = four_metres_away();
    let ball = |radius_cm: f64| PosedBody {
        spheres: vec![Sphere { centre_cm: DVec3::new(0.0, 100.0, 0.0), radius_cm }],
        cones: Vec::new(),
    };
    // The actor: a ball of 30 cm, about 37.5 px across the image at 4 m.
    let actor = silhouette(&camera, &ball(30.0), DVec3::ZERO).image_mask();
    let foreground = Mask {
        width_px: VGA.width_px,
        height_px: VGA.height_px,
        on: actor.iter().map(|&m| m == 1).collect(),
    };
    let distance = distance_to(&foreground);
    let terms = FrameTerms::new(&distance, &distance, &foreground, 10.0);
    let band_cm = 5.0;
    let band_px = 500.0 * band_cm / 400.0;
    let uncovered = |radius_cm: f64| {
        let body = silhouette(&camera, &ball(radius_cm), DVec3::ZERO);
        let widened = silhouette(&camera, &ball(radius_cm + band_cm), DVec3::ZERO);
        terms.fit_in_band(&body, &widened, band_px).unwrap().uncovered_px
    };
    let (exact, short) = (uncovered(30.0), uncovered(27.0));
    // 3 cm short at 4 m is 3.75 px; the band's outer rings are longer than
    // its inner ones, so a little less of it is on the actor.
    assert!(exact < 0.1, "a body the actor's size: {exact} px");
    assert!((2.5..=3.75).contains(&short), "a body 3.75 px too small: {short} px");
    assert!(uncovered(20.0) > short, "smaller still");
    // Without a band there is no such term.
    let body = silhouette(&camera, &ball(27.0), DVec3::ZERO);
    assert_eq!(terms.fit(&body).unwrap().uncovered_px, 0.0);
}

/// The fused tracker computes a frame's distances only up to its energy's
/// truncation (`PipelineParams::truncate_px`): its fits must be exactly those
/// from the whole distance transforms, for bodies on the actor, beside it,
/// and on rows of the image far from any foreground.
#[test]
fn fits_from_truncated_distances_are_the_fits_from_whole_ones() {
    use embusen::image::Mask;
    use embusen::image::distance::{distance_to, distance_to_truncated};
    use embusen::track::energy::FrameTerms;
    let camera = four_metres_away();
    let ball = |centre_cm: DVec3, radius_cm: f64| PosedBody {
        spheres: vec![Sphere { centre_cm, radius_cm }],
        cones: Vec::new(),
    };
    let actor = silhouette(&camera, &ball(DVec3::new(0.0, 100.0, 0.0), 30.0), DVec3::ZERO).image_mask();
    let foreground = Mask {
        width_px: VGA.width_px,
        height_px: VGA.height_px,
        on: actor.iter().map(|&m| m == 1).collect(),
    };
    // The actor's own outline as its edges.
    let edges = Mask {
        width_px: VGA.width_px,
        height_px: VGA.height_px,
        on: (0..actor.len())
            .map(|i| {
                let (x, y) = (i % VGA.width_px as usize, i / VGA.width_px as usize);
                foreground.on[i]
                    && (x == 0
                        || !foreground.on[i - 1]
                        || y == 0
                        || !foreground.on[i - VGA.width_px as usize])
            })
            .collect(),
    };
    let truncation_px = 12.5;
    let (whole_edges, whole_outside) = (distance_to(&edges), distance_to(&foreground));
    let (cut_edges, cut_outside) =
        (distance_to_truncated(&edges, truncation_px), distance_to_truncated(&foreground, truncation_px));
    let whole = FrameTerms::new(&whole_edges, &whole_outside, &foreground, truncation_px);
    let cut = FrameTerms::new(&cut_edges, &cut_outside, &foreground, truncation_px);
    let mut compared = 0;
    for (x_cm, y_cm, radius_cm) in [
        (0.0, 100.0, 30.0),
        (8.0, 95.0, 25.0),
        (60.0, 100.0, 30.0),
        (0.0, 260.0, 40.0),
        (-150.0, -40.0, 20.0),
    ] {
        let body = silhouette(&camera, &ball(DVec3::new(x_cm, y_cm, 0.0), radius_cm), DVec3::ZERO);
        let widened = silhouette(&camera, &ball(DVec3::new(x_cm, y_cm, 0.0), radius_cm + 5.0), DVec3::ZERO);
        let (a, b) = (whole.fit_in_band(&body, &widened, 6.0), cut.fit_in_band(&body, &widened, 6.0));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert_eq!(a.fused_energy(1.0, 0.5).to_bits(), b.fused_energy(1.0, 0.5).to_bits(), "{x_cm}, {y_cm}");
        assert_eq!(
            (a.truncated_chamfer_px, a.outside_px, a.uncovered_px),
            (b.truncated_chamfer_px, b.outside_px, b.uncovered_px)
        );
        assert_eq!((a.near_edge_share, a.on_foreground_share), (b.near_edge_share, b.on_foreground_share));
        compared += 1;
    }
    assert_eq!(compared, 5);
}
