"""The Python API — scenes, simulations, NumPy results, errors.

Run from the repository root: `python -m pytest ancf-python/tests`.
"""

import json
import math
import pathlib
import warnings

import numpy as np
import pytest

import ancf

ROOT = pathlib.Path(__file__).resolve().parents[2]
PENDULUM = ROOT / "scenes" / "pendulum.toml"
IMPACT = ROOT / "scenes" / "wire_rod_impact.toml"

BASE = {
    "analysis": {"kind": "dynamic", "end_time": 0.01, "time_step": 1e-3, "spectral_radius": 1.0},
    "gravity": {"acceleration": [0.0, 0.0, -9.81]},
    "material": [
        {"name": "steel", "model": "st-venant-kirchhoff", "density": 7800.0,
         "youngs_modulus": 2e11, "poisson_ratio": 0.3}
    ],
    "wire": {"length": 1.0, "elements": 4, "layers": [{"material": "steel", "outer_radius": 0.01}]},
    "support": [{"node": 0, "kind": "pin"}],
}


def test_scene_from_file_toml_and_dict_agree():
    a = ancf.Scene.from_file(PENDULUM)
    b = ancf.Scene.from_toml(PENDULUM.read_text())
    assert (a.elements, a.unknowns, a.kind) == (b.elements, b.unknowns, b.kind)
    c = ancf.Scene.from_dict(BASE)
    assert c.elements == 4 and c.kind == "dynamic"
    assert "4 elements" in repr(c)


def test_scene_warns_of_a_contact_its_time_step_does_not_resolve():
    assert ancf.Scene.from_file(IMPACT).warnings == []
    stiff = IMPACT.read_text().replace("contact_stiffness = 5e7", "contact_stiffness = 5e9")
    with pytest.warns(ancf.PlausibilityWarning, match="does not resolve rod 0"):
        (w,) = ancf.Scene.from_toml(stiff).warnings
    assert "analysis.time_step = 1e-4 s does not resolve rod 0's line contact" in w
    assert ancf.Scene.from_dict(BASE).warnings == []
    # The simulation's summary carries them as summary.json does (absent when none).
    with pytest.warns(ancf.PlausibilityWarning):
        scene = ancf.Scene.from_toml(stiff)
    assert ancf.Simulation(scene).summary()["warnings"] == [w]
    assert "warnings" not in ancf.Simulation(ancf.Scene.from_file(IMPACT)).summary()


def test_a_unit_slip_is_a_python_warning_that_the_filter_makes_an_error():
    assert issubclass(ancf.PlausibilityWarning, UserWarning)
    slip = ancf.Material.st_venant_kirchhoff(density=7.85, youngs_modulus=2e11)
    wire = ancf.Wire(1.0, 4).layer(slip, 0.01).support(0, "pin")
    with pytest.warns(ancf.PlausibilityWarning, match="density"):
        ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.002)
    d = json.loads(json.dumps(BASE))
    d["material"][0]["youngs_modulus"] = 2e5
    with pytest.warns(ancf.PlausibilityWarning, match="youngs_modulus"):
        ancf.Scene.from_dict(d)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ancf.PlausibilityWarning, match="density"):
            ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.002)
        with pytest.raises(ancf.PlausibilityWarning, match="youngs_modulus"):
            ancf.Scene.from_dict(d)
        # A plausible scene raises nothing.
        ancf.Scene.from_dict(BASE)


def test_a_stress_past_yield_is_warned_of_when_the_run_ends():
    soft = ancf.Material.st_venant_kirchhoff(density=7800.0, youngs_modulus=2e11, yield_stress=1e6)
    tube = ancf.Wire(0.5, 2).layer(ancf.Material.st_venant_kirchhoff(7800.0, 2e11), 0.01).support(0, "fixed")
    wire = tube.member("post", 1.0, 4, origin=[0.0, 1.0, 0.0], direction=[1.0, 0.0, 0.0],
                       layers=[(soft, 0.02)]).support(0, "clamp", beam="post").load(4, [0.0, 0.0, -500.0], beam="post")
    # The wire's contact with the post is not resolved at this step (it
    # never comes near): that too is said when the wire is built.
    with pytest.warns(ancf.PlausibilityWarning, match='member "post"'):
        sim = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.005)
    sim.run(until=0.003)
    with pytest.warns(ancf.PlausibilityWarning, match='beam "post"'):
        sim.run()
    assert any('beam "post"' in w for w in sim.summary()["warnings"])


@pytest.mark.parametrize(
    "edit, field",
    [
        (lambda d: d["wire"].update(elements=0), "wire.elements"),
        (lambda d: d["wire"]["layers"][0].update(outer_radius=-0.01), "wire.layers[0].outer_radius"),
        (lambda d: d["wire"].update(length=math.nan), "wire.length"),
        (lambda d: d["analysis"].update(time_step="1e-3"), "analysis.time_step"),  # wrong type
        (lambda d: d["wire"].update(colour="red"), "wire.colour"),  # unknown key
        (lambda d: d["wire"].update(length=object()), "wire.length"),  # not a TOML type
    ],
)
def test_bad_input_raises_scene_error_naming_the_field(edit, field):
    d = json.loads(json.dumps(BASE))
    edit(d)
    with pytest.raises(ancf.SceneError) as e:
        ancf.Scene.from_dict(d)
    assert isinstance(e.value, ValueError)
    assert e.value.field == field
    if field:
        assert field in str(e.value)


def test_unknown_key_and_wrong_type_are_named_in_the_message():
    d = json.loads(json.dumps(BASE))
    d["wire"]["colour"] = "red"
    with pytest.raises(ancf.SceneError, match="colour"):
        ancf.Scene.from_dict(d)
    with pytest.raises(FileNotFoundError) as e:
        ancf.Scene.from_file(ROOT / "no-such-scene.toml")
    assert e.value.filename.endswith("no-such-scene.toml")
    with pytest.raises(FileNotFoundError):
        ancf.run(ROOT / "no-such-scene.toml", ROOT / "out-never-written")
    assert not (ROOT / "out-never-written").exists()


