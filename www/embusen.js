// @ts-check
// embusen's player in the page: `mount` builds the player's elements, reads
// files and URLs into bytes, and ties together its controls, its pointer and
// keys and its animation loop, each below in a section of its own (one file:
// each file of a player's first load costs its download). Parsing, kinematics, the translation
// method, plot layout, all drawing, and every choice and default the controls
// offer come from Rust (./pkg/embusen.js; its types in ./pkg/embusen.d.ts,
// which these files are checked against).
//
//   import { mount } from "./embusen.js";
//   const handle = await mount(document.querySelector("#here"), { src: "walk.bvh", autoplay: true });
//   handle.destroy(); // stops it and gives back everything it holds

import init, { Player, options as playerOptions } from "./pkg/embusen.js";

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
 * @property {string} [video] a video of the recording's take (`src` is its suit BVH): a camera-tracking
 *   panel (camera.js) is mounted under the player, its tracks shown in this player's 3D view
 * @property {string} [camera] with `video`: the camera.json's URL
 * @property {string} [background] with `video`: the background still's URL
 * @property {string} [board] with `video`: a still of the ChArUco board (its BOARD.json beside it)
 * @property {string} [truth] with `video`: the true hips per video frame (CSV)
 * @property {number} [offsetS] with `video`: added to a video frame's time to read the BVH (s), as `--offset-s`
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

/** The event the wasm module sends the window when it panics (src/web/panic.rs). */
const PANIC_EVENT = "embusen-panic";

/** The mounted players' ways to show a panic: after one the module is unusable. */
const panicked = new Set(/** @type {Array<(message: string) => void>} */ ([]));
window.addEventListener(PANIC_EVENT, (event) => {
  const message = String(/** @type {CustomEvent} */ (event).detail);
  for (const show of panicked) show(message);
});

/** @type {Promise<Options> | null} */
let wasmReady = null;
/** Loads the wasm module once per page, however many players there are (and the camera panel). */
export function loadWasm() {
  wasmReady ??= init({ module_or_path: new URL("./pkg/embusen_bg.wasm", import.meta.url) })
    .then(() => playerOptions())
    .catch((e) => {
      wasmReady = null; // a later mount tries again
      throw e;
    });
  return wasmReady;
}

// --- The player's controls: their HTML, the playback controls (play, frame,
// speed, loop, follow, the original's ghost), and with the full chrome the
// method's settings, the file picker, the exports and the info panel. Every
// choice and default comes from the wasm module's `options()`.

const FULL_CONTROLS = `
  <label class="file">Open… <input type="file" multiple accept=".bvh,.csv,.txt"></label>
  <span class="sep"></span>
  <label>method <select data-setting="method"></select></label>
  <label class="paper-only">smoothing <select data-setting="smoothing"></select></label>
  <label class="paper-only">window <input data-setting="window" type="number"> s</label>
  <label class="paper-only">dyEps <input data-setting="dyeps" type="number"> cm</label>
  <label class="contact-only" title="how far the sole lies below the foot's lowest joint when the foot stands flat">sole
    <select data-setting="sole"></select> cm below the joints</label>
  <label>left foot <select data-setting="left"></select></label>
  <label>right foot <select data-setting="right"></select></label>
  <span class="sep"></span>
  <button data-action="export-recording" title="download the recording as the method chosen corrects it (a camera track's is the camera panel's)">⬇ corrected file</button>
  <button data-action="export-hips" title="download the hips trajectory, original and as the method chosen corrects it, as CSV">⬇ hips CSV</button>`;

const PLAYBACK_CONTROLS = `
  <button data-action="play" title="play/pause (space)">▶</button>
  <input class="slider" type="range" min="0" max="0" value="0" aria-label="frame">
  <span class="readout">0.00 s · frame 0 / 0</span>
  <label>speed <select data-action="speed"></select></label>
  <label><input type="checkbox" data-action="loop"> loop</label>
  <label><input type="checkbox" data-action="follow"> follow</label>
  <label><input type="checkbox" data-action="solid"> solid</label>
  <label title="the body's soft shadow on the floor: how high it is"><input type="checkbox" data-action="shadow"> shadow</label>
  <label>original <select data-action="ghost"></select></label>`;

