"""docs/tutorial.md, step 9: the Python script runs and prints the numbers
the tutorial quotes for steps 5 and 6."""

import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_the_tutorial_script_prints_the_quoted_loads():
    script = ROOT / "docs" / "tutorial" / "drop_cable.py"
    out = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, check=True
    ).stdout
    assert "first contact at 0.2627 s" in out, out
    peak, impulse = map(float, re.search(r"rail: filtered peak ([\d.]+) N, impulse ([\d.]+) N s", out).groups())
    assert abs(peak - 159.0) <= 0.5 and abs(impulse - 8.03) <= 0.005, out
    smooth = float(re.search(r"frictionless rail: filtered peak ([\d.]+) N", out).group(1))
    assert abs(smooth - 161.0) <= 0.5, out
