"""Fit the weakened-bending coefficient ω of a stranded conductor to tip
deflections, as the paper obtains ω from experiments (Lan, Tian & Yu 2020).

The "measurement" in tip_deflection_synthetic.csv is SYNTHETIC: made by this
model with ω = 0.15 plus 1 % Gaussian noise (seed 7) — it stands in for a
bending test of a conductor sample, not for real data. Run from the
repository root:

    python ancf-python/examples/fit_bending_factor.py
"""

import csv
import pathlib
import tempfile

import numpy as np
from scipy.optimize import minimize_scalar

import ancf

HERE = pathlib.Path(__file__).parent

# A 1 m ACSR "Drake" sample (smeared layers as in scenes/wire_rod_impact.toml),
# clamped at one end, a transverse force F at the other; statics.
SCENE = """
[analysis]
kind = "static"
load_steps = 2

[[material]]
name = "steel-core"
model = "st-venant-kirchhoff"
density = 5990.0
youngs_modulus = 154e9
bending_factor = {omega}

[[material]]
name = "aluminium-strands"
model = "st-venant-kirchhoff"
density = 2026.0
youngs_modulus = 51.7e9
bending_factor = {omega}

[wire]
length = 1.0
elements = 8
layers = [ {{ material = "steel-core", outer_radius = 0.0052 }},
           {{ material = "aluminium-strands", outer_radius = 0.01407 }} ]

[[support]]
node = 0
kind = "clamp"

[[load]]
node = "last"
force = [0.0, 0.0, {force}]

[output]
vtk = false
plots = false
"""


def tip_deflection(omega, force):
    """Tip deflection (m, downward positive) under `force` N with bending factor ω."""
    scene = ancf.Scene.from_toml(SCENE.format(omega=omega, force=-force))
    with tempfile.TemporaryDirectory() as out:
        summary = ancf.run(scene, out)
    if summary["status"] != "completed":
        raise ancf.SimulationError(summary["message"])
    return -summary["tip"]["displacement"][2]


def main():
    rows = [r for r in csv.reader(open(HERE / "tip_deflection_synthetic.csv")) if r and not r[0].startswith("#")]
    forces = np.array([float(r[0]) for r in rows[1:]])
    measured = np.array([float(r[1]) for r in rows[1:]])

    def misfit(omega):
        model = np.array([tip_deflection(omega, f) for f in forces])
        return float(np.sum(((model - measured) / measured) ** 2))

    fit = minimize_scalar(misfit, bounds=(0.02, 1.0), method="bounded", options={"xatol": 1e-4})
    print(f"fitted bending factor ω = {fit.x:.4f} (synthetic data made with 0.15), "
          f"rms relative misfit {np.sqrt(fit.fun / len(forces)):.2%}, {fit.nfev} evaluations")


if __name__ == "__main__":
    main()