/**
 * What the controls work on.
 * @typedef {object} Controlled
 * @property {HTMLElement} element the player's
 * @property {Player} player
 * @property {Options} choices
 * @property {<T extends Element>(selector: string, type: new (...args: any[]) => T) => T} get the element at `selector`, a `type`
 *   (any: a constructor's arguments are whatever the DOM's are)
 * @property {(message: string) => void} showError
 * @property {(fileList: FileList | File[]) => Promise<void>} open
 * @property {AbortSignal} signal removes the listeners
 */

/**
 * Each setting's control: its `data-setting`, the field of `Settings` it
 * sets, how it shows the field's value, and how it reads it back.
 * @type {Array<{ control: string, field: keyof Settings, show: (value: Settings[keyof Settings]) => string, read: (text: string) => Settings[keyof Settings] }>}
 */
const SETTING_CONTROLS = [
  { control: "method", field: "method", show: String, read: String },
  { control: "smoothing", field: "smoothing", show: String, read: String },
  { control: "window", field: "window_s", show: String, read: Number },
  { control: "dyeps", field: "dy_eps_cm", show: String, read: Number },
  { control: "sole", field: "sole_depth_cm", show: (v) => (v === null ? "auto" : String(v)), read: (t) => (t === "auto" ? null : Number(t)) },
  { control: "left", field: "left_foot", show: String, read: String },
  { control: "right", field: "right_foot", show: String, read: String },
];

/** A thrown value's message. @param {unknown} e */
const messageOf = (e) => String(e instanceof Error ? e.message : e);

/**
 * Fills a `<select>` with `[value, label]` entries and selects `selected`.
 * @param {HTMLSelectElement} select
 * @param {Array<[string, string]>} entries
 * @param {string} selected
 */
function fillSelect(select, entries, selected) {
  select.replaceChildren(...entries.map(([value, label]) => new Option(label, value, false, value === selected)));
}

/** A setting's control. @param {HTMLElement} element @param {string} control */
function settingControl(element, control) {
  const found = element.querySelector(`[data-setting=${control}]`);
  if (found instanceof HTMLInputElement || found instanceof HTMLSelectElement) return found;
  throw new Error(`embusen: no setting control ${control}`);
}

/**
 * The playback controls, wired.
 * @param {Controlled} c
 * @param {(on: boolean) => void} setPlaying
 */
function wirePlayback({ player, choices, get, showError, signal }, setPlaying) {
  const { defaults } = choices;
  const speed = get("[data-action=speed]", HTMLSelectElement);
  fillSelect(speed, choices.speeds.map((s) => [String(s), `${s}×`]), String(defaults.speed));
  const ghost = get("[data-action=ghost]", HTMLSelectElement);
  fillSelect(ghost, choices.ghosts.map((g) => [g.value, g.label]), defaults.ghost);
  const looping = get("[data-action=loop]", HTMLInputElement);
  looping.checked = defaults.looping;
  const follow = get("[data-action=follow]", HTMLInputElement);
  follow.checked = defaults.follow;
  const solid = get("[data-action=solid]", HTMLInputElement);
  solid.checked = defaults.solid;
  const shadow = get("[data-action=shadow]", HTMLInputElement);
  shadow.checked = defaults.shadow;
  const slider = get(".slider", HTMLInputElement);
  get("[data-action=play]", HTMLButtonElement).addEventListener("click", () => setPlaying(!player.playing()), { signal });
  slider.addEventListener("input", () => player.set_frame(+slider.value), { signal });
  /** @param {() => void} change */
  const guarded = (change) => () => {
    try {
      change();
      showError("");
    } catch (e) {
      showError(messageOf(e));
    }
  };
  speed.addEventListener("change", () => {
    try {
      player.set_speed(+speed.value);
    } catch (e) {
      showError(messageOf(e));
    }
  }, { signal });
  looping.addEventListener("change", () => player.set_looping(looping.checked), { signal });
  follow.addEventListener("change", () => player.set_follow(follow.checked), { signal });
  solid.addEventListener("change", () => player.set_solid(solid.checked), { signal });
  shadow.addEventListener("change", () => player.set_shadow(shadow.checked), { signal });
  ghost.addEventListener("change", guarded(() => player.set_ghost(/** @type {import("./pkg/embusen.js").Ghost} */ (ghost.value))), { signal });
}

