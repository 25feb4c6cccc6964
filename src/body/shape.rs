//! The body's surface, from the skeleton: a sphere on each joint and a cone
//! tangent to the two spheres of each bone, so the radius runs linearly
//! along the bone (a sphere-swept cone, the convex hull of its two spheres).
//! This is the surface the paper's SQM mesh (Bærentzen et al. 2012)
//! approximates; the camera tracker renders its silhouette, the app draws
//! its [`Mesh`].
//!
//! The default radii are fractions of the body's stature, which is
//! estimated from the legs' bone lengths, and each joint's part of the body
//! (hips, spine, head, upper arm, …) is recognised from its name and its
//! place in the tree, not from one rig's exact names.
//!
//! **Sources.** Segment lengths as fractions of stature `H` are Drillis &
//! Contini's (R. Drillis, R. Contini, *Body segment parameters*, Tech. Rep.
//! 1166-03, New York University, 1966; as drawn in D. A. Winter,
//! *Biomechanics and Motor Control of Human Movement*, 4th ed., Fig. 4.1):
//! thigh 0.245 H, shank 0.246 H, hand 0.108 H, foot 0.152 H, head and neck
//! from the shoulders 0.182 H. Girths, breadths and depths are the means of
//! the 2012 US Army survey, ANSUR II (C. C. Gordon et al., *2012
//! Anthropometric Survey of U.S. Army Personnel: Methods and Summary
//! Statistics*, NATICK/TR-15/007, 2014), men's and women's averaged and
//! divided by their mean stature (1.69 m), rounded to a few per mille: a
//! limb's radius is its girth over 2π (a limb's section is nearly round), the
//! trunk's is the mean of its half-breadth and half-depth (a circle between
//! the two widths the camera sees, front-on and side-on).

use glam::{DVec3, Vec3};

use crate::body::feet::{above_hips, detect_feet, hips_joint};
use crate::error::Error;

/// What a sphere of the body stands for: its default radius and where its
/// centre sits follow from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Part {
    /// The hips joint: the pelvis.
    Pelvis,
    /// A joint of the spine between the hips and the neck.
    Trunk,
    Neck,
    /// The head's joint at the top of the neck.
    HeadJoint,
    /// The skull, beyond the head's joint.
    Skull,
    /// The joint at the inner end of the collar bone.
    Clavicle,
    /// The shoulder joint, with the deltoid around it.
    Shoulder,
    Elbow,
    Wrist,
    /// The middle of the hand, beyond the wrist.
    Palm,
    /// A finger joint.
    Finger,
    /// The end of the fingers.
    Fingertip,
    /// The hip joint, the thigh's top.
    Hip,
    Knee,
    Ankle,
    /// The ball of the foot (the toes' joint).
    Toes,
    /// The tip of the foot.
    ToeTip,
    /// A joint of no part we recognise: a small sphere.
    Other,
}

/// Default radius of each part, as a fraction of stature (sources in the
/// module's documentation).
fn radius_fraction(part: Part, trunk_t: f64) -> f64 {
    match part {
        // Hip breadth 0.204 H, buttock depth 0.145 H.
        Part::Pelvis => 0.087,
        Part::Trunk => trunk_fraction(trunk_t),
        // Neck circumference at its base 0.24 H (above it 0.22 H).
        Part::Neck => 0.038,
        Part::HeadJoint => 0.034,
        // Head breadth 0.091 H, head length 0.117 H: the mean of the halves.
        Part::Skull => 0.052,
        Part::Clavicle => 0.035,
        // Shoulder joints sit 0.10 H off the midline, bideltoid breadth is
        // 0.28 H: the deltoid reaches 0.04 H beyond the joint.
        Part::Shoulder => 0.040,
        // Forearm circumference 0.165 H near the elbow.
        Part::Elbow => 0.026,
        // Wrist circumference 0.098 H.
        Part::Wrist => 0.016,
        // Hand breadth 0.049 H, thickness about 0.017 H.
        Part::Palm => 0.021,
        Part::Finger => 0.010,
        Part::Fingertip => 0.010,
        // Thigh circumference 0.35 H, just below the hip joint.
        Part::Hip => 0.055,
        // Knee circumference 0.22 H (the calf, 0.225 H, is just below).
        Part::Knee => 0.035,
        // Ankle circumference 0.13 H; the heel and malleoli add to it.
        Part::Ankle => 0.024,
        // Foot breadth 0.06 H at the ball, its height there about 0.03 H.
        Part::Toes => 0.021,
        Part::ToeTip => 0.012,
        Part::Other => 0.015,
    }
}

