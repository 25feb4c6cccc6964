#!/usr/bin/env bash
# embusen's one entry point. It installs what it needs on a fresh machine.
#   ./build.sh serve   build the web app into dist/ and serve it on 127.0.0.1
#   ./build.sh build   build the web app into dist/ (a static site: any host works)
#   ./build.sh test    every test: format, lints, native, wasm, browser
#   ./build.sh bench   the speed figures (native core, then in the browser)
#   ./build.sh demo    the command-line tool on the built-in demo recording
#   ./build.sh golden [COMMIT]  output byte for byte as at COMMIT (tests/golden.sh)
#   ./build.sh speed [COMMIT]   embusen track's whole process, COMMIT's and this tree's side by side (benches/speed.sh)
set -euo pipefail
cd "$(dirname "$0")"

PORT="${PORT:-8765}"
WASM_TARGET=wasm32-unknown-unknown
# Where cargo builds: its own default, or CARGO_TARGET_DIR when set.
TARGET_DIR="${CARGO_TARGET_DIR:-target}"

# --- installing what is missing --------------------------------------------

ensure_rust() {
    rustup component list --installed 2>/dev/null | grep -q '^rustfmt' || rustup component add rustfmt
    rustup component list --installed 2>/dev/null | grep -q '^clippy' || rustup component add clippy
    rustup target list --installed | grep -qx "$WASM_TARGET" || rustup target add "$WASM_TARGET"
}

# wasm-bindgen-cli must be exactly the version of the wasm-bindgen crate in Cargo.lock.
wasm_bindgen_version() {
    awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock
}

ensure_wasm_bindgen() {
    local want
    want="$(wasm_bindgen_version)"
    if ! command -v wasm-bindgen >/dev/null || [ "$(wasm-bindgen --version | awk '{print $2}')" != "$want" ]; then
        echo "installing wasm-bindgen-cli $want (takes a few minutes once)" >&2
        cargo install wasm-bindgen-cli --version "$want"
    fi
}

ensure_node_packages() {
    if [ ! -x node_modules/.bin/wasm-opt ] || [ ! -x node_modules/.bin/tsc ] || [ ! -d node_modules/playwright-core ] \
        || [ ! -d node_modules/three ]; then
        npm ci --no-audit --no-fund
    fi
}

ensure_chromium() {
    if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null; then
        echo "installing Debian's chromium and chromium-driver" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null
    fi
}

# The CLI and the tests read video through ffmpeg and ffprobe.
ensure_ffmpeg() {
    if ! command -v ffmpeg >/dev/null || ! command -v ffprobe >/dev/null; then
        echo "installing Debian's ffmpeg" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq ffmpeg >/dev/null
    fi
}

# --- building ------------------------------------------------------------------

# The library for wasm with only the features $1, bound for the page into $2,
# optimised by wasm-opt for $3: -O3 for speed, -Oz for size.
build_wasm() {
    cargo build --lib --profile wasm-release --target "$WASM_TARGET" --no-default-features --features "$1"
    mkdir -p "$2"
    wasm-bindgen --target web --out-dir "$2" "$TARGET_DIR/$WASM_TARGET/wasm-release/embusen.wasm"
    # npm's binaryen: Debian's wasm-opt (108) breaks this module. The
    # producers and target-features sections are notes for tools, not for
    # the browser: 0.2 KB gzipped of the player's download.
    # shellcheck disable=SC2086 # $3: the optimisation flags, one word each
    node_modules/.bin/wasm-opt $3 --strip-producers --strip-target-features \
        --enable-simd --enable-bulk-memory --enable-nontrapping-float-to-int \
        --enable-sign-ext --enable-mutable-globals --enable-reference-types --enable-multivalue \
        "$2/embusen_bg.wasm" -o "$2/embusen_bg.wasm"
}

cmd_build() {
    ensure_rust
    ensure_wasm_bindgen
    ensure_node_packages
    rm -rf dist
    # Three modules (src/web/mod.rs): the player, which every page loads; the
    # camera tracker, fetched with a take to track; the board detector,
    # fetched only to calibrate from a board still.
    # The player is what every page and embed downloads before it shows
    # anything (its first load gated at 360 KB gzipped, tests/browser/), and it runs
    # a method once per file or setting: built for size, 0.8 KB gzipped
    # less than for speed. The tracker runs for every frame of a video, and
    # the detector searches every pixel of a still: built for speed.
    # --converge: the size passes again until they find nothing more, 0.1
    # KB gzipped.
    build_wasm web-player dist/pkg "-Oz --converge"
    build_wasm web-camera dist/pkg-camera -O3
    build_wasm web-board dist/pkg-board -O3
    cp -r www/. dist/
    echo "built dist/ ($(du -sh dist | cut -f1))" >&2
}

cmd_serve() {
    cmd_build
    echo "embusen: http://127.0.0.1:$PORT/" >&2
    exec python3 -m http.server "$PORT" --bind 127.0.0.1 --directory dist
}

# --- testing ---------------------------------------------------------------------

cmd_test() {
    ensure_rust
    ensure_ffmpeg
    cargo fmt --check
    cargo clippy --all-targets --quiet -- -D warnings
    cargo clippy --lib --target "$WASM_TARGET" --quiet -- -D warnings
    cargo test --release
    cmd_build
    # The JS shell against the TypeScript types of the wasm API (tsconfig.json).
    node_modules/.bin/tsc -p tsconfig.json
    ensure_chromium
    CHROMEDRIVER=/usr/bin/chromedriver WASM_BINDGEN_TEST_TIMEOUT=120 \
        cargo test --release --target "$WASM_TARGET" --test wasm --test image --test track_browser
    # One file at a time: the camera tests track at full speed, which would
    # starve the player tests' animation checks running beside them.
    node --test --test-concurrency=1 tests/browser/app.test.mjs tests/browser/camera.test.mjs
}

cmd_bench() {
    ensure_ffmpeg
    cargo bench --bench core
    cargo bench --bench image
    cargo bench --bench silhouette
    cargo bench --bench track
    cmd_build
    ensure_chromium
    node tests/browser/bench.mjs
}

cmd_demo() {
    cargo run --release --quiet --bin embusen
}

case "${1:-serve}" in
    serve) cmd_serve ;;
    build) cmd_build ;;
    test) cmd_test ;;
    bench) cmd_bench ;;
    demo) cmd_demo ;;
    golden) exec tests/golden.sh "${@:2}" ;;
    speed) ensure_ffmpeg && exec benches/speed.sh "${@:2}" ;;
    *)
        echo "usage: ./build.sh [serve|build|test|bench|demo|golden [COMMIT]|speed [COMMIT]]" >&2
        exit 2
        ;;
esac
