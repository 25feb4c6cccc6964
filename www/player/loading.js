// @ts-check
// The player's loads: a file picked or dropped, or a URL, read into bytes
// and given to the wasm player; each shows "Loading…" and, on failure, the
// error, keeping what was open.

import { fetchOk, messageOf } from "../files.js";

/** @typedef {import("../pkg/embusen.js").Player} Player */

/** @param {string} url */
const fetchBytes = async (url) => new Uint8Array(await (await fetchOk(url)).arrayBuffer());
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
export function loaders(player, guarded, showError) {
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
 * A load's guard: it shows "Loading…" and, on failure, the error, keeping
 * what was open; a success hides the camera take (it belongs to the
 * recording it was open with) and shows the new recording's facts.
 * @param {HTMLElement} element
 * @param {{loadingBox: HTMLElement, legendBox: HTMLElement}} boxes
 * @param {{showError: (message: string) => void, refresh: () => void, wake: () => void}} then
 * @param {() => boolean} destroyed
 */
export function loadGuard(element, { loadingBox, legendBox }, { showError, refresh, wake }, destroyed) {
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
