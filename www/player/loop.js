// @ts-check
// The player's animation loop. It runs every animation frame while the
// player plays or the user acts on it; paused and left alone for a second,
// it looks again only five times a second, so that an idle player gives its
// core to the page's other work (the camera tracker's worker: software
// compositing 60 frames a second halved its speed). Anything the user does
// wakes it at once. Each frame it writes on the page only what changed.

/** @typedef {import("../pkg/embusen.js").Player} Player */
/** @typedef {import("../embusen.js").Clock} Clock */

export class AnimationLoop {
  #request = 0;
  #idleTimer = 0;
  #idleTicks = 0;
  #last = performance.now();

  /**
   * @param {Player} player
   * @param {(frame: number, playing: boolean) => void} show writes what changed on the page for `frame`
   */
  constructor(player, show) {
    this.player = player;
    this.show = show;
  }

  /** The clock followed, if any. @type {Clock | null} */
  clock = null;

  /** Whether the recording plays: the clock's, when followed. */
  playing() {
    return this.clock ? this.clock.playing() : this.player.playing();
  }

  /** Plays or pauses the clock followed, or the player's own. @param {boolean} on */
  play(on) {
    if (this.clock) this.clock.setPlaying(on);
    else this.player.set_playing(on);
    this.wake();
  }

  /** Follows `clock` (`null`: the player's own, paused until asked to play). @param {Clock | null} clock */
  follow(clock) {
    this.player.set_playing(false);
    this.clock = clock;
  }

  /** @param {number} now */
  #tick = (now) => {
    this.#request = 0;
    this.clock?.agree(this.player);
    this.player.tick(this.clock ? 0 : (now - this.#last) / 1000);
    this.#last = now;
    this.show(this.player.frame(), this.playing());
    this.#idleTicks = this.playing() ? 0 : this.#idleTicks + 1;
    if (this.#idleTicks < 60) this.#request = requestAnimationFrame(this.#tick);
    else this.#idleTimer = window.setTimeout(() => {
      this.#idleTimer = 0;
      this.#request = requestAnimationFrame(this.#tick);
    }, 200);
  };

  /** Starts it: playback time counts from now. */
  start() {
    this.#last = performance.now();
    this.#request = requestAnimationFrame(this.#tick);
  }

  /** Back to every animation frame, now. */
  wake() {
    this.#idleTicks = 0;
    if (!this.#idleTimer) return;
    clearTimeout(this.#idleTimer);
    this.#idleTimer = 0;
    this.start();
  }

  stop() {
    if (this.#request) cancelAnimationFrame(this.#request);
    clearTimeout(this.#idleTimer);
    this.#request = this.#idleTimer = 0;
  }
}

/**
 * What the loop writes on the page for each frame: only what changed, so an
 * unchanged page is not repainted.
 * @param {HTMLElement} element
 * @param {Player} player
 * @param {HTMLInputElement} slider
 * @param {HTMLElement} readout
 * @param {HTMLButtonElement} playButton
 */
export function frameShower(element, player, slider, readout, playButton) {
  return (/** @type {number} */ frame, /** @type {boolean} */ playing) => {
    if (+slider.value !== frame) slider.value = String(frame);
    if (element.dataset.frame !== String(frame)) element.dataset.frame = String(frame);
    const said = `${player.time_s().toFixed(2)} s · frame ${frame} / ${Math.max(0, player.frame_count() - 1)}`;
    if (readout.textContent !== said) readout.textContent = said;
    const label = playing ? "❚❚" : "▶";
    if (playButton.textContent !== label) playButton.textContent = label;
  };
}
