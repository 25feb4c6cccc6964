//! The body's surface, from the skeleton: a sphere on each joint and a cone
//! tangent to the two spheres of each bone, so the radius runs linearly
//! along the bone (a sphere-swept cone, the convex hull of its two spheres).
//! This is the surface the paper's SQM mesh (Bærentzen et al. 2012)
//! approximates; the camera tracker renders its silhouette, the app draws
//! its [`Mesh`].
//!
//! The default radii and the parts of the body they belong to are in
//! [`crate::body::proportions`], the default body's construction in
//! [`crate::body::default_shape`], the display mesh in [`crate::body::mesh`];
//! their public names are re-exported here.

use glam::DVec3;

pub use crate::body::mesh::Mesh;
pub use crate::body::proportions::{Part, estimate_stature_cm};
use crate::error::Error;

/// Where a sphere's centre is, in a pose.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Anchor {
    /// At the joint.
    Joint(usize),
    /// `distance_cm` beyond `joint`, on the line from `from` through `joint`
    /// (at `joint` when the two coincide): the palm beyond the wrist, the
    /// skull beyond the neck, where the skeleton has no joint.
    Beyond { joint: usize, from: usize, distance_cm: f64 },
}

/// One sphere of a [`BodyShape`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShapeSphere {
    pub anchor: Anchor,
    pub radius_cm: f64,
    pub part: Part,
}

/// The body as spheres on the skeleton's joints and cones between them: what
/// stays the same from frame to frame. [`BodyShape::pose`] places it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyShape {
    pub spheres: Vec<ShapeSphere>,
    /// Pairs of indices into `spheres`, each joined by the cone tangent to
    /// both.
    pub links: Vec<(usize, usize)>,
    /// The stature the default radii were scaled to (cm).
    pub stature_cm: f64,
    /// The number of joints a pose must have.
    pub joint_count: usize,
}

/// A sphere in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub centre_cm: DVec3,
    pub radius_cm: f64,
}

/// A [`BodyShape`] in one frame's pose.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PosedBody {
    pub spheres: Vec<Sphere>,
    /// Pairs of indices into `spheres`: the cone tangent to both.
    pub cones: Vec<(usize, usize)>,
}

impl BodyShape {
    /// The sphere centred on `joint`, if it has one.
    pub fn sphere_at(&self, joint: usize) -> Option<usize> {
        self.spheres.iter().position(|s| s.anchor == Anchor::Joint(joint))
    }

    /// Sets the radius of the sphere on `joint`; `false` when it has none.
    pub fn set_radius_cm(&mut self, joint: usize, radius_cm: f64) -> bool {
        match self.sphere_at(joint) {
            Some(i) => {
                self.spheres[i].radius_cm = radius_cm;
                true
            }
            None => false,
        }
    }

    /// `posed` (a pose of this shape) with `band_cm` more on the radius of
    /// every sphere but those of the knees, ankles and feet: the outline of
    /// a band around the body that narrows to nothing at the ankles, so it
    /// never reaches the floor by the feet, where the body's cast shadow and
    /// its contact lie.
    pub fn widened(&self, posed: &PosedBody, band_cm: f64) -> PosedBody {
        let mut widened = posed.clone();
        for (sphere, shape) in widened.spheres.iter_mut().zip(&self.spheres) {
            if !matches!(shape.part, Part::Knee | Part::Ankle | Part::Toes | Part::ToeTip) {
                sphere.radius_cm += band_cm;
            }
        }
        widened
    }

    /// Multiplies the radius of every sphere of `part` by `factor`.
    pub fn scale_part(&mut self, part: Part, factor: f64) {
        for sphere in self.spheres.iter_mut().filter(|s| s.part == part) {
            sphere.radius_cm *= factor;
        }
    }

