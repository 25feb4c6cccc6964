//! `cargo bench --bench silhouette`: milliseconds per silhouette of the
//! default body (the built-in demo's skeleton and motion) at two sizes on
//! screen, in a 640×480 camera with a barrel lens: the render alone, the
//! render with an energy summed over its spans, and the outer contour; and
//! the posing and the display mesh.
//! Prints figures; asserts nothing.

// A benchmark may panic on what it does not expect.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::{Duration, Instant};

use embusen::body::shape::{BodyShape, PosedBody};
use embusen::camera::{Camera, Distortion, ImageSize, Intrinsics};
use embusen::track::silhouette::{Silhouette, SilhouetteRenderer};
use glam::{DAffine3, DMat3, DVec3};

/// Median wall time of `f` over enough runs to fill about half a second.
fn median_time(mut f: impl FnMut()) -> Duration {
    f();
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 5 || (start.elapsed() < Duration::from_millis(500) && times.len() < 100_000) {
        let t = Instant::now();
        f();
        times.push(t.elapsed());
    }
    times.sort();
    times[times.len() / 2]
}

/// A camera `distance_cm` in front of the body, at chest height.
fn camera(distance_cm: f64) -> Camera {
    let eye = DVec3::new(0.3 * distance_cm, 140.0, distance_cm);
    let forward = (DVec3::new(0.0, 90.0, 0.0) - eye).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let world_from_camera =
        DAffine3::from_mat3_translation(DMat3::from_cols(right, forward.cross(right), forward), eye);
    Camera {
        image_size: ImageSize { width_px: 640, height_px: 480 },
        intrinsics: Intrinsics { fx_px: 480.0, fy_px: 480.0, cx_px: 319.5, cy_px: 239.5 },
        distortion: Distortion { k1: -0.05, k2: 0.02, p1: -0.0003, p2: -0.0002, k3: 0.0 },
        camera_from_world: world_from_camera.inverse(),
    }
}

fn main() {
    let recording = embusen::synth::demo::demo().recording();
    let shape =
        BodyShape::standard(&recording.joint_names, &recording.parents, recording.poses.frame(0)).unwrap();
    // Frames spread over the kata, each centred under the camera's aim.
    let bodies: Vec<PosedBody> = (0..recording.frame_count())
        .step_by(recording.frame_count() / 16)
        .map(|f| {
            let hips = recording.poses.at(f, 0);
            shape.pose(recording.poses.frame(f), DVec3::new(-hips.x, 0.0, -hips.z)).unwrap()
        })
        .collect();
    let t = median_time(|| {
        for f in (0..recording.frame_count()).step_by(recording.frame_count() / 16) {
            std::hint::black_box(shape.pose(recording.poses.frame(f), DVec3::ZERO).unwrap());
        }
    });
    println!(
        "pose the body ({} spheres, {} cones): {:6.2} µs",
        shape.spheres.len(),
        shape.links.len(),
        t.as_secs_f64() * 1e6 / bodies.len() as f64
    );
    let t = median_time(|| {
        for body in &bodies {
            std::hint::black_box(body.mesh(16));
        }
    });
    let triangles = bodies[0].mesh(16).indices.len() / 3;
    println!(
        "its mesh for display (16 segments, {triangles} triangles): {:6.2} µs",
        t.as_secs_f64() * 1e6 / bodies.len() as f64
    );
    // A per-pixel image term, prefix-summed per row: what an energy reads.
    let prefix: Vec<f64> = (0..480 * 641).map(|i| (i % 641) as f64 * 0.5).collect();
    for distance_cm in [540.0, 270.0] {
        let camera = camera(distance_cm);
        let mut renderer = SilhouetteRenderer::new(&camera);
        let mut out = Silhouette::empty(camera.image_size);
        let heights: Vec<u32> =
            bodies.iter().map(|b| renderer.render(b, DVec3::ZERO).bounds.height()).collect();
        let mean_height = heights.iter().sum::<u32>() as f64 / heights.len() as f64;
        let per = |t: Duration| t.as_secs_f64() * 1e3 / bodies.len() as f64;
        let render = median_time(|| {
            for (i, body) in bodies.iter().enumerate() {
                renderer.render_into(body, DVec3::new(i as f64 * 0.1, 0.0, 0.0), &mut out);
                std::hint::black_box(&out);
            }
        });
        let energy = median_time(|| {
            for (i, body) in bodies.iter().enumerate() {
                renderer.render_into(body, DVec3::new(i as f64 * 0.1, 0.0, 0.0), &mut out);
                let sum: f64 = out
                    .spans
                    .iter()
                    .map(|s| {
                        let row = s.row as usize * 641;
                        prefix[row + s.end as usize] - prefix[row + s.start as usize]
                    })
                    .sum();
                std::hint::black_box(sum);
            }
        });
        let contour = median_time(|| {
            for (i, body) in bodies.iter().enumerate() {
                renderer.render_into(body, DVec3::new(i as f64 * 0.1, 0.0, 0.0), &mut out);
                std::hint::black_box(out.contour());
            }
        });
        println!(
            "silhouette, body {mean_height:3.0} px tall, 640×480: render {:7.4} ms, + energy over spans {:7.4} ms, \
             + contour {:7.4} ms",
            per(render),
            per(energy),
            per(contour)
        );
    }
}