/**
 * The full chrome's controls, wired: the file picker, the method's
 * settings, the exports, a drop on the player.
 * @param {Controlled} c
 * @param {() => void} refresh shows the settings in use
 */
function wireFullControls(c, refresh) {
  const { element, player, choices, get, showError, open, signal } = c;
  const { defaults } = choices;
  const file = get("input[type=file]", HTMLInputElement);
  file.addEventListener("change", () => file.files && open(file.files), { signal });
  fillSelect(get("[data-setting=method]", HTMLSelectElement), choices.methods.map((m) => [m.value, m.label]), defaults.settings.method);
  fillSelect(get("[data-setting=smoothing]", HTMLSelectElement), choices.smoothings.map((m) => [m.value, m.label]), defaults.settings.smoothing);
  fillSelect(
    get("[data-setting=sole]", HTMLSelectElement),
    [["auto", "auto"], ...choices.sole_depths_cm.map((d) => /** @type {[string, string]} */ ([String(d), String(d)]))],
    "auto",
  );
  for (const [control, range] of /** @type {const} */ ([["window", choices.window_s], ["dyeps", choices.dy_eps_cm]])) {
    const input = get(`[data-setting=${control}]`, HTMLInputElement);
    input.min = String(range.min);
    input.max = String(range.max);
    input.step = String(range.step);
  }
  element.dataset.method = defaults.settings.method;
  for (const { control, field, read } of SETTING_CONTROLS) {
    const input = settingControl(element, control);
    input.addEventListener("change", () => {
      try {
        player.set_settings({ ...player.settings(), [field]: read(input.value) });
        showError("");
      } catch (e) {
        showError(messageOf(e));
      }
      refresh(); // on error too: the controls show the settings in use
    }, { signal });
  }
  /** @param {() => Export} make */
  const download = (make) => {
    try {
      const { name, text } = make();
      const a = document.createElement("a");
      a.href = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
      a.download = name;
      a.click();
      setTimeout(() => URL.revokeObjectURL(a.href), 1000);
    } catch (e) {
      showError(messageOf(e));
    }
  };
  get("[data-action=export-recording]", HTMLButtonElement).addEventListener("click", () => download(() => player.export_recording()), { signal });
  get("[data-action=export-hips]", HTMLButtonElement).addEventListener("click", () => download(() => player.export_hips_csv()), { signal });
  // A drop here is this player's: preventDefault tells the page's own drop handler so.
  element.addEventListener("dragover", (e) => e.preventDefault(), { signal });
  element.addEventListener("drop", (e) => {
    e.preventDefault();
    if (e.dataTransfer) open(e.dataTransfer.files);
  }, { signal });
}

/**
 * Shows the open recording's facts (with the full chrome) and the settings in use.
 * @param {Controlled} c
 */
function showInfo({ element, player, get }) {
  get(".slider", HTMLInputElement).max = String(Math.max(0, player.frame_count() - 1));
  const info = element.querySelector(".info");
  // Nothing open (the first load failed): no facts to show.
  if (!info || player.frame_count() === 0) return;
  const about = player.info();
  const rows = [
    ["file", about.name],
    ["joints", String(about.joint_names.length)],
    ["frames", String(about.frame_count)],
    ["rate", `${+about.fps.toFixed(2)} Hz`],
    ["duration", `${about.duration_s.toFixed(2)} s`],
    ["feet", `${about.feet.left} / ${about.feet.right}`],
    ["method", about.method],
    ...(about.sole_depth
      ? [["sole", `${about.sole_depth.depth_cm} cm below the lowest foot joint${about.sole_depth.estimated ? " (estimated)" : ""}`]]
      : []),
    ["accelerations", about.accel_source],
  ];
  info.replaceChildren(
    ...rows.map(([k, v]) => {
      const r = document.createElement("div");
      const key = document.createElement("b");
      const value = document.createElement("span");
      key.textContent = k;
      value.textContent = v;
      r.append(key, " ", value);
      return r;
    }),
    ...about.warnings.map((w) => Object.assign(document.createElement("div"), { className: "warning", textContent: `⚠ ${w}` })),
  );
  const joints = about.joint_names.map((name) => /** @type {[string, string]} */ ([name, name]));
  fillSelect(get("[data-setting=left]", HTMLSelectElement), joints, about.feet.left);
  fillSelect(get("[data-setting=right]", HTMLSelectElement), joints, about.feet.right);
  const settings = player.settings();
  for (const { control, field, show } of SETTING_CONTROLS) {
    if (field === "left_foot" || field === "right_foot") continue; // null: detected, shown above
    settingControl(element, control).value = show(settings[field]);
  }
  // The paper method's own settings only show when it is chosen.
  element.dataset.method = settings.method;
  sayWhatDownloadsHold(element, settings.method);
}

