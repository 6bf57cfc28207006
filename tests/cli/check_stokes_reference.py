#!/usr/bin/python3
"""The finite-element reference (perf/stokes_reference.py) against the
closed-form one: a square array of cylinders of solid fraction 0.2 and
0.5 (Sangani & Acrivos 1982, METHOD.md), with the grain centred and with
it across the cell's corner (the script then meshes a translate of the
cell), and driven along y (--drive y: the array is isotropic, so kyy is the
same number). Fails if any k/L^2 is more than 0.5 % off.

    check_stokes_reference.py SOURCE_DIR WORK_DIR
"""
import csv
import math
import os
import subprocess
import sys

source, work = sys.argv[1], sys.argv[2]
L = 0.1
SANGANI_ACRIVOS = {0.2: 1 / 51.53, 0.5: 1 / 532.55}  # k / L^2
failures = 0
for fraction, reference in SANGANI_ACRIVOS.items():
    r = L * math.sqrt(fraction / math.pi)
    cases = {"centred": (0.05, 0.05, "x"), "across the corner": (0.0, 0.0, "x"),
             "centred, driven along y": (0.05, 0.05, "y")}
    for where, (cx, cy, drive) in cases.items():
        out = os.path.join(work, f"c{fraction}-{where.replace(' ', '-').replace(',', '')}")
        os.makedirs(out, exist_ok=True)
        grains = os.path.join(out, "grains.txt")
        with open(grains, "w") as f:
            f.write(f"# one cylinder, solid fraction {fraction}\n{cx} {cy} {r}\n")
        subprocess.run([sys.executable, os.path.join(source, "perf", "stokes_reference.py"), "--grains", grains,
                        "--segments", "100", "--drive", drive, "--out", out], check=True, capture_output=True)
        with open(os.path.join(out, "stokes_reference.csv")) as f:
            k = float(next(csv.DictReader(f))[f"k{drive}{drive}"]) / L**2
        error = k / reference - 1
        ok = abs(error) < 0.005
        failures += not ok
        print(f"c = {fraction}, {where}: k/L^2 = {k:.6f}, Sangani-Acrivos {reference:.6f}, "
              f"error {error * 100:+.3f} % {'ok' if ok else 'FAILED'}")
print("stokes reference ok" if failures == 0 else f"{failures} failed")
sys.exit(1 if failures else 0)