def test_a_syntax_error_names_its_field_line_and_column():
    with pytest.raises(ancf.SceneError) as e:
        ancf.Scene.from_toml('[wire]\nlength = 1.0\nelements = "x"\n')
    assert (e.value.field, e.value.line, e.value.column) == ("wire.elements", 3, 12)
    d = json.loads(json.dumps(BASE))
    d["wire"]["elements"] = 0
    with pytest.raises(ancf.SceneError) as e:
        ancf.Scene.from_dict(d)
    assert e.value.field == "wire.elements" and e.value.line is None


def test_pendulum_tip_equals_the_cli_run(tmp_path):
    sim = ancf.Simulation(ancf.Scene.from_file(PENDULUM))
    r = sim.run(until=1.0, every=10)
    summary = ancf.run(PENDULUM, tmp_path / "out")
    assert summary["status"] == "completed"
    # Same core, same steps: the same bits, not approximately.
    assert list(r.tip[-1]) == summary["tip"]["position"]
    assert list(sim.tip) == summary["tip"]["position"]
    assert (tmp_path / "out" / "timeseries.csv").exists()


def test_summary_has_the_cli_summary_keys_and_numbers(tmp_path):
    sim = ancf.Simulation(ancf.Scene.from_file(PENDULUM))
    sim.run(every=1000)
    ours = sim.summary()
    cli = ancf.run(PENDULUM, tmp_path / "out")
    for key in ["status", "analysis", "elements", "unknowns", "time", "steps", "newton_iterations",
                "factorizations", "step_cuts", "kernel", "simd", "tip"]:
        assert ours[key] == cli[key], key
    for key, value in ours["energy"].items():
        assert value == cli["energy"][key], key
    assert ours["message"] == cli["message"] and ours["effects"] == cli["effects"]
    assert ours["strains"] == cli["strains"]


@pytest.mark.parametrize("text", ["pendulum", "impact"])
def test_summary_has_exactly_the_keys_of_summary_json(tmp_path, text):
    path = PENDULUM if text == "pendulum" else IMPACT
    scene = path.read_text().replace("end_time = 1.0 ", "end_time = 0.3 ")
    (tmp_path / "s.toml").write_text(scene)
    sim = ancf.Simulation(ancf.Scene.from_toml(scene))
    sim.run(every=1000)
    cli = ancf.run(tmp_path / "s.toml", tmp_path / "out")
    assert set(sim.summary()) == set(cli)
    for key in ["contact", "tip", "energy"]:
        if key in cli:
            assert set(sim.summary()[key]) == set(cli[key]), key


def test_arrays_have_numpy_shapes_and_dtypes():
    scene = ancf.Scene.from_file(PENDULUM)
    sim = ancf.Simulation(scene)
    r = sim.run(until=0.05, every=5)
    assert len(r) == 10
    assert r.time.dtype == np.float64 and r.time.shape == (10,)
    assert r.tip.shape == (10, 3)
    for name in ["kinetic", "strain", "gravity", "total", "dissipated"]:
        assert getattr(r, name).shape == (10,)
    assert r.rod_force.shape == (10, 0)
    assert sim.nodes.shape == (scene.elements + 1, 3)
    assert sim.velocities.shape == (scene.elements + 1, 3)
    # The gradients: unit, orthogonal triads of a pendulum that swings in
    # its plane (r_y normal to it, untouched).
    g = sim.gradients
    assert g.shape == (scene.elements + 1, 9)
    rx, ry, rz = g[:, 0:3], g[:, 3:6], g[:, 6:9]
    assert np.abs(np.linalg.norm(rx, axis=1) - 1.0).max() < 1e-2
    assert np.abs(np.einsum("ij,ij->i", rx, rz)).max() < 1e-2
    assert np.abs(ry - [0.0, 1.0, 0.0]).max() < 1e-9
    assert sim.tip.shape == (3,)
    assert set(sim.energies) >= {"kinetic", "strain", "gravity", "total", "dissipated"}
    assert sim.steps == (50, 1000)
    assert abs(sim.time - 0.05) < 1e-12


def test_step_callback_and_energy_balance():
    sim = ancf.Simulation(ancf.Scene.from_file(PENDULUM))
    sim.step()
    assert sim.steps[0] == 1
    seen = []
    r = sim.run(until=0.1, every=20, callback=lambda s: seen.append(s.time))
    assert seen == list(r.time)
    # ρ∞ = 1: total energy conserved (the swing exchanges tens of J).
    assert np.max(np.abs(r.total - r.total[0])) < 1e-2


def test_contact_loads_per_rod(tmp_path):
    text = IMPACT.read_text().replace("end_time = 1.0", "end_time = 0.3").replace("elements = 64", "elements = 16")
    sim = ancf.Simulation(ancf.Scene.from_toml(text))
    r = sim.run(every=100)
    assert r.rod_force.shape == (len(r), 1)
    (rod,) = sim.contact
    assert rod["peak_force"] > 0 and rod["impulse"] > 0 and rod["cfc"] == 60.0
    assert rod["force"].shape == (3,)
    s = sim.summary()
    assert s["steps"] == 3000 and s["contact"]["rods"][0]["impulse"] == rod["impulse"]
    assert s["contact"]["rods"][0]["law"] == "line"
    # One blow within 0.3 s: the first impact is the whole load so far.
    assert 0.2 < rod["first_contact_time"] < 0.3
    assert rod["first_impact_impulse"] == rod["impulse"]
    assert 0.9 * rod["filtered_peak_force"] <= rod["first_impact_filtered_peak"] <= rod["filtered_peak_force"]
    # The wire's contact record is the CLI's, bit for bit (checkpoints and
    # all: they do not change a run's results).
    cli = ancf.run(ancf.Scene.from_toml(text), tmp_path / "out")
    for key in ["first_time", "max_normal_force", "max_penetration"]:
        assert s["contact"][key] == cli["contact"][key], key
    assert s["contact"]["first_time"] == rod["first_contact_time"]


