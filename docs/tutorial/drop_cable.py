"""The tutorial's cable from Python: run it, read the rail's load, change
one thing (the rail without friction) and compare.

    python drop_cable.py          (from docs/tutorial, with ancf installed)
"""

import pathlib

import ancf

here = pathlib.Path(__file__).parent
scene = ancf.Scene.from_file(here / "drop_cable.toml")
sim = ancf.Simulation(scene)
r = sim.run(until=0.8, every=10)  # NumPy arrays, every 10th step
rail = sim.contact[0]
print(f"first contact at {rail['first_contact_time']:.4f} s")
print(f"rail: filtered peak {rail['filtered_peak_force']:.1f} N, impulse {rail['impulse']:.3f} N s")
print(f"largest raw force in the samples: {r.rod_force.max():.1f} N")

# The same cable onto a frictionless rail: the scene's text, edited
# (Scene.from_dict takes a dictionary, as tomllib.loads gives).
edited = scene.source.replace("friction = 0.3", "friction = 0.0")
smooth = ancf.Simulation(ancf.Scene.from_toml(edited))
smooth.run(until=0.8, every=100)
print(f"frictionless rail: filtered peak {smooth.contact[0]['filtered_peak_force']:.1f} N")
