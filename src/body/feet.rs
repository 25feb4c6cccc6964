//! Which joints are the feet. Translation methods pin a foot to the floor, so
//! they need to know the left and right foot joints; recordings name them in
//! many ways, so we recognise the common spellings and let the user override.

use std::ops::{Index, IndexMut};

/// Left or right: the one way the crate names a side of the body (a foot,
/// or in the demo's rig the limbs on that side).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Foot {
    Left,
    Right,
}

impl Foot {
    /// Both feet, left first: the order of every per-foot listing.
    pub const BOTH: [Foot; 2] = [Foot::Left, Foot::Right];

    /// The other foot.
    pub fn other(self) -> Foot {
        match self {
            Foot::Left => Foot::Right,
            Foot::Right => Foot::Left,
        }
    }

    /// `left` or `right`, as the user reads and types it.
    pub fn name(self) -> &'static str {
        match self {
            Foot::Left => "left",
            Foot::Right => "right",
        }
    }
}

/// One value per foot, indexed by [`Foot`]: `feet[Foot::Left]`, or by field.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct PerFoot<T> {
    pub left: T,
    pub right: T,
}

impl<T> PerFoot<T> {
    pub fn new(left: T, right: T) -> PerFoot<T> {
        PerFoot { left, right }
    }

    /// `value(foot)` for each foot.
    pub fn from_fn(mut value: impl FnMut(Foot) -> T) -> PerFoot<T> {
        PerFoot { left: value(Foot::Left), right: value(Foot::Right) }
    }

    pub fn map<U>(self, mut f: impl FnMut(T) -> U) -> PerFoot<U> {
        PerFoot { left: f(self.left), right: f(self.right) }
    }

    pub fn as_ref(&self) -> PerFoot<&T> {
        PerFoot { left: &self.left, right: &self.right }
    }

    /// `(foot, value)`, left first.
    pub fn iter(&self) -> impl Iterator<Item = (Foot, &T)> {
        [(Foot::Left, &self.left), (Foot::Right, &self.right)].into_iter()
    }
}

impl<T> Index<Foot> for PerFoot<T> {
    type Output = T;
    fn index(&self, foot: Foot) -> &T {
        match foot {
            Foot::Left => &self.left,
            Foot::Right => &self.right,
        }
    }
}

impl<T> IndexMut<Foot> for PerFoot<T> {
    fn index_mut(&mut self, foot: Foot) -> &mut T {
        match foot {
            Foot::Left => &mut self.left,
            Foot::Right => &mut self.right,
        }
    }
}

/// The joint indices of the two feet (the ankle-level joint, e.g. `LeftFoot`).
pub type FootJoints = PerFoot<usize>;

/// Lower-cased names with separators removed, so `Foot_L`, `foot.l`,
/// `mixamorig:LeftFoot` and `LeftFoot` compare alike.
fn normalise(name: &str) -> String {
    let base = name.rsplit([':', '|']).next().unwrap_or(name);
    base.chars().filter(|c| c.is_ascii_alphanumeric()).map(|c| c.to_ascii_lowercase()).collect()
}

/// Spellings of the foot joints, normalised, best first. Ankles come after
/// feet: when both exist, the `Foot` joint is the one exporters place at the
/// ankle and the `Ankle` one may be a helper bone.
const FOOT_NAME_PAIRS: [(&str, &str); 6] = [
    ("leftfoot", "rightfoot"),
    ("footl", "footr"),
    ("lfoot", "rfoot"),
    ("leftankle", "rightankle"),
    ("anklel", "ankler"),
    ("lankle", "rankle"),
];

/// Finds the feet among the joint names, or `None` when there is no
/// recognisable pair.
pub fn detect_feet(joint_names: &[String]) -> Option<FootJoints> {
    let normalised: Vec<String> = joint_names.iter().map(|n| normalise(n)).collect();
    let find = |wanted: &str| normalised.iter().position(|n| n == wanted);
    for (left_name, right_name) in FOOT_NAME_PAIRS {
        if let (Some(left), Some(right)) = (find(left_name), find(right_name)) {
            return Some(FootJoints { left, right });
        }
    }
    None
}

/// The feet named by the user, or detected when `left`/`right` are `None`.
pub fn resolve_feet(
    joint_names: &[String],
    left: Option<&str>,
    right: Option<&str>,
) -> Result<FootJoints, String> {
    let detected = detect_feet(joint_names);
    let pick = |name: Option<&str>, side: &str, fallback: Option<usize>| match name {
        Some(n) => joint_names
            .iter()
            .position(|j| j == n)
            .ok_or_else(|| format!("no joint named `{n}` for the {side} foot")),
        None => fallback.ok_or_else(|| {
            format!(
                "cannot tell which joint is the {side} foot; name it with --{side}-foot (joints: {})",
                joint_names.join(", ")
            )
        }),
    };
    Ok(FootJoints {
        left: pick(left, "left", detected.map(|f| f.left))?,
        right: pick(right, "right", detected.map(|f| f.right))?,
    })
}