def test_a_graded_wire_built_in_code():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    wire = ancf.Wire(1.0, 1).graded([(0.5, 2), (0.5, 8)]).layer(steel, 0.01)
    sim = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.01)
    assert sim.summary()["elements"] == 10
    with pytest.raises(ValueError, match=r"segments\[1\].elements"):
        ancf.Wire(1.0, 1).graded([(0.5, 2), (0.5, 0)])
    with pytest.raises(ValueError, match=r"segments\[0\].length"):
        ancf.Wire(1.0, 1).graded([(-0.5, 2)])


def test_simulation_errors():
    static = dict(json.loads(json.dumps(BASE)), analysis={"kind": "static"})
    with pytest.raises(ancf.SceneError) as e:
        ancf.Simulation(ancf.Scene.from_dict(static))
    assert e.value.field == "analysis.kind"
    sim = ancf.Simulation(ancf.Scene.from_dict(BASE))
    sim.run()
    with pytest.raises(ancf.SimulationError, match="end time"):
        sim.step()
    with pytest.raises(ValueError):
        sim.run(every=0)


def test_a_rust_panic_is_a_python_exception():
    with pytest.raises(BaseException, match="deliberate panic"):
        ancf._ancf._panic_for_test()
    # The interpreter goes on.
    assert ancf.Scene.from_dict(BASE).elements == 4


def test_quadrature_integrates_the_area():
    y, z, w = ancf.quadrature(0.5, 1.0, 3)
    assert y.shape == z.shape == w.shape == (7,)
    assert abs(w.sum() - math.pi * (1.0 - 0.25)) < 1e-12
    with pytest.raises(ValueError):
        ancf.quadrature(1.0, 0.5, 3)


def pendulum_wire():
    """scenes/pendulum.toml's wire, written as code."""
    core = ancf.Material.st_venant_kirchhoff(density=7200.0, youngs_modulus=2e9)
    return (
        ancf.Wire(1.0, 4)
        .layer(core, 0.01)
        .layer(core, 0.02)
        .support(0, "pin")
        .gravity([0.0, 0.0, -9.81])
    )


def test_a_wire_built_in_code_equals_the_pendulum_scene():
    # scenes/pendulum.toml written as code: same model, same bits.
    wire = pendulum_wire()
    built = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=1.0, spectral_radius=1.0)
    from_file = ancf.Simulation(ancf.Scene.from_file(PENDULUM))
    built.run(every=1000)
    from_file.run(every=1000)
    assert list(built.tip) == list(from_file.tip)
    # Without ρ∞, both take the one default.
    built = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.2)
    text = PENDULUM.read_text().replace("spectral_radius = 1.0", "").replace(
        "end_time = 1.0", "end_time = 0.2")
    from_file = ancf.Simulation(ancf.Scene.from_toml(text))
    built.run(every=100)
    from_file.run(every=100)
    assert list(built.tip) == list(from_file.tip)


def test_a_damped_wire_built_in_code_equals_the_damped_scene():
    # `[damping]` in a scene and Wire.kelvin_voigt / Wire.rayleigh in code:
    # the same model, the same bits, and the damping dissipates.
    wire = pendulum_wire()
    base = PENDULUM.read_text().replace("end_time = 1.0", "end_time = 0.2")
    for built, table in [
        (wire.kelvin_voigt(1e-3),
         '\n[damping]\nkind = "kelvin-voigt"\nstrain_rate_coefficient = 1e-3\n'),
        (wire.rayleigh(mass=0.5, stiffness=1e-4),
         '\n[damping]\nkind = "rayleigh"\nmass = 0.5\nstiffness = 1e-4\n'),
    ]:
        in_code = ancf.Simulation.from_wire(built, time_step=1e-3, end_time=0.2, spectral_radius=1.0)
        from_scene = ancf.Simulation(ancf.Scene.from_toml(base + table))
        in_code.run(every=100)
        from_scene.run(every=100)
        assert list(in_code.tip) == list(from_scene.tip)
        assert in_code.energies["dissipated"] > 0.0
    with pytest.raises(ValueError, match="^coefficient: "):
        wire.kelvin_voigt(-1.0)
    with pytest.raises(ValueError, match="^mass: "):
        wire.rayleigh()


def test_damping_of_one_beam_acts_on_that_beam_alone():
    # Wire.kelvin_voigt(c, beam=...) is the scene's `damping` in that
    # beam's own table; a damped tube beside the wire leaves the wire alone.
    wire = pendulum_wire()
    base = PENDULUM.read_text().replace("end_time = 1.0", "end_time = 0.2")
    own = base.replace(
        "quadrature = { axial = 3, section = 3 }",
        'quadrature = { axial = 3, section = 3 }\n'
        'damping = { kind = "kelvin-voigt", strain_rate_coefficient = 1e-3 }', 1)
    in_code = ancf.Simulation.from_wire(
        wire.kelvin_voigt(1e-3, beam="wire"), time_step=1e-3, end_time=0.2, spectral_radius=1.0)
    from_scene = ancf.Simulation(ancf.Scene.from_toml(own))
    in_code.run(every=100)
    from_scene.run(every=100)
    assert list(in_code.tip) == list(from_scene.tip)
    assert in_code.energies["dissipated"] > 0.0

    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    frame = wire.member("tube", 1.0, 4, [0.5, -0.5, -1.0], [0.0, 1.0, 0.0], [(steel, 0.03)],
                        inner_radius=0.027).support(0, "clamp", beam="tube")
    runs = {}
    for name, built in [("undamped", frame), ("tube", frame.rayleigh(mass=5.0, beam="tube")),
                        ("wire", frame.rayleigh(mass=5.0, beam="wire"))]:
        sim = ancf.Simulation.from_wire(built, time_step=1e-3, end_time=0.2, spectral_radius=1.0)
        sim.run(every=100)
        runs[name] = sim
    # The tube's damping changes the wire only through the shared Newton
    # iterations (within their tolerance); the wire's own moves its tip.
    moved = {k: float(np.abs(runs[k].tip - runs["undamped"].tip).max()) for k in ("tube", "wire")}
    assert moved["tube"] < 1e-6 and moved["wire"] > 1e-3, moved
    assert runs["wire"].energies["dissipated"] > 0.0
    with pytest.raises(ValueError, match="^beam: "):
        wire.kelvin_voigt(1e-3, beam="tube")


