// @ts-check
// One clock for a take: its video's. While a take's video is open, the
// player shows the recording at the video's instant and its controls (play,
// the slider, the keys, a click on a plot) drive the video. The instants are
// `embusen track`'s: video frame `i` is at `i / fps` s, and the recording is
// read `offset` s later (the offset field, `--offset-s`).

/** @typedef {import("./inputs.js").TakeVideo} TakeVideo */

/**
 * The take's video as a clock for the player (`Handle.followClock`); the
 * other views' videos (`followers`) are kept at the same instant of the
 * recording.
 * @param {TakeVideo} video the first view's
 * @param {() => number} offsetS the recording's time at the video's 0 s
 * @param {() => Array<{video: TakeVideo, offsetS: number}>} [followers] the other views' videos and offsets
 * @returns {import("../embusen.js").Clock}
 */
export function videoClock(video, offsetS, followers = () => []) {
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
  /** The instant the other views were last moved to, and whether the first played. */
  let followed = { timeS: NaN, playing: false };
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
      // The others are moved only when the first moved (or started or
      // stopped): in between, their own frames may be read exactly
      // (a median still, a layer, a board), which a seek back would undo.
      const playing = !element.paused && !element.ended;
      if (agreed.timeS !== followed.timeS || playing !== followed.playing) {
        for (const f of followers()) follow(f.video, agreed.timeS - f.offsetS, playing);
        followed = { timeS: agreed.timeS, playing };
      }
    },
    playing: () => !element.paused && !element.ended,
    setPlaying: (on) => {
      for (const v of [element, ...followers().map((f) => f.video.element)]) {
        if (on) v.play().catch(() => {}); // refused (no user gesture): it stays paused, and says so
        else v.pause();
      }
    },
  };
}

/**
 * Keeps another view's video at `timeS` of its own: seeked to the frame
 * there while paused; while playing, it plays along and is seeked only when
 * it drifts more than two frames (a seek each frame would stall it).
 * @param {TakeVideo} video
 * @param {number} timeS
 * @param {boolean} playing whether the first view's video plays
 */
function follow(video, timeS, playing) {
  const { element, fps, frameCount } = video;
  if (element.seeking) return; // the last seek lands first: a seek each frame would stall it
  const frame = Math.min(frameCount - 1, Math.max(0, Math.floor(timeS * fps + 1e-6)));
  const shown = Math.min(frameCount - 1, Math.floor(element.currentTime * fps + 1e-6));
  if (playing && element.paused && timeS >= 0 && timeS * fps < frameCount) element.play().catch(() => {});
  if (!playing && !element.paused) element.pause();
  if (Math.abs(frame - shown) > (playing ? 2 : 0)) element.currentTime = (frame + 0.5) / fps;
}
