"""Exudyn side of the pendulum comparison: the flexible pendulum of
scenes/pendulum.toml — L = 1 m, circular section R = 0.02 m, E = 2 GPa,
rho = 7200 kg/m^3, pinned at one end, released horizontally, gravity -z —
with Exudyn's 3D ANCF cable (12 DOF per element), generalized-alpha with
rho_inf = 1, modified Newton, h = 1e-3 s. Prints one JSON line per element
count: ms per step and microseconds per unknown per step.
Run through bench/peers/compare_exudyn.sh (it makes the virtual environment).
"""
import json
import math
import sys
import time

import exudyn as exu
from exudyn.beams import GenerateStraightLineANCFCable
from exudyn.itemInterface import ObjectANCFCable

L, R, E, RHO, G = 1.0, 0.02, 2e9, 7200.0, 9.81
A = math.pi * R**2
I = math.pi * R**4 / 4


def run(n: int, steps: int) -> dict:
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    cable = ObjectANCFCable(physicsMassPerLength=RHO * A, physicsBendingStiffness=E * I, physicsAxialStiffness=E * A)
    GenerateStraightLineANCFCable(
        mbs, [0, 0, 0], [L, 0, 0], n, cable, massProportionalLoad=[0, 0, -G],
        fixedConstraintsNode0=[1, 1, 1, 0, 0, 0], fixedConstraintsNode1=[0, 0, 0, 0, 0, 0],
    )
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = steps
    s.timeIntegration.endTime = steps * 1e-3
    s.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    s.timeIntegration.newton.useModifiedNewton = True
    s.timeIntegration.verboseMode = 0
    s.solutionSettings.writeSolutionToFile = False
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse  # sparse, like ours
    s.linearSolverSettings.reuseAnalyzedPattern = True  # symbolic analysis once, like ours
    t0 = time.perf_counter()
    exu.SolveDynamic(mbs, s)
    wall = time.perf_counter() - t0
    unknowns = mbs.systemData.ODE2Size() - 3  # three position coordinates are constrained
    ms = 1e3 * wall / steps
    return {"elements": n, "unknowns": unknowns, "ms_per_step": ms, "us_per_unknown_step": 1e3 * ms / unknowns}


if __name__ == "__main__":
    sizes = [int(a) for a in sys.argv[1:]] or [4, 16, 64, 256]
    for n in sizes:
        print(json.dumps(run(n, 200 if n <= 64 else 50)), flush=True)