def test_a_supports_response_is_the_runs(tmp_path):
    # `[output] response_frequencies`: the same oscillators' peaks in the
    # Python summary as in the run's summary.json.
    text = PENDULUM.read_text().replace("end_time = 1.0", "end_time = 0.3").replace(
        "[output]", "[output]\nresponse_frequencies = [0.5, 40.0]\nresponse_damping = 0.05")
    sim = ancf.Simulation(ancf.Scene.from_toml(text))
    sim.run()
    (pin,) = sim.supports
    assert [r["frequency"] for r in pin["response"]] == [0.5, 40.0]
    assert all(r["damping"] == 0.05 and len(r["peak"]) == 3 for r in pin["response"])
    ancf.run(ancf.Scene.from_toml(text), tmp_path / "out")
    written = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert written["supports"][0]["response"] == pin["response"]
    assert "response" not in ancf.Simulation(ancf.Scene.from_file(PENDULUM)).supports[0]


def test_the_summary_says_what_computed_it():
    sim = ancf.Simulation(ancf.Scene.from_file(PENDULUM))
    build = sim.summary()["build"]
    assert set(build) == {"version", "commit", "dirty", "rustc", "kernel_orders"}
    assert build["commit"] == "unknown" or len(build["commit"]) == 40
    assert build["rustc"].startswith("rustc ")
    assert build["kernel_orders"]


def test_wire_builder_errors():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    with pytest.raises(ValueError, match="length"):
        ancf.Wire(-1.0, 4)
    with pytest.raises(ValueError, match="outer_radius"):
        ancf.Wire(1.0, 4).layer(steel, -0.01)
    with pytest.raises(ValueError, match="kind"):
        ancf.Wire(1.0, 4).support(0, "glue")
    with pytest.raises(ValueError, match="axis"):
        ancf.Wire(1.0, 4).rod([0, 0, 0], [0, 0, 0], 0.02, 5e7)
    with pytest.raises(TypeError):
        ancf.Wire(1.0, "four")
    with pytest.raises(ancf.SceneError) as e:  # no layer
        ancf.Simulation.from_wire(ancf.Wire(1.0, 4), time_step=1e-3, end_time=0.01)
    assert e.value.field == "layers"
    with pytest.raises(ValueError, match="poisson_ratio"):
        ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.7)


def test_a_wire_with_a_rod_reports_contact():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3, 0.1)
    wire = (
        ancf.Wire(1.0, 16)
        .layer(steel, 0.01)
        .support(0, "pin")
        .gravity([0.0, 0.0, -9.81])
        .rod([0.5, 0.0, -0.2], [0.0, 1.0, 0.0], 0.02, 5e7, friction=0.3, length=0.4)
    )
    sim = ancf.Simulation.from_wire(wire, time_step=1e-4, end_time=0.3)
    r = sim.run(every=100)
    assert r.rod_force.shape == (30, 1)
    assert sim.contact[0]["impulse"] > 0.0


def test_a_wire_dropped_on_the_ground_is_held_and_reported_as_the_cli_reports_it(tmp_path):
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3, 0.1)
    wire = (
        ancf.Wire(1.0, 16)
        .layer(steel, 0.01)
        .support(0, "pin")
        .gravity([0.0, 0.0, -9.81])
        .ground([0.0, 0.0, -0.3], [0.0, 0.0, 1.0], 5e7, friction=0.5, restitution=0.5)
    )
    sim = ancf.Simulation.from_wire(wire, time_step=1e-4, end_time=0.6)
    sim.run()
    # The swinging wire reaches the ground and stays above it.
    assert sim.nodes[:, 2].min() > -0.3
    ground = sim.summary()["contact"]["ground"]
    assert len(ground) == 1 and ground[0]["impulse"] > 0.0
    assert 0.0 < ground[0]["max_depth"] < 0.01
    assert sim.summary()["contact"]["rods"] == []
    with pytest.raises(ValueError, match="restitution"):
        ancf.Wire(1.0, 4).ground([0, 0, 0], [0, 0, 1], 5e7, restitution_model="flores")
    with pytest.raises(ValueError, match="normal"):
        ancf.Wire(1.0, 4).ground([0, 0, 0], [0, 0, 0], 5e7)
    with pytest.raises(ValueError, match="stiffness"):
        ancf.Wire(1.0, 4).ground([0, 0, 0], [0, 0, 1], -1.0)


def test_contact_damping_takes_energy_only_when_asked():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3, 0.1)

    def dissipated(**damping):
        wire = (
            ancf.Wire(1.0, 16)
            .layer(steel, 0.01)
            .support(0, "pin")
            .gravity([0.0, 0.0, -9.81])
            .rod([0.5, 0.0, -0.2], [0.0, 1.0, 0.0], 0.02, 5e7, **damping)
        )
        sim = ancf.Simulation.from_wire(wire, time_step=1e-4, end_time=0.3)
        sim.run()
        return sim.energies["dissipated"]

    assert dissipated() == 0.0
    assert dissipated(restitution=0.3) > 0.0
    with pytest.raises(ValueError, match="restitution"):
        dissipated(restitution=1.5)
    with pytest.raises(ValueError, match="restitution_model"):
        dissipated(restitution=0.5, restitution_model="newton")


def test_ctrl_c_stops_a_run_at_its_last_completed_step():
    import os
    import signal
    import threading

    # Long enough (seconds even at 16 elements) to be running when the
    # signal comes.
    text = (
        IMPACT.read_text()
        .replace("elements = 64", "elements = 16")
        .replace("end_time = 1.0", "end_time = 10.0")
    )
    assert "end_time = 10.0" in text
    sim = ancf.Simulation(ancf.Scene.from_toml(text))
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.run(every=20)
    finally:
        timer.cancel()
    done, total = sim.steps
    assert 0 < done < total and done % 20 == 0, (done, total)
    t = sim.time
    sim.step()  # the simulation goes on from there
    assert sim.time > t


