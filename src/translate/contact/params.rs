//! The contact method's parameters: physical quantities in cm, s and g, not
//! fitted to any recording. The costs the method weighs are squares of
//! dimensionless ratios (a height over `touch_cm`, a velocity change over
//! `slip_cm_per_s`, …), added up per `cost_time_s` of evidence.

/// Parameters of the contact method. The defaults are physical quantities,
/// not fitted to any recording.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactParams {
    /// A sole point this high above the floor costs as much to pin as a
    /// velocity change of `slip_cm_per_s`: a sole's thickness plus the
    /// centimetre or so that tracking noise moves a planted foot.
    pub touch_cm: f64,
    /// A sole point higher than this is never pinned.
    pub lift_cm: f64,
    /// The unit of velocity change (cm/s) in the cost: a foot
    /// sliding this fast costs as much as a point `touch_cm` off the floor.
    /// Walking is ~130 cm/s and a swinging foot twice that; 25 cm/s is well
    /// below both and well above tracking noise.
    pub slip_cm_per_s: f64,
    /// A coasting stretch is a flight when gravity's arc lifts the feet at
    /// least this far above the floor, so a few millimetres of tracking
    /// noise never look like a jump.
    pub flight_margin_cm: f64,
    /// How far the sole lies below the foot's lowest joint when the foot
    /// stands flat ([`crate::body::sole`]); `None`: estimated from the recording,
    /// as the depth among [`SOLE_DEPTHS_CM`] whose best contacts fit the
    /// physics best.
    pub sole_depth_cm: Option<f64>,
    /// The costs add up evidence over time, in units of this duration (s): a
    /// height or an accelerometer reading held for this long costs its
    /// square once, and so does a velocity change spread over it, so a
    /// second of evidence weighs the same at any frame rate. The contacts
    /// are chosen on frames about this far apart (see the sampling grid in
    /// `grid.rs`): a change of pinned point is a jump of velocity, and a jump
    /// costs once per frame it happens in.
    pub cost_time_s: f64,
    /// A second of coasting costs as much as this many velocity changes of
    /// one `slip_cm_per_s`. Pinning a foot that slides at `u` costs
    /// `(u / slip)²` when it starts and again when it stops, however long it
    /// slides: a running flight (~0.15 s, every foot ≥ 100 cm/s off: ≥ 32
    /// pinned against 9 coasting) coasts, and a walk's handover (~0.1 s, feet
    /// ~40 cm/s off: ~5 against 6) mostly does not.
    pub coast_cost_per_s: f64,
    /// What a second of coasting costs where the body is in place
    /// (`still::in_place`), on a noisy pose: in place a body leaves
    /// the floor only to jump, and a coast there carries the velocity the
    /// pose's noise gave its last pin, not a momentum (the suit-grade dances'
    /// and kicks' coasts carried 50–150 cm/s where the truth stood on one
    /// foot). Eight times the moving price; four times, or no coasting in
    /// place at all, move the figures little (docs/contact.md).
    pub in_place_coast_cost_per_s: f64,
    /// A body whose hips progress slower than `√(Fr g L)` is in place, with
    /// `Fr` this Froude number and `L` its standing hips height: 1/16 is
    /// half the speed of its easiest walk (Froude number 1/4, where the
    /// legs' pendulum exchanges its energies best), slower than a walk keeps
    /// going: 74 cm/s for hips 90 cm high.
    pub in_place_froude: f64,
    /// How far either side of a frame (s) the hips' progress is read for
    /// [`ContactParams::in_place_froude`]: about two steps either side at the
    /// easiest walk's cadence, so the hips' sway over each foot cancels and
    /// the strides' progress remains.
    pub in_place_window_s: f64,
    /// The shortest stance (s) whose own velocity is read against the
    /// smoothed one, on a noisy pose (`carry.rs`): a sprinter's contact,
    /// 0.1 s; shorter, its mean is mostly the landing's and the take-off's
    /// noise.
    pub min_carried_stance_s: f64,
    /// How far either side of a coast (s, a Gaussian's deviation) the
    /// stances' readings set by how much its smoothed velocity falls short
    /// (`carry.rs`): about two steps either side at an easy walk's cadence,
    /// so a stride's stances average their noise and a change of gait is
    /// followed within a second. (0.5 and 2 s move the shared medians by
    /// at most 0.25 % of the path, docs/contact.md.)
    pub carry_window_s: f64,
    /// The longest a body can coast (s): the time in the air of a standing
    /// jump 30 cm high. Without a limit one wrong velocity would be carried
    /// across a whole recording.
    pub max_coast_s: f64,
    /// Where the contacts are chosen on fewer frames than recorded (from
    /// 45 fps), tracking jitter is first smoothed away over this time scale
    /// (s), the standard deviation of a Gaussian: three frames at 100 Hz, well
    /// under a heel-to-toe roll (50–100 ms). The grid keeps no detail finer
    /// than its step, and an inertial suit's millimetres of jitter, left in,
    /// decide which frame of a step looks smoothest. Only the choice of
    /// contacts sees the smoothed paths; the pinned points hold still
    /// unsmoothed. Below 45 fps every frame is used, unsmoothed.
    pub jitter_s: f64,
    /// The distance (cm) between a pinned point and the centre of mass's
    /// floor projection that costs as much as one `slip_cm_per_s` of
    /// velocity change: a foot bears the weight at its centre of pressure,
    /// near that projection. A body's length, so that it never outweighs the
    /// evidence of motion and only decides between points equally low and
    /// equally smooth, as in a flat foot turning on the spot.
    pub com_prior_cm: f64,
    /// With accelerometers: a pinned foot reading this far from 1 g costs as
    /// much as one `slip_cm_per_s` of velocity change (a still foot reads
    /// 1 g, and half a g off is a clearly moving foot). While coasting, a
    /// foot reading `a` g says the body rests on it by `r = 1 − |a − 1| / this`
    /// (nothing below zero), which costs `(r / this)²` per `cost_time_s`.
    pub accel_slip_g: f64,
    /// A flight needs a body on the floor rising into it, or falling out of
    /// it, faster than this (cm/s) over the last (first)
    /// `ballistic_evidence_s` on the floor: a hop of one centimetre leaves the
    /// floor at 44 cm/s, and a body standing in a stance bobs far slower.
    pub min_takeoff_cm_per_s: f64,
    /// How long (s) before a take-off, or after a landing, the centre of
    /// mass's rise or fall is measured to tell a flight (see
    /// `min_takeoff_cm_per_s`): a few frames, so that one frame's jitter does
    /// not decide, and well within a running stance (~0.2 s), so that what is
    /// measured is the push-off.
    pub ballistic_evidence_s: f64,
    /// The tracking noise a foot's velocity may keep when the contacts are
    /// chosen (cm/s): half a `slip_cm_per_s`, so that noise alone never costs
    /// as much as one unit of velocity change. A pose whose measured noise
    /// (`super::noise`) exceeds it is smoothed, over the least time that
    /// brings it down to this; a clean optical pose is not smoothed at all.
    pub max_velocity_noise_cm_per_s: f64,
    /// The longest that smoothing may reach (s, the Gaussian's standard
    /// deviation): a heel-to-toe roll, so that a step's contacts stay apart
    /// however noisy the pose.
    pub max_noise_smoothing_s: f64,
    /// How far either side of a frame (s) the pose's noise is read near it,
    /// where that noise bursts beyond the recording's median
    /// (`noise::local_noise_cm`): a kick, a slash or a swing of the
    /// arms, whose fast segments carry more of it, lasts a few tenths of a
    /// second, and ±0.2 s holds a dozen of the choice's frames for a median.
    pub noise_window_s: f64,
    /// Where the body moves slowly beside the pose's noise (standing,
    /// bowing, shifting its weight), the hips' path is smoothed further,
    /// until the noise left moves the hips at most this share of the
    /// body's own speed (`still.rs`): white noise of velocity `k v` beside
    /// a motion of speed `v` lengthens a path by about `k² / 4`, so a fifth
    /// is 1 % — and a suit's noise, correlated over a few frames, is more
    /// than the fourth difference reads.
    pub still_noise_share: f64,
    /// The longest that further smoothing may reach (s, the Gaussian's
    /// standard deviation): a weight shift takes half a second or more, so
    /// it passes.
    pub max_still_smoothing_s: f64,
    /// A centre of mass lower than this above the floor (cm) is taken to be
    /// this high when reckoning the floor's push: a body crouched or lying
    /// down is not an inverted pendulum, and the push would grow without
    /// bound.
    pub min_com_height_cm: f64,
    /// Whether a double support pays for its two feet moving apart beyond
    /// the pose's noise (`solve.rs`): where one foot is still landing or
    /// already lifting, the mean of the two follows half of its motion, and
    /// a noisy pose's steps came out short. On for the translation. The
    /// camera tracker's prediction goes without it
    /// ([`crate::track::suit_motion`]): its smoother learns from the camera
    /// how far the suit's steps are off in scale and heading, which takes
    /// out such a bias but not noise, and the mean of two feet is the
    /// steadier step.
    pub double_support_slides: bool,
}

