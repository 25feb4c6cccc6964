// @ts-check
// How the player says what went wrong: the error box under the player
// (a thrown value's message is ../files.js's), and the wasm module's
// panic, told to every player on the page (after one the module is
// unusable, so each stops and says so).

/** The event the wasm module sends the window when it panics (src/web/panic.rs). */
const PANIC_EVENT = "embusen-panic";

/** The mounted players' ways to show a panic: after one the module is unusable. */
const panicked = new Set(/** @type {Array<(message: string) => void>} */ ([]));
window.addEventListener(PANIC_EVENT, (event) => {
  const message = String(/** @type {CustomEvent} */ (event).detail);
  for (const show of panicked) show(message);
});

/**
 * Shows the wasm module's panic with `show` until the returned function is called.
 * @param {(message: string) => void} show
 * @returns {() => void} stops showing it
 */
export function onPanic(show) {
  panicked.add(show);
  return () => panicked.delete(show);
}


/**
 * Shows a message in the error box; an empty one hides it.
 * @param {HTMLElement} errorBox
 */
export function errorShower(errorBox) {
  return (/** @type {string} */ message) => {
    errorBox.textContent = message;
    errorBox.hidden = !message;
  };
}
