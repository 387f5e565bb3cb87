#!/usr/bin/env bash
# Every test of the project: the Rust workspace (cargo test), then the
# Python package built into a throw-away virtual environment (pytest).
# Needs a Rust toolchain and python3 with venv; fetches crates and PyPI packages.
set -euo pipefail
cd "$(dirname "$0")/.."
# The Rust tests get a temporary folder of their own, which must be empty
# when they end: a test leaves nothing behind (a failing one may keep its
# folder to look at, and then the suite has failed anyway).
scratch=$(mktemp -d)
export TMPDIR="$scratch"
cargo test --release --workspace
# The Slurm test is marked ignored (a machine without Slurm reports it as
# not run). It runs here where a Slurm answers: one already running, or
# one started for it where its daemons are installed and this is root
# (stopped again afterwards).
slurm_idle() { sinfo -h -o %T 2>/dev/null | grep -q idle; }
started_slurm=""
if ! slurm_idle && [ "$(id -u)" = 0 ] && command -v slurmctld >/dev/null 2>&1 \
    && command -v slurmd >/dev/null 2>&1 && command -v munged >/dev/null 2>&1; then
  bash scripts/slurm-local.sh start >/dev/null 2>&1 && started_slurm=1 || true
fi
slurm_status=0
if slurm_idle; then
  cargo test --release --test sweep_slurm -- --include-ignored || slurm_status=$?
else
  echo "the Slurm sweep test is ignored: no Slurm answers here (Debian: apt-get install slurm-wlm munge, then run as root)"
fi
if [ -n "$started_slurm" ]; then
  bash scripts/slurm-local.sh stop >/dev/null 2>&1 || true
fi
[ "$slurm_status" = 0 ] || exit "$slurm_status"
left=$(ls -A "$scratch")
rm -rf "$scratch"
unset TMPDIR
if [ -n "$left" ]; then
  echo "the Rust tests left files in their temporary folder: $left" >&2
  exit 1
fi
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