impl ContactParams {
    /// An error when a parameter is out of its range: a sole depth, when
    /// given, is 0 to [`MAX_SOLE_DEPTH_CM`]; the lengths, durations and
    /// units are finite and positive, the margins and the coasting cost
    /// finite and not negative.
    pub fn check(&self) -> Result<(), String> {
        if let Some(depth) = self.sole_depth_cm
            && !(0.0..=MAX_SOLE_DEPTH_CM).contains(&depth)
        {
            return Err(format!("the sole depth must be between 0 and {MAX_SOLE_DEPTH_CM} cm, not {depth}"));
        }
        // Lengths, durations and units must be above zero; margins, the
        // coasting cost and the smoothing may be zero.
        let (positive, not_negative) = (true, false);
        let ranges = [
            ("touch_cm", self.touch_cm, positive),
            ("slip_cm_per_s", self.slip_cm_per_s, positive),
            ("cost_time_s", self.cost_time_s, positive),
            ("max_coast_s", self.max_coast_s, positive),
            ("min_carried_stance_s", self.min_carried_stance_s, not_negative),
            ("com_prior_cm", self.com_prior_cm, positive),
            ("accel_slip_g", self.accel_slip_g, positive),
            ("ballistic_evidence_s", self.ballistic_evidence_s, positive),
            ("min_com_height_cm", self.min_com_height_cm, positive),
            ("max_velocity_noise_cm_per_s", self.max_velocity_noise_cm_per_s, positive),
            ("max_noise_smoothing_s", self.max_noise_smoothing_s, not_negative),
            ("noise_window_s", self.noise_window_s, positive),
            ("in_place_window_s", self.in_place_window_s, positive),
            ("carry_window_s", self.carry_window_s, positive),
            ("still_noise_share", self.still_noise_share, positive),
            ("max_still_smoothing_s", self.max_still_smoothing_s, not_negative),
            ("lift_cm", self.lift_cm, not_negative),
            ("flight_margin_cm", self.flight_margin_cm, not_negative),
            ("coast_cost_per_s", self.coast_cost_per_s, not_negative),
            ("in_place_coast_cost_per_s", self.in_place_coast_cost_per_s, not_negative),
            ("in_place_froude", self.in_place_froude, not_negative),
            ("jitter_s", self.jitter_s, not_negative),
            ("min_takeoff_cm_per_s", self.min_takeoff_cm_per_s, not_negative),
        ];
        for (name, value, above_zero) in ranges {
            let in_range = if above_zero { value > 0.0 } else { value >= 0.0 };
            if !(value.is_finite() && in_range) {
                let range = if above_zero { "positive" } else { "not negative" };
                return Err(format!("the contact parameter {name} must be finite and {range}, not {value}"));
            }
        }
        // The time scales are parts of a step, a stance or a flight: longer
        // than a few seconds they would span the recording (and their counts
        // of frames would overflow at high rates).
        for (name, value) in [
            ("cost_time_s", self.cost_time_s),
            ("max_coast_s", self.max_coast_s),
            ("jitter_s", self.jitter_s),
            ("ballistic_evidence_s", self.ballistic_evidence_s),
            ("max_noise_smoothing_s", self.max_noise_smoothing_s),
            ("noise_window_s", self.noise_window_s),
            ("max_still_smoothing_s", self.max_still_smoothing_s),
            ("in_place_window_s", self.in_place_window_s),
            ("min_carried_stance_s", self.min_carried_stance_s),
            ("carry_window_s", self.carry_window_s),
        ] {
            if value > MAX_TIME_SCALE_S {
                return Err(format!(
                    "the contact parameter {name} must be at most {MAX_TIME_SCALE_S} s, not {value}"
                ));
            }
        }
        Ok(())
    }
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            touch_cm: 2.5,
            lift_cm: 5.0,
            slip_cm_per_s: 25.0,
            flight_margin_cm: 1.0,
            sole_depth_cm: None,
            cost_time_s: 1.0 / 30.0,
            coast_cost_per_s: 60.0,
            in_place_coast_cost_per_s: 480.0,
            in_place_froude: 1.0 / 16.0,
            in_place_window_s: 1.0,
            min_carried_stance_s: 0.1,
            carry_window_s: 1.0,
            max_coast_s: 0.5,
            jitter_s: 0.03,
            com_prior_cm: 100.0,
            accel_slip_g: 0.5,
            min_takeoff_cm_per_s: 20.0,
            ballistic_evidence_s: 0.05,
            min_com_height_cm: 30.0,
            max_velocity_noise_cm_per_s: 12.5,
            max_noise_smoothing_s: 0.1,
            noise_window_s: 0.2,
            still_noise_share: 0.2,
            max_still_smoothing_s: 0.3,
            double_support_slides: true,
        }
    }
}

/// The sole depths (cm) tried when the recording does not say: a toe end
/// site marks the skin (0), a ball-of-foot joint centre sits 2–3 cm above the
/// skin, and a shoe adds up to 3 cm more.
pub const SOLE_DEPTHS_CM: [f64; 7] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0];

/// The longest any of the method's time scales may be (s).
pub const MAX_TIME_SCALE_S: f64 = 5.0;

/// The deepest sole that can be given (cm): a platform shoe's.
pub const MAX_SOLE_DEPTH_CM: f64 = 20.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_pass_and_out_of_range_values_do_not() {
        assert_eq!(ContactParams::default().check(), Ok(()));
        let bad = [
            ContactParams { touch_cm: 0.0, ..ContactParams::default() },
            ContactParams { cost_time_s: f64::NAN, ..ContactParams::default() },
            ContactParams { jitter_s: -0.01, ..ContactParams::default() },
            ContactParams { max_coast_s: f64::INFINITY, ..ContactParams::default() },
            ContactParams { cost_time_s: 1.0e6, ..ContactParams::default() },
        ];
        for params in bad {
            assert!(params.check().is_err(), "{params:?}");
        }
    }
}
