// @ts-check
// A camera take in the player: a camera-tracked take of the open recording
// shown in the 3D view with its legend, and the camera panel under the
// player for a take (`video`), whose code is imported only then, so that a
// player alone (an embed, the demo) downloads none of it.

import { messageOf } from "../files.js";

/** @typedef {import("../pkg/embusen.js").Player} Player */
/** @typedef {import("../pkg/embusen.js").Options} Options */
/** @typedef {import("../embusen.js").CameraTakeView} CameraTakeView */
/** @typedef {import("../embusen.js").CameraHandle} CameraHandle */
/** @typedef {import("../embusen.js").MountOptions} MountOptions */
/** @typedef {import("../embusen.js").Handle} Handle */

/**
 * The 3D view's camera take: its legend, and showing and clearing it.
 * @param {Player} player
 * @param {Options} choices
 * @param {HTMLElement} legendBox
 * @param {(message: string) => void} showError
 * @param {() => void} wake
 */
export function cameraTakes(player, choices, legendBox, showError, wake) {
  legendBox.replaceChildren(...choices.take_legend.map(({ label, color_css }) => {
    const row = document.createElement("div");
    const swatch = document.createElement("span");
    swatch.style.cssText = `display:inline-block;width:16px;height:4px;margin-right:6px;vertical-align:middle;background:${color_css}`;
    row.append(swatch, label);
    return row;
  }));
  /** @param {CameraTakeView} take */
  const show = ({ cameraHipsCm, frustumCm, series }) => {
    try {
      player.show_camera_take(Float64Array.from(cameraHipsCm), Float64Array.from(frustumCm), series);
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
  const clear = () => {
    player.clear_camera_take();
    legendBox.hidden = true;
    wake();
  };
  return { show, clear };
}

/**
 * The camera panel in `host` under the player, for a take (`options.video`):
 * its code only now, and only for a take, so a player alone loads none of it.
 * @param {HTMLElement} host
 * @param {MountOptions} options
 * @param {Handle} handle the player's
 * @param {() => boolean} destroyed whether the player went meanwhile
 * @returns {Promise<CameraHandle | null>}
 */
async function mountCamera(host, options, handle, destroyed) {
  const { mountCameraTracking } = await import("../camera.js");
  const { video, src, camera, background, board, truth, method, offsetS, track, autotrack } = options;
  const panel = await mountCameraTracking(host, {
    video, src, camera, background, board, truth, method, offsetS, track, autotrack, player: handle,
  });
  if (!destroyed()) return (handle.camera = panel);
  panel.destroy();
  return null;
}

/**
 * The camera panel under the player (`options.video`) and its element: put
 * up once the first recording is open, and gone with the player.
 */
export function cameraPanel() {
  /** @type {{host: HTMLElement, panel: CameraHandle | null} | null} */
  let camera = null;
  return {
    /**
     * @param {HTMLElement} element the player's
     * @param {MountOptions} options
     * @param {Handle} handle the player's
     * @param {() => boolean} destroyed whether the player went meanwhile
     */
    async open(element, options, handle, destroyed) {
      /** @type {{host: HTMLElement, panel: CameraHandle | null}} */
      const c = { host: document.createElement("div"), panel: null };
      camera = c;
      element.insertAdjacentElement("afterend", c.host);
      c.panel = await mountCamera(c.host, options, handle, destroyed);
    },
    close() {
      camera?.panel?.destroy();
      camera?.host.remove();
      camera = null;
    },
  };
}
