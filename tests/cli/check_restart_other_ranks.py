"""Compares two checkpoints particle by particle (by id): a run continued on
another number of processes has the same physics, so its fields agree with
the uninterrupted run to round-off (sums are taken in another order).

usage: check_restart_other_ranks.py A.h5 B.h5 TOLERANCE [PERIOD]

PERIOD: the positions are compared at the nearest periodic image of a cell
of that side in every direction (a particle on a periodic face may have
been wrapped in one run and not yet in the other).
"""
import sys

import h5py
import numpy as np

a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
tolerance = float(sys.argv[3])
period = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
assert a.attrs["step"] == b.attrs["step"], (a.attrs["step"], b.attrs["step"])
order_a, order_b = np.argsort(a["id"][...]), np.argsort(b["id"][...])
assert np.array_equal(a["id"][...][order_a], b["id"][...][order_b]), "different particles"
worst = 0.0
for name in ["x", "v", "rho"]:
    fa, fb = a[name][...][order_a], b[name][...][order_b]
    scale = np.abs(fa).max() if name != "x" else 1.0
    difference = fa - fb
    if name == "x" and period > 0:
        difference -= period * np.round(difference / period)
    diff = np.abs(difference).max() / scale
    print(f"{name}: max difference {diff:.3e} (relative to max |{name}|)")
    worst = max(worst, diff)
print(f"ranks {a.attrs['ranks']} vs {b.attrs['ranks']}: worst {worst:.3e}")
sys.exit(0 if worst <= tolerance else 1)