def test_a_failing_run_raises_with_the_cause_and_keeps_its_output(tmp_path):
    text = PENDULUM.read_text().replace("time_step = 1e-3", "time_step = 0.2").replace(
        "end_time = 1.0", "end_time = 1.0\nmax_iterations = 1"
    )
    with pytest.raises(ancf.SimulationError) as e:
        ancf.run(ancf.Scene.from_toml(text), tmp_path / "out")
    assert "step" in str(e.value) and "Likely cause" in str(e.value)
    assert e.value.summary["status"] == "failed"
    assert (tmp_path / "out" / "summary.json").exists()


def test_ctrl_c_stops_ancf_run_and_keeps_the_output(tmp_path):
    import os
    import signal
    import threading

    # Long enough (several seconds) to be running when the signal comes.
    text = IMPACT.read_text().replace("end_time = 1.0", "end_time = 5.0")
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            ancf.run(ancf.Scene.from_toml(text), tmp_path / "out")
    finally:
        timer.cancel()
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert (tmp_path / "out" / "timeseries.csv").exists()


def test_a_tube_is_a_wire_with_a_bore():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    tube = ancf.Wire(2.0, 8).layer(steel, 0.05).bore(0.046).support(0, "clamp")
    solid = ancf.Wire(2.0, 8).layer(steel, 0.05).support(0, "clamp")

    def largest_sag(wire):
        sim = ancf.Simulation.from_wire(wire.gravity([0, 0, -9.81]), time_step=1e-3, end_time=0.2)
        return -sim.run(every=1).tip[:, 2].min()

    # Self-weight sag scales with ρA / EI: the tube's is about half the bar's.
    ratio = largest_sag(tube) / largest_sag(solid)
    assert 0.4 < ratio < 0.7, ratio
    with pytest.raises(ancf.SceneError) as e:
        ancf.Simulation.from_wire(
            ancf.Wire(2.0, 8).layer(steel, 0.05).bore(0.05).support(0, "clamp"),
            time_step=1e-3,
            end_time=0.01,
        )
    assert e.value.field == "layers[0].outer_radius"


def test_support_loads_after_a_break_match_the_cli(tmp_path):
    # A 20 m span sagging between two pins; the right one lets go at t = 0.
    scene = json.loads(json.dumps(BASE))
    scene["analysis"].update(end_time=0.05, time_step=1e-3, initial="static", spectral_radius=0.9)
    scene["wire"].update(length=20.0, elements=20)
    scene["wire"]["layers"][0]["outer_radius"] = 0.005
    scene["support"] = [{"node": 0, "kind": "pin"}, {"node": "last", "kind": "pin", "release_time": 0.0}]
    sim = ancf.Simulation(ancf.Scene.from_dict(scene))
    sim.run()
    left, right = sim.supports
    assert (left["beam"], left["node"], right["node"]) == ("wire", 0, 20)
    assert left["time"].shape == (51,) and left["force"].shape == (51, 3)
    # t = 0 is the static equilibrium with both pins: they share the weight.
    weight = 7800.0 * math.pi * 0.005**2 * 20.0 * 9.81
    assert abs(left["static_force"][2] + right["static_force"][2] - weight) < 1e-6 * weight
    assert np.all(left["force"][0] == left["static_force"])
    # The released pin carries nothing after the break; the other one peaks.
    assert np.all(right["force"][1:] == 0.0)
    peak = np.max(np.linalg.norm(left["force"], axis=1))
    assert left["peak_force"] == peak
    assert left["ratio_to_static"] == pytest.approx(peak / np.linalg.norm(left["static_force"]), rel=1e-12)
    cli = ancf.run(ancf.Scene.from_dict(scene), tmp_path / "out")
    assert [s["peak_force"] for s in cli["supports"]] == [s["peak_force"] for s in sim.summary()["supports"]]
    table = np.genfromtxt(tmp_path / "out" / "supports.csv", delimiter=",", names=True)
    assert table.dtype.names == ("time", "s0_fx", "s0_fy", "s0_fz", "s1_fx", "s1_fy", "s1_fz")
    assert np.allclose(table["s0_fz"], left["force"][:, 2], rtol=1e-9, atol=0.0)
    # Started at rest in the unloaded shape, t = 0 holds no static load: no ratios.
    scene["analysis"]["initial"] = "reference"
    sim = ancf.Simulation(ancf.Scene.from_dict(scene))
    sim.run()
    assert sim.supports[0]["peak_force"] > 0.0
    assert "ratio_to_static" not in sim.supports[0]


def test_a_wire_on_springs_equals_its_scene():
    # Two elastic posts with dashpots, in code and as a scene: the same bits;
    # a negative stiffness is refused naming the support's field.
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    wire = (
        ancf.Wire(2.0, 8)
        .layer(steel, 0.01)
        .spring(0, [2e4, 2e4, 2e4], rotational_stiffness=10.0, damping=50.0)
        .spring(8, [2e4, 2e4, 2e4], rotational_stiffness=10.0, damping=50.0)
        .gravity([0.0, 0.0, -9.81])
    )
    built = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.05)
    scene = json.loads(json.dumps(BASE))
    scene["analysis"].update(end_time=0.05, time_step=1e-3, spectral_radius=0.9)
    scene["wire"].update(length=2.0, elements=8)
    post = {"kind": "spring", "stiffness": [2e4, 2e4, 2e4], "rotational_stiffness": 10.0, "damping": 50.0}
    scene["support"] = [dict(post, node=0), dict(post, node="last")]
    from_file = ancf.Simulation(ancf.Scene.from_dict(scene))
    built.run()
    from_file.run()
    assert list(built.tip) == list(from_file.tip)
    assert built.energies["dissipated"] > 0.0
    # The posts carry the span's weight between them, less what moves.
    left, right = built.supports
    assert left["force"].shape == (51, 3) and left["static_force"] == [0.0, 0.0, 0.0]
    with pytest.raises(ancf.SceneError) as e:
        ancf.Simulation.from_wire(
            ancf.Wire(2.0, 8).layer(steel, 0.01).spring(8, [1.0, -1.0, 1.0]), time_step=1e-3, end_time=0.01)
    assert e.value.field == "supports[0].stiffness[1]"


