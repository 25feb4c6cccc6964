// @ts-check
// embusen's JavaScript shell. It only wires the page: it builds the player's
// elements, reads files and URLs into bytes, forwards pointer and keyboard
// input, and runs the animation loop. Parsing, kinematics, the translation
// method, plot layout, all drawing, and every choice and default the controls
// offer come from Rust (./pkg/embusen.js; its types in ./pkg/embusen.d.ts,
// which this file is checked against).
//
//   import { mount } from "./embusen.js";
//   const handle = await mount(document.querySelector("#here"), { src: "walk.bvh", autoplay: true });
//   handle.destroy(); // stops it and gives back everything it holds

import init, { Player, options as playerOptions } from "./pkg/embusen.js";

/** @typedef {import("./pkg/embusen.js").Settings} Settings */
/** @typedef {import("./pkg/embusen.js").Options} Options */
/** @typedef {import("./pkg/embusen.js").Export} Export */

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
 * @property {any} [camera] with `video`: the camera panel's handle (camera.js `mountCameraTracking`)
 * @property {() => void} destroy stops the player and releases its loop, observer, listeners and wasm memory,
 *   and the camera panel's video and workers
 */

/**
 * A camera-tracked take of the open recording, as `Player.show_camera_take` takes it.
 * @typedef {object} CameraTakeView
 * @property {string} bodyShapeJson the body model (the camera module's `body_shape_json`)
 * @property {ArrayLike<number>} cameraHipsCm x, y, z per frame of the recording (its coordinates, cm): the camera track's hips
 * @property {ArrayLike<number>} frustumCm the camera: line segments, 6 numbers each (two ends x, y, z, cm; the camera module's `camera_frustum`)
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
  <button data-action="export-recording" title="download the corrected recording">⬇ corrected file</button>
  <button data-action="export-hips" title="download the hips trajectory as CSV">⬇ hips CSV</button>`;

const PLAYBACK_CONTROLS = `
  <button data-action="play" title="play/pause (space)">▶</button>
  <input class="slider" type="range" min="0" max="0" value="0" aria-label="frame">
  <span class="readout">0.00 s · frame 0 / 0</span>
  <label>speed <select data-action="speed"></select></label>
  <label><input type="checkbox" data-action="loop"> loop</label>
  <label><input type="checkbox" data-action="follow"> follow</label>
  <label>original <select data-action="ghost"></select></label>`;

/** The 3D view's legend of the floor paths (shown with a camera take), over the view's bottom left. */
const LEGEND_STYLE = "position:absolute;left:8px;bottom:8px;padding:4px 8px;border-radius:4px;"
  + "background:rgba(22,24,28,0.78);font-size:12px;line-height:1.5;pointer-events:none";

/**
 * Each setting's control: its `data-setting`, the field of `Settings` it
 * sets, how it shows the field's value, and how it reads it back.
 * @type {Array<{ control: string, field: keyof Settings, show: (value: any) => string, read: (text: string) => any }>}
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

/**
 * Fills a `<select>` with `[value, label]` entries and selects `selected`.
 * @param {HTMLSelectElement} select
 * @param {Array<[string, string]>} entries
 * @param {string} selected
 */
