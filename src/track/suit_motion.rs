//! The suit's motion at the video's instants: the pose relative to its hips
//! and the contact method's floor path (the inertial prediction), sampled at
//! each video frame's time. The video and the BVH need not share a rate or a
//! length: video frame `i` is at `i / video_fps` s, and the BVH is read at
//! that time plus `offset_s` (the BVH's clock runs `offset_s` ahead of the
//! video's), joint positions linear between its frames.

use glam::{DVec2, DVec3};

use crate::body::skeleton::Poses;
use crate::error::Error;
use crate::io::recording::{FeetChoice, Recording};
use crate::translate::Method;
use crate::translate::contact::ContactParams;

/// The suit's recording as the tracker reads it, at any video time.
#[derive(Clone, Debug)]
pub struct SuitMotion {
    /// Per BVH frame, the joints relative to the hips' floor point: the hips
    /// at x = z = 0 and at their height above the floor (as the contact
    /// method stands the body on it), the floor at y = 0.
    pub body_cm: Poses,
    /// Per BVH frame, the hips' floor position by the contact method (x, z,
    /// cm), from wherever its first frame is.
    pub inertial_floor_cm: Vec<DVec2>,
    /// Per BVH frame, the hips' floor position as the suit's own
    /// translation has it (x, z, cm).
    pub suit_floor_cm: Vec<DVec2>,
    pub hips: usize,
    pub bvh_fps: f64,
}

/// Where a video instant falls in the BVH: between frames `a` and `a + 1`,
/// `t` of the way (0 ≤ t < 1), or past either end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BvhInstant {
    Between {
        a: usize,
        t: f64,
    },
    /// Before the first frame or after the last: no pose.
    Outside,
}

impl SuitMotion {
    /// Reads `recording` (its own translation kept aside as the suit's) and
    /// runs the contact method on it, a double support's feet free to move
    /// apart ([`ContactParams::double_support_slides`]): the tracker's
    /// smoother corrects the steps' scale from the camera, not their noise
    /// (with the slides paid for, the fused track's mean error on the shared
    /// scenes, over five runs each: walk 4.30 → 4.82 cm, walk_turns
    /// 3.34 → 3.54, run 6.26 → 6.52).
    pub fn new(recording: &Recording) -> Result<SuitMotion, Error> {
        let feet = recording.feet(&FeetChoice::default())?;
        let hips = recording.hips(feet);
        let prediction = ContactParams { double_support_slides: false, ..ContactParams::default() };
        let translated = recording.translate(&FeetChoice::default(), &Method::Contact(prediction))?;
        let ground_cm = translated.contact().map_or(0.0, |c| c.ground_cm);
        let n = recording.frame_count();
        let mut body_cm = translated.poses.clone();
        for f in 0..n {
            let hips_now = translated.poses.at(f, hips);
            let origin = DVec3::new(hips_now.x, ground_cm, hips_now.z);
            for p in &mut body_cm.positions_cm[f * body_cm.joint_count..(f + 1) * body_cm.joint_count] {
                *p -= origin;
            }
        }
        let floor = |poses: &Poses, f: usize| {
            let p = poses.at(f, hips);
            DVec2::new(p.x, p.z)
        };
        Ok(SuitMotion {
            inertial_floor_cm: (0..n).map(|f| floor(&translated.poses, f)).collect(),
            suit_floor_cm: (0..n).map(|f| floor(&recording.poses, f)).collect(),
            body_cm,
            hips,
            bvh_fps: recording.fps,
        })
    }

    pub fn frame_count(&self) -> usize {
        self.body_cm.frame_count()
    }

    /// Where `time_s` on the BVH's clock falls among its frames.
    pub fn instant(&self, time_s: f64) -> BvhInstant {
        let n = self.frame_count();
        let position = time_s * self.bvh_fps;
        // Half a frame of slack at the ends: a video frame a hair past the
        // BVH's last one is that frame, not a missing pose.
        if n == 0 || !position.is_finite() || position < -0.5 || position > (n - 1) as f64 + 0.5 {
            return BvhInstant::Outside;
        }
        let clamped = position.clamp(0.0, (n - 1) as f64);
        let a = (clamped.floor() as usize).min(n.saturating_sub(2));
        let t = if n > 1 { clamped - a as f64 } else { 0.0 };
        BvhInstant::Between { a, t }
    }

    /// The body relative to its hips' floor point at `instant` (see
    /// [`SuitMotion::body_cm`]); `None` outside the BVH.
    pub fn body_at(&self, instant: BvhInstant) -> Option<Vec<DVec3>> {
        let BvhInstant::Between { a, t } = instant else { return None };
        let b = (a + 1).min(self.frame_count() - 1);
        let (pa, pb) = (self.body_cm.frame(a), self.body_cm.frame(b));
        Some(pa.iter().zip(pb).map(|(p, q)| p.lerp(*q, t)).collect())
    }

