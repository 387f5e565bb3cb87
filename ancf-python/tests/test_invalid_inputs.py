"""The same invalid value is refused for the same reason through a scene
(read by the package) and through the package's own calls (Material,
Wire, Wire.rod, Simulation.from_wire): the cases of
ancf-core/tests/data/invalid_inputs.toml, which the core's tests run
through the scene file and the Rust builder.

Run from the repository root: `python -m pytest ancf-python/tests`.
"""

import copy
import pathlib
import tomllib

import pytest

import ancf

ROOT = pathlib.Path(__file__).resolve().parents[2]
TABLE = ROOT / "ancf-core" / "tests" / "data" / "invalid_inputs.toml"
CASES = tomllib.loads(TABLE.read_text())["case"]

BASE = {
    "analysis": {"kind": "dynamic", "end_time": 0.01, "time_step": 1e-3},
    "material": [
        {"name": "steel", "model": "st-venant-kirchhoff", "density": 7800.0,
         "youngs_modulus": 2e11, "poisson_ratio": 0.3}
    ],
    "wire": {"length": 1.0, "elements": 4, "layers": [{"material": "steel", "outer_radius": 0.01}]},
    "support": [{"node": 0, "kind": "pin"}],
    "rod": [{"center": [0.5, 0.0, -0.2], "axis": [0.0, 1.0, 0.0], "radius": 0.02,
             "contact_law": "line", "contact_stiffness": 5e7}],
}

# Wire.rod spells the rod's stiffness `stiffness`.
ROD_ARGUMENT = {"contact_stiffness": "stiffness"}


def scene_error(case):
    """The scene refuses the case: (field, message)."""
    d = copy.deepcopy(BASE)
    part, p, v = case["part"], case["parameter"], case["value"]
    table = {
        "material": lambda: d["material"][0],
        "layer": lambda: d["wire"]["layers"][0],
        "rod": lambda: d["rod"][0],
    }.get(part, lambda: d[part])()
    table[p] = v
    with pytest.raises(ancf.SceneError) as e:
        ancf.Scene.from_dict(d)
    field = e.value.field
    message = str(e.value).removeprefix(f"{field}: ")
    return field, message


def call_error(case):
    """The package's own call refuses the case: (argument, message)."""
    part, p, v = case["part"], case["parameter"], case["value"]
    material = {"density": 7800.0, "youngs_modulus": 2e11, "poisson_ratio": 0.3,
                "bending_factor": 1.0}
    rod = {"radius": 0.02, "stiffness": 5e7, "friction": 0.0}
    length, radius = 1.0, 0.01
    settings = {"time_step": 1e-3, "end_time": 0.01}
    if part == "material":
        material[p] = v
    elif part == "rod":
        rod[ROD_ARGUMENT.get(p, p)] = v
    elif part == "layer":
        radius = v
    elif part == "wire":
        length = v
    elif part == "analysis":
        settings[p] = v
    with pytest.raises(ValueError) as e:
        steel = ancf.Material.st_venant_kirchhoff(**material)
        wire = (
            ancf.Wire(length, 4)
            .layer(steel, radius)
            .support(0, "pin")
            .rod([0.5, 0.0, -0.2], [0.0, 1.0, 0.0], **rod)
        )
        ancf.Simulation.from_wire(wire, **settings)
    argument, _, message = str(e.value).partition(": ")
    return argument, message


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c['part']}.{c['parameter']}={c['value']}")
def test_every_invalid_value_is_refused_for_the_same_reason(case):
    field, scene_message = scene_error(case)
    assert field.endswith(case["parameter"])
    assert case["reason"] in scene_message
    argument, message = call_error(case)
    assert argument == ROD_ARGUMENT.get(case["parameter"], case["parameter"])
    assert message == scene_message
