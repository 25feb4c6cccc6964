// @ts-check
// embusen's player in the page: `mount` builds the player's elements and ties
// together its parts, each a module of player/ with one job: elements.js its
// HTML, controls.js and info.js its controls and info panel, input.js its
// pointer and keys, loop.js its animation loop, loading.js its files and
// URLs, take.js a camera take, errors.js its errors, wasm.js the wasm module,
// teardown.js what `destroy` gives back. Parsing, kinematics, the translation
// method, plot layout, all drawing, and every choice and default the controls
// offer come from Rust (./pkg/embusen.js; its types in ./pkg/embusen.d.ts,
// which these files are checked against). This file keeps the public API:
// `mount`, `loadWasm` and the types other files import.
//
//   import { mount } from "./embusen.js";
//   const handle = await mount(document.querySelector("#here"), { src: "walk.bvh", autoplay: true });
//   handle.destroy(); // stops it and gives back everything it holds

import { wirePlayback, wireFullControls } from "./player/controls.js";
import { buildPlayer, canvasSizer } from "./player/elements.js";
import { errorShower, onPanic } from "./player/errors.js";
import { messageOf } from "./files.js";
import { showInfo } from "./player/info.js";
import { wireKeys, wirePlots, wireView, wakeOnInput } from "./player/input.js";
import { loadGuard, loaders } from "./player/loading.js";
import { AnimationLoop, frameShower } from "./player/loop.js";
import { cameraPanel, cameraTakes } from "./player/take.js";
import { keepTabIndex, release } from "./player/teardown.js";
import { startWasm } from "./player/wasm.js";

export { loadWasm } from "./player/wasm.js";

/** @typedef {import("./pkg/embusen.js").Player} Player */
/** @typedef {import("./pkg/embusen.js").PlayerSettings} Settings */
/** @typedef {import("./pkg/embusen.js").Options} Options */
/** @typedef {import("./pkg/embusen.js").Export} Export */
/** @typedef {import("./pkg/embusen.js").TakeSeries} TakeSeries */

/**
 * @typedef {object} MountOptions
 * @property {string} [src] the recording's URL; without it the built-in demo plays
 * @property {string} [accel] its accelerometer CSV's URL
 * @property {boolean} [autoplay]
 * @property {"full" | "minimal"} [chrome] "full": file picker, settings, export, info; "minimal": for embeds
 * @property {"document"} [keyboard] "document": keys page-wide; else when the player has focus
 * @property {string | string[]} [video] a video of the recording's take (`src` is its suit BVH): a camera-tracking
 *   panel (camera.js) is mounted under the player, its tracks shown in this player's 3D view
 * @property {string | string[]} [camera] with `video`: the camera.json's URL
 * @property {string | string[]} [background] with `video`: the background still's URL
 * @property {string | string[]} [board] with `video`: a still of the ChArUco board (its BOARD.json beside it)
 * @property {string} [truth] with `video`: the true hips per video frame (CSV)
 * @property {number | number[]} [offsetS] with `video`: added to a video frame's time to read the BVH (s), as `--offset-s`
 * @property {string} [track] with `video`: its track CSV (`src` the BVH tracked with it), shown with no tracking
 * @property {boolean} [autotrack] with `video`: track on opening
 * @property {"fused" | "paper"} [method] with `video`: the camera tracker
 */

/**
 * @typedef {object} Handle
 * @property {Player} player the wasm player
 * @property {HTMLElement} element
 * @property {(files: FileList | File[]) => Promise<void>} open opens a BVH (+ its accelerometer CSV) or a table
 * @property {(src: string, accel?: string) => Promise<void>} openUrl
 * @property {Promise<void>} ready resolves when the first recording is open
 * @property {(take: CameraTakeView) => boolean} showCameraTake shows a camera-tracked take of the open
 *   recording in the 3D view; false when it cannot (the error box says why, and the view stays as it was)
 * @property {() => void} clearCameraTake back to the recording alone
 * @property {(clock: Clock | null) => void} followClock shows the recording at `clock`'s instant, its controls
 *   driving `clock` (`null`: back to the player's own), and measures the player's canvases again
 * @property {() => void} wake redraws at once: for a clock that moved by itself
 * @property {CameraHandle} [camera] with `video`: the camera panel's handle (camera.js `mountCameraTracking`)
 * @property {() => void} destroy stops the player and releases its loop, observer, listeners and wasm memory,
 *   and the camera panel's video and workers
 */

/** @typedef {Awaited<ReturnType<typeof import("./camera.js").mountCameraTracking>>} CameraHandle */

/**
 * A clock the player follows instead of its own: a take's video (camera/clock.js).
 * @typedef {object} Clock
 * @property {(player: Player) => void} agree puts the player at the clock's instant, or the clock at the player's
 * @property {() => boolean} playing
 * @property {(on: boolean) => void} setPlaying
 */

