// @ts-check
// The player's pointer and keyboard: orbit (drag), pan (right or shift drag,
// two fingers), zoom (wheel, pinch) in the 3D view; click or drag on a plot
// to seek; space, arrows, Home and End; and anything the user does wakes the
// animation loop.

/** @typedef {import("../pkg/embusen.js").Player} Player */

/**
 * Orbit, pan and zoom in the 3D view.
 * @param {HTMLCanvasElement} view
 * @param {Player} player
 * @param {AbortSignal} signal removes the listeners
 */
export function wireView(view, player, signal) {
  /** @type {Map<number, { x: number, y: number, pan: boolean }>} */
  const pointers = new Map();
  view.addEventListener("contextmenu", (e) => e.preventDefault(), { signal });
  view.addEventListener("pointerdown", (e) => {
    view.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey });
  }, { signal });
  view.addEventListener("pointermove", (e) => {
    const last = pointers.get(e.pointerId);
    if (!last) return;
    const [dx, dy] = [e.clientX - last.x, e.clientY - last.y];
    if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const before = Math.hypot(a.x - b.x, a.y - b.y);
      last.x = e.clientX;
      last.y = e.clientY;
      const after = Math.hypot(a.x - b.x, a.y - b.y);
      if (before > 0 && after > 0) player.zoom(before / after);
      player.pan(dx / 2, dy / 2);
    } else {
      if (last.pan) player.pan(dx, dy);
      else player.orbit(dx, dy);
      last.x = e.clientX;
      last.y = e.clientY;
    }
  }, { signal });
  /** @param {PointerEvent} e */
  const release = (e) => pointers.delete(e.pointerId);
  view.addEventListener("pointerup", release, { signal });
  view.addEventListener("pointercancel", release, { signal });
  view.addEventListener("wheel", (e) => {
    e.preventDefault();
    player.zoom(Math.exp(e.deltaY * 0.001));
  }, { passive: false, signal });
}

/**
 * Click or drag on a plot: seek.
 * @param {HTMLCanvasElement} plots
 * @param {Player} player
 * @param {AbortSignal} signal
 */
export function wirePlots(plots, player, signal) {
  /** @param {PointerEvent} e */
  const seek = (e) => {
    const r = plots.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    player.seek_plot((e.clientX - r.left) * dpr, (e.clientY - r.top) * dpr);
  };
  plots.addEventListener("pointerdown", (e) => {
    plots.setPointerCapture(e.pointerId);
    seek(e);
  }, { signal });
  plots.addEventListener("pointermove", (e) => {
    if (plots.hasPointerCapture(e.pointerId)) seek(e);
  }, { signal });
}

/**
 * The keys, on `target` (the player's element, or the document).
 * @param {Document | HTMLElement} target
 * @param {Player} player
 * @param {(on: boolean) => void} setPlaying
 * @param {AbortSignal} signal
 */
export function wireKeys(target, player, setPlaying, signal) {
  target.addEventListener("keydown", (e) => {
    if (!(e instanceof KeyboardEvent)) return;
    const t = e.target;
    const typing = t instanceof Element && t.closest("input, select, textarea");
    if (typing && !(t instanceof HTMLInputElement && t.type === "range")) return;
    /** @type {Record<string, () => void>} */
    const actions = {
      " ": () => setPlaying(!player.playing()),
      ArrowLeft: () => player.step(-1),
      ArrowRight: () => player.step(1),
      Home: () => player.set_frame(0),
      End: () => player.set_frame(player.frame_count() - 1),
    };
    const action = actions[e.key];
    if (action) {
      e.preventDefault();
      action();
    }
  }, { signal });
}

/**
 * Anything the user does on the player wakes its loop.
 * @param {HTMLElement} element
 * @param {() => void} wake
 * @param {AbortSignal} signal
 */
export function wakeOnInput(element, wake, signal) {
  for (const type of ["pointerdown", "pointermove", "wheel", "keydown", "input", "change"]) {
    element.addEventListener(type, wake, { signal, passive: true });
  }
}
