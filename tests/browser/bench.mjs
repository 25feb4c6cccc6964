// `./build.sh bench`, browser half: figures measured in one headless Chromium
// run. Prints; asserts nothing.
//   - parse + kinematics of heian_nidan.bvh: embusen (wasm) vs three.js's
//     BVHLoader (parse, then sample every frame and compute world positions)
//   - file bytes → first frame drawn, for heian_nidan.bvh and a 100,000-frame file
//   - the first load of the page and of an embed with the demo: every
//     response gzipped, measured in the browser as the size gate measures it
//   - the gzipped size of the files index.html loads
//   - the fused tracker in the page: walk.mp4 (640×480) and slash scaled to a
//     portrait 1080×1920 (as benches/speed.sh makes it), frames a second
import { execFileSync } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { gzipSync } from "node:zlib";
import { join } from "node:path";
import { startServer, launchBrowser, firstLoad, waitReady, DIST, DATA, HAVE_DATA, FIRST_LOAD_PAGES, FIRST_LOAD_LIMIT_BYTES } from "./harness.mjs";

const PAGE = `<!doctype html><html><head>
<script type="importmap">{"imports": {"three": "/node_modules/three/build/three.module.js"}}</script>
</head><body><canvas id="v" width="640" height="480"></canvas><canvas id="p" width="640" height="480"></canvas>
<script type="module">
  import init, { Player, parse_and_kinematics } from "/pkg/embusen.js";
  import * as THREE from "three";
  import { BVHLoader } from "/node_modules/three/examples/jsm/loaders/BVHLoader.js";
  await init();
  const median = (xs) => xs.sort((a, b) => a - b)[xs.length >> 1];
  function time(f, runs) {
    f();
    const t = [];
    for (let i = 0; i < runs; i++) { const s = performance.now(); f(); t.push(performance.now() - s); }
    return median(t);
  }
  window.bench = async (runs) => {
    const text = await (await fetch("/data/karate/heian_nidan.bvh")).text();
    const bytes = new TextEncoder().encode(text);
    const ours = time(() => parse_and_kinematics(bytes), runs);
    const theirs = time(() => {
      const result = new BVHLoader().parse(text);
      const mixer = new THREE.AnimationMixer(result.skeleton.bones[0]);
      mixer.clipAction(result.clip).play();
      const frames = result.clip.tracks[0].times.length;
      const p = new THREE.Vector3();
      let sum = 0;
      for (let f = 0; f < frames; f++) {
        mixer.setTime(result.clip.tracks[0].times[f]);
        result.skeleton.bones[0].updateMatrixWorld(true);
        for (const bone of result.skeleton.bones) sum += p.setFromMatrixPosition(bone.matrixWorld).x;
      }
      return sum;
    }, runs);
    const gl = document.querySelector("#v").getContext("webgl2");
    const player = new Player(document.querySelector("#v"), document.querySelector("#p"));
    player.resize(640, 480, 640, 480);
    // Two figures: until every draw call of the first frame (3D view and
    // plots) is issued, and until the GPU has finished it (a pixel read waits
    // for it). Here the GPU is software (swiftshader), which dominates the second.
    const firstFrame = (b) => {
      const s = performance.now();
      player.load("x.bvh", b);
      player.draw();
      const issued = performance.now() - s;
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
      return [issued, performance.now() - s];
    };
    const medianPair = (pairs) => [median(pairs.map((p) => p[0])), median(pairs.map((p) => p[1]))];
    const firstNidan = medianPair([0, 1, 2, 3, 4].map(() => firstFrame(bytes)));
    // 100,000 frames: the kata's rows repeated.
    const [head, body] = text.split(/Frame Time:[^\\n]*\\n/);
    const rows = body.split("\\n").filter((r) => r.trim());
    const big = [head.replace(/Frames:\\s*\\d+/, "Frames: 100000"), "Frame Time: 0.01"];
    for (let i = 0; i < 100000; i++) big.push(rows[i % rows.length]);
    const bigBytes = new TextEncoder().encode(big.join("\\n") + "\\n");
    const firstBig = medianPair([0, 1, 2].map(() => firstFrame(bigBytes)));
    return { ours, theirs, firstNidan, firstBig, bigMB: bigBytes.length / 1e6, frames: player.frame_count() };
  };
  window.ready = true;
</script></body></html>`;

