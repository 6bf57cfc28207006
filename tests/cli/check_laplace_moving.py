"""check_laplace_moving.py RUN_DIR LARGEST_CURRENTS JUMP_TOLERANCE: a drop at rest with a moving interface.

Reads summary.json's `capillary` (the pressure jump beyond the kernel's reach of the interface, sigma / R, and
the largest speed over sigma / mu) and `phases` (each phase's phase_field_volume) and checks that the currents
are below LARGEST_CURRENTS of sigma / mu, the jump within JUMP_TOLERANCE (relative) of sigma / R, and each
phase's volume kept to 1e-10 of the cell's (the start's, from phases_history.csv's first row).
"""
import csv
import json
import os
import sys

run, largest, tolerance = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
summary = json.load(open(os.path.join(run, "summary.json")))
capillary = summary["capillary"]
currents = capillary["capillary_number"]
jump_error = capillary["pressure_jump"] / capillary["laplace_pressure"] - 1
with open(os.path.join(run, "phases_history.csv")) as f:
    first = next(csv.DictReader(f))
volumes = [p["phase_field_volume"] for p in summary["phases"]]
starts = [float(first[f"phase_field_volume_{i}"]) for i in range(len(volumes))]
cell = sum(starts)
drift = max(abs(v - s) for v, s in zip(volumes, starts)) / cell
print(f"currents {currents:.3e} of sigma/mu, jump {100 * jump_error:+.2f} %, volumes kept to {drift:.1e}")
assert currents < largest, f"currents {currents:.3e} of sigma/mu, above {largest}"
assert abs(jump_error) < tolerance, f"jump {100 * jump_error:+.2f} % off sigma / R"
assert drift < 1e-10, f"a phase's volume moved by {drift:.1e} of the cell's"
print("drop at rest with weak currents")
