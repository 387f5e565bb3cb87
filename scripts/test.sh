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
"$tmp/venv/bin/pip" install -q --disable-pip-version-check "maturin>=1.16,<2" "numpy>=1.21" pytest
# The extension shares the workspace's build directory: ancf-core is compiled once.
CARGO_TARGET_DIR="$PWD/target" "$tmp/venv/bin/pip" install -q --disable-pip-version-check ./ancf-python
"$tmp/venv/bin/python" -m pytest -q ancf-python/tests