/**
 * The player's downloads say whose result they hold: the method's, not a
 * camera track's (that one is the camera panel's).
 * @param {HTMLElement} element
 * @param {string} method
 */
function sayWhatDownloadsHold(element, method) {
  const recording = element.querySelector("[data-action=export-recording]");
  const hips = element.querySelector("[data-action=export-hips]");
  if (recording) recording.textContent = `⬇ file by ${method}`;
  if (hips) hips.textContent = `⬇ hips CSV by ${method}`;
}

// --- The player's pointer and keyboard: orbit (drag), pan (right or shift drag,
// two fingers), zoom (wheel, pinch) in the 3D view; click or drag on a plot
// to seek; space, arrows, Home and End.

/**
 * Orbit, pan and zoom in the 3D view.
 * @param {HTMLCanvasElement} view
 * @param {Player} player
 * @param {AbortSignal} signal removes the listeners
 */
function wireView(view, player, signal) {
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
function wirePlots(plots, player, signal) {
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
function wireKeys(target, player, setPlaying, signal) {
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

// --- The player's animation loop. It runs every animation frame while the
// player plays or the user acts on it; paused and left alone for a second,
// it looks again only five times a second, so that an idle player gives its
// core to the page's other work (the camera tracker's worker: software
// compositing 60 frames a second halved its speed). Anything the user does
// wakes it at once.

class AnimationLoop {
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

// --- the player

/** The 3D view's legend of the floor paths (shown with a camera take), over the view's bottom left. */
const LEGEND_STYLE = "position:absolute;left:8px;bottom:8px;padding:4px 8px;border-radius:4px;"
  + "background:rgba(22,24,28,0.78);font-size:12px;line-height:1.5;pointer-events:none";

/**
 * Fills `element` with the player's elements; gives back a typed finder.
 * @param {HTMLElement} element
 * @param {"full" | "minimal"} chrome
 */
function buildPlayer(element, chrome) {
  element.classList.add("embusen", `embusen-${chrome}`);
  element.tabIndex = 0;
  element.innerHTML = `
    <div class="stage"><canvas class="view"></canvas>
      <div class="legend" hidden style="${LEGEND_STYLE}"></div>
      <div class="loading" hidden>Loading…</div></div>
    <canvas class="plots"></canvas>
    <div class="error" role="alert" hidden></div>
    <div class="controls">${PLAYBACK_CONTROLS}${chrome === "full" ? FULL_CONTROLS : ""}</div>
    ${chrome === "full" ? '<div class="info"></div>' : ""}`;
  /**
   * The element under the player matching `selector`, which must be a `type`.
   * @template {Element} T
   * @param {string} selector
   * @param {new (...args: any[]) => T} type (any: a constructor's arguments are whatever the DOM's are)
   * @returns {T}
   */
  const get = (selector, type) => {
    const found = element.querySelector(selector);
    if (!(found instanceof type)) throw new Error(`embusen: no ${type.name} at ${selector}`);
    return found;
  };
  return get;
}

/**
 * The 3D view's camera take: its legend, and showing and clearing it.
 * @param {Player} player
 * @param {Options} choices
 * @param {HTMLElement} legendBox
 * @param {(message: string) => void} showError
 * @param {() => void} wake
 */
function cameraTakes(player, choices, legendBox, showError, wake) {
  legendBox.replaceChildren(...choices.take_legend.map(({ label, color_css }) => {
    const row = document.createElement("div");
    const swatch = document.createElement("span");
    swatch.style.cssText = `display:inline-block;width:16px;height:4px;margin-right:6px;vertical-align:middle;background:${color_css}`;
    row.append(swatch, label);
    return row;
  }));
  /** @param {CameraTakeView} take */
  const show = ({ cameraHipsCm, frustumCm, series }) => {
    try {
      player.show_camera_take(Float64Array.from(cameraHipsCm), Float64Array.from(frustumCm), series);
      legendBox.hidden = false;
      showError("");
      return true;
    } catch (e) {
      showError(messageOf(e)); // and the view stays as it was
      return false;
    } finally {
      wake();
    }
  };
  const clear = () => {
    player.clear_camera_take();
    legendBox.hidden = true;
    wake();
  };
  return { show, clear };
}

/** @param {string} url */
const fetchBytes = async (url) => {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
};
/** @param {string} url */
const fileName = (url) => decodeURIComponent(new URL(url, location.href).pathname.split("/").pop() || url);
/** @param {Blob} file */
const bytesOf = async (file) => new Uint8Array(await file.arrayBuffer());

/**
 * The player's loads: each shows "Loading…", and on failure the error,
 * keeping what was open.
 * @param {Player} player
 * @param {(work: () => void) => Promise<void>} guarded runs a load
 * @param {(message: string) => void} showError
 */
function loaders(player, guarded, showError) {
  /** @param {FileList | File[]} fileList */
  const open = async (fileList) => {
    const files = [...fileList];
    const bvh = files.find((f) => /\.bvh$/i.test(f.name));
    const csv = files.find((f) => /\.(csv|txt)$/i.test(f.name));
    const main = bvh ?? csv ?? files[0];
    if (!main) return;
    const accel = bvh ? csv : undefined;
    const [bytes, accelBytes] = await Promise.all([bytesOf(main), accel ? bytesOf(accel) : undefined]);
    await guarded(() => player.load(main.name, bytes, accel?.name, accelBytes));
  };
  /** @param {string} src @param {string} [accel] */
  const openUrl = async (src, accel) => {
    try {
      const [bytes, accelBytes] = await Promise.all([fetchBytes(src), accel ? fetchBytes(accel) : undefined]);
      await guarded(() => player.load(fileName(src), bytes, accel && fileName(accel), accelBytes));
    } catch (e) {
      showError(messageOf(e));
    }
  };
  return { open, openUrl };
}

/**
 * The camera panel in `host` under the player, for a take (`options.video`):
 * its code only now, and only for a take, so a player alone loads none of it.
 * @param {HTMLElement} host
 * @param {MountOptions} options
 * @param {Handle} handle the player's
 * @param {() => boolean} destroyed whether the player went meanwhile
 * @returns {Promise<CameraHandle | null>}
 */
async function mountCamera(host, options, handle, destroyed) {
  const { mountCameraTracking } = await import("./camera.js");
  const { video, src, camera, background, board, truth, method, offsetS, track, autotrack } = options;
  const panel = await mountCameraTracking(host, {
    video, src, camera, background, board, truth, method, offsetS, track, autotrack, player: handle,
  });
  if (!destroyed()) return (handle.camera = panel);
  panel.destroy();
  return null;
}

/**
 * The wasm module (once per page) and a player over the two canvases.
 * @param {HTMLCanvasElement} view
 * @param {HTMLCanvasElement} plots
 */
async function startWasm(view, plots) {
  const choices = await loadWasm();
  return { choices, player: new Player(view, plots) };
}

/**
 * A load's guard: it shows "Loading…" and, on failure, the error, keeping
 * what was open; a success hides the camera take (it belongs to the
 * recording it was open with) and shows the new recording's facts.
 * @param {HTMLElement} element
 * @param {{loadingBox: HTMLElement, legendBox: HTMLElement}} boxes
 * @param {{showError: (message: string) => void, refresh: () => void, wake: () => void}} then
 * @param {() => boolean} destroyed
 */
function loadGuard(element, { loadingBox, legendBox }, { showError, refresh, wake }, destroyed) {
  return async (/** @type {() => void} */ work) => {
    loadingBox.hidden = false;
    element.dataset.state = "loading";
    await new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));
    if (destroyed()) return;
    try {
      work();
      legendBox.hidden = true;
      showError("");
      refresh();
    } catch (e) {
      showError(messageOf(e));
    } finally {
      loadingBox.hidden = true;
      element.dataset.state = "ready";
      wake();
    }
  };
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
function frameShower(element, player, slider, readout, playButton) {
  return (/** @type {number} */ frame, /** @type {boolean} */ playing) => {
    if (+slider.value !== frame) slider.value = String(frame);
    if (element.dataset.frame !== String(frame)) element.dataset.frame = String(frame);
    const said = `${player.time_s().toFixed(2)} s · frame ${frame} / ${Math.max(0, player.frame_count() - 1)}`;
    if (readout.textContent !== said) readout.textContent = said;
    const label = playing ? "❚❚" : "▶";
    if (playButton.textContent !== label) playButton.textContent = label;
  };
}

/**
 * Gives back what a destroyed player held: its wasm memory, its GPU
 * context, its elements and marks.
 * @param {HTMLElement} element
 * @param {"full" | "minimal"} chrome
 * @param {Player} player
 * @param {HTMLCanvasElement} view
 */
function release(element, chrome, player, view) {
  try {
    player.free();
  } catch {
    // After a panic the module cannot free; the page is going away anyway.
  }
  // Give the GPU context back now rather than at garbage collection: a page has only a few.
  view.getContext("webgl2")?.getExtension("WEBGL_lose_context")?.loseContext();
  element.replaceChildren();
  element.classList.remove("embusen", `embusen-${chrome}`);
  for (const key of ["state", "frame", "method"]) delete element.dataset[key];
  delete /** @type {HTMLElement & {embusen?: Handle}} */ (element).embusen;
}

/**
 * Mounts a player into `element`. Without `src` it opens the built-in demo.
 * Resolves to a handle with the Rust `player`, `open(files)` and `destroy()`.
 * @param {HTMLElement} element
 * @param {MountOptions} [options]
 * @returns {Promise<Handle>}
 */
export async function mount(element, options = {}) {
  const chrome = options.chrome ?? "minimal";
  const tabIndexBefore = element.getAttribute("tabindex");
  const restoreTabIndex = () => {
    if (tabIndexBefore === null) element.removeAttribute("tabindex");
    else element.setAttribute("tabindex", tabIndexBefore);
  };
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
  /** @param {string} message */
  const showError = (message) => {
    errorBox.textContent = message;
    errorBox.hidden = !message;
  };
  const loop = new AnimationLoop(player, frameShower(element, player, slider, readout, playButton));
  const wake = () => loop.wake();
  const refresh = () => showInfo(controlled);
  const guarded = loadGuard(element, { loadingBox, legendBox }, { showError, refresh, wake }, () => destroyed);
  const { open, openUrl } = loaders(player, guarded, showError);
  /** @type {Controlled} */
  const controlled = { element, player, choices, get, showError, open, signal };
  const take = cameraTakes(player, choices, legendBox, showError, wake);
  const resize = () => {
    const dpr = window.devicePixelRatio || 1;
    const [v, p] = [view.getBoundingClientRect(), plots.getBoundingClientRect()];
    player.resize(Math.round(v.width * dpr), Math.round(v.height * dpr), Math.round(p.width * dpr), Math.round(p.height * dpr));
    player.draw();
    wake();
  };
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
  // Anything the user does wakes the loop.
  for (const type of ["pointerdown", "pointermove", "wheel", "keydown", "input", "change"]) {
    element.addEventListener(type, wake, { signal, passive: true });
  }
  /** @param {string} message */
  const showPanic = (message) => {
    loop.stop();
    playButton.textContent = "▶";
    playButton.disabled = true;
    showError(`embusen stopped on an internal error; reload the page. ${message}`);
  };
  panicked.add(showPanic);
  /** The camera panel under the player (`options.video`) and its element. @type {{host: HTMLElement, panel: CameraHandle | null} | null} */
  let camera = null;
  const destroy = () => {
    if (destroyed) return;
    destroyed = true;
    camera?.panel?.destroy();
    camera?.host.remove();
    camera = null;
    loop.stop();
    resizeObserver.disconnect();
    listeners.abort();
    panicked.delete(showPanic);
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
  if (options.video && !destroyed) {
    /** @type {{host: HTMLElement, panel: CameraHandle | null}} */
    const c = { host: document.createElement("div"), panel: null };
    camera = c;
    element.insertAdjacentElement("afterend", c.host);
    c.panel = await mountCamera(c.host, options, handle, () => destroyed);
  }
  return handle;
}
