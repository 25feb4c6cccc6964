//! The body's surface as triangles for display: each sphere of a
//! [`PosedBody`] a latitude–longitude sphere, each cone a band between its
//! two circles of contact. The app's 3D view draws it.

use glam::{DVec3, Vec3};

use crate::body::shape::{PosedBody, Sphere};

/// A triangle mesh for display, in world cm: a normal per vertex, three
/// indices per triangle, counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions_cm: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
}

impl PosedBody {
    /// A plain tessellation for display: each sphere a latitude–longitude
    /// sphere of `segments` meridians (at least 3) and half as many
    /// parallels, each cone a band of `segments` quads between its two
    /// tangent circles. The pieces overlap; a depth buffer draws their union.
    pub fn mesh(&self, segments: u32) -> Mesh {
        let segments = segments.max(3);
        let around: Vec<(f64, f64)> = (0..segments)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / segments as f64;
                (libm::cos(a), libm::sin(a))
            })
            .collect();
        let parallels = (segments / 2).max(2);
        let rings: Vec<(f64, f64)> = (0..=parallels)
            .map(|i| {
                let a = std::f64::consts::PI * i as f64 / parallels as f64;
                (libm::cos(a), libm::sin(a))
            })
            .collect();
        let mut mesh = Mesh::default();
        for s in &self.spheres {
            let first = mesh.positions_cm.len() as u32;
            for &(cos_polar, sin_polar) in &rings {
                for &(c, si) in &around {
                    let normal = DVec3::new(sin_polar * c, cos_polar, sin_polar * si);
                    mesh.push_vertex(s.centre_cm + normal * s.radius_cm, normal);
                }
            }
            for ring in 0..parallels {
                let row = first + ring * segments;
                mesh.push_band(row, row + segments, segments);
            }
        }
        for &(a, b) in &self.cones {
            let (Some(a), Some(b)) = (self.spheres.get(a), self.spheres.get(b)) else { continue };
            let Some(cone) = TangentCone::between(a, b) else { continue };
            let first = mesh.positions_cm.len() as u32;
            let (u, v) = cone.axis.any_orthonormal_pair();
            for (centre, radius) in [(cone.centre_a, cone.radius_a), (cone.centre_b, cone.radius_b)] {
                for &(c, s) in &around {
                    let radial = u * c + v * s;
                    let normal = radial * cone.cos_slope + cone.axis * cone.sin_slope;
                    mesh.push_vertex(centre + radial * radius, normal);
                }
            }
            mesh.push_band(first, first + segments, segments);
        }
        mesh
    }
}

/// The lateral surface of the cone tangent to two spheres: its two circles
/// of contact, and the slope of its normal towards the smaller sphere.
struct TangentCone {
    axis: DVec3,
    centre_a: DVec3,
    radius_a: f64,
    centre_b: DVec3,
    radius_b: f64,
    /// The normal is `radial · cos_slope + axis · sin_slope`.
    cos_slope: f64,
    sin_slope: f64,
}

impl TangentCone {
    /// `None` when one sphere holds the other (no cone shows).
    fn between(a: &Sphere, b: &Sphere) -> Option<TangentCone> {
        let along = b.centre_cm - a.centre_cm;
        let d = along.length();
        let gap = (a.radius_cm - b.radius_cm).abs();
        if d.is_nan() || gap.is_nan() || d <= gap {
            return None;
        }
        let axis = along / d;
        let sin_slope = (a.radius_cm - b.radius_cm) / d;
        let cos_slope = (1.0 - sin_slope * sin_slope).sqrt();
        Some(TangentCone {
            axis,
            centre_a: a.centre_cm + axis * (a.radius_cm * sin_slope),
            radius_a: a.radius_cm * cos_slope,
            centre_b: b.centre_cm + axis * (b.radius_cm * sin_slope),
            radius_b: b.radius_cm * cos_slope,
            cos_slope,
            sin_slope,
        })
    }
}

impl Mesh {
    fn push_vertex(&mut self, position_cm: DVec3, normal: DVec3) {
        self.positions_cm.push(position_cm.as_vec3());
        self.normals.push(normal.as_vec3());
    }

    /// Two triangles per quad between ring `a` and ring `b` of `count`
    /// vertices each, closing the band.
    fn push_band(&mut self, a: u32, b: u32, count: u32) {
        for i in 0..count {
            let j = (i + 1) % count;
            self.indices.extend_from_slice(&[a + i, b + i, b + j, a + i, b + j, a + j]);
        }
    }
}
