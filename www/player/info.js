// @ts-check
// The player's info panel (full chrome): the open recording's facts, its
// warnings, and the settings in use shown in the settings' controls, with
// the downloads saying whose result they hold.

import { SETTING_CONTROLS, fillSelect, settingControl } from "./controls.js";

/**
 * Shows the open recording's facts (with the full chrome) and the settings in use.
 * @param {import("./controls.js").Controlled} c
 */
export function showInfo({ element, player, get }) {
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