/**
 * A camera-tracked take of the open recording, as `Player.show_camera_take` takes it.
 * @typedef {object} CameraTakeView
 * @property {ArrayLike<number>} cameraHipsCm x, y, z per frame of the recording (its coordinates, cm): the camera track's hips
 * @property {ArrayLike<number>} frustumCm the camera: line segments, 6 numbers each (two ends x, y, z, cm; the camera module's `CameraView.frustum_cm`)
 * @property {TakeSeries} [series] per video frame the uncertainty and the error against a truth, for the plots' (f)
 */


/**
 * Mounts a player into `element`. Without `src` it opens the built-in demo.
 * Resolves to a handle with the Rust `player`, `open(files)` and `destroy()`.
 * @param {HTMLElement} element
 * @param {MountOptions} [options]
 * @returns {Promise<Handle>}
 */
export async function mount(element, options = {}) {
  const chrome = options.chrome ?? "minimal";
  const restoreTabIndex = keepTabIndex(element);
  const get = buildPlayer(element, chrome);
  const [view, plots] = [get("canvas.view", HTMLCanvasElement), get("canvas.plots", HTMLCanvasElement)];
  const [errorBox, loadingBox, legendBox] = [get(".error", HTMLElement), get(".loading", HTMLElement), get(".legend", HTMLElement)];
  const [slider, readout, playButton] = [get(".slider", HTMLInputElement), get(".readout", HTMLElement), get("[data-action=play]", HTMLButtonElement)];
  const { choices, player } = await startWasm(view, plots).catch((e) => {
    // No wasm or no WebGL2 here: say so in the element, and to the caller.
    errorBox.textContent = `embusen cannot run here: ${messageOf(e)}`;
    errorBox.hidden = false;
    element.dataset.state = "error";
    restoreTabIndex();
    throw e;
  });
  // Every listener goes with this signal, so destroy() removes them all at once.
  const listeners = new AbortController();
  const { signal } = listeners;
  let destroyed = false;
  const showError = errorShower(errorBox);
  const loop = new AnimationLoop(player, frameShower(element, player, slider, readout, playButton));
  const wake = () => loop.wake();
  const refresh = () => showInfo(controlled);
  const guarded = loadGuard(element, { loadingBox, legendBox }, { showError, refresh, wake }, () => destroyed);
  const { open, openUrl } = loaders(player, guarded, showError);
  /** @type {import("./player/controls.js").Controlled} */
  const controlled = { element, player, choices, get, showError, open, signal };
  const take = cameraTakes(player, choices, legendBox, showError, wake);
  const resize = canvasSizer(player, view, plots, wake);
  const resizeObserver = new ResizeObserver(() => destroyed || resize());
  resizeObserver.observe(element);
  const setPlaying = (/** @type {boolean} */ on) => loop.play(on);
  // The clock's owner may have laid the player out anew: measured again.
  const followClock = (/** @type {Clock | null} */ clock) => destroyed || (loop.follow(clock), resize());
  wirePlayback(controlled, setPlaying);
  if (chrome === "full") wireFullControls(controlled, refresh);
  wireView(view, player, signal);
  wirePlots(plots, player, signal);
  wireKeys(options.keyboard === "document" ? document : element, player, setPlaying, signal);
  wakeOnInput(element, wake, signal);
  const stopShowingPanic = onPanic((message) => {
    loop.stop();
    playButton.textContent = "▶";
    playButton.disabled = true;
    showError(`embusen stopped on an internal error; reload the page. ${message}`);
  });
  const camera = cameraPanel();
  const destroy = () => {
    if (destroyed) return;
    destroyed = true;
    camera.close();
    loop.stop();
    resizeObserver.disconnect();
    listeners.abort();
    stopShowingPanic();
    release(element, chrome, player, view);
    restoreTabIndex();
  };
  const ready = (async () => {
    if (options.src) await openUrl(options.src, options.accel);
    else await guarded(() => player.load_demo());
    if (destroyed) return;
    resize();
    setPlaying(Boolean(options.autoplay));
    loop.start(); // playback starts now, not when loading began
  })();
  /** @type {Handle} */
  const handle = {
    player, element, open, openUrl, ready, destroy, showCameraTake: take.show, clearCameraTake: take.clear, followClock, wake,
  };
  /** @type {HTMLElement & {embusen?: Handle}} */ (element).embusen = handle;
  await ready;
  // A video, or several (a take filmed by several cameras; none given is [] from a page's address).
  if ([options.video ?? []].flat().length > 0 && !destroyed) await camera.open(element, options, handle, () => destroyed);
  return handle;
}