def test_clearance_in_python_equals_the_cli(tmp_path):
    # The pendulum's tip swings below z = -0.5 m: the zone is entered.
    text = PENDULUM.read_text().replace("end_time = 1.0", "end_time = 0.6") + (
        '\n[[clearance]]\nkind = "half-space"\npoint = [0.0, 0.0, -0.5]\nnormal = [0.0, 0.0, 1.0]\n')
    sim = ancf.Simulation(ancf.Scene.from_toml(text))
    sim.run(every=50)
    (ours,) = sim.summary()["clearance"]
    (cli,) = ancf.run(ancf.Scene.from_toml(text), tmp_path / "out")["clearance"]
    assert ours == cli
    assert ours["entered"] and ours["min_distance"] < -0.3


def test_a_member_in_code_equals_its_scene(tmp_path):
    # A tube member beside the wire, built in code and read from a scene:
    # the same supports' loads, named by beam.
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    wire = (
        ancf.Wire(2.0, 4)
        .layer(steel, 0.01)
        .support(0, "pin")
        .gravity([0.0, 0.0, -9.81])
        .member("tube", 4.0, 8, [1.0, -2.0, -2.0], [0.0, 1.0, 0.0], [(steel, 0.05)], inner_radius=0.046)
        .support(0, "clamp", beam="tube")
        .support(8, "pin", beam="tube")
        .load(4, [0.0, 0.0, -1000.0], beam="tube")
    )
    built = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.01)
    scene = json.loads(json.dumps(BASE))
    scene["analysis"].update(end_time=0.01, time_step=1e-3, spectral_radius=0.9)
    scene["wire"].update(length=2.0, elements=4)
    scene["beam"] = [{"name": "tube", "length": 4.0, "elements": 8, "origin": [1.0, -2.0, -2.0],
                      "direction": [0.0, 1.0, 0.0],
                      "layers": [{"material": "steel", "inner_radius": 0.046, "outer_radius": 0.05}]}]
    scene["support"] = [{"node": 0, "kind": "pin"}, {"beam": "tube", "node": 0, "kind": "clamp"},
                        {"beam": "tube", "node": "last", "kind": "pin"}]
    scene["load"] = [{"beam": "tube", "node": 4, "force": [0.0, 0.0, -1000.0]}]
    from_file = ancf.Simulation(ancf.Scene.from_dict(scene))
    built.run()
    from_file.run()
    assert [(s["beam"], s["node"]) for s in built.supports] == [("wire", 0), ("tube", 0), ("tube", 8)]
    assert [list(s["force"][-1]) for s in built.supports] == [list(s["force"][-1]) for s in from_file.supports]
    assert built.summary()["elements"] == 12
    (tube,) = built.summary()["beams"]
    assert tube["name"] == "tube" and tube == from_file.summary()["beams"][0]
    assert tube["max_bending_moment"] > 0.0 and tube["max_von_mises"] > 0.0
    cli = ancf.run(ancf.Scene.from_dict(scene), tmp_path / "out")
    assert cli["beams"][0] == from_file.summary()["beams"][0]
    with pytest.raises(ancf.SceneError) as e:
        ancf.Simulation.from_wire(wire.support(9, "pin", beam="tube"), time_step=1e-3, end_time=0.01)
    assert e.value.field == "supports[3].node"


def test_vectors_are_three_numbers():
    # A fourth entry is refused, not dropped.
    scene = json.loads(json.dumps(BASE))
    scene["load"] = [{"node": 4, "force": [0.0, 0.0, -1.0, 12345.0]}]
    with pytest.raises(ancf.SceneError, match="exactly 3 numbers"):
        ancf.Scene.from_dict(scene)


@pytest.mark.parametrize("elements", [2**40, 2**62])
def test_a_wire_too_large_is_refused_not_a_crash(elements):
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    with pytest.raises(ancf.SceneError) as e:
        ancf.Simulation.from_wire(ancf.Wire(1.0, elements).layer(steel, 0.01).support(0, "pin"),
                                  time_step=1e-3, end_time=0.01)
    assert e.value.field == "elements"


def test_a_dict_that_holds_itself_is_refused_not_a_crash():
    d = {}
    d["analysis"] = d
    with pytest.raises(ancf.SceneError, match="nested deeper than 32 levels"):
        ancf.Scene.from_dict(d)
    deep = []
    for _ in range(10_000):
        deep = [deep]
    scene = json.loads(json.dumps(BASE))
    scene["wire"]["origin"] = deep
    with pytest.raises(ancf.SceneError, match="nested deeper"):
        ancf.Scene.from_dict(scene)


def test_the_wire_falls_onto_a_member_in_code_as_in_its_scene(tmp_path):
    # The impact scene with its rod a clamped steel bar: the bar's contact
    # load (first contact, filtered peak, impulse) in the summary, equal to
    # the CLI's, the same from a wire built in code.
    text = IMPACT.read_text()
    rod = text[text.index("[[rod]]"):text.index("[output]")]
    bar = (
        '[[beam]]\nname = "bar"\nlength = 0.6\nelements = 8\norigin = [1.0, -0.3, -0.3]\n'
        'direction = [0.0, 1.0, 0.0]\nlayers = [ { material = "rod-steel", outer_radius = 0.02 } ]\n'
        'contact_law = "line"\ncontact_stiffness = 5e7\nfriction = 0.3\n\n'
        '[[support]]\nbeam = "bar"\nnode = 0\nkind = "clamp"\n\n'
        '[[support]]\nbeam = "bar"\nnode = "last"\nkind = "clamp"\n\n'
    )
    text = text.replace(rod, bar).replace("end_time = 1.0", "end_time = 0.35")
    sim = ancf.Simulation(ancf.Scene.from_toml(text))
    sim.run()
    (ours,) = sim.summary()["beams"]
    assert ours["first_contact_time"] is not None and 0.2 < ours["first_contact_time"] < 0.3
    assert ours["filtered_peak_force"] > 100.0 and ours["impulse"] > 0.0
    assert ours["max_bending_moment"] > 0.0
    cli = ancf.run(ancf.Scene.from_toml(text), tmp_path / "out")
    assert cli["beams"][0] == ours
    forces = (tmp_path / "out" / "member_forces.csv").read_text().splitlines()
    header = forces[0].split(",")
    assert header[-1] == "bar_moment"
    moments = [float(line.split(",")[-1]) for line in forces[1:]]
    # The step's largest moment: its largest over the run is the summary's
    # (to the CSV's ten significant digits).
    assert max(moments) == pytest.approx(ours["max_bending_moment"], rel=1e-9)
    # A member built in code touches the wire alike.
    steel_core = ancf.Material.st_venant_kirchhoff(5990.0, 154e9, 0.0, 0.1)
    alu = ancf.Material.st_venant_kirchhoff(2026.0, 51.7e9, 0.0, 0.1)
    rod_steel = ancf.Material.st_venant_kirchhoff(7850.0, 200e9, 0.3)
    wire = (
        ancf.Wire(2.0, 64)
        .layer(steel_core, 0.0052)
        .layer(alu, 0.01407)
        .support(0, "pin")
        .gravity([0.0, 0.0, -9.81])
        .member("bar", 0.6, 8, [1.0, -0.3, -0.3], [0.0, 1.0, 0.0], [(rod_steel, 0.02)],
                contact_law="line", contact_stiffness=5e7, friction=0.3)
        .support(0, "clamp", beam="bar")
        .support(8, "clamp", beam="bar")
    )
    built = ancf.Simulation.from_wire(wire, time_step=1e-4, end_time=0.35, spectral_radius=1.0)
    built.run()
    (theirs,) = built.summary()["beams"]
    # Newton to its default tolerance here, 1e-4 in the scene.
    assert math.isclose(theirs["filtered_peak_force"], ours["filtered_peak_force"], rel_tol=1e-3)


