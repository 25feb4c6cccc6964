//! The recording's data layout, after BVHView: a skeleton is a set of parallel
//! per-joint arrays indexed by joint number (parents always before children),
//! and the motion is one flat, frame-major array of channel values.

use glam::DVec3;

/// What one BVH channel drives. Rotations are in degrees, positions in the
/// file's unit (centimetres for every recording we know of).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Channel {
    Xposition,
    Yposition,
    Zposition,
    Xrotation,
    Yrotation,
    Zrotation,
}

impl Channel {
    /// The name as written in a BVH `CHANNELS` line.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }

    /// Parses a `CHANNELS` word; BVH writers differ in case, so it is ignored.
    pub fn parse(word: &str) -> Option<Channel> {
        const ALL: [Channel; 6] = [
            Channel::Xposition,
            Channel::Yposition,
            Channel::Zposition,
            Channel::Xrotation,
            Channel::Yrotation,
            Channel::Zrotation,
        ];
        ALL.into_iter().find(|c| c.name().eq_ignore_ascii_case(word))
    }

    /// The axis index (0 = X, 1 = Y, 2 = Z).
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }

    pub fn is_position(self) -> bool {
        matches!(self, Channel::Xposition | Channel::Yposition | Channel::Zposition)
    }
}

/// A joint hierarchy as parallel arrays. End sites are joints too (with no
/// channels and `is_end_site` set) so that forward kinematics, plots and the
/// RMoCap table all see the same list; they are named `EndSite<index>`, which
/// is RMoCap's convention and what `heian_shodan.csv` uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    pub names: Vec<String>,
    /// `parents[j] < j` for every joint but the root (`None`).
    pub parents: Vec<Option<usize>>,
    /// The OFFSET of each joint from its parent, in cm.
    pub offsets_cm: Vec<DVec3>,
    /// The channels of each joint, in file order (the order rotations compose).
    pub channels: Vec<Vec<Channel>>,
    /// Index of each joint's first channel within a frame's values.
    pub first_channel: Vec<usize>,
    pub is_end_site: Vec<bool>,
}

impl Skeleton {
    pub fn joint_count(&self) -> usize {
        self.names.len()
    }

    /// Total channels per frame.
    pub fn channel_count(&self) -> usize {
        self.channels.iter().map(Vec::len).sum()
    }

    /// The joint called `name` (exact match).
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// Appends a joint and returns its index.
    pub fn push_joint(
        &mut self,
        name: String,
        parent: Option<usize>,
        offset_cm: DVec3,
        channels: Vec<Channel>,
        is_end_site: bool,
    ) -> usize {
        let first = self.channel_count();
        self.names.push(name);
        self.parents.push(parent);
        self.offsets_cm.push(offset_cm);
        self.channels.push(channels);
        self.first_channel.push(first);
        self.is_end_site.push(is_end_site);
        self.names.len() - 1
    }

    /// Recomputes `first_channel` after channels were added or removed.
    pub fn renumber_channels(&mut self) {
        let mut next = 0;
        for (first, channels) in self.first_channel.iter_mut().zip(&self.channels) {
            *first = next;
            next += channels.len();
        }
    }
}

/// Channel values for every frame, frame-major: frame `f`'s values are
/// `values[f * channel_count .. (f + 1) * channel_count]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    pub channel_count: usize,
    pub frame_time_s: f64,
    pub values: Vec<f64>,
}

impl Motion {
    pub fn frame_count(&self) -> usize {
        self.values.len().checked_div(self.channel_count).unwrap_or(0)
    }

    pub fn frame(&self, f: usize) -> &[f64] {
        &self.values[f * self.channel_count..(f + 1) * self.channel_count]
    }

    pub fn frame_mut(&mut self, f: usize) -> &mut [f64] {
        &mut self.values[f * self.channel_count..(f + 1) * self.channel_count]
    }

    pub fn fps(&self) -> f64 {
        1.0 / self.frame_time_s
    }

    /// Sets every position channel of `joint` to its frame-0 value in every
    /// frame: the joint's own translation is removed, its rotations kept.
    pub fn hold_positions_at_first_frame(&mut self, skeleton: &Skeleton, joint: usize) {
        if self.frame_count() == 0 {
            return;
        }
        let first = skeleton.first_channel[joint];
        for (i, channel) in skeleton.channels[joint].iter().enumerate() {
            if channel.is_position() {
                let value = self.frame(0)[first + i];
                for values in self.values.chunks_mut(self.channel_count) {
                    values[first + i] = value;
                }
            }
        }
    }
}

/// Global joint positions for every frame, frame-major like [`Motion`]: the
/// common ground of a BVH (after forward kinematics) and an RMoCap table (which
/// stores them directly). Every translation method reads and writes this.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Poses {
    pub joint_count: usize,
    pub positions_cm: Vec<DVec3>,
}

