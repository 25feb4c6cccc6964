//! What can hold the body up in a frame: the two soles, each one's point
//! nearest the floor, and the candidates for the contact, with the one rule
//! for how a pinned point moves the hips.

use glam::DVec3;

use super::horizontal;
use super::pressure::PressureSegment;
use crate::body::feet::{Foot, PerFoot};
use crate::body::sole::{Sole, SolePart};

/// How the hips move from frame `f - 1` to `f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Candidate {
    /// Point `point` of the sole of `foot` stays where it was.
    Point { foot: Foot, point: usize },
    /// Both feet stay where they were (their lowest points): the mean.
    Double,
    /// No foot holds still: the centre of mass keeps its velocity.
    Coast,
}

/// Per foot and frame, its sole point nearest the floor; per frame, where
/// that puts the floor.
pub(super) struct LowestPoints {
    /// Per foot and frame, the index of its sole point nearest the floor.
    pub point: PerFoot<Vec<usize>>,
    /// Per foot and frame, that point's height above its flat-foot level,
    /// relative to the hips (cm).
    pub height_cm: PerFoot<Vec<f64>>,
    /// Per frame, the hips' height with the lower of the two on the floor (cm).
    pub standing_cm: Vec<f64>,
}

impl LowestPoints {
    /// The lowest points of `soles` in each of their frames.
    pub fn of(soles: &PerFoot<Sole>) -> LowestPoints {
        let n = soles.left.frame_count();
        let lowest = soles.as_ref().map(|sole| (0..n).map(|f| sole.lowest(f)).collect::<Vec<_>>());
        let point = lowest.as_ref().map(|points| points.iter().map(|p| p.point).collect());
        let height_cm: PerFoot<Vec<f64>> =
            lowest.as_ref().map(|points| points.iter().map(|p| p.height_above_flat_cm).collect());
        let standing_cm = (0..n).map(|f| -height_cm.left[f].min(height_cm.right[f])).collect();
        LowestPoints { point, height_cm, standing_cm }
    }

    /// The points a double support pins in frame `f`: each foot's lowest.
    pub fn double_support(&self, f: usize) -> PerFoot<usize> {
        PerFoot::new(self.point.left[f], self.point.right[f])
    }

    /// The foot whose lowest point is lower in frame `f` (the left of two
    /// equally low).
    pub fn lower_foot(&self, f: usize) -> Foot {
        if self.height_cm.right[f] < self.height_cm.left[f] { Foot::Right } else { Foot::Left }
    }
}

/// Two soles over the same frames and their lowest points.
pub(super) struct Footing {
    pub soles: PerFoot<Sole>,
    pub lowest: LowestPoints,
}

impl Footing {
    pub fn new(soles: PerFoot<Sole>) -> Footing {
        let lowest = LowestPoints::of(&soles);
        Footing { soles, lowest }
    }

    pub fn frame_count(&self) -> usize {
        self.lowest.standing_cm.len()
    }

    /// Every candidate, in a fixed order: the left sole's points, the
    /// right's, double support, coasting.
    pub fn candidates(&self) -> Vec<Candidate> {
        let mut all: Vec<Candidate> = Foot::BOTH
            .into_iter()
            .flat_map(|foot| {
                (0..self.soles[foot].point_count()).map(move |point| Candidate::Point { foot, point })
            })
            .collect();
        all.extend([Candidate::Double, Candidate::Coast]);
        all
    }

    /// The hips' horizontal velocity from frame `f - 1` to `f` (cm/s, the
    /// frames `dt` s apart) if `candidate` holds: the pinned point stays
    /// where it was, and with both feet down the hips follow the mean of
    /// their lowest points in frame `f - 1`. `None` for `Coast`, whose
    /// velocity is carried. `f` is at least 1.
    pub fn hips_velocity(&self, candidate: Candidate, f: usize, dt: f64) -> Option<DVec3> {
        let pinned = |foot: Foot, point: usize| {
            let sole = &self.soles[foot];
            -horizontal(sole.at(f, point) - sole.at(f - 1, point)) / dt
        };
        match candidate {
            Candidate::Point { foot, point } => Some(pinned(foot, point)),
            Candidate::Double => {
                let pins = self.lowest.double_support(f - 1);
                Some((pinned(Foot::Left, pins.left) + pinned(Foot::Right, pins.right)) * 0.5)
            }
            Candidate::Coast => None,
        }
    }

    /// The height above the floor of sole point `point` of `foot` in frame
    /// `f`, with the lowest sole point on the floor (cm).
    pub fn clearance_cm(&self, foot: Foot, point: usize, f: usize) -> f64 {
        self.lowest.standing_cm[f] + self.soles[foot].height_above_flat_cm(f, point)
    }

    /// Where the floor can push the body from in frame `f` if `candidate`
    /// holds: the segment (relative to the hips) on which the centre of
    /// pressure lies. A foot presses anywhere between its heel and its toes,
    /// whichever point of it rolls; two feet anywhere between their lowest
    /// points. `None` for `Coast`: the floor does not push a coasting body.
    pub fn pressure_segment(&self, candidate: Candidate, f: usize) -> Option<PressureSegment> {
        match candidate {
            Candidate::Point { foot, .. } => {
                let sole = &self.soles[foot];
                Some(PressureSegment { from: sole.at(f, 0), to: sole.at(f, sole.tip) })
            }
            Candidate::Double => {
                let pins = self.lowest.double_support(f);
                Some(PressureSegment {
                    from: self.soles.left.at(f, pins.left),
                    to: self.soles.right.at(f, pins.right),
                })
            }
            Candidate::Coast => None,
        }
    }

    /// The sole part `foot` is on in frame `f` when `candidate` holds: the
    /// pinned one if `candidate` pins that foot's point, else the foot's
    /// lowest.
    pub fn contact_part(&self, candidate: Candidate, foot: Foot, f: usize) -> SolePart {
        let sole = &self.soles[foot];
        match candidate {
            Candidate::Point { foot: pinned, point } if pinned == foot => sole.parts[point],
            _ => sole.parts[self.lowest.point[foot][f]],
        }
    }
}