function fillSelect(select, entries, selected) {
  select.replaceChildren(...entries.map(([value, label]) => new Option(label, value, false, value === selected)));
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
   * @param {new (...args: any[]) => T} type
   * @returns {T}
   */
  const get = (selector, type) => {
    const found = element.querySelector(selector);
    if (!(found instanceof type)) throw new Error(`embusen: no ${type.name} at ${selector}`);
    return found;
  };
  const view = get("canvas.view", HTMLCanvasElement);
  const plots = get("canvas.plots", HTMLCanvasElement);
  const errorBox = get(".error", HTMLElement);
  const loadingBox = get(".loading", HTMLElement);
  const legendBox = get(".legend", HTMLElement);
  const slider = get(".slider", HTMLInputElement);
  const readout = get(".readout", HTMLElement);
  const playButton = get("[data-action=play]", HTMLButtonElement);
  const info = element.querySelector(".info");
  /** @param {string} control */
  const settingControl = (control) => {
    const found = element.querySelector(`[data-setting=${control}]`);
    if (found instanceof HTMLInputElement || found instanceof HTMLSelectElement) return found;
    throw new Error(`embusen: no setting control ${control}`);
  };

  /** @type {Options} */
  let choices;
  /** @type {Player} */
  let player;
  try {
    choices = await loadWasm();
    player = new Player(view, plots);
  } catch (e) {
    // No wasm or no WebGL2 here: say so in the element, and to the caller.
    errorBox.textContent = `embusen cannot run here: ${String(e instanceof Error ? e.message : e)}`;
    errorBox.hidden = false;
    element.dataset.state = "error";
    restoreTabIndex();
    throw e;
  }
  // Every listener goes with this signal, so destroy() removes them all at once.
  const listeners = new AbortController();
  const { signal } = listeners;
  let destroyed = false;
  /** The animation frame requested and not yet run, 0 for none. */
  let frameRequest = 0;

  // --- errors, loading, info ------------------------------------------------
  /** @param {string} message */
  const showError = (message) => {
    errorBox.textContent = message;
    errorBox.hidden = !message;
  };
  /** @param {unknown} e */
  const messageOf = (e) => String(e instanceof Error ? e.message : e);
  /** @param {boolean} on */
  const setLoading = (on) => {
    loadingBox.hidden = !on;
    element.dataset.state = on ? "loading" : "ready";
  };
  /** @returns {Promise<void>} */
  const nextPaint = () => new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));

  /** Shows the open recording's facts and the settings in use. */
  const refresh = () => {
    slider.max = String(Math.max(0, player.frame_count() - 1));
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
        const row = document.createElement("div");
        const key = document.createElement("b");
        const value = document.createElement("span");
        key.textContent = k;
        value.textContent = v;
        row.append(key, " ", value);
        return row;
      }),
      ...about.warnings.map((w) => {
        const row = document.createElement("div");
        row.className = "warning";
        row.textContent = `⚠ ${w}`;
        return row;
      }),
    );
    const joints = about.joint_names.map((name) => /** @type {[string, string]} */ ([name, name]));
    fillSelect(get("[data-setting=left]", HTMLSelectElement), joints, about.feet.left);
    fillSelect(get("[data-setting=right]", HTMLSelectElement), joints, about.feet.right);
    const settings = player.settings();
    for (const { control, field, show } of SETTING_CONTROLS) {
      if (field === "left_foot" || field === "right_foot") continue; // null: detected, shown above
      settingControl(control).value = show(settings[field]);
    }
    // The paper method's own settings only show when it is chosen.
    element.dataset.method = settings.method;
  };

  /**
   * Runs a load; on failure shows the error and keeps what was open.
   * @param {() => void} work
   */
  const guarded = async (work) => {
    setLoading(true);
    await nextPaint();
    if (destroyed) return;
    try {
      work();
      legendBox.hidden = true; // a take belongs to the recording it was open with
      showError("");
      refresh();
    } catch (e) {
      showError(messageOf(e));
    } finally {
      setLoading(false);
      wake();
    }
  };

  /** @param {Blob} file */
  const bytesOf = async (file) => new Uint8Array(await file.arrayBuffer());
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
  /** @param {string} url */
  const fetchBytes = async (url) => {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    return new Uint8Array(await response.arrayBuffer());
  };
  /** @param {string} url */
  const fileName = (url) => decodeURIComponent(new URL(url, location.href).pathname.split("/").pop() || url);
  /**
   * @param {string} src
   * @param {string} [accel]
   */
  const openUrl = async (src, accel) => {
    try {
      const [bytes, accelBytes] = await Promise.all([fetchBytes(src), accel ? fetchBytes(accel) : undefined]);
      await guarded(() => player.load(fileName(src), bytes, accel && fileName(accel), accelBytes));
    } catch (e) {
      showError(messageOf(e));
    }
  };

  // --- a camera-tracked take ------------------------------------------------------
  legendBox.replaceChildren(...choices.take_legend.map(({ label, color_css }) => {
    const row = document.createElement("div");
    const swatch = document.createElement("span");
    swatch.style.cssText = `display:inline-block;width:16px;height:4px;margin-right:6px;vertical-align:middle;background:${color_css}`;
    row.append(swatch, label);
    return row;
  }));
  /** @param {CameraTakeView} take */
  const showCameraTake = ({ bodyShapeJson, cameraHipsCm, frustumCm }) => {
    try {
      player.show_camera_take(bodyShapeJson, Float64Array.from(cameraHipsCm), Float64Array.from(frustumCm));
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
  const clearCameraTake = () => {
    player.clear_camera_take();
    legendBox.hidden = true;
    wake();
  };

  // --- size -------------------------------------------------------------------
  const resize = () => {
    const dpr = window.devicePixelRatio || 1;
    const v = view.getBoundingClientRect();
    const p = plots.getBoundingClientRect();
    player.resize(Math.round(v.width * dpr), Math.round(v.height * dpr), Math.round(p.width * dpr), Math.round(p.height * dpr));
    player.draw();
    wake();
  };
  const resizeObserver = new ResizeObserver(() => destroyed || resize());
  resizeObserver.observe(element);

  // --- controls -----------------------------------------------------------------
  /** @param {boolean} on */
  const setPlaying = (on) => {
    player.set_playing(on);
    wake();
    playButton.textContent = on ? "❚❚" : "▶";
  };
  const { defaults } = choices;
  const speed = get("[data-action=speed]", HTMLSelectElement);
  fillSelect(speed, choices.speeds.map((s) => [String(s), `${s}×`]), String(defaults.speed));
  const ghost = get("[data-action=ghost]", HTMLSelectElement);
  fillSelect(ghost, choices.ghosts.map((g) => [g.value, g.label]), defaults.ghost);
  const looping = get("[data-action=loop]", HTMLInputElement);
  looping.checked = defaults.looping;
  const follow = get("[data-action=follow]", HTMLInputElement);
  follow.checked = defaults.follow;

  playButton.addEventListener("click", () => setPlaying(!player.playing()), { signal });
  slider.addEventListener("input", () => player.set_frame(+slider.value), { signal });
  speed.addEventListener("change", () => {
    try {
      player.set_speed(+speed.value);
    } catch (e) {
      showError(messageOf(e));
    }
  }, { signal });
  looping.addEventListener("change", () => player.set_looping(looping.checked), { signal });
  follow.addEventListener("change", () => player.set_follow(follow.checked), { signal });
  ghost.addEventListener("change", () => {
    try {
      player.set_ghost(/** @type {import("./pkg/embusen.js").Ghost} */ (ghost.value));
      showError("");
    } catch (e) {
      showError(messageOf(e));
    }
  }, { signal });

  if (chrome === "full") {
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
      const input = settingControl(control);
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
    get("[data-action=export-recording]", HTMLButtonElement)
      .addEventListener("click", () => download(() => player.export_recording()), { signal });
    get("[data-action=export-hips]", HTMLButtonElement)
      .addEventListener("click", () => download(() => player.export_hips_csv()), { signal });
    // A drop here is this player's: preventDefault tells the page's own drop handler so.
    element.addEventListener("dragover", (e) => e.preventDefault(), { signal });
    element.addEventListener("drop", (e) => {
      e.preventDefault();
      if (e.dataTransfer) open(e.dataTransfer.files);
    }, { signal });
  }

  // --- pointer: orbit (drag), pan (right/shift drag, two fingers), zoom (wheel, pinch)
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

  // Click or drag on a plot: seek.
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

  // --- keyboard -----------------------------------------------------------------
  const keyTarget = options.keyboard === "document" ? document : element;
  keyTarget.addEventListener("keydown", (e) => {
    if (!(e instanceof KeyboardEvent)) return;
    const target = e.target;
    const typing = target instanceof Element && target.closest("input, select, textarea");
    if (typing && !(target instanceof HTMLInputElement && target.type === "range")) return;
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

  // --- the animation loop ---------------------------------------------------------
  // It runs every animation frame while the player plays or the user acts on
  // it; paused and left alone for a second, it looks again only five times a
  // second, so that an idle player gives its core to the page's other work
  // (the camera tracker's worker: software compositing 60 frames a second
  // halved its speed). Anything the user does wakes it at once.
  let last = performance.now();
  let idleTicks = 0;
  let idleTimer = 0;
  /** @param {number} now */
  const loop = (now) => {
    frameRequest = 0;
    player.tick((now - last) / 1000);
    last = now;
    const frame = player.frame();
    // Only what changed is written: an unchanged page is not repainted.
    if (+slider.value !== frame) slider.value = String(frame);
    if (element.dataset.frame !== String(frame)) element.dataset.frame = String(frame);
    const said = `${player.time_s().toFixed(2)} s · frame ${frame} / ${Math.max(0, player.frame_count() - 1)}`;
    if (readout.textContent !== said) readout.textContent = said;
    if (!player.playing() && playButton.textContent !== "▶") playButton.textContent = "▶";
    idleTicks = player.playing() ? 0 : idleTicks + 1;
    if (idleTicks < 60) frameRequest = requestAnimationFrame(loop);
    else idleTimer = window.setTimeout(() => {
      idleTimer = 0;
      frameRequest = requestAnimationFrame(loop);
    }, 200);
  };
  const wake = () => {
    idleTicks = 0;
    if (!idleTimer) return;
    clearTimeout(idleTimer);
    idleTimer = 0;
    last = performance.now();
    frameRequest = requestAnimationFrame(loop);
  };
  for (const type of ["pointerdown", "pointermove", "wheel", "keydown", "input", "change"]) {
    element.addEventListener(type, wake, { signal, passive: true });
  }
  const stopLoop = () => {
    if (frameRequest) cancelAnimationFrame(frameRequest);
    clearTimeout(idleTimer);
    frameRequest = idleTimer = 0;
  };

  /** @param {string} message */
  const showPanic = (message) => {
    stopLoop();
    playButton.textContent = "▶";
    playButton.disabled = true;
    showError(`embusen stopped on an internal error; reload the page. ${message}`);
  };
  panicked.add(showPanic);

  /** The camera panel under the player (`options.video`) and its element. @type {{panel: any, host: HTMLElement} | null} */
  let camera = null;
  const destroy = () => {
    if (destroyed) return;
    destroyed = true;
    camera?.panel?.destroy();
    camera?.host.remove();
    camera = null;
    stopLoop();
    resizeObserver.disconnect();
    listeners.abort();
    panicked.delete(showPanic);
    try {
      player.free();
    } catch {
      // After a panic the module cannot free; the page is going away anyway.
    }
    // Give the GPU context back now rather than at garbage collection: a page has only a few.
    view.getContext("webgl2")?.getExtension("WEBGL_lose_context")?.loseContext();
    element.replaceChildren();
    element.classList.remove("embusen", `embusen-${chrome}`);
    restoreTabIndex();
    for (const key of ["state", "frame", "method"]) delete element.dataset[key];
    delete /** @type {any} */ (element).embusen;
  };

  // --- first recording ----------------------------------------------------------------
  const ready = (async () => {
    if (options.src) await openUrl(options.src, options.accel);
    else await guarded(() => player.load_demo());
    if (destroyed) return;
    resize();
    setPlaying(Boolean(options.autoplay));
    last = performance.now(); // playback starts now, not when loading began
    frameRequest = requestAnimationFrame(loop);
  })();
  /** @type {Handle} */
  const handle = { player, element, open, openUrl, ready, destroy, showCameraTake, clearCameraTake };
  /** @type {any} */ (element).embusen = handle;
  await ready;
  if (options.video && !destroyed) {
    // The panel's code only now, and only for a take: a player alone loads none of it.
    const host = document.createElement("div");
    element.insertAdjacentElement("afterend", host);
    camera = { panel: null, host };
    const { mountCameraTracking } = await import("./camera.js");
    const { video, src, camera: cameraUrl, background, board, truth, method } = options;
    const panel = await mountCameraTracking(host, { video, src, camera: cameraUrl, background, board, truth, method, player: handle });
    if (destroyed) panel.destroy();
    else (camera.panel = panel, (/** @type {Handle} */ (handle).camera = panel));
  }
  return handle;
}