/// Joint positions farther than this from the origin (cm) are no body on a
/// floor: 100 km, far beyond any capture volume, and far enough below
/// `f64`'s range that differences and sums of them stay finite.
pub const MAX_POSITION_CM: f64 = 1.0e7;

impl Poses {
    /// An error naming the first frame with a joint position that is not a
    /// finite number within [`MAX_POSITION_CM`] of the origin: the methods
    /// would turn it into NaN.
    pub fn check_positions(&self) -> Result<(), String> {
        let joints = self.joint_count.max(1);
        let usable = |p: &DVec3| p.is_finite() && p.abs().max_element() <= MAX_POSITION_CM;
        match self.positions_cm.iter().position(|p| !usable(p)) {
            Some(i) => Err(format!(
                "joint {} in frame {} is at {:?} cm: not a finite position within {} km of the origin",
                i % joints,
                i / joints,
                self.positions_cm[i],
                MAX_POSITION_CM / 1.0e5
            )),
            None => Ok(()),
        }
    }

    pub fn frame_count(&self) -> usize {
        self.positions_cm.len().checked_div(self.joint_count).unwrap_or(0)
    }

    pub fn frame(&self, f: usize) -> &[DVec3] {
        &self.positions_cm[f * self.joint_count..(f + 1) * self.joint_count]
    }

    /// The position of `joint` in frame `f`.
    pub fn at(&self, f: usize, joint: usize) -> DVec3 {
        self.positions_cm[f * self.joint_count + joint]
    }

    /// One joint's trajectory over all frames.
    pub fn trajectory(&self, joint: usize) -> Vec<DVec3> {
        (0..self.frame_count()).map(|f| self.at(f, joint)).collect()
    }

    /// Moves every joint of frame `f` by `shift_cm[f]`: how a translation
    /// method's result is applied to global positions.
    pub fn shifted(&self, shift_cm: &[DVec3]) -> Poses {
        let mut out = self.clone();
        for (f, frame) in out.positions_cm.chunks_mut(self.joint_count.max(1)).enumerate() {
            for p in frame {
                *p += shift_cm[f];
            }
        }
        out
    }
}

/// Bones for a recording that stores no hierarchy (an RMoCap table): the
/// tree of joint pairs whose distance stays most nearly constant over the
/// recording — bones are rigid, other pairs are not — grown from joint 0 (a
/// minimum spanning tree, Prim's algorithm, O(joints²·samples)).
pub fn infer_parents(poses: &Poses) -> Vec<Option<usize>> {
    let n = poses.joint_count;
    let frames = poses.frame_count();
    if n == 0 || frames == 0 {
        return vec![None; n];
    }
    // Up to 64 frames spread over the recording are plenty to tell rigid pairs.
    let step = (frames / 64).max(1);
    let sampled: Vec<usize> = (0..frames).step_by(step).collect();
    let cost = |a: usize, b: usize| -> f64 {
        let d: Vec<f64> = sampled.iter().map(|&f| poses.at(f, a).distance(poses.at(f, b))).collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / d.len() as f64;
        // Spread of the length, plus a little of the length itself so that of
        // two rigid candidates (a bone, or two joints of one segment) the
        // nearer one wins.
        var.sqrt() + 0.01 * mean
    };
    let mut parents = vec![None; n];
    let mut in_tree = vec![false; n];
    let mut best: Vec<(f64, usize)> = (0..n).map(|j| (cost(0, j), 0)).collect();
    in_tree[0] = true;
    for _ in 1..n {
        let Some(next) = (0..n).filter(|&j| !in_tree[j]).min_by(|&a, &b| best[a].0.total_cmp(&best[b].0))
        else {
            break;
        };
        in_tree[next] = true;
        parents[next] = Some(best[next].1);
        for j in 0..n {
            if !in_tree[j] {
                let c = cost(next, j);
                if c < best[j].0 {
                    best[j] = (c, next);
                }
            }
        }
    }
    parents
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inferred_bones_of_the_demo_match_its_hierarchy() {
        let demo = crate::synth::demo::demo();
        let recording = demo.recording();
        let inferred = infer_parents(&recording.poses);
        // As undirected edges the trees agree (the root of the search is the hips).
        let edges = |parents: &[Option<usize>]| {
            let mut e: Vec<(usize, usize)> =
                parents.iter().enumerate().filter_map(|(j, p)| p.map(|p| (p.min(j), p.max(j)))).collect();
            e.sort();
            e
        };
        let expected = edges(&recording.parents);
        let found = edges(&inferred);
        let common = found.iter().filter(|e| expected.contains(e)).count();
        assert!(common + 2 >= expected.len(), "{common} of {} bones recovered", expected.len());
    }
}