    /// The spheres and cones in one frame's pose (global joint positions,
    /// cm), moved by `shift_cm` (a floor position: the same shift added to
    /// every joint, as the translation methods do).
    pub fn pose(&self, frame_cm: &[DVec3], shift_cm: DVec3) -> Result<PosedBody, Error> {
        if frame_cm.len() != self.joint_count {
            return Err(Error::whole(
                "<body shape>",
                format!("a pose of {} joints for a body of {}", frame_cm.len(), self.joint_count),
            ));
        }
        let mut spheres = Vec::with_capacity(self.spheres.len());
        for (i, s) in self.spheres.iter().enumerate() {
            let Some(centre_cm) = anchor_point(s.anchor, frame_cm) else {
                return Err(Error::whole(
                    "<body shape>",
                    format!("sphere {i} hangs on {:?}: no joint of a pose of {}", s.anchor, frame_cm.len()),
                ));
            };
            spheres.push(Sphere { centre_cm: centre_cm + shift_cm, radius_cm: s.radius_cm });
        }
        Ok(PosedBody { spheres, cones: self.links.clone() })
    }
}

/// The point of `anchor` in a pose; `None` when it names a joint the pose
/// does not have.
fn anchor_point(anchor: Anchor, frame_cm: &[DVec3]) -> Option<DVec3> {
    match anchor {
        Anchor::Joint(j) => frame_cm.get(j).copied(),
        Anchor::Beyond { joint, from, distance_cm } => {
            let at = *frame_cm.get(joint)?;
            let along = at - *frame_cm.get(from)?;
            let length = along.length();
            Some(if length > 1e-9 { at + along * (distance_cm / length) } else { at })
        }
    }
}

