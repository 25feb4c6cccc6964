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
}

/// Global joint positions for every frame, frame-major like [`Motion`]: the
/// common ground of a BVH (after forward kinematics) and an RMoCap table (which
/// stores them directly). Every translation method reads and writes this.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Poses {
    pub joint_count: usize,
    pub positions_cm: Vec<DVec3>,
}

impl Poses {
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
