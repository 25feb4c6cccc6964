#!/usr/bin/env bash
# embusen's one entry point for building, running and testing.
#   ./build.sh demo    run the CLI on the built-in demo recording
#   ./build.sh test    all tests (format, lints, unit, integration, parity)
#   ./build.sh bench   print the speed figures
# It installs what it needs on a fresh machine.
set -euo pipefail
cd "$(dirname "$0")"

ensure_rust_components() {
    # rustfmt and clippy come with the usual toolchain profile; add them if not.
    rustup component list --installed 2>/dev/null | grep -q '^rustfmt' || rustup component add rustfmt
    rustup component list --installed 2>/dev/null | grep -q '^clippy' || rustup component add clippy
}

cmd_demo() {
    cargo run --release --quiet --bin embusen
}

cmd_test() {
    ensure_rust_components
    cargo fmt --check
    cargo clippy --all-targets --quiet -- -D warnings
    cargo test --release
}

cmd_bench() {
    cargo bench --bench core
}

case "${1:-demo}" in
    demo) cmd_demo ;;
    test) cmd_test ;;
    bench) cmd_bench ;;
    *)
        echo "usage: ./build.sh [demo|test|bench]" >&2
        exit 2
        ;;
esac
