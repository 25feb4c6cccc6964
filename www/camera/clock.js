// @ts-check
// One clock for a take: its video's. While a take's video is open, the
// player shows the recording at the video's instant and its controls (play,
// the slider, the keys, a click on a plot) drive the video. The instants are
// `embusen track`'s: video frame `i` is at `i / fps` s, and the recording is
// read `offset` s later (the offset field, `--offset-s`).

/**
 * The take's video as a clock for the player (`Handle.followClock`).
 * @param {import("./inputs.js").TakeVideo} video
 * @param {() => number} offsetS the recording's time at the video's 0 s
 * @returns {import("../embusen.js").Clock}
 */
export function videoClock(video, offsetS) {
  const { element, fps, frameCount } = video;
  /** The video frame nearest, or at, `timeS` of the video. @param {number} timeS @param {(x: number) => number} round */
  const frameAt = (timeS, round) => Math.min(frameCount - 1, Math.max(0, round(timeS * fps + 1e-6)));
  // The frame on screen spans its time to the next's.
  const timeS = () => frameAt(element.currentTime, Math.floor) / fps + offsetS();
  /** @param {number} t */
  const seek = (t) => {
    const frame = frameAt(t - offsetS(), Math.round);
    // The middle of the frame, clear of rounding at its edges.
    if (frame !== frameAt(element.currentTime, Math.floor)) element.currentTime = (frame + 0.5) / fps;
  };
  /** The clock's instant and the player's frame when they last agreed. */
  let agreed = { timeS: NaN, frame: -1 };
  return {
    // Where the player was moved (its slider, keys, plots) the video is
    // seeked to its instant, even as it plays; where only the clock moved
    // (it plays, it was seeked, the offset changed) the player goes to the
    // clock's. The player's frame is kept where the video can only come
    // near it (a 60 fps video under a 100 Hz recording), so that a step is
    // never undone.
    agree: (player) => {
      if (player.frame() !== agreed.frame) {
        seek(player.time_s());
      } else if (timeS() !== agreed.timeS) {
        const last = Math.max(0, player.frame_count() - 1);
        player.set_frame(Math.min(last, Math.max(0, Math.round(timeS() * player.fps()))));
      }
      agreed = { timeS: timeS(), frame: player.frame() };
    },
    playing: () => !element.paused && !element.ended,
    setPlaying: (on) => {
      if (on) element.play().catch(() => {}); // refused (no user gesture): it stays paused, and says so
      else element.pause();
    },
  };
}