/// The trunk's radius (fraction of stature) at `t` of the way from the hips
/// joint (0) to the neck (1): pelvis, waist (breadth 0.18 H, depth
/// 0.135 H), chest (breadth 0.19 H, depth 0.145 H), linear between.
fn trunk_fraction(t: f64) -> f64 {
    const PROFILE: [(f64, f64); 3] = [(0.0, 0.087), (0.4, 0.079), (0.75, 0.084)];
    let t = t.clamp(0.0, 1.0);
    let mut previous = PROFILE[0];
    for point in PROFILE {
        if t <= point.0 {
            let span = point.0 - previous.0;
            return if span > 0.0 {
                previous.1 + (point.1 - previous.1) * (t - previous.0) / span
            } else {
                point.1
            };
        }
        previous = point;
    }
    previous.1
}

/// Thigh plus shank, as a fraction of stature (Drillis & Contini).
const LEG_FRACTION: f64 = 0.245 + 0.246;
/// Joints closer than this to their parent (fraction of stature) get no
/// sphere of their own: Bandai's end sites sit exactly on their joints.
const COINCIDENT_FRACTION: f64 = 0.01;
/// Where the top of the head lies beyond the head's joint when the skeleton
/// has no head end site to say so (fraction of stature): from the top of the
/// neck (Bandai's `Head`, at the skull's base, a little above the chin) to
/// the vertex; the head is 0.13 H from chin to vertex.
const HEAD_JOINT_TO_VERTEX: f64 = 0.125;
/// A child this far from a limb's last joint (fraction of stature) already
/// gives the hand, foot or head its extent; a shorter one (or none) does not.
const EXTENT_CHILD_FRACTION: f64 = 0.03;
/// Beyond the wrist along the forearm: the palm's centre and the fingertips'
/// (the hand is 0.108 H long), as fractions of stature.
const WRIST_TO_PALM: f64 = 0.04;
const WRIST_TO_FINGERTIP: f64 = 0.085;
/// Beyond the ball of the foot along the foot: the toes' tip.
const TOES_TO_TIP: f64 = 0.035;

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

/// A triangle mesh for display, in world cm: a normal per vertex, three
/// indices per triangle, counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions_cm: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
}

/// The lower-cased letters and digits of a joint's name after any namespace
/// (`mixamorig:LeftArm` → `leftarm`).
fn name_key(name: &str) -> String {
    let base = name.rsplit([':', '|']).next().unwrap_or(name);
    base.chars().filter(char::is_ascii_alphanumeric).map(|c| c.to_ascii_lowercase()).collect()
}

/// The part a joint's name says, or `None`. Words are tried in an order that
/// keeps them apart: `forearm` before `arm`, `upleg` before `leg`, finger
/// names before `hand` (`LeftHandIndex1`).
fn part_of_name(name: &str) -> Option<Part> {
    const WORDS: [(&[&str], Part); 12] = [
        (&["thumb", "index", "middle", "ring", "pinky", "little", "finger"], Part::Finger),
        (&["toe"], Part::Toes),
        (&["foot", "ankle"], Part::Ankle),
        (&["forearm", "lowerarm", "elbow"], Part::Elbow),
        (&["hand", "wrist", "palm"], Part::Wrist),
        (&["arm", "humerus"], Part::Shoulder),
        (&["clavicle", "collar", "shoulder", "scapula"], Part::Clavicle),
        (&["thigh", "upleg", "upperleg", "hip"], Part::Hip),
        (&["shin", "calf", "lowerleg", "knee", "leg"], Part::Knee),
        (&["head"], Part::HeadJoint),
        (&["neck"], Part::Neck),
        (&["spine", "chest", "abdomen", "torso", "back", "waist", "thorax", "belly"], Part::Trunk),
    ];
    let key = name_key(name);
    WORDS.iter().find(|(words, _)| words.iter().any(|w| key.contains(w))).map(|(_, part)| *part)
}

