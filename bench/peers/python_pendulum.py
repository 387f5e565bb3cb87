"""Python side by side: the pendulum of scenes/pendulum.toml
through ancf's Python API and through Exudyn's (its ANCF cable, as in
exudyn_pendulum.py), in one process. For ancf: time per step when Python
calls `sim.step()` each step, and when `sim.run()` steps inside Rust — their
difference is the per-call overhead. Prints a table. Run through
bench/peers/compare_python.sh (it builds both into a virtual environment).
"""
import pathlib
import sys
import time

import ancf

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import exudyn_pendulum  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
TEXT = (ROOT / "scenes" / "pendulum.toml").read_text()


def ancf_times(n, steps):
    scene = ancf.Scene.from_toml(TEXT.replace("elements = 4", f"elements = {n}"))
    best_call, best_run = float("inf"), float("inf")
    for _ in range(3):
        sim = ancf.Simulation(scene)
        sim.run(until=0.005)  # settle the predictor history like the Rust bench
        t0 = time.perf_counter()
        for _ in range(steps):
            sim.step()
        best_call = min(best_call, (time.perf_counter() - t0) / steps)
        sim = ancf.Simulation(scene)
        sim.run(until=0.005)
        t0 = time.perf_counter()
        sim.run(until=0.005 + steps * 1e-3, every=steps)
        best_run = min(best_run, (time.perf_counter() - t0) / steps)
    return scene.unknowns, best_call, best_run


print(f"{'elements':>8} | {'Exudyn ms/step':>14} | {'ancf sim.step() ms':>18} {'ancf run() ms':>13} {'call overhead µs':>16} | {'ancf/Exudyn per step':>20}")
for n, steps in [(4, 300), (16, 300), (64, 200), (256, 100)]:
    ex = exudyn_pendulum.run(n, steps)
    unknowns, call, inside = ancf_times(n, steps)
    print(f"{n:>8} | {ex['ms_per_step']:>14.4f} | {1e3 * call:>18.4f} {1e3 * inside:>13.4f} {1e6 * (call - inside):>16.2f} | {1e3 * call / ex['ms_per_step']:>20.2f}")
