// @ts-check
// A take's options as a page's address gives them, read one way for
// index.html and embed.html: `?video=…&src=…&camera=…&background=…&board=…
// &truth=…&offset=…&track=…&autotrack=1`. A take filmed by several cameras
// repeats `video`, `camera`, `background`, `board` and `offset`, the i-th
// for the i-th view (as `embusen track` pairs its flags).

/**
 * The camera panel's options in `params` (see camera.js's `CameraOptions`;
 * `src` is the player's, read by each page itself).
 * @param {URLSearchParams} params
 */
export function takeOptionsOf(params) {
  const one = (/** @type {string} */ key) => params.get(key) ?? undefined;
  return {
    video: params.getAll("video"),
    camera: params.getAll("camera"),
    background: params.getAll("background"),
    board: params.getAll("board"),
    truth: one("truth"),
    offsetS: params.getAll("offset").map(Number),
    track: one("track"),
    autotrack: params.get("autotrack") === "1",
  };
}
