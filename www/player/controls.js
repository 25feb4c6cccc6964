// @ts-check
// The player's controls: their HTML, the playback controls (play, frame,
// speed, loop, follow, solid, shadow, the original's ghost), and with the
// full chrome the method's settings, the file picker, the exports and a drop
// on the player. Every choice and default comes from the wasm module's
// `options()`; the info panel (info.js) shows the settings in use.

import { download, messageOf } from "../files.js";

/** @typedef {import("../pkg/embusen.js").Player} Player */
/** @typedef {import("../pkg/embusen.js").PlayerSettings} Settings */
/** @typedef {import("../pkg/embusen.js").Options} Options */
/** @typedef {import("../pkg/embusen.js").Export} Export */

export const FULL_CONTROLS = `
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

export const PLAYBACK_CONTROLS = `
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
export const SETTING_CONTROLS = [
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
export function fillSelect(select, entries, selected) {
  select.replaceChildren(...entries.map(([value, label]) => new Option(label, value, false, value === selected)));
}

/** A setting's control. @param {HTMLElement} element @param {string} control */
export function settingControl(element, control) {
  const found = element.querySelector(`[data-setting=${control}]`);
  if (found instanceof HTMLInputElement || found instanceof HTMLSelectElement) return found;
  throw new Error(`embusen: no setting control ${control}`);
}

/**
 * The playback controls, wired.
 * @param {Controlled} c
 * @param {(on: boolean) => void} setPlaying
 */
export function wirePlayback({ player, choices, get, showError, signal }, setPlaying) {
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
  ghost.addEventListener("change", guarded(() => player.set_ghost(/** @type {import("../pkg/embusen.js").Ghost} */ (ghost.value))), { signal });
}

/**
 * The full chrome's controls, wired: the file picker, the method's
 * settings, the exports, a drop on the player.
 * @param {Controlled} c
 * @param {() => void} refresh shows the settings in use
 */
export function wireFullControls(c, refresh) {
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
  const save = (make) => {
    try {
      const { name, text } = make();
      download(text, name);
    } catch (e) {
      showError(messageOf(e));
    }
  };
  get("[data-action=export-recording]", HTMLButtonElement).addEventListener("click", () => save(() => player.export_recording()), { signal });
  get("[data-action=export-hips]", HTMLButtonElement).addEventListener("click", () => save(() => player.export_hips_csv()), { signal });
  // A drop here is this player's: preventDefault tells the page's own drop handler so.
  element.addEventListener("dragover", (e) => e.preventDefault(), { signal });
  element.addEventListener("drop", (e) => {
    e.preventDefault();
    if (e.dataTransfer) open(e.dataTransfer.files);
  }, { signal });
}
