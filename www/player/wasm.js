// @ts-check
// The wasm module for the player: fetched and instantiated once per page,
// however many players there are (and the camera panel), and a Rust
// `Player` over a player's two canvases.

import init, { Player, options as playerOptions } from "../pkg/embusen.js";

/** @typedef {import("../pkg/embusen.js").Options} Options */

/** @type {Promise<Options> | null} */
let wasmReady = null;
/** Loads the wasm module once per page, however many players there are (and the camera panel). */
export function loadWasm() {
  wasmReady ??= init({ module_or_path: new URL("../pkg/embusen_bg.wasm", import.meta.url) })
    .then(() => playerOptions())
    .catch((e) => {
      wasmReady = null; // a later mount tries again
      throw e;
    });
  return wasmReady;
}

/**
 * The wasm module (once per page) and a player over the two canvases.
 * @param {HTMLCanvasElement} view
 * @param {HTMLCanvasElement} plots
 */
export async function startWasm(view, plots) {
  const choices = await loadWasm();
  return { choices, player: new Player(view, plots) };
}
