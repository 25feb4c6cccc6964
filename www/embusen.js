// embusen's JavaScript shell. It only wires the page: it builds the player's
// elements, reads files and URLs into bytes, forwards pointer and keyboard
// input, and runs the animation loop. Parsing, kinematics, the translation
// method, plot layout and all drawing happen in Rust (./pkg/embusen.js).
//
//   import { mount } from "./embusen.js";
//   const player = await mount(document.querySelector("#here"), { src: "walk.bvh", autoplay: true });

import init, { Player } from "./pkg/embusen.js";

let wasmReady = null;
/** Loads the wasm module once per page, however many players there are. */
function loadWasm() {
  wasmReady ??= init({ module_or_path: new URL("./pkg/embusen_bg.wasm", import.meta.url) });
  return wasmReady;
}

const FULL_CONTROLS = `
  <label class="file">Open… <input type="file" multiple accept=".bvh,.csv,.txt"></label>
  <span class="sep"></span>
  <label>method <select data-setting="method"><option value="contact">contact</option><option value="paper">paper (Hachaj &amp; Ogiela)</option></select></label>
  <label class="paper-only">smoothing <select data-setting="smoothing"><option value="faithful">faithful (R)</option><option value="clean">clean</option></select></label>
  <label class="paper-only">window <input data-setting="window" type="number" min="0.05" max="10" step="0.05" value="1"> s</label>
  <label class="paper-only">dyEps <input data-setting="dyeps" type="number" min="0" max="100" step="0.5" value="5"> cm</label>
  <label class="contact-only" title="how far the sole lies below the foot's lowest joint when the foot stands flat">sole <select data-setting="sole">
    <option value="auto">auto</option><option>0</option><option>1</option><option>2</option><option>3</option>
    <option>4</option><option>5</option><option>6</option></select> cm below the joints</label>
  <label>left foot <select data-setting="left"></select></label>
  <label>right foot <select data-setting="right"></select></label>
  <span class="sep"></span>
  <button data-action="export-recording" title="download the corrected recording">⬇ corrected file</button>
  <button data-action="export-hips" title="download the hips trajectory as CSV">⬇ hips CSV</button>`;

const PLAYBACK_CONTROLS = `
  <button data-action="play" title="play/pause (space)">▶</button>
  <input class="slider" type="range" min="0" max="0" value="0" aria-label="frame">
  <span class="readout">0.00 s · frame 0 / 0</span>
  <label>speed <select data-action="speed">
    <option value="0.25">0.25×</option><option value="0.5">0.5×</option><option value="1" selected>1×</option>
    <option value="2">2×</option><option value="4">4×</option></select></label>
  <label><input type="checkbox" data-action="loop" checked> loop</label>
  <label><input type="checkbox" data-action="follow"> follow</label>
  <label>original <select data-action="ghost"><option value="overlay">overlay</option>
    <option value="side">side by side</option><option value="hidden">hidden</option></select></label>`;

/** The info panel's row for the contact method's sole depth, `[depth, estimated]`. */
function soleRow([depth, estimated]) {
  if (depth === undefined) return [];
  return [["sole", `${depth} cm below the lowest foot joint${estimated ? " (estimated)" : ""}`]];
}

/**
 * Mounts a player into `element`. Options: `src`, `accel` (URLs), `autoplay`,
 * `chrome`: "full" (file picker, settings, export, info) or "minimal" (for
 * iframes and embeds), `keyboard`: "document" to take keys page-wide (else the
 * player takes them when focused). Without `src` it opens the built-in demo.
 * Resolves to an object with the Rust `player` and `open(files)`.
 */
