// @ts-check
// A player's teardown: what a destroyed player gives back (its wasm memory,
// its GPU context, its elements and marks), and the element's tab index as
// it was before the player came.

/** @typedef {import("../pkg/embusen.js").Player} Player */

/**
 * Gives back what a destroyed player held: its wasm memory, its GPU
 * context, its elements and marks.
 * @param {HTMLElement} element
 * @param {"full" | "minimal"} chrome
 * @param {Player} player
 * @param {HTMLCanvasElement} view
 */
export function release(element, chrome, player, view) {
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
  delete /** @type {HTMLElement & {embusen?: import("../embusen.js").Handle}} */ (element).embusen;
}

/**
 * Notes `element`'s tab index (the player sets one); gives back how to put it back.
 * @param {HTMLElement} element
 */
export function keepTabIndex(element) {
  const tabIndexBefore = element.getAttribute("tabindex");
  return () => {
    if (tabIndexBefore === null) element.removeAttribute("tabindex");
    else element.setAttribute("tabindex", tabIndexBefore);
  };
}