/// The hips: the joint where the two legs meet, i.e. the nearest common
/// ancestor of the two feet in `parents`. Some files put a static root above
/// the hips (optical datasets often do) or add a pelvis helper, so "joint 0"
/// is not reliably the body's centre; the legs' meeting point is. Joint 0
/// when the feet share no ancestor.
pub fn hips_joint(parents: &[Option<usize>], feet: FootJoints) -> usize {
    let ancestors = |mut joint: usize| {
        let mut chain = vec![joint];
        while let Some(parent) = parents.get(joint).copied().flatten() {
            if chain.contains(&parent) {
                break; // a cycle would be a malformed hierarchy; stop rather than loop
            }
            chain.push(parent);
            joint = parent;
        }
        chain
    };
    let left = ancestors(feet.left);
    ancestors(feet.right).into_iter().find(|j| left.contains(j) && *j != feet.left).unwrap_or(0)
}

/// The joints above `hips`, nearest first: not the body, but what exporters
/// put above it (optical datasets' static `joint_Root` on the floor under the
/// start, a world or reference node). Neither drawn nor weighed.
pub fn above_hips(parents: &[Option<usize>], hips: usize) -> Vec<usize> {
    let mut above = Vec::new();
    let mut joint = parents.get(hips).copied().flatten();
    while let Some(j) = joint.filter(|&j| j != hips && !above.contains(&j)) {
        above.push(j);
        joint = parents.get(j).copied().flatten();
    }
    above
}

/// The foot joint and every joint below it (toes, end sites): the points of
/// the foot that can touch the floor.
pub fn foot_points(parents: &[Option<usize>], foot_joint: usize) -> Vec<usize> {
    let mut points = vec![foot_joint];
    // Parents come before children in BVH order, but a table's inferred tree
    // need not be ordered, so grow the set until it stops changing.
    loop {
        let before = points.len();
        for (joint, parent) in parents.iter().enumerate() {
            if let Some(p) = parent
                && points.contains(p)
                && !points.contains(&joint)
            {
                points.push(joint);
            }
        }
        if points.len() == before {
            return points;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn skeleton_named(names: &[&str]) -> Vec<String> {
        names.iter().map(|n| n.to_string()).collect()
    }

    #[test]
    fn detects_common_spellings() {
        for (l, r) in [
            ("LeftFoot", "RightFoot"),
            ("Foot_L", "Foot_R"),
            ("l_foot", "r_foot"),
            ("LeftAnkle", "RightAnkle"),
            ("mixamorig:LeftFoot", "mixamorig:RightFoot"),
            ("foot.l", "foot.r"),
        ] {
            let s = skeleton_named(&["Hips", l, r]);
            assert_eq!(detect_feet(&s), Some(FootJoints { left: 1, right: 2 }), "{l} / {r}");
        }
    }

    #[test]
    fn prefers_foot_over_toe() {
        let s = skeleton_named(&["Hips", "LeftToeBase", "RightToeBase", "LeftFoot", "RightFoot"]);
        assert_eq!(detect_feet(&s), Some(FootJoints { left: 3, right: 4 }));
    }

    #[test]
    fn override_and_missing() {
        let s = skeleton_named(&["Hips", "A", "B"]);
        assert!(detect_feet(&s).is_none());
        assert_eq!(resolve_feet(&s, Some("A"), Some("B")), Ok(FootJoints { left: 1, right: 2 }));
        assert!(resolve_feet(&s, None, None).unwrap_err().contains("--left-foot"));
        assert!(resolve_feet(&s, Some("Z"), Some("B")).unwrap_err().contains("`Z`"));
    }

    #[test]
    fn hips_are_where_the_legs_meet() {
        // 0 static root, 1 hips, 2 spine, 3/4 left thigh/foot, 5/6 right thigh/foot, 7 left toe
        let parents = [None, Some(0), Some(1), Some(1), Some(3), Some(1), Some(5), Some(4)];
        assert_eq!(hips_joint(&parents, FootJoints { left: 4, right: 6 }), 1);
        assert_eq!(above_hips(&parents, 1), vec![0]);
        assert_eq!(above_hips(&parents, 0), Vec::<usize>::new());
        // A cycle in a malformed hierarchy ends the walk.
        assert_eq!(above_hips(&[Some(1), Some(2), Some(1)], 0), vec![1, 2]);
        assert_eq!(foot_points(&parents, 4), vec![4, 7]);
        assert_eq!(hips_joint(&[None, None], FootJoints { left: 0, right: 1 }), 0);
    }
}
