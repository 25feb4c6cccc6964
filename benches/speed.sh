#!/usr/bin/env bash
# The whole `embusen track` process at BASE and at the work tree, side by
# side in one run (issue 46): walk at 640×480, walk scaled to 1440×1080
# and slash scaled to a portrait 1080×1920 (their cameras' K scaled with
# them), each the median of RUNS runs taken in
# turn (base, here, base, here, … so a drift of the machine's speed hits
# both), decoding, start-up and writing included; then the ratios; and
# last the fused tracker alone, one thread, as `cargo bench --bench track`
# times it at each commit.
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

# Another scene of DATA at another size: `scaled_scene NAME W H SCALE
# CROP_X` writes WORK/NAME-WxH/ with NAME's video and background scaled
# SCALE times (bicubic), then cropped to W×H from column CROP_X, and its
# camera's K to match (a pixel's centre at (x + 0.5) · SCALE − 0.5, less
# CROP_X); prints the folder.
scaled_scene() {
    local name="$1" width="$2" height="$3" scale="$4" crop_x="$5"
    local dir="$WORK/$name-${width}x$height" filter
    filter="scale=iw*$scale:ih*$scale:flags=bicubic,crop=$width:$height:$crop_x:0"
    mkdir -p "$dir"
    if [ ! -f "$dir/$name.mp4" ]; then
        ffmpeg -v error -y -i "$DATA/$name.mp4" -vf "$filter" -c:v libx264 -crf 16 -pix_fmt yuv420p "$dir/$name.mp4"
        ffmpeg -v error -y -i "$DATA/$name.background.png" -vf "$filter" "$dir/$name.background.png"
        python3 - "$DATA/$name.camera.json" "$dir/$name.camera.json" "$width" "$height" "$scale" "$crop_x" <<'PY'
import json, sys
source, target, width, height, s, crop_x = sys.argv[1:]
camera = json.load(open(source))
s, crop_x = float(s), float(crop_x)
camera["image_size"] = {"width": int(width), "height": int(height)}
K = camera["K"]
K[0][0] *= s
K[1][1] *= s
K[0][2] = (K[0][2] + 0.5) * s - 0.5 - crop_x
K[1][2] = (K[1][2] + 0.5) * s - 0.5
json.dump(camera, open(target, "w"), indent=1)
PY
    fi
    echo "$dir"
}

# The scenes: NAME FOLDER FRAMES. walk as filmed; walk at 1440×1080; and
# slash as a portrait phone films it, 1080×1920 (4 times, the column
# where the actor stands kept: the body 700 px tall).
SCENES=(
    "walk $DATA 195"
    "walk $(scaled_scene walk 1440 1080 2.25 0) 195"
    "slash $(scaled_scene slash 1080 1920 4 1480) 360"
)

# The wall seconds of one run of `BIN track DIR/NAME.mp4 … -o OUT`.
seconds_of() {
    local bin="$1" name="$2" dir="$3" out="$4" start end
    start="$(date +%s%N)"
    "$bin" track "$dir/$name.mp4" --bvh "$DATA/$name.suit.bvh" --camera "$dir/$name.camera.json" \
        --background "$dir/$name.background.png" -o "$out" >/dev/null 2>&1
    end="$(date +%s%N)"
    echo "$(((end - start) / 1000000))"
}

median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

printf '%-32s %14s %14s %10s\n' "embusen track, fused" "base $(git rev-parse --short "$BASE")" \
    "here $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src || echo +)" "here/base"
rm -f "$WORK/here.ms"
for scene in "${SCENES[@]}"; do
    read -r name dir frames <<<"$scene"
    size="$(python3 -c 'import json, sys; s = json.load(open(sys.argv[1]))["image_size"]; print("%dx%d" % (s["width"], s["height"]))' "$dir/$name.camera.json")"
    base_ms=() head_ms=()
    seconds_of "$HEAD_BIN" "$name" "$dir" "$WORK/warm.bvh" >/dev/null # the page cache warm
    for _ in $(seq "$RUNS"); do
        base_ms+=("$(seconds_of "$BASE_BIN" "$name" "$dir" "$WORK/base-$name-$size.bvh")")
        head_ms+=("$(seconds_of "$HEAD_BIN" "$name" "$dir" "$WORK/head-$name-$size.bvh")")
    done
    base="$(printf '%s\n' "${base_ms[@]}" | median)"
    head="$(printf '%s\n' "${head_ms[@]}" | median)"
    awk -v s="$name $size" -v b="$base" -v h="$head" -v n="$frames" 'BEGIN {
        printf "%-32s %12.2f s %12.2f s %10.2f\n", "whole process, " s, b / 1000, h / 1000, h / b
        printf "%-32s %11.1f ms %11.1f ms %10.2f\n", "  a video frame", b / n, h / n, h / b }'
    cmp -s "$WORK/base-$name-$size.bvh" "$WORK/head-$name-$size.bvh" || echo "  (the BVHs differ at $name $size)"
    echo "$name $size $head $frames" >>"$WORK/here.ms"
done
# The issue's measure: a 1440×1080 frame against a 640×480 one, here.
awk '{ ms[$1 " " $2] = $3 / $4 } END {
    printf "%-32s %43.2f\n", "here, walk 1440x1080 / 640x480", ms["walk 1440x1080"] / ms["walk 640x480"] }' "$WORK/here.ms"

# The fused tracker alone on walk 640×480, one thread, the frames decoded
# beforehand (`cargo bench --bench track`'s "fused tracker", pipeline and
# path energies included): issue 46 step 3's measure, BASE's bench and
# this tree's run in turn. BASE's sources find ../shared beside them
# through a link in WORK (its bench reads the data from there).
ln -sfn "$ROOT/../shared" "$WORK/shared"
fused_ms_of() {
    (cd "$1" && CARGO_TARGET_DIR="$2" cargo bench --quiet --bench track 2>/dev/null) |
        awk '/fused tracker/ { print $3 }'
}
base_ms=() head_ms=()
for _ in $(seq "$RUNS"); do
    base_ms+=("$(fused_ms_of "$WORK/base-src" "$WORK/base-target")")
    head_ms+=("$(fused_ms_of "$ROOT" "${CARGO_TARGET_DIR:-$ROOT/target}")")
done
base="$(printf '%s\n' "${base_ms[@]}" | median)"
head="$(printf '%s\n' "${head_ms[@]}" | median)"
awk -v b="$base" -v h="$head" 'BEGIN {
    printf "%-32s %11.2f ms %11.2f ms %10.2f\n", "fused tracker alone, walk", b, h, h / b }'
