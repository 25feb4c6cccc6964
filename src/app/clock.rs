//! The playback clock: where in a recording playback is, whether it runs,
//! how fast, and what one animation frame's wall time advances it by.
//! Browser-free, so native tests drive it; the wasm `Player` owns one.

/// The slowest and fastest playback speeds.
pub const MIN_SPEED: f64 = 0.25;
pub const MAX_SPEED: f64 = 4.0;

/// The speeds a player offers, slowest first.
pub const SPEEDS: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];

/// The most wall time one tick advances by (s): after the tab was hidden or
/// the machine stalled, playback resumes where it was instead of jumping.
pub const MAX_TICK_S: f64 = 0.25;

/// Playback over a recording of `frame_count` frames at `fps`.
#[derive(Clone, Debug, PartialEq)]
pub struct Clock {
    time_s: f64,
    playing: bool,
    speed: f64,
    looping: bool,
    frame_count: usize,
    fps: f64,
}

impl Default for Clock {
    fn default() -> Self {
        Clock { time_s: 0.0, playing: false, speed: 1.0, looping: true, frame_count: 0, fps: 0.0 }
    }
}

impl Clock {
    /// A new recording: back to its first frame; playing, speed and looping stay.
    pub fn set_recording(&mut self, frame_count: usize, fps: f64) {
        self.frame_count = frame_count;
        self.fps = fps;
        self.time_s = 0.0;
    }

    pub fn frame_count(&self) -> usize {
        self.frame_count
    }

    pub fn fps(&self) -> f64 {
        self.fps
    }

    fn last_frame(&self) -> usize {
        self.frame_count.saturating_sub(1)
    }

    /// The time of the last frame (s).
    fn last_s(&self) -> f64 {
        if self.fps > 0.0 { self.last_frame() as f64 / self.fps } else { 0.0 }
    }

    /// The frame shown: the one nearest the playback time.
    pub fn frame(&self) -> usize {
        ((self.time_s * self.fps).round().max(0.0) as usize).min(self.last_frame())
    }

    /// The time of the frame shown (s), so a readout and the frame agree.
    pub fn frame_time_s(&self) -> f64 {
        if self.fps > 0.0 { self.frame() as f64 / self.fps } else { 0.0 }
    }

    /// Jumps to `frame`, clamped to the recording.
    pub fn set_frame(&mut self, frame: usize) {
        self.time_s = if self.fps > 0.0 { frame.min(self.last_frame()) as f64 / self.fps } else { 0.0 };
    }

    /// Moves by `frames` (negative: back), clamped to the recording.
    pub fn step(&mut self, frames: i64) {
        let frame = (self.frame() as i64).saturating_add(frames);
        self.set_frame(frame.max(0) as usize);
    }

    pub fn playing(&self) -> bool {
        self.playing
    }

    pub fn set_playing(&mut self, playing: bool) {
        self.playing = playing;
    }

    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Sets the playback speed, clamped to [`MIN_SPEED`]–[`MAX_SPEED`]; NaN,
    /// which is no speed (and would stop the clock for good), keeps the
    /// speed it had.
    pub fn set_speed(&mut self, speed: f64) {
        if !speed.is_nan() {
            self.speed = speed.clamp(MIN_SPEED, MAX_SPEED);
        }
    }

    pub fn looping(&self) -> bool {
        self.looping
    }

    pub fn set_looping(&mut self, looping: bool) {
        self.looping = looping;
    }

    /// Advances by `dt_s` seconds of wall time (at most [`MAX_TICK_S`]) times
    /// the speed, when playing. Past the last frame it starts over when
    /// looping, else it stops on the last frame.
    pub fn tick(&mut self, dt_s: f64) {
        if !self.playing || self.frame_count == 0 {
            return;
        }
        let dt_s = if dt_s.is_nan() { 0.0 } else { dt_s.clamp(0.0, MAX_TICK_S) };
        self.time_s += dt_s * self.speed;
        let last_s = self.last_s();
        if self.time_s > last_s {
            if self.looping && last_s > 0.0 {
                self.time_s = 0.0;
            } else {
                self.time_s = last_s;
                self.playing = false;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clock(frame_count: usize, fps: f64) -> Clock {
        let mut clock = Clock::default();
        clock.set_recording(frame_count, fps);
        clock
    }

    #[test]
    fn plays_at_its_speed() {
        let mut c = clock(1000, 100.0);
        c.tick(0.1);
        assert_eq!(c.frame(), 0, "paused: time stands still");
        c.set_playing(true);
        c.tick(0.1);
        assert_eq!(c.frame(), 10);
        c.set_speed(2.0);
        c.tick(0.1);
        assert_eq!(c.frame(), 30);
        assert!((c.frame_time_s() - 0.3).abs() < 1e-12);
    }

    #[test]
    fn speed_is_clamped() {
        let mut c = clock(10, 100.0);
        c.set_speed(100.0);
        assert_eq!(c.speed(), MAX_SPEED);
        c.set_speed(0.0);
        assert_eq!(c.speed(), MIN_SPEED);
        c.set_speed(f64::NAN);
        assert_eq!(c.speed(), MIN_SPEED, "NaN keeps the speed there was");
    }

    #[test]
    fn a_long_stall_advances_a_quarter_second() {
        let mut c = clock(1000, 100.0);
        c.set_playing(true);
        c.tick(10.0);
        assert_eq!(c.frame(), 25);
        c.tick(-1.0);
        c.tick(f64::NAN);
        assert_eq!(c.frame(), 25, "no step back, no NaN");
    }

    #[test]
    fn loops_or_stops_at_the_end() {
        let mut c = clock(11, 10.0); // frames 0..=10, last at 1 s
        c.set_playing(true);
        c.set_frame(9);
        c.tick(0.2);
        assert_eq!(c.frame(), 0, "looped");
        assert!(c.playing());
        c.set_looping(false);
        c.set_frame(9);
        c.tick(0.2);
        assert_eq!(c.frame(), 10, "stopped on the last frame");
        assert!(!c.playing());
    }

    #[test]
    fn frames_are_clamped_and_rounded() {
        let mut c = clock(5, 30.0);
        c.set_frame(99);
        assert_eq!(c.frame(), 4);
        c.step(-2);
        assert_eq!(c.frame(), 2);
        c.step(-10);
        assert_eq!(c.frame(), 0);
        c.step(i64::MAX);
        assert_eq!(c.frame(), 4);
        c.set_playing(true);
        c.set_frame(1);
        c.tick(0.6 / 30.0); // 1.6 frames: the nearest is 2
        assert_eq!(c.frame(), 2);
    }

    #[test]
    fn a_new_recording_starts_at_its_first_frame() {
        let mut c = clock(100, 100.0);
        c.set_frame(50);
        c.set_playing(true);
        c.set_recording(20, 30.0);
        assert_eq!((c.frame(), c.frame_count(), c.fps(), c.playing()), (0, 20, 30.0, true));
    }

    #[test]
    fn no_recording_is_frame_zero() {
        let mut c = Clock::default();
        c.set_playing(true);
        c.tick(0.1);
        c.set_frame(3);
        c.step(2);
        assert_eq!((c.frame(), c.frame_time_s()), (0, 0.0));
        let mut single = clock(1, 100.0);
        single.set_playing(true);
        single.tick(0.1);
        assert_eq!(single.frame(), 0);
        assert!(!single.playing(), "one frame: nothing to loop over");
    }
}
