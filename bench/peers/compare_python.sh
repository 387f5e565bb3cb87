#!/usr/bin/env bash
# Python side by side: the pendulum through ancf's Python API and
# through Exudyn's, in one process. Builds ancf-python and installs Exudyn
# from PyPI into a throw-away virtual environment. Run from the repository
# root:  bash bench/peers/compare_python.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 -m venv "$tmp/venv"
"$tmp/venv/bin/pip" install --quiet "exudyn==1.13.6" numpy "maturin>=1.16,<2"
CARGO_TARGET_DIR="$PWD/target" "$tmp/venv/bin/pip" install --quiet ./ancf-python
"$tmp/venv/bin/python" bench/peers/python_pendulum.py 2>/dev/null
