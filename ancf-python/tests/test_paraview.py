"""ParaView output read by an independent reader (meshio): the frames a
run writes are the wire's state."""

import json
import re

import numpy as np

import ancf
from test_api import BASE

# Points per ring around the tube and rings per element of vtk.rs.
ANGLES, STATIONS = 16, 4


def test_the_last_frame_is_the_final_state(tmp_path):
    import meshio

    scene = json.loads(json.dumps(BASE))
    scene["analysis"].update(end_time=0.02, time_step=1e-3)
    ancf.run(ancf.Scene.from_dict(scene), tmp_path / "out")
    vtk = tmp_path / "out" / "vtk"
    pvd = (vtk / "wire.pvd").read_text()
    frames = re.findall(r'timestep="([^"]+)"[^>]*file="(wire_[0-9]+\.vtu)"', pvd)
    assert float(frames[-1][0]) == 0.02, pvd
    mesh = meshio.read(vtk / frames[-1][1])
    rings = 4 * STATIONS + 1
    assert mesh.points.shape == (rings * ANGLES, 3)
    assert mesh.cells[0].type == "quad" and len(mesh.cells[0].data) == (rings - 1) * ANGLES
    # A ring's points are the section's edge at 16 equal angles: their mean
    # is the centerline, at the nodes the final nodes.
    centre = mesh.points.reshape(rings, ANGLES, 3).mean(axis=1)
    nodes = np.genfromtxt(tmp_path / "out" / "final_nodes.csv", delimiter=",", names=True)
    final = np.column_stack([nodes["x"], nodes["y"], nodes["z"]])
    assert np.abs(centre[::STATIONS] - final).max() < 1e-6
    # The displacement is from the straight reference along x.
    moved = mesh.point_data["displacement"].reshape(rings, ANGLES, 3).mean(axis=1)
    reference = np.column_stack([np.linspace(0.0, 1.0, rings), np.zeros(rings), np.zeros(rings)])
    assert np.abs(centre - reference - moved).max() < 1e-6
    assert np.abs(moved).max() > 1e-4  # the wire fell and swung
    assert mesh.point_data["green_lagrange_strain"].shape == (rings * ANGLES, 6)
    # A wire falling in its plane does not twist.
    assert np.abs(mesh.point_data["twist"]).max() < 1e-6
    # final_nodes.csv gives each node's gradients too, as the simulation does.
    assert nodes.dtype.names == ("node", "x", "y", "z", "rx_x", "rx_y", "rx_z",
                                 "ry_x", "ry_y", "ry_z", "rz_x", "rz_y", "rz_z")