function downloadSize() {
  const files = ["index.html", "embusen.js", "style.css", "pkg/embusen.js", "pkg/embusen_bg.wasm"];
  let raw = 0;
  let gz = 0;
  const rows = files.map((f) => {
    const bytes = readFileSync(join(DIST, f));
    const z = gzipSync(bytes, { level: 9 }).length;
    raw += bytes.length;
    gz += z;
    return `    ${f.padEnd(22)} ${(bytes.length / 1024).toFixed(1).padStart(8)} KB  gzip ${(z / 1024).toFixed(1).padStart(7)} KB`;
  });
  return { raw, gz, rows };
}

const size = downloadSize();
console.log("download (everything index.html loads):");
for (const row of size.rows) console.log(row);
console.log(`    total                  ${(size.raw / 1024).toFixed(1).padStart(8)} KB  gzip ${(size.gz / 1024).toFixed(1).padStart(7)} KB (goal ≤ 600 KB)`);

const portrait = existsSync(join(DATA, "optical", "slash.mp4")) ? portraitSlash() : null;
const server = await startServer({ "/bench.html": PAGE, ...(portrait?.files ?? {}) });
const browser = await launchBrowser();
try {
  console.log("first load with the demo, in headless Chromium (every response, gzipped level 9):");
  for (const [path, selector] of FIRST_LOAD_PAGES) {
    const { total, sizes } = await firstLoad(browser, server.url, path, selector);
    const largest = sizes.toSorted((a, b) => b[1] - a[1]).slice(0, 3).map(([p, s]) => `${p} ${(s / 1000).toFixed(1)}`);
    console.log(`  ${path.padEnd(12)} ${(total / 1000).toFixed(1)} KB (gate ${FIRST_LOAD_LIMIT_BYTES / 1000} KB; largest: ${largest.join(", ")})`);
  }
  await printDemoFrameRate(browser, server);
  if (HAVE_DATA) {
    await printTimings(browser, server);
    if (portrait) await printTrackingRate(browser, server);
  } else console.log(`SKIPPED: ${DATA} not found; no browser timing figures`);
} finally {
  await browser.close();
  await server.close();
  if (portrait) rmSync(portrait.folder, { recursive: true, force: true });
}

/**
 * slash scaled 4 times and cropped to a portrait 1080×1920 where the actor
 * stands, with its background and its camera scaled to match (as
 * benches/speed.sh makes it), written by ffmpeg in a scratch folder:
 * `{ folder, files }`, the files to serve at /portrait/.
 */
function portraitSlash() {
  const folder = mkdtempSync(join(tmpdir(), "embusen-bench-"));
  const filter = "scale=iw*4:ih*4:flags=bicubic,crop=1080:1920:1480:0";
  const ffmpeg = (input, output, ...codec) =>
    execFileSync("ffmpeg", ["-v", "error", "-y", "-i", join(DATA, "optical", input), "-vf", filter, ...codec, join(folder, output)]);
  ffmpeg("slash.mp4", "slash.mp4", "-c:v", "libx264", "-crf", "16", "-pix_fmt", "yuv420p");
  ffmpeg("slash.background.png", "slash.background.png");
  const camera = JSON.parse(readFileSync(join(DATA, "optical", "slash.camera.json"), "utf8"));
  const [s, cropX] = [4, 1480];
  camera.image_size = { width: 1080, height: 1920 };
  camera.K[0][0] *= s;
  camera.K[1][1] *= s;
  camera.K[0][2] = (camera.K[0][2] + 0.5) * s - 0.5 - cropX;
  camera.K[1][2] = (camera.K[1][2] + 0.5) * s - 0.5;
  const file = (name, type) => ({ type, body: readFileSync(join(folder, name)) });
  const files = {
    "/portrait/slash.mp4": file("slash.mp4", "video/mp4"),
    "/portrait/slash.background.png": file("slash.background.png", "image/png"),
    "/portrait/slash.camera.json": { type: "application/json", body: JSON.stringify(camera) },
  };
  return { folder, files };
}