    /// The suit's own translation (its hips' floor position, x, z, cm) at
    /// each of `times_s` on the BVH's clock: what the suit alone says, to
    /// measure the trackers against; NaN outside the BVH.
    pub fn suit_floor_at(&self, times_s: &[f64]) -> Vec<DVec2> {
        times_s
            .iter()
            .map(|&t| SuitMotion::floor_at(&self.suit_floor_cm, self.instant(t)).unwrap_or(DVec2::NAN))
            .collect()
    }

    /// A per-frame floor path read at `instant`.
    pub fn floor_at(path: &[DVec2], instant: BvhInstant) -> Option<DVec2> {
        let BvhInstant::Between { a, t } = instant else { return None };
        let b = (a + 1).min(path.len().checked_sub(1)?);
        Some(path.get(a)?.lerp(path[b], t))
    }
}

/// The video's frames: how many and at what rate, and the BVH's clock
/// relative to the video's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoTiming {
    pub fps: f64,
    pub frame_count: usize,
    /// Added to a video frame's time to read the BVH (s).
    pub offset_s: f64,
}

impl VideoTiming {
    /// The BVH time of video frame `i` (s).
    pub fn bvh_time_s(&self, i: usize) -> f64 {
        i as f64 / self.fps + self.offset_s
    }

    /// The BVH times of video frames 0 to `count` − 1 (s).
    pub fn bvh_times_s(&self, count: usize) -> Vec<f64> {
        (0..count).map(|i| self.bvh_time_s(i)).collect()
    }

    /// The video frame, fractional, read at BVH time `bvh_time_s`: the
    /// inverse of [`VideoTiming::bvh_time_s`], outside 0 to the last frame
    /// where the video does not film that instant.
    pub fn video_position(&self, bvh_time_s: f64) -> f64 {
        (bvh_time_s - self.offset_s) * self.fps
    }

    /// The video frames with no pose in `motion` as ranges (first, last),
    /// for a warning.
    pub fn frames_without_pose(&self, motion: &SuitMotion) -> Vec<(usize, usize)> {
        let mut ranges: Vec<(usize, usize)> = Vec::new();
        for i in 0..self.frame_count {
            if motion.instant(self.bvh_time_s(i)) != BvhInstant::Outside {
                continue;
            }
            match ranges.last_mut() {
                Some((_, last)) if *last + 1 == i => *last = i,
                _ => ranges.push((i, i)),
            }
        }
        ranges
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(frames: usize, fps: f64) -> SuitMotion {
        let body = (0..frames).flat_map(|f| [DVec3::new(0.0, 90.0, 0.0), DVec3::new(f as f64, 0.0, 0.0)]);
        SuitMotion {
            body_cm: Poses { joint_count: 2, positions_cm: body.collect() },
            inertial_floor_cm: (0..frames).map(|f| DVec2::new(f as f64, 0.0)).collect(),
            suit_floor_cm: vec![DVec2::ZERO; frames],
            hips: 0,
            bvh_fps: fps,
        }
    }

    #[test]
    fn a_video_at_another_rate_reads_the_bvh_between_its_frames() {
        let m = motion(31, 30.0);
        // A 60 fps video: its frame 3 is 1.5 BVH frames in.
        let timing = VideoTiming { fps: 60.0, frame_count: 61, offset_s: 0.0 };
        let instant = m.instant(timing.bvh_time_s(3));
        assert_eq!(instant, BvhInstant::Between { a: 1, t: 0.5 });
        assert_eq!(m.body_at(instant).unwrap()[1], DVec3::new(1.5, 0.0, 0.0));
        assert_eq!(SuitMotion::floor_at(&m.inertial_floor_cm, instant), Some(DVec2::new(1.5, 0.0)));
        assert!(timing.frames_without_pose(&m).is_empty());
        // The last BVH frame is read exactly, not extrapolated.
        assert_eq!(m.body_at(m.instant(1.0)).unwrap()[1], DVec3::new(30.0, 0.0, 0.0));
    }

    #[test]
    fn video_frames_past_the_bvh_are_named() {
        let m = motion(31, 30.0);
        let timing = VideoTiming { fps: 30.0, frame_count: 40, offset_s: -0.1 };
        assert_eq!(timing.frames_without_pose(&m), [(0, 2), (34, 39)]);
        assert_eq!(m.body_at(m.instant(-1.0)), None);
    }
}
