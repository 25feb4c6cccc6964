//! How the floor pushes the centre of mass: along the line from the centre
//! of pressure to the centre of mass, holding the body up (the inverted
//! pendulum). A centre of mass `d` cm ahead of the pressure point and `h` cm
//! above the floor is pushed forward at `g d / h`: a walker speeds up once
//! past the stance foot and slows down before it, and a body held by a foot
//! far behind it cannot be moving backwards.

use glam::DVec3;

use super::horizontal;
use crate::signal::accel::STANDARD_GRAVITY_CM_PER_S2;

/// The segment on which the centre of pressure lies, relative to the hips
/// (cm): under one foot from heel to toes, under two from one foot to the
/// other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PressureSegment {
    pub from: DVec3,
    pub to: DVec3,
}

/// The floor's push on a centre of mass over one frame, per cm that the
/// centre of mass stands ahead of the centre of pressure.
#[derive(Clone, Copy, Debug)]
pub(super) struct FloorPush {
    /// The centre of mass relative to the hips (cm).
    hips_to_com_cm: DVec3,
    /// The change of horizontal velocity (cm/s) over the frame per cm of
    /// lean: `g / h · dt`, `h` the centre of mass's height.
    per_cm: f64,
}

impl FloorPush {
    /// The push on a centre of mass at `hips_to_com_cm` with the hips
    /// `standing_cm` above the floor, over `dt` s. A centre of mass lower than
    /// `min_com_height_cm` is reckoned at that height.
    pub fn new(hips_to_com_cm: DVec3, standing_cm: f64, dt: f64, min_com_height_cm: f64) -> FloorPush {
        let com_height_cm = (standing_cm + hips_to_com_cm.y).max(min_com_height_cm);
        FloorPush { hips_to_com_cm, per_cm: STANDARD_GRAVITY_CM_PER_S2 / com_height_cm * dt }
    }

    /// The velocity changes the floor can give from a centre of pressure on
    /// `segment`; no push at all without one.
    pub fn range_from(&self, segment: Option<PressureSegment>) -> PushRange {
        segment.map_or(
            PushRange { start: DVec3::ZERO, along: DVec3::ZERO },
            |PressureSegment { from, to }| PushRange {
                start: horizontal(self.hips_to_com_cm - from) * self.per_cm,
                along: -horizontal(to - from) * self.per_cm,
            },
        )
    }
}

/// The velocity changes (cm/s) a floor's push can give: `start + s · along`
/// for `s` in [0, 1], the centre of pressure from one end of its segment to
/// the other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PushRange {
    pub start: DVec3,
    pub along: DVec3,
}

impl PushRange {
    /// The part of the velocity change `change` (cm/s) that the push does
    /// not explain, with the centre of pressure placed where on its segment
    /// it explains most.
    pub fn unexplained(&self, change: DVec3) -> DVec3 {
        let r = change - self.start;
        let along = self.along;
        let s = if along.length_squared() > 0.0 {
            (r.dot(along) / along.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        r - s * along
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_push_comes_from_within_the_pressure_segment() {
        // Centre of mass at the origin; pressure anywhere from 10 cm behind
        // it to 20 cm behind it (a foot); `k` cm/s of push per cm.
        let (com, from, to, k) = (DVec3::ZERO, DVec3::new(0.0, 0.0, -10.0), DVec3::new(0.0, 0.0, -20.0), 0.5);
        let range = PushRange { start: (com - from) * k, along: -(to - from) * k };
        // Pressed from the middle of the foot: pushed forward 7.5 cm/s,
        // fully explained; from the heel end, 10.
        let explained = |change: DVec3| range.unexplained(change).length();
        assert!(explained(DVec3::new(0.0, 0.0, 7.5)) < 1e-12);
        assert!(explained(DVec3::new(0.0, 0.0, 10.0)) < 1e-12);
        // Not from beyond the foot (2.5 cm/s short of the nearest end), nor
        // from the far side of the centre of mass.
        assert!((explained(DVec3::new(0.0, 0.0, 2.5)) - 2.5).abs() < 1e-12);
        assert!((explained(DVec3::new(0.0, 0.0, -5.0)) - 10.0).abs() < 1e-12);
    }

    #[test]
    fn the_push_is_reckoned_from_the_segment_and_the_height() {
        // A centre of mass 20 cm up (below the 30 cm floor of the reckoning)
        // and 10 cm ahead of a heel whose toes are 20 cm further ahead.
        let push = FloorPush::new(DVec3::new(0.0, -70.0, 10.0), 90.0, 0.1, 30.0);
        let per_cm = STANDARD_GRAVITY_CM_PER_S2 / 30.0 * 0.1;
        let range =
            push.range_from(Some(PressureSegment { from: DVec3::ZERO, to: DVec3::new(0.0, 0.0, 20.0) }));
        assert!((range.start - DVec3::new(0.0, 0.0, 10.0 * per_cm)).length() < 1e-12);
        assert!((range.along - DVec3::new(0.0, 0.0, -20.0 * per_cm)).length() < 1e-12);
        assert_eq!(push.range_from(None), PushRange { start: DVec3::ZERO, along: DVec3::ZERO });
    }
}
