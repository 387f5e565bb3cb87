#!/usr/bin/env bash
# Side-by-side pendulum timing, ancf against Exudyn's ANCF cable.
# Installs Exudyn from PyPI into a throw-away virtual environment, runs the
# same pendulum (scenes/pendulum.toml geometry and material, rho_inf = 1,
# modified Newton, h = 1e-3 s) in both, and prints the cost per unknown per
# step and the ratio. Run from the repository root:  bash bench/peers/compare_exudyn.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
venv="${EXUDYN_VENV:-$(mktemp -d)/exudyn-venv}"
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet "exudyn==1.13.6" numpy
"$venv/bin/python" bench/peers/exudyn_pendulum.py 4 16 64 256 2>/dev/null > /tmp/exudyn_pendulum.jsonl
cargo build --release --quiet
./target/release/ancf bench --json > /tmp/ancf_bench.json
python3 - <<'PY'
import json
ex = [json.loads(l) for l in open("/tmp/exudyn_pendulum.jsonl") if l.startswith("{")]
ours = json.load(open("/tmp/ancf_bench.json"))
unknowns = {4: 57, 16: 201, 64: 777, 256: 3081}  # our pendulum: 24-DOF beam, pin at node 0
print(f"{'elements':>8} | {'Exudyn ms/step':>14} {'µs/unk/step':>11} | {'ancf ms/step':>12} {'µs/unk/step':>11} | {'ratio per unknown (ancf/Exudyn)':>31}")
for e in ex:
    n = e["elements"]
    ms = ours["step_ms"][str(n)]
    per = 1e3 * ms / unknowns[n]
    print(f"{n:>8} | {e['ms_per_step']:>14.4f} {e['us_per_unknown_step']:>11.2f} | {ms:>12.4f} {per:>11.2f} | {per / e['us_per_unknown_step']:>31.2f}")
PY