def test_the_package_says_its_version():
    assert ancf.__version__.count(".") == 2
    assert ancf.__version__ == ancf._ancf.__version__


def test_adaptive_steps_from_a_dict_match_the_cli(tmp_path):
    scene = json.loads(json.dumps(BASE))
    scene["analysis"].update(end_time=0.2, time_step="auto", error_tolerance=1e-6)
    sim = ancf.Simulation(ancf.Scene.from_dict(scene))
    sim.run(every=1)
    ours = sim.summary()
    steps = ours["time_steps"]
    assert steps["adaptive"] is True
    assert steps["shortest_s"] <= steps["mean_s"] <= steps["longest_s"] <= 0.2 / 100
    assert abs(sim.time - 0.2) == 0.0, "the last step ends at end_time exactly"
    assert "adaptive steps" in ours["message"]
    toml = PENDULUM.read_text().replace("time_step = 1e-3", 'time_step = "auto"\nerror_tolerance = 1e-6')
    (tmp_path / "a.toml").write_text(toml)
    cli = ancf.run(tmp_path / "a.toml", tmp_path / "out")
    again = ancf.Simulation(ancf.Scene.from_toml(toml))
    again.run(every=1000)
    assert again.summary()["time_steps"] == cli["time_steps"]
    assert again.summary()["steps"] == cli["steps"]


def test_a_time_step_that_is_neither_seconds_nor_auto_names_the_field():
    scene = json.loads(json.dumps(BASE))
    scene["analysis"]["time_step"] = "fast"
    with pytest.raises(ancf.SceneError, match="analysis.time_step"):
        ancf.Scene.from_dict(scene)


def test_adaptive_steps_of_a_wire_built_in_code_equal_the_scene_file():
    core = ancf.Material.st_venant_kirchhoff(density=7200.0, youngs_modulus=2e9)
    wire = (
        ancf.Wire(1.0, 4)
        .layer(core, 0.01)
        .layer(core, 0.02)
        .support(0, "pin")
        .gravity([0.0, 0.0, -9.81])
    )
    built = ancf.Simulation.from_wire(
        wire, time_step="auto", end_time=0.2, spectral_radius=1.0, error_tolerance=1e-6,
        max_time_step=5e-3)
    text = PENDULUM.read_text().replace("end_time = 1.0", "end_time = 0.2").replace(
        "time_step = 1e-3", 'time_step = "auto"\nerror_tolerance = 1e-6\nmax_time_step = 5e-3')
    from_file = ancf.Simulation(ancf.Scene.from_toml(text))
    ours, theirs = built.run(every=1), from_file.run(every=1)
    assert list(ours.time) == list(theirs.time)
    assert ours.tip.tolist() == theirs.tip.tolist()
    steps = built.summary()["time_steps"]
    assert steps["adaptive"] is True and steps["longest_s"] <= 5e-3
    assert steps == from_file.summary()["time_steps"]


@pytest.mark.parametrize("arguments, field", [
    (dict(time_step="fast"), "time_step"),
    (dict(time_step="auto"), "error_tolerance"),
    (dict(time_step="auto", error_tolerance=-1e-6), "error_tolerance"),
    (dict(time_step="auto", error_tolerance=1e-6, max_time_step=1.0), "max_time_step"),
    (dict(time_step=1e-3, error_tolerance=1e-6), "error_tolerance"),
    (dict(time_step=1e-3, max_time_step=1e-2), "max_time_step"),
])
def test_adaptive_step_arguments_that_do_not_fit_name_the_argument(arguments, field):
    wire = ancf.Wire(1.0, 4).layer(ancf.Material.st_venant_kirchhoff(7800.0, 2e11), 0.01)
    with pytest.raises(ValueError, match=f"^{field}: "):
        ancf.Simulation.from_wire(wire, end_time=0.1, **arguments)


def test_a_yielding_cantilever_in_code():
    s235 = ancf.Material.elastic_plastic(7850.0, 2.1e11, 2.35e8, poisson_ratio=0.3, rate_d=40.4, rate_q=5.0)
    wire = (
        ancf.Wire(3.0, 8)
        .layer(s235, 0.05)
        .bore(0.046)
        .support(0, "clamp")
        .load(8, [0.0, 0.0, -1733.0])
    )
    sim = ancf.Simulation.from_wire(wire, time_step=5e-4, end_time=0.03)
    sim.run()
    summary = sim.summary()
    assert summary["energy"]["plastic"] > 0.0
    assert summary["strains"][0]["plastic_work"] > 0.0
    assert summary["strains"][0]["max_plastic_strain"]["max_strain"] > 0.0
    with pytest.raises(ValueError, match="rate_q"):
        ancf.Material.elastic_plastic(7850.0, 2.1e11, 2.35e8, rate_d=40.4)
    with pytest.raises(ValueError, match="hardening"):
        ancf.Material.elastic_plastic(7850.0, 2.1e11, 2.35e8, hardening="linear")
    with pytest.raises(ValueError, match="hardening_modulus"):
        ancf.Material.elastic_plastic(7850.0, 2.1e11, 2.35e8, hardening_modulus=-1.0)


