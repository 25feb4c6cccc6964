//! The default body of a skeleton, sphere by sphere: each joint's part
//! recognised (`proportions`), the trunk's joints placed between the hips
//! and the neck, end sites on their joints left out, and the spheres the
//! skeleton has no joint for (the skull, the palm, the fingertips, the toes'
//! tip) placed beyond their joints: [`BodyShape::standard`] and
//! [`BodyShape::with_stature`], here beside their builder so that `shape`
//! (the body's types and posing) needs nothing of this file.

use glam::DVec3;

use crate::body::feet::{above_hips, detect_feet, hips_joint};
use crate::body::proportions::estimate_stature_cm;
use crate::body::proportions::{
    COINCIDENT_FRACTION, EXTENT_CHILD_FRACTION, HEAD_JOINT_TO_VERTEX, TOES_TO_TIP, WRIST_TO_FINGERTIP,
    WRIST_TO_PALM, name_key, part_of_name, radius_fraction,
};
use crate::body::shape::{Anchor, BodyShape, Part, ShapeSphere};
use crate::error::Error;

impl BodyShape {
    /// The default body of a skeleton: radii from anthropometric proportions
    /// scaled to the stature [`estimate_stature_cm`] finds. `pose_cm` is any
    /// frame of its global joint positions (bone lengths and, where the
    /// skeleton has no joint for the head's top or the hand's end, bone
    /// directions are read from it).
    pub fn standard(
        joint_names: &[String],
        parents: &[Option<usize>],
        pose_cm: &[DVec3],
    ) -> Result<BodyShape, Error> {
        let stature_cm = estimate_stature_cm(joint_names, parents, pose_cm);
        BodyShape::with_stature(joint_names, parents, pose_cm, stature_cm)
    }

    /// As [`BodyShape::standard`], for a body of a known stature (cm).
    pub fn with_stature(
        joint_names: &[String],
        parents: &[Option<usize>],
        pose_cm: &[DVec3],
        stature_cm: f64,
    ) -> Result<BodyShape, Error> {
        let n = joint_names.len();
        if parents.len() != n || pose_cm.len() != n {
            return Err(Error::whole(
                "<body shape>",
                format!(
                    "{n} joint names, {} parents and {} positions: they must be as many",
                    parents.len(),
                    pose_cm.len()
                ),
            ));
        }
        if !(stature_cm.is_finite() && stature_cm > 0.0) {
            return Err(Error::whole(
                "<body shape>",
                format!("stature {stature_cm} cm: expected a positive length"),
            ));
        }
        if let Some(bad) = parents.iter().enumerate().find(|(j, p)| p.is_some_and(|p| p >= n || p == *j)) {
            return Err(Error::whole(
                "<body shape>",
                format!("joint {} has parent {:?}: not a joint", bad.0, bad.1),
            ));
        }
        Ok(Builder::new(joint_names, parents, pose_cm, stature_cm).build())
    }
}

/// The default body of one skeleton, sphere by sphere.
pub(super) struct Builder<'a> {
    parents: &'a [Option<usize>],
    pose_cm: &'a [DVec3],
    stature_cm: f64,
    parts: Vec<Option<Part>>,
    children: Vec<Vec<usize>>,
    /// Where each joint of the trunk lies from the hips (0) to the neck (1).
    trunk_t: Vec<f64>,
    spheres: Vec<ShapeSphere>,
    links: Vec<(usize, usize)>,
    /// The sphere that stands for each joint: its own, or its parent's when
    /// the two coincide.
    sphere_of: Vec<Option<usize>>,
}

impl<'a> Builder<'a> {
    pub(super) fn new(
        names: &[String],
        parents: &'a [Option<usize>],
        pose_cm: &'a [DVec3],
        stature_cm: f64,
    ) -> Self {
        let n = names.len();
        let mut children = vec![Vec::new(); n];
        for (j, p) in parents.iter().enumerate() {
            if let Some(p) = *p {
                children[p].push(j);
            }
        }
        let hips = match detect_feet(names) {
            Some(feet) => Some(hips_joint(parents, feet)),
            None => names.iter().position(|n| matches!(name_key(n).as_str(), "hips" | "pelvis" | "hip")),
        };
        let mut parts: Vec<Option<Part>> =
            names.iter().map(|n| Some(part_of_name(n).unwrap_or(Part::Other))).collect();
        let mut trunk_t = vec![0.0; n];
        if let Some(hips) = hips {
            // Above the hips is no body: a static floor root, a world node.
            for j in above_hips(parents, hips) {
                parts[j] = None;
            }
            parts[hips] = Some(Part::Pelvis);
            // Every joint on the way from the hips to the neck is trunk,
            // whatever its name, its radius by how far along it lies.
            let neck =
                (0..n).find(|&j| parts[j] == Some(Part::Neck) && ancestors(parents, j).contains(&hips));
            if let Some(neck) = neck {
                let chain: Vec<usize> =
                    ancestors(parents, neck).into_iter().take_while(|&j| j != hips).collect();
                let length = |j: usize| parents[j].map_or(0.0, |p| pose_cm[j].distance(pose_cm[p]));
                let total: f64 = chain.iter().map(|&j| length(j)).sum();
                let mut from_neck = 0.0;
                for &j in &chain {
                    if j != neck {
                        parts[j] = Some(Part::Trunk);
                        trunk_t[j] = if total > 0.0 { 1.0 - from_neck / total } else { 0.5 };
                    }
                    from_neck += length(j);
                }
            }
        }
        // Unnamed leaves (end sites) are the ends of their parents' parts.
        for j in 0..n {
            if children[j].is_empty()
                && parts[j] == Some(Part::Other)
                && let Some(p) = parents[j]
            {
                parts[j] = match parts[p] {
                    Some(Part::HeadJoint | Part::Skull) => Some(Part::Skull),
                    Some(Part::Wrist | Part::Finger) => Some(Part::Fingertip),
                    Some(Part::Ankle | Part::Toes) => Some(Part::ToeTip),
                    other => other.map(|_| Part::Other),
                };
            }
        }
        // A head part under a head part is the head's top (`HeadTop_End`),
        // a toe under a toe the foot's tip.
        for j in 0..n {
            if let Some(p) = parents[j] {
                match (parts[p], parts[j]) {
                    (Some(Part::HeadJoint | Part::Skull), Some(Part::HeadJoint)) => {
                        parts[j] = Some(Part::Skull)
                    }
                    (Some(Part::Toes), Some(Part::Toes)) if children[j].is_empty() => {
                        parts[j] = Some(Part::ToeTip)
                    }
                    _ => {}
                }
            }
        }
        Builder {
            parents,
            pose_cm,
            stature_cm,
            parts,
            children,
            trunk_t,
            spheres: Vec::new(),
            links: Vec::new(),
            sphere_of: vec![None; n],
        }
    }

