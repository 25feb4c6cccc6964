// `./build.sh bench`, browser half: figures measured in one headless Chromium
// run. Prints; asserts nothing.
//   - parse + kinematics of heian_nidan.bvh: embusen (wasm) vs three.js's
//     BVHLoader (parse, then sample every frame and compute world positions)
//   - file bytes → first frame drawn, for heian_nidan.bvh and a 100,000-frame file
//   - the first load of the page and of an embed with the demo: every
//     response gzipped, measured in the browser as the size gate measures it
//   - the gzipped size of the files index.html loads
import { readFileSync } from "node:fs";
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

const server = await startServer({ "/bench.html": PAGE });
const browser = await launchBrowser();
try {
  console.log("first load with the demo, in headless Chromium (every response, gzipped level 9):");
  for (const [path, selector] of FIRST_LOAD_PAGES) {
    const { total, sizes } = await firstLoad(browser, server.url, path, selector);
    const largest = sizes.toSorted((a, b) => b[1] - a[1]).slice(0, 3).map(([p, s]) => `${p} ${(s / 1000).toFixed(1)}`);
    console.log(`  ${path.padEnd(12)} ${(total / 1000).toFixed(1)} KB (gate ${FIRST_LOAD_LIMIT_BYTES / 1000} KB; largest: ${largest.join(", ")})`);
  }
  await printDemoFrameRate(browser, server);
  if (HAVE_DATA) await printTimings(browser, server);
  else console.log(`SKIPPED: ${DATA} not found; no browser timing figures`);
} finally {
  await browser.close();
  await server.close();
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