impl PosedBody {
    /// The same body moved by `shift_cm`.
    pub fn translated(&self, shift_cm: DVec3) -> PosedBody {
        let spheres =
            self.spheres.iter().map(|s| Sphere { centre_cm: s.centre_cm + shift_cm, ..*s }).collect();
        PosedBody { spheres, cones: self.cones.clone() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::proportions::LEG_FRACTION;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    /// A tiny skeleton: hips, one leg down to the toes with a zero-length end
    /// site, and a spine to the head.
    fn little_body() -> (Vec<String>, Vec<Option<usize>>, Vec<DVec3>) {
        let names = names(&[
            "Root",
            "Hips",
            "LeftUpLeg",
            "LeftLeg",
            "LeftFoot",
            "LeftToe",
            "EndSite6",
            "RightUpLeg",
            "RightLeg",
            "RightFoot",
            "Spine",
            "Neck",
            "Head",
        ]);
        let parents = vec![
            None,
            Some(0),
            Some(1),
            Some(2),
            Some(3),
            Some(4),
            Some(5),
            Some(1),
            Some(7),
            Some(8),
            Some(1),
            Some(10),
            Some(11),
        ];
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let pose = vec![
            p(0.0, 0.0, 0.0),
            p(0.0, 90.0, 0.0),
            p(8.0, 88.0, 0.0),
            p(8.0, 48.0, 0.0),
            p(8.0, 8.0, 0.0),
            p(8.0, 3.0, 12.0),
            p(8.0, 3.0, 12.0),
            p(-8.0, 88.0, 0.0),
            p(-8.0, 48.0, 0.0),
            p(-8.0, 8.0, 0.0),
            p(0.0, 115.0, 0.0),
            p(0.0, 135.0, 0.0),
            p(0.0, 142.0, 0.0),
        ];
        (names, parents, pose)
    }

    #[test]
    fn the_default_body_skips_the_root_and_coincident_end_sites() {
        let (names, parents, pose) = little_body();
        let shape = BodyShape::standard(&names, &parents, &pose).unwrap();
        assert!((shape.stature_cm - 80.0 / LEG_FRACTION).abs() < 1e-9);
        assert_eq!(shape.sphere_at(0), None, "the floor root");
        assert_eq!(shape.sphere_at(6), None, "the end site on the toes");
        assert_eq!(shape.spheres[shape.sphere_at(1).unwrap()].part, Part::Pelvis);
        assert_eq!(shape.spheres[shape.sphere_at(10).unwrap()].part, Part::Trunk);
        let skull = shape.spheres.iter().find(|s| s.part == Part::Skull).unwrap();
        let posed = shape.pose(&pose, DVec3::new(5.0, 0.0, 0.0)).unwrap();
        let at = posed.spheres[shape.spheres.iter().position(|s| s == skull).unwrap()].centre_cm;
        // Along the neck, above the head's joint, shifted.
        assert!((at.x - 5.0).abs() < 1e-9 && at.y > 142.0 + 10.0, "{at}");
        // Every sphere but the first is linked to one before it: one tree.
        assert_eq!(shape.links.len(), shape.spheres.len() - 1);
        assert!(shape.links.iter().all(|&(a, b)| a < b && b < shape.spheres.len()));
        assert!(shape.pose(&pose[1..], DVec3::ZERO).is_err());
        // Radii are the caller's to change.
        let mut thin = shape.clone();
        assert!(thin.set_radius_cm(3, 2.5) && !thin.set_radius_cm(0, 2.5));
        assert_eq!(thin.spheres[thin.sphere_at(3).unwrap()].radius_cm, 2.5);
        thin.scale_part(Part::Trunk, 0.5);
        let trunk = thin.sphere_at(10).unwrap();
        assert_eq!(thin.spheres[trunk].radius_cm, 0.5 * shape.spheres[trunk].radius_cm);
    }

    #[test]
    fn the_mesh_has_outward_normals_on_its_surface() {
        let (names, parents, pose) = little_body();
        let posed = BodyShape::standard(&names, &parents, &pose).unwrap().pose(&pose, DVec3::ZERO).unwrap();
        let mesh = posed.mesh(12);
        assert_eq!(mesh.positions_cm.len(), mesh.normals.len());
        assert!(
            mesh.indices.len().is_multiple_of(3)
                && mesh.indices.iter().all(|&i| (i as usize) < mesh.positions_cm.len())
        );
        for (p, n) in mesh.positions_cm.iter().zip(&mesh.normals) {
            assert!((n.length() - 1.0).abs() < 1e-5);
            // On the surface of some piece (a sphere, or the hull of a linked
            // pair), and a step along the normal leaves that piece.
            let (p, n) = (p.as_dvec3(), n.as_dvec3());
            let gaps = |q: DVec3| -> Vec<f64> {
                posed
                    .spheres
                    .iter()
                    .map(|s| q.distance(s.centre_cm) - s.radius_cm)
                    .chain(
                        posed.cones.iter().map(|&(a, b)| swept_gap(q, &posed.spheres[a], &posed.spheres[b])),
                    )
                    .collect()
            };
            let on = gaps(p);
            let out = gaps(p + n * 0.1);
            let piece = (0..on.len()).min_by(|&a, &b| on[a].abs().total_cmp(&on[b].abs())).unwrap();
            assert!(on[piece].abs() < 1e-3, "vertex {p} is {} cm off the surface", on[piece]);
            assert!(out[piece] > 0.05, "the normal {n} at {p} points inwards");
        }
    }

    /// How far `p` lies outside the union of balls centred on the segment
    /// with linearly varying radius (negative inside): the least of a convex
    /// function of the place along the segment, by golden-section search.
    fn swept_gap(p: DVec3, a: &Sphere, b: &Sphere) -> f64 {
        let gap = |t: f64| {
            p.distance(a.centre_cm.lerp(b.centre_cm, t)) - (a.radius_cm + (b.radius_cm - a.radius_cm) * t)
        };
        let ratio = 0.5 * (5f64.sqrt() - 1.0);
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..80 {
            let (m1, m2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
            if gap(m1) < gap(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        gap(0.5 * (lo + hi))
    }
}
