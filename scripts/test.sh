#!/usr/bin/env bash
# Every test of the project: the Rust workspace (cargo test), then the
# Python package built into a throw-away virtual environment (pytest).
# Needs a Rust toolchain and python3 with venv; fetches crates and PyPI packages.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --workspace
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 -m venv "$tmp/venv"
"$tmp/venv/bin/pip" install -q --disable-pip-version-check "maturin>=1.16,<2" "numpy>=1.21" pytest meshio
# One abi3 wheel (any CPython ≥ 3.9), built in the workspace's build
# directory so that ancf-core is compiled once, then installed from it.
CARGO_TARGET_DIR="$PWD/target" "$tmp/venv/bin/maturin" build --release --quiet \
    -m ancf-python/Cargo.toml -o "$tmp/dist"
"$tmp/venv/bin/pip" install -q --disable-pip-version-check "$tmp"/dist/ancf-*.whl
"$tmp/venv/bin/python" -m pytest -q ancf-python/tests
