"""The flexible pendulum of scenes/pendulum.toml from Python: tip path and
energies with matplotlib. Run from the repository root:

    python ancf-python/examples/pendulum.py        # writes pendulum.png
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import ancf

sim = ancf.Simulation(ancf.Scene.from_file("scenes/pendulum.toml"))
r = sim.run(every=5)  # a record every 5 steps (5 ms) to the end time (1 s)

fig, (path, energy) = plt.subplots(1, 2, figsize=(11, 4.5))
path.plot(r.tip[:, 0], r.tip[:, 2])
path.set(xlabel="tip x (m)", ylabel="tip z (m)", title="Tip path", aspect="equal")
for name in ["kinetic", "strain", "gravity", "total"]:
    energy.plot(r.time, getattr(r, name), label=name)
energy.set(xlabel="time t (s)", ylabel="energy (J)", title="Energies (ρ∞ = 1: total conserved)")
energy.legend()
fig.tight_layout()
fig.savefig("pendulum.png", dpi=120)
drift = abs(r.total - r.total[0]).max()
print(f"tip at t = {r.time[-1]:.3f} s: {r.tip[-1]} m; total energy drift {drift:.2e} J; wrote pendulum.png")