/** The fused tracker in the page, from the address to the finished take, on walk and the portrait slash. */
async function printTrackingRate(browser, server) {
  const takes = [
    ["walk.mp4, 640×480", "/data/optical/walk", "/data/optical/walk", 60],
    ["slash at 1080×1920", "/portrait/slash", "/data/optical/slash", 20],
  ];
  for (const [name, scene, suit, goal] of takes) {
    const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
    try {
      page.on("pageerror", (e) => console.error("page error:", e));
      await page.goto(`${server.url}/?autoplay=0&video=${scene}.mp4&src=${suit}.suit.bvh` +
        `&camera=${scene}.camera.json&background=${scene}.background.png`);
      await page.waitForFunction(() => document.querySelector("#camera-panel")?.embusenCamera, null, { timeout: 60000 });
      const r = await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.track());
      console.log(`  ${name} tracked in the page (fused): ${r.framesPerSecond.toFixed(1)} frames a second ` +
        `(a frame read in ${r.readMsPerFrame.toFixed(1)} ms, tracked in ${r.trackMsPerFrame.toFixed(1)} ms, ` +
        `its path scored in ${r.scoreMsPerFrame.toFixed(1)} ms; goal ≥ ${goal})`);
    } finally {
      await page.close();
    }
  }
}

/** Parse + kinematics against three.js, and bytes → first frame, on the shared katas. */
async function printTimings(browser, server) {
  const page = await browser.newPage();
  page.on("pageerror", (e) => console.error("page error:", e));
  await page.goto(server.url + "/bench.html");
  await page.waitForFunction(() => window.ready === true, null, { timeout: 60000 });
  const r = await page.evaluate((runs) => window.bench(runs), 15);
  console.log("in headless Chromium (software WebGL):");
  console.log(`  parse + kinematics, heian_nidan.bvh: embusen ${r.ours.toFixed(2)} ms, three.js BVHLoader ${r.theirs.toFixed(2)} ms → ${(r.theirs / r.ours).toFixed(1)}× (goal ≥ 3×)`);
  const first = ([issued, done]) => `${issued.toFixed(1)} ms issued, ${done.toFixed(1)} ms rendered by the software GPU`;
  console.log(`  bytes → first frame, heian_nidan.bvh: ${first(r.firstNidan)} (goal ≤ 100 ms)`);
  console.log(`  bytes → first frame, ${r.frames} frames (${r.bigMB.toFixed(1)} MB): ${first(r.firstBig)} (goal < 1000 ms)`);
}

/**
 * The demo playing in the page at 1280×800: the page's frames a second
 * (animation frames, each the player's tick and draw), with the body's
 * shadow on and off, side by side.
 */
async function printDemoFrameRate(browser, server) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    await page.goto(server.url + "/");
    await waitReady(page, "#app");
    const rate = (shadow) => page.evaluate(async (shadow) => {
      const app = document.querySelector("#app");
      const box = app.querySelector("[data-action=shadow]");
      if (box.checked !== shadow) box.click();
      if (!app.embusen.player.playing()) app.querySelector("[data-action=play]").click();
      await new Promise((ok) => setTimeout(ok, 500));
      const [first, start] = [app.embusen.player.frame(), performance.now()];
      let frames = 0;
      await new Promise((ok) => {
        const step = () => (++frames, performance.now() - start < 3000 ? requestAnimationFrame(step) : ok());
        requestAnimationFrame(step);
      });
      const seconds = (performance.now() - start) / 1000;
      return { fps: frames / seconds, moved: app.embusen.player.frame() !== first };
    }, shadow);
    const [on, off] = [await rate(true), await rate(false)];
    const said = ({ fps, moved }) => `${fps.toFixed(1)}${moved ? "" : " (did not play)"}`;
    console.log(`  the demo playing at 1280×800: ${said(on)} frames a second with the shadow, ${said(off)} without (goal ≥ 60)`);
  } finally {
    await page.close();
  }
}