    fn radius_cm(&self, part: Part, joint: usize) -> f64 {
        radius_fraction(part, self.trunk_t[joint]) * self.stature_cm
    }

    fn bone_cm(&self, joint: usize) -> f64 {
        self.parents[joint].map_or(f64::INFINITY, |p| self.pose_cm[joint].distance(self.pose_cm[p]))
    }

    fn push(&mut self, anchor: Anchor, part: Part, radius_cm: f64, link_to: Option<usize>) -> usize {
        self.spheres.push(ShapeSphere { anchor, radius_cm, part });
        let index = self.spheres.len() - 1;
        if let Some(other) = link_to {
            self.links.push((other, index));
        }
        index
    }

    /// The longest child bone of `joint` (cm), 0 with none.
    fn longest_child_cm(&self, joint: usize) -> f64 {
        self.children[joint].iter().map(|&c| self.bone_cm(c)).fold(0.0, f64::max)
    }

    pub(super) fn build(mut self) -> BodyShape {
        let h = self.stature_cm;
        // Parents come before children in a BVH, but an inferred tree need
        // not be ordered: visit the tree from its roots.
        let mut order: Vec<usize> = (0..self.parents.len()).filter(|&j| self.parents[j].is_none()).collect();
        let mut next = 0;
        while next < order.len() {
            let j = order[next];
            order.extend(self.children[j].iter().copied());
            next += 1;
        }
        for j in order {
            let Some(part) = self.parts[j] else { continue };
            let parent_sphere = self.parents[j].and_then(|p| self.sphere_of[p]);
            // A joint on top of its parent adds nothing (Bandai's end sites).
            if parent_sphere.is_some() && self.bone_cm(j) < COINCIDENT_FRACTION * h {
                self.sphere_of[j] = parent_sphere;
                continue;
            }
            // The head's top inside the skull: the skull already covers it.
            if part == Part::Skull && self.parts[self.parents[j].unwrap_or(j)] == Some(Part::HeadJoint) {
                self.sphere_of[j] = parent_sphere;
                continue;
            }
            let own = self.push(Anchor::Joint(j), part, self.radius_cm(part, j), parent_sphere);
            self.sphere_of[j] = Some(own);
            let from = self.parents[j].unwrap_or(j);
            let reaches = self.longest_child_cm(j) >= EXTENT_CHILD_FRACTION * h;
            match part {
                Part::HeadJoint => {
                    // The skull's centre one head radius below its top: the
                    // top is the head's end site when it has one, else
                    // estimated along the neck.
                    let skull_r = radius_fraction(Part::Skull, 0.0) * h;
                    let top = self.children[j]
                        .iter()
                        .map(|&c| (c, self.bone_cm(c)))
                        .filter(|&(_, l)| l >= 0.05 * h)
                        .max_by(|a, b| a.1.total_cmp(&b.1));
                    let anchor = match top {
                        Some((c, length)) => {
                            Anchor::Beyond { joint: c, from: j, distance_cm: -skull_r.min(length) }
                        }
                        None => Anchor::Beyond {
                            joint: j,
                            from,
                            distance_cm: (HEAD_JOINT_TO_VERTEX * h - skull_r).max(0.0),
                        },
                    };
                    self.push(anchor, Part::Skull, skull_r, Some(own));
                }
                Part::Wrist if !reaches => {
                    let palm = self.push(
                        Anchor::Beyond { joint: j, from, distance_cm: WRIST_TO_PALM * h },
                        Part::Palm,
                        radius_fraction(Part::Palm, 0.0) * h,
                        Some(own),
                    );
                    self.push(
                        Anchor::Beyond { joint: j, from, distance_cm: WRIST_TO_FINGERTIP * h },
                        Part::Fingertip,
                        radius_fraction(Part::Fingertip, 0.0) * h,
                        Some(palm),
                    );
                }
                Part::Toes if !reaches => {
                    self.push(
                        Anchor::Beyond { joint: j, from, distance_cm: TOES_TO_TIP * h },
                        Part::ToeTip,
                        radius_fraction(Part::ToeTip, 0.0) * h,
                        Some(own),
                    );
                }
                _ => {}
            }
        }
        BodyShape { spheres: self.spheres, links: self.links, stature_cm: h, joint_count: self.parents.len() }
    }
}

/// `joint` and its ancestors, nearest first (stops at a cycle).
fn ancestors(parents: &[Option<usize>], joint: usize) -> Vec<usize> {
    let mut chain = vec![joint];
    let mut at = joint;
    while let Some(p) = parents.get(at).copied().flatten() {
        if chain.contains(&p) {
            break;
        }
        chain.push(p);
        at = p;
    }
    chain
}
