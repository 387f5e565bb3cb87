"""ancf — ANCF beam simulator for electrical wires and cables, from Python.

Scenes use the same TOML schema and validation as the ``ancf`` command
line; results are NumPy arrays. Units are SI (m, kg, s, N, Pa, J).

    >>> import ancf
    >>> sim = ancf.Simulation(ancf.Scene.from_file("scenes/pendulum.toml"))
    >>> r = sim.run(until=1.0, every=10)
    >>> r.tip[-1]            # last node's position at t = 1 s, m
"""

import json as _json
import os as _os
import warnings as _warnings

from ._ancf import (  # noqa: F401
    Material,
    PlausibilityWarning,
    RunResult,
    Scene,
    SceneError,
    Simulation,
    SimulationError,
    Wire,
    quadrature,
)
from . import _ancf

__version__ = _ancf.__version__

# Where an error of TOML syntax or type sits (set on such errors; None else).
SceneError.line = None
SceneError.column = None

__all__ = [
    "Scene",
    "Simulation",
    "Material",
    "Wire",
    "RunResult",
    "SceneError",
    "SimulationError",
    "PlausibilityWarning",
    "run",
    "quadrature",
]


def run(scene, out, quiet=True):
    """Run a scene as ``ancf run`` does and return its summary (a dict).

    ``scene`` is a path to a scene file or an ``ancf.Scene``; the outputs
    (summary.json, timeseries.csv, rod_forces.csv, plots, VTK) are written
    into the directory ``out``. A run that fails numerically raises
    ``SimulationError`` naming the step, the time and the likely cause; the
    outputs up to the last converged step are kept, and the exception's
    ``summary`` attribute holds the summary.
    """
    if not isinstance(scene, Scene):
        if not isinstance(scene, (str, _os.PathLike)):
            raise TypeError("scene: a path to a scene file or an ancf.Scene")
        scene = Scene.from_file(_os.fspath(scene))
    summary = _json.loads(_ancf._run(scene, _os.fspath(out), quiet))
    # The scene's own were raised when it was built; the run's follow.
    for w in summary.get("warnings", []):
        if w not in scene.warnings:
            _warnings.warn(w, PlausibilityWarning, stacklevel=2)
    if summary["status"] == "failed":
        error = SimulationError(summary["message"])
        error.summary = summary
        raise error
    return summary
