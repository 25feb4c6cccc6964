// @ts-check
// The player's elements: the 3D view, the plots, the legend, the loading,
// error and info boxes and the controls, built once into the element the
// player mounts in, found by a typed finder, and the canvases measured
// whenever the player's size changes.

import { FULL_CONTROLS, PLAYBACK_CONTROLS } from "./controls.js";

/** @typedef {import("../pkg/embusen.js").Player} Player */

/** The 3D view's legend of the floor paths (shown with a camera take), over the view's bottom left. */
const LEGEND_STYLE = "position:absolute;left:8px;bottom:8px;padding:4px 8px;border-radius:4px;"
  + "background:rgba(22,24,28,0.78);font-size:12px;line-height:1.5;pointer-events:none";

/**
 * Fills `element` with the player's elements; gives back a typed finder.
 * @param {HTMLElement} element
 * @param {"full" | "minimal"} chrome
 */
export function buildPlayer(element, chrome) {
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
 * Measures the player's canvases and tells the player their sizes in device
 * pixels; it draws at once and wakes the loop.
 * @param {Player} player
 * @param {HTMLCanvasElement} view
 * @param {HTMLCanvasElement} plots
 * @param {() => void} wake
 */
export function canvasSizer(player, view, plots, wake) {
  return () => {
    const dpr = window.devicePixelRatio || 1;
    const [v, p] = [view.getBoundingClientRect(), plots.getBoundingClientRect()];
    player.resize(Math.round(v.width * dpr), Math.round(v.height * dpr), Math.round(p.width * dpr), Math.round(p.height * dpr));
    player.draw();
    wake();
  };
}