/// The body's stature (cm) estimated from its bones: thigh plus shank over
/// their share of stature, averaged over both legs; without recognisable
/// legs, the largest distance between two joints of the pose (a standing
/// body's height, a T-pose's span: both near the stature). `pose_cm` is any
/// frame (bone lengths do not change).
pub fn estimate_stature_cm(joint_names: &[String], parents: &[Option<usize>], pose_cm: &[DVec3]) -> f64 {
    let bone = |j: usize| -> Option<f64> {
        let p = parents.get(j).copied().flatten()?;
        Some(pose_cm.get(j)?.distance(*pose_cm.get(p)?))
    };
    let leg = |ankle: usize| -> Option<f64> {
        let knee = parents.get(ankle).copied().flatten()?;
        let length = bone(ankle)? + bone(knee)?;
        (length > 0.0).then_some(length)
    };
    if let Some(feet) = detect_feet(joint_names)
        && let (Some(left), Some(right)) = (leg(feet.left), leg(feet.right))
    {
        return 0.5 * (left + right) / LEG_FRACTION;
    }
    let mut widest: f64 = 0.0;
    for (i, a) in pose_cm.iter().enumerate() {
        for b in &pose_cm[i + 1..] {
            widest = widest.max(a.distance(*b));
        }
    }
    widest
}

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

/// The default body of one skeleton, sphere by sphere.
struct Builder<'a> {
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
    fn new(names: &[String], parents: &'a [Option<usize>], pose_cm: &'a [DVec3], stature_cm: f64) -> Self {
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

    fn build(mut self) -> BodyShape {
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

impl PosedBody {
    /// The same body moved by `shift_cm`.
    pub fn translated(&self, shift_cm: DVec3) -> PosedBody {
        let spheres =
            self.spheres.iter().map(|s| Sphere { centre_cm: s.centre_cm + shift_cm, ..*s }).collect();
        PosedBody { spheres, cones: self.cones.clone() }
    }

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

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn parts_are_told_by_role_across_rigs() {
        let cases = [
            ("UpperArm_L", Part::Shoulder),
            ("LeftArm", Part::Shoulder),
            ("mixamorig:LeftForeArm", Part::Elbow),
            ("LowerArm_R", Part::Elbow),
            ("Shoulder_L", Part::Clavicle),
            ("LeftShoulder", Part::Clavicle),
            ("UpperLeg_L", Part::Hip),
            ("LeftThigh", Part::Hip),
            ("RightUpLeg", Part::Hip),
            ("LowerLeg_L", Part::Knee),
            ("LeftLeg", Part::Knee),
            ("Foot_L", Part::Ankle),
            ("Toes_R", Part::Toes),
            ("LeftHandIndex1", Part::Finger),
            ("Hand_L", Part::Wrist),
            ("SpineMid", Part::Trunk),
            ("Chest", Part::Trunk),
            ("Head", Part::HeadJoint),
        ];
        for (name, part) in cases {
            assert_eq!(part_of_name(name), Some(part), "{name}");
        }
        assert_eq!(part_of_name("EndSite6"), None);
    }

    #[test]
    fn trunk_profile_is_continuous() {
        assert_eq!(trunk_fraction(0.0), 0.087);
        assert!((trunk_fraction(0.4) - 0.079).abs() < 1e-12);
        assert_eq!(trunk_fraction(1.0), 0.084);
        assert!(trunk_fraction(0.2) < 0.087 && trunk_fraction(0.2) > 0.079);
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
