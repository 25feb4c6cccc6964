// @ts-check
// The camera panel's wasm modules, fetched and instantiated on this thread
// once, the first time each is asked for: the camera module (pkg-camera/:
// the video's rate, the camera's overlays, the plots) with a take, the board
// module (pkg-board/: the ChArUco detector) only when a board is used.

/**
 * @template T
 * @param {() => Promise<T & {default: (options: {module_or_path: URL}) => Promise<unknown>}>} load
 * @param {string} dir
 * @returns {() => Promise<T>}
 */
function lazyModule(load, dir) {
  /** @type {Promise<T> | null} */
  let loaded = null;
  return () =>
    (loaded ??= load().then(async (m) => {
      await m.default({ module_or_path: new URL(`../${dir}/embusen_bg.wasm`, import.meta.url) });
      return m;
    }));
}

/** The camera module. */
export const loadCameraModule = lazyModule(() => import("../pkg-camera/embusen.js"), "pkg-camera");
/** The board module. */
export const loadBoardModule = lazyModule(() => import("../pkg-board/embusen.js"), "pkg-board");