def test_counts_that_are_not_whole_numbers_say_so_in_the_users_words():
    with pytest.raises(ValueError, match="must be a whole number ≥ 0, got -4") as e:
        ancf.Wire(1.0, -4)
    assert "while processing 'elements'" in getattr(e.value, "__notes__", [""])[0]
    with pytest.raises(TypeError, match="must be a whole number, got 2.5"):
        ancf.Wire(1.0, 2.5)
    with pytest.raises(TypeError, match="must be a whole number, got True"):
        ancf.Wire(1.0, True)
    with pytest.raises(ValueError, match="got -1"):
        ancf.Wire(1.0, 4).support(-1, "pin")
    with pytest.raises(ValueError, match="got -2"):
        ancf.Wire(1.0, 4).graded([(1.0, -2)])
    wire = ancf.Wire(1.0, 4).layer(ancf.Material.st_venant_kirchhoff(7800.0, 2e11), 0.01).support(0, "pin")
    sim = ancf.Simulation.from_wire(wire, time_step=1e-3, end_time=0.002)
    with pytest.raises(ValueError, match="got -3"):
        sim.run(every=-3)
    assert len(sim.run(every=1).time) == 2  # the two steps


def test_a_members_contact_keys_follow_the_scenes_rules():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    wire = ancf.Wire(1.0, 4).layer(steel, 0.01).support(0, "pin")

    def member(**contact):
        return wire.member("tube", 1.0, 4, [0.5, -0.5, -1.0], [0.0, 1.0, 0.0], [(steel, 0.03)], **contact)

    for contact, field in [
        ({"contact_stiffness": 5e7}, "contact_law"),  # a stiffness without its law
        ({"contact_law": "hertz", "contact_stiffness": 5e7}, "contact_stiffness"),
        ({"contact_law": "line"}, "contact_stiffness"),
        ({"contact_law": "penalty"}, "contact_law"),
        ({"restitution_model": "flores"}, "restitution"),  # a model without its coefficient
        ({"restitution": 0.5, "restitution_model": "newton"}, "restitution_model"),
    ]:
        with pytest.raises(ValueError, match=f"^{field}: "):
            member(**contact)
        # The scene file refuses the same keys at the same field.
        scene = json.loads(json.dumps(BASE))
        scene["beam"] = [{"name": "tube", "length": 1.0, "elements": 4, "origin": [0.5, -0.5, -1.0],
                          "direction": [0.0, 1.0, 0.0],
                          "layers": [{"material": "steel", "outer_radius": 0.03}], **contact}]
        with pytest.raises(ancf.SceneError) as e:
            ancf.Scene.from_dict(scene)
        assert e.value.field == f"beam[0].{field}", (contact, e.value.field)
    member(contact_law="line", contact_stiffness=5e7, restitution=0.5, restitution_model="flores")


def test_a_ground_names_the_members_that_touch_it():
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    wire = (
        ancf.Wire(1.0, 4).layer(steel, 0.01).support(0, "fixed").support(4, "fixed")
        .member("tube", 1.0, 4, [0.0, 1.0, -0.5], [1.0, 0.0, 0.0], [(steel, 0.02)])
        .gravity([0.0, 0.0, -9.81])
    )
    with pytest.raises(ValueError, match="^beams: .*leaves out the wire"):
        wire.ground([0.0, 0.0, -0.52], [0.0, 0.0, 1.0], 1e7, beams=["tube"])
    with pytest.raises(ancf.SceneError, match='no frame member is named "post"'):
        ancf.Simulation.from_wire(
            wire.ground([0.0, 0.0, -0.52], [0.0, 0.0, 1.0], 1e7, beams=["wire", "post"]),
            time_step=1e-4, end_time=1e-3)
    # The tube, 2 cm above the ground under its own weight, falls onto it
    # and the ground takes its load; without it named, it falls through.
    for named, touches in [(["wire", "tube"], True), (None, False)]:
        grounded = wire.ground([0.0, 0.0, -0.54], [0.0, 0.0, 1.0], 1e7, beams=named)
        sim = ancf.Simulation.from_wire(grounded, time_step=1e-4, end_time=0.12)
        sim.run()
        (ground,) = sim.contact
        assert (ground["peak_force"] > 0.0) == touches, ground


@pytest.mark.parametrize(
    "stepping, field",
    [
        ({"time_step": 1e-3, "error_tolerance": 1e-6}, "error_tolerance"),
        ({"time_step": 1e-3, "max_time_step": 1e-3}, "max_time_step"),
        ({"time_step": "auto"}, "error_tolerance"),
        ({"time_step": "auto", "error_tolerance": 1e-6, "max_time_step": 0.0}, "max_time_step"),
        ({"time_step": "auto", "error_tolerance": -1.0}, "error_tolerance"),
    ],
)
def test_stepping_follows_the_scenes_rule_with_the_scenes_words(stepping, field):
    steel = ancf.Material.st_venant_kirchhoff(7800.0, 2e11, 0.3)
    wire = ancf.Wire(1.0, 4).layer(steel, 0.01).support(0, "pin")
    with pytest.raises(ValueError) as in_code:
        ancf.Simulation.from_wire(wire, end_time=0.01, **stepping)
    d = json.loads(json.dumps(BASE))
    d["analysis"].pop("time_step")
    d["analysis"].update(stepping)
    with pytest.raises(ancf.SceneError) as in_scene:
        ancf.Scene.from_dict(d)
    assert in_scene.value.field == f"analysis.{field}"
    # The same reason, each in its own field's name.
    assert str(in_code.value) == f"{field}: " + str(in_scene.value).split(": ", 1)[1]
