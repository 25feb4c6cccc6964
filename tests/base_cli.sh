# shellcheck shell=bash
# Sourced by tests/golden.sh and benches/speed.sh: the CLI built at a
# commit, apart from the work tree.

# Builds `embusen` at commit $1 in folder $2 (its sources in $2/base-src,
# built once per commit into $2/base-target); prints the binary's path.
build_base_cli() {
    local commit dir="$2"
    commit="$(git rev-parse --verify "$1^{commit}")"
    mkdir -p "$dir"
    if [ "$(cat "$dir/base-commit" 2>/dev/null)" != "$commit" ]; then
        rm -rf "$dir/base-src"
        mkdir -p "$dir/base-src"
        git archive "$commit" | tar -x -C "$dir/base-src"
        echo "$commit" >"$dir/base-commit"
    fi
    (cd "$dir/base-src" && CARGO_TARGET_DIR="$dir/base-target" cargo build --release --quiet --bin embusen) >&2
    echo "$dir/base-target/release/embusen"
}

# Sets BASE_BIN, `embusen` at commit $1 (built in folder $2), and
# HEAD_BIN, the work tree's (built where cargo builds).
build_base_and_head_cli() {
    BASE_BIN="$(build_base_cli "$1" "$2")"
    cargo build --release --quiet --bin embusen
    HEAD_BIN="${CARGO_TARGET_DIR:-$PWD/target}/release/embusen"
}