export async function mount(element, options = {}) {
  const chrome = options.chrome ?? "minimal";
  element.classList.add("embusen", `embusen-${chrome}`);
  element.tabIndex = 0;
  element.innerHTML = `
    <div class="stage"><canvas class="view"></canvas>
      <div class="loading" hidden>Loading…</div></div>
    <canvas class="plots"></canvas>
    <div class="error" role="alert" hidden></div>
    <div class="controls">${PLAYBACK_CONTROLS}${chrome === "full" ? FULL_CONTROLS : ""}</div>
    ${chrome === "full" ? '<div class="info"></div>' : ""}`;
  const $ = (selector) => element.querySelector(selector);
  const view = $("canvas.view");
  const plots = $("canvas.plots");

  await loadWasm();
  const player = new Player(view, plots);
  const handle = { player, element, open: null, ready: null };
  element.embusen = handle;

  // --- errors, loading, info ------------------------------------------------
  const showError = (message) => {
    const box = $(".error");
    box.textContent = message;
    box.hidden = !message;
  };
  const setLoading = (on) => {
    $(".loading").hidden = !on;
    element.dataset.state = on ? "loading" : "ready";
  };
  const nextPaint = () => new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));

  const refreshInfo = () => {
    $(".slider").max = String(Math.max(0, player.frame_count() - 1));
    const info = $(".info");
    if (info) {
      const frames = player.frame_count();
      const fps = player.fps();
      const rows = [
        ["file", player.name()],
        ["joints", String(player.joint_names().length)],
        ["frames", String(frames)],
        ["rate", `${+fps.toFixed(2)} Hz`],
        ["duration", `${(frames / fps).toFixed(2)} s`],
        ["feet", player.feet().join(" / ")],
        ["method", player.method()],
        ...soleRow(player.sole_depth()),
        ["accelerations", player.accel_source()],
      ];
      info.replaceChildren(
        ...rows.map(([k, v]) => {
          const row = document.createElement("div");
          row.innerHTML = "<b></b> <span></span>";
          row.firstChild.textContent = k;
          row.lastChild.textContent = v;
          return row;
        }),
        ...player.warnings().map((w) => {
          const row = document.createElement("div");
          row.className = "warning";
          row.textContent = `⚠ ${w}`;
          return row;
        }),
      );
      for (const [side, index] of [["left", 0], ["right", 1]]) {
        const select = $(`[data-setting=${side}]`);
        select.replaceChildren(
          ...player.joint_names().map((name) => new Option(name, name, false, name === player.feet()[index])),
        );
      }
    }
  };

  /** Runs a load; on failure shows the error and keeps what was open. */
  const guarded = async (work) => {
    setLoading(true);
    await nextPaint();
    try {
      work();
      showError("");
      refreshInfo();
    } catch (e) {
      showError(String(e.message ?? e));
    } finally {
      setLoading(false);
    }
  };

  const bytesOf = async (file) => new Uint8Array(await file.arrayBuffer());
  /** Opens files: a BVH (+ its accelerometer CSV) or a table. */
  handle.open = async (fileList) => {
    const files = [...fileList];
    const bvh = files.find((f) => /\.bvh$/i.test(f.name));
    const csv = files.find((f) => /\.(csv|txt)$/i.test(f.name));
    const main = bvh ?? csv ?? files[0];
    if (!main) return;
    const accel = bvh ? csv : undefined;
    const [bytes, accelBytes] = await Promise.all([bytesOf(main), accel ? bytesOf(accel) : undefined]);
    await guarded(() => player.load(main.name, bytes, accel?.name, accelBytes));
  };
  const fetchBytes = async (url) => {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    return new Uint8Array(await response.arrayBuffer());
  };
  handle.openUrl = async (src, accel) => {
    try {
      const [bytes, accelBytes] = await Promise.all([fetchBytes(src), accel ? fetchBytes(accel) : undefined]);
      const name = decodeURIComponent(new URL(src, location.href).pathname.split("/").pop() || src);
      const accelName = accel ? decodeURIComponent(new URL(accel, location.href).pathname.split("/").pop()) : undefined;
      await guarded(() => player.load(name, bytes, accelName, accelBytes));
    } catch (e) {
      showError(String(e.message ?? e));
    }
  };

  // --- size -------------------------------------------------------------------
  const resize = () => {
    const dpr = window.devicePixelRatio || 1;
    const v = view.getBoundingClientRect();
    const p = plots.getBoundingClientRect();
    player.resize(Math.round(v.width * dpr), Math.round(v.height * dpr), Math.round(p.width * dpr), Math.round(p.height * dpr));
    player.draw();
  };
  new ResizeObserver(resize).observe(element);

  // --- controls -----------------------------------------------------------------
  const playButton = $("[data-action=play]");
  const setPlaying = (on) => {
    player.set_playing(on);
    playButton.textContent = on ? "❚❚" : "▶";
  };
  playButton.addEventListener("click", () => setPlaying(!player.playing()));
  $(".slider").addEventListener("input", (e) => player.set_frame(+e.target.value));
  $("[data-action=speed]").addEventListener("change", (e) => player.set_speed(+e.target.value));
  $("[data-action=loop]").addEventListener("change", (e) => player.set_looping(e.target.checked));
  $("[data-action=follow]").addEventListener("change", (e) => player.set_follow(e.target.checked));
  $("[data-action=ghost]").addEventListener("change", (e) => player.set_ghost(e.target.value));

  if (chrome === "full") {
    $("input[type=file]").addEventListener("change", (e) => handle.open(e.target.files));
    const applySettings = () => {
      try {
        player.set_settings(
          $("[data-setting=method]").value,
          $("[data-setting=smoothing]").value,
          +$("[data-setting=window]").value,
          +$("[data-setting=dyeps]").value,
          $("[data-setting=left]").value,
          $("[data-setting=right]").value,
          $("[data-setting=sole]").value === "auto" ? undefined : +$("[data-setting=sole]").value,
        );
        showError("");
        refreshInfo();
      } catch (e) {
        showError(String(e.message ?? e));
      }
      // The paper method's own settings only show when it is chosen.
      element.dataset.method = $("[data-setting=method]").value;
    };
    element.dataset.method = "contact";
    element.querySelectorAll("[data-setting]").forEach((input) => input.addEventListener("change", applySettings));
    const download = ([name, text]) => {
      const a = document.createElement("a");
      a.href = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
      a.download = name;
      a.click();
      setTimeout(() => URL.revokeObjectURL(a.href), 1000);
    };
    $("[data-action=export-recording]").addEventListener("click", () => download(player.export_recording()));
    $("[data-action=export-hips]").addEventListener("click", () => download(player.export_hips_csv()));
    element.addEventListener("dragover", (e) => e.preventDefault());
    element.addEventListener("drop", (e) => {
      e.preventDefault();
      handle.open(e.dataTransfer.files);
    });
  }

  // --- pointer: orbit (drag), pan (right/shift drag, two fingers), zoom (wheel, pinch)
  const pointers = new Map();
  view.addEventListener("contextmenu", (e) => e.preventDefault());
  view.addEventListener("pointerdown", (e) => {
    view.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey });
  });
  view.addEventListener("pointermove", (e) => {
    const last = pointers.get(e.pointerId);
    if (!last) return;
    const [dx, dy] = [e.clientX - last.x, e.clientY - last.y];
    if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const before = Math.hypot(a.x - b.x, a.y - b.y);
      last.x = e.clientX;
      last.y = e.clientY;
      const after = Math.hypot(a.x - b.x, a.y - b.y);
      if (before > 0 && after > 0) player.zoom(before / after);
      player.pan(dx / 2, dy / 2);
    } else {
      if (last.pan) player.pan(dx, dy);
      else player.orbit(dx, dy);
      last.x = e.clientX;
      last.y = e.clientY;
    }
  });
  const release = (e) => pointers.delete(e.pointerId);
  view.addEventListener("pointerup", release);
  view.addEventListener("pointercancel", release);
  view.addEventListener("wheel", (e) => {
    e.preventDefault();
    player.zoom(Math.exp(e.deltaY * 0.001));
  }, { passive: false });

  // Click or drag on a plot: seek.
  const seek = (e) => {
    const r = plots.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    player.seek_plot((e.clientX - r.left) * dpr, (e.clientY - r.top) * dpr);
  };
  plots.addEventListener("pointerdown", (e) => {
    plots.setPointerCapture(e.pointerId);
    seek(e);
  });
  plots.addEventListener("pointermove", (e) => {
    if (plots.hasPointerCapture(e.pointerId)) seek(e);
  });

  // --- keyboard -----------------------------------------------------------------
  const keyTarget = options.keyboard === "document" ? document : element;
  keyTarget.addEventListener("keydown", (e) => {
    if (e.target.closest?.("input, select, textarea") && e.target.type !== "range") return;
    const actions = {
      " ": () => setPlaying(!player.playing()),
      ArrowLeft: () => player.step(-1),
      ArrowRight: () => player.step(1),
      Home: () => player.set_frame(0),
      End: () => player.set_frame(player.frame_count() - 1),
    };
    const action = actions[e.key];
    if (action) {
      e.preventDefault();
      action();
    }
  });

  // --- the animation loop ---------------------------------------------------------
  let last = performance.now();
  const readout = $(".readout");
  const slider = $(".slider");
  const loop = (now) => {
    player.tick((now - last) / 1000);
    last = now;
    const frame = player.frame();
    if (+slider.value !== frame) slider.value = String(frame);
    element.dataset.frame = String(frame);
    readout.textContent = `${player.time_s().toFixed(2)} s · frame ${frame} / ${Math.max(0, player.frame_count() - 1)}`;
    if (!player.playing() && playButton.textContent !== "▶") playButton.textContent = "▶";
    requestAnimationFrame(loop);
  };

  // --- first recording ----------------------------------------------------------------
  handle.ready = (async () => {
    if (options.src) await handle.openUrl(options.src, options.accel);
    else await guarded(() => player.load_demo());
    resize();
    setPlaying(Boolean(options.autoplay));
    last = performance.now(); // playback starts now, not when loading began
    requestAnimationFrame(loop);
  })();
  await handle.ready;
  return handle;
}
