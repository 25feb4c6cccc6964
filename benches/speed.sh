#!/usr/bin/env bash
# The whole `embusen track` process at BASE and at the work tree, side by
# side in one run (issue 46): walk at 640×480 and walk scaled to 1440×1080
# (its camera's K scaled with it), each the median of RUNS runs taken in
# turn (base, here, base, here, … so a drift of the machine's speed hits
# both), decoding, start-up and writing included; then the ratios.
#
#   benches/speed.sh [BASE]     (or: ./build.sh speed [BASE]; RUNS=5)
#
# BASE defaults to afae6b6, where issue 46's figures were measured. The
# outputs of the two are compared too: a speed-up that changes the bytes is
# said (a change meant to alter them is judged by eval-track instead).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
BASE="${1:-afae6b6}"
RUNS="${RUNS:-5}"
DATA="$ROOT/../shared/data/optical"
WORK="$ROOT/target/speed"

if [ ! -d "$DATA" ]; then
    echo "SKIPPED: $DATA not found; nothing to time" >&2
    exit 0
fi
# shellcheck source=tests/base_cli.sh
source tests/base_cli.sh
build_base_and_head_cli "$BASE" "$WORK"

# walk at 1440×1080: the video, its background and its camera scaled by
# 2.25 (a pixel's centre at (x + 0.5) · 2.25 − 0.5).
BIG="$WORK/walk-1440x1080"
mkdir -p "$BIG"
if [ ! -f "$BIG/walk.mp4" ]; then
    ffmpeg -v error -y -i "$DATA/walk.mp4" -vf scale=1440:1080:flags=bicubic -c:v libx264 -crf 16 -pix_fmt yuv420p "$BIG/walk.mp4"
    ffmpeg -v error -y -i "$DATA/walk.background.png" -vf scale=1440:1080:flags=bicubic "$BIG/walk.background.png"
    python3 - "$DATA/walk.camera.json" "$BIG/walk.camera.json" <<'PY'
import json, sys
camera = json.load(open(sys.argv[1]))
s = 2.25
camera["image_size"] = {"width": 1440, "height": 1080}
K = camera["K"]
K[0][0] *= s
K[1][1] *= s
K[0][2] = (K[0][2] + 0.5) * s - 0.5
K[1][2] = (K[1][2] + 0.5) * s - 0.5
json.dump(camera, open(sys.argv[2], "w"), indent=1)
PY
fi

# The wall seconds of one run of `BIN track VIDEO_DIR/walk.mp4 … -o OUT`.
seconds_of() {
    local bin="$1" dir="$2" out="$3" start end
    start="$(date +%s%N)"
    "$bin" track "$dir/walk.mp4" --bvh "$DATA/walk.suit.bvh" --camera "$dir/walk.camera.json" \
        --background "$dir/walk.background.png" -o "$out" >/dev/null 2>&1
    end="$(date +%s%N)"
    echo "$(((end - start) / 1000000))"
}

median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

FRAMES=195
printf '%-28s %14s %14s %10s\n' "embusen track walk, fused" "base $(git rev-parse --short "$BASE")" \
    "here $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src || echo +)" "here/base"
for scene in 640x480 1440x1080; do
    dir="$DATA"
    [ "$scene" = 1440x1080 ] && dir="$BIG"
    base_ms=() head_ms=()
    seconds_of "$HEAD_BIN" "$dir" "$WORK/warm.bvh" >/dev/null # the page cache warm
    for _ in $(seq "$RUNS"); do
        base_ms+=("$(seconds_of "$BASE_BIN" "$dir" "$WORK/base-$scene.bvh")")
        head_ms+=("$(seconds_of "$HEAD_BIN" "$dir" "$WORK/head-$scene.bvh")")
    done
    base="$(printf '%s\n' "${base_ms[@]}" | median)"
    head="$(printf '%s\n' "${head_ms[@]}" | median)"
    awk -v s="$scene" -v b="$base" -v h="$head" -v n="$FRAMES" 'BEGIN {
        printf "%-28s %12.2f s %12.2f s %10.2f\n", "whole process, " s, b / 1000, h / 1000, h / b
        printf "%-28s %11.1f ms %11.1f ms %10.2f\n", "  a video frame", b / n, h / n, h / b }'
    cmp -s "$WORK/base-$scene.bvh" "$WORK/head-$scene.bvh" || echo "  (the BVHs differ at $scene)"
done
