"""Scene dicts mutated at random (seeded): every one is either a valid
scene, whose first steps run or fail with SimulationError, or a SceneError
naming a field — never another exception, never a crash."""

import json
import math
import pathlib
import random

import pytest

import ancf

tomllib = pytest.importorskip("tomllib")  # Python ≥ 3.11

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The shipped scenes, and the design keys (a ground under a member,
# plasticity, springs, responses, a release) in a scene small enough to step.
SCENES = ["scenes/pendulum.toml", "scenes/wire_rod_impact.toml",
          "scenes/span_break_elastic_frame.toml", "tests/data/fuzz_design.toml"]

VALUES = [0, -1, 1, 2**40, 1e300, -1e-300, math.nan, math.inf, "", "x", "last", True,
          [], [1.0], [1.0, 2.0, 3.0, 4.0], [0.0, 0.0, 0.0], {}, {"a": 1}, 0.5, 1e-9]


def leaves(d, path=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from leaves(v, path + (k,))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from leaves(v, path + (i,))
    yield path


def mutate(d, rng):
    paths = [p for p in leaves(d) if p]
    path = rng.choice(paths)
    parent = d
    for k in path[:-1]:
        parent = parent[k]
    key = path[-1]
    if rng.random() < 0.2 and isinstance(parent, dict):
        del parent[key]
    else:
        parent[key] = rng.choice(VALUES)
    return ".".join(map(str, path))


# Mutated values are often implausible ones: those are warned of, by design.
@pytest.mark.filterwarnings("ignore::ancf.PlausibilityWarning")
@pytest.mark.parametrize("name", SCENES)
def test_mutated_scene_dicts_are_refused_by_field_or_run(name):
    base = tomllib.loads((ROOT / name).read_text())
    rng = random.Random(20261203)
    refused = 0
    for _ in range(150):
        d = json.loads(json.dumps(base))
        what = mutate(d, rng)
        try:
            scene = ancf.Scene.from_dict(d)
        except ancf.SceneError as e:
            assert e.field, f"{what}: {e}"
            refused += 1
            continue
        if scene.elements > 200:
            continue  # valid; too large to step here
        try:
            # A static start that finds no equilibrium fails here, named.
            sim = ancf.Simulation(scene)
            for _ in range(3):
                if sim.steps[0] < sim.steps[1]:
                    sim.step()
        except ancf.SimulationError:
            pass
    assert refused > 50
