#!/usr/bin/python3
"""perf/blobs.py at a tiny size: exact porosity, a periodic field, the same
image for the same seed (another for another seed), the percolation check,
every output format read back (by perf/openfoam_side_by_side.py's reader),
and PoreSPH running the 2D and 3D images from their scenes.

    check_blobs.py POREPSH_EXECUTABLE SOURCE_DIR WORK_DIR

Prints "blobs ok" when every check passes; exits 77 (skipped) without
SciPy, h5py or Pillow (scripts/setup.sh test|tools installs them).
"""
import json
import os
import shutil
import subprocess
import sys

import numpy as np

for module in ("scipy", "h5py", "PIL"):
    try:
        __import__(module)
    except ImportError:
        print(f"check_blobs.py: Python module {module} is missing: skipped (scripts/setup.sh tools installs it)")
        sys.exit(77)

poresph, source, work = sys.argv[1:4]
perf = os.path.join(source, "perf")
sys.path.insert(0, perf)
import blobs  # noqa: E402
from openfoam_side_by_side import read_image, solid_of  # noqa: E402

failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what}{': ' + detail if detail and not ok else ''}")
    if not ok:
        failures.append(what)


def run_blobs(*args):
    done = subprocess.run([sys.executable, os.path.join(perf, "blobs.py"), *args], capture_output=True, text=True)
    print(done.stdout + done.stderr, end="")
    return done


shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
os.chdir(work)

# Porosity to a voxel, 2D and 3D, odd sizes included.
for shape, porosity in [((40, 24), 0.4), ((17, 12, 9), 0.35), ((16, 16, 16), 0.2)]:
    solid, _ = blobs.blobs(shape, porosity, 1.5, 3)
    check(f"{shape} at porosity {porosity}: {int(round(porosity * solid.size))} pore voxels",
          int((~solid).sum()) == int(round(porosity * solid.size)))

# The field is periodic: filtering a rolled noise gives the rolled field.
noise = np.random.default_rng(5).standard_normal((20, 14, 10))
field = blobs.smooth(noise, 2.0)
for shift in [(7, 0, 0), (0, 5, 0), (0, 0, 3), (11, 13, 9)]:
    rolled = blobs.smooth(np.roll(noise, shift, axis=(0, 1, 2)), 2.0)
    check(f"wrap-around: the field of the noise rolled by {shift} is the rolled field",
          np.allclose(rolled, np.roll(field, shift, axis=(0, 1, 2)), atol=1e-12))
# Across the box's faces the field is as smooth as inside: the jump from the last layer to the
# first is no larger than between neighbours inside.
inside = np.mean(np.abs(np.diff(field, axis=0)))
across = np.mean(np.abs(field[0] - field[-1]))
check("the field is continuous across the faces", across < 1.5 * inside, f"{across} against {inside}")
# The filter is a Gaussian of the asked sigma: a delta spreads with that variance along each axis.
delta = np.zeros((64, 48, 40))
delta[0, 0, 0] = 1.0
kernel = blobs.smooth(delta, 3.0)
for axis, n in enumerate(kernel.shape):
    d = np.minimum(np.arange(n), n - np.arange(n)).astype(float)
    marginal = kernel.sum(axis=tuple(a for a in range(3) if a != axis))
    variance = float((marginal * d ** 2).sum() / marginal.sum())
    check(f"kernel variance along axis {axis}: {variance:.4f} ~ 9", abs(variance - 9.0) < 1e-3)

# Determinism per seed, through the command line.
a = run_blobs("--shape", "24", "20", "16", "--porosity", "0.35", "--sigma", "2", "--seed", "7", "--output", "a.raw")
b = run_blobs("--shape", "24", "20", "16", "--porosity", "0.35", "--sigma", "2", "--seed", "7", "--output", "b.raw")
c = run_blobs("--shape", "24", "20", "16", "--porosity", "0.35", "--sigma", "2", "--seed", "8", "--output", "c.raw")
check("blobs.py exits 0", a.returncode == b.returncode == c.returncode == 0)
raw = [open(f, "rb").read() for f in ("a.raw", "b.raw", "c.raw")]
check("the same seed gives the same bytes", raw[0] == raw[1])
check("another seed gives another image", raw[0] != raw[2])
check("raw: 24 x 20 x 16 bytes", len(raw[0]) == 24 * 20 * 16)

# Percolation: a channel along x only, a pocket, and the report of the command line.
s = np.ones((8, 8, 8), dtype=bool)
s[:, 3, 4] = False
rep = blobs.percolation_report(s)
check("a channel along x percolates along x only", rep["percolates"] == {"x": True, "y": False, "z": False}, str(rep))
s[5, 3, 4] = True
rep = blobs.percolation_report(s)
check("the channel cut: no axis, all pore isolated",
      not any(rep["percolates"].values()) and rep["isolated_pore_fraction"] == 1.0, str(rep))
# A path that crosses the x faces twice, joined only through y's wrap-around, still percolates along x.
s = np.ones((6, 6), dtype=bool)
for i in range(6):
    s[i, i] = False
    s[i, (i + 1) % 6] = False
rep = blobs.percolation_report(s)
check("a diagonal path through the periodic faces percolates along x and y",
      rep["percolates"] == {"x": True, "y": True}, str(rep))
check("the command line says which axes percolate", "percolates along x, y, z" in a.stdout, a.stdout)
low = run_blobs("--shape", "24", "24", "24", "--porosity", "0.03", "--sigma", "1", "--seed", "1",
                "--require-percolation")
check("porosity 0.03 does not percolate, and --require-percolation fails", low.returncode == 1)

# Every format reads back to the same voxels.
d = run_blobs("--shape", "20", "12", "8", "--porosity", "0.4", "--sigma", "1.5", "--seed", "2",
              "--output", "f.raw", "--output", "f.tif", "--output", "f.h5", "--output", "f.npy",
              "--dataset", "/segmented/phase", "--json", "f.json")
ref = np.load("f.npy")
check("npy: shape [x, y, z]", ref.shape == (20, 12, 8))
check("json porosity is the image's", abs(json.load(open("f.json"))["porosity"] - (1 - ref.mean())) < 1e-15)
for path, kw in [("f.raw", dict(shape=[20, 12, 8])), ("f.tif", {}), ("f.h5", dict(dataset="/segmented/phase"))]:
    back = solid_of(read_image(path, **kw), None)
    check(f"{path} reads back to the same voxels", back.shape == ref.shape and bool((back == ref).all()))
e = run_blobs("--shape", "30", "20", "--porosity", "0.5", "--sigma", "2", "--seed", "4", "--output", "g.png",
              "--output", "g.npy")
check("png (2D) reads back", bool((solid_of(read_image("g.png"), None) == np.load("g.npy")).all()))

# PoreSPH reads the raw output from the scene blobs.py writes: 2D and 3D, a few steps.
for name, shape, porosity, sigma, seed in [("blobs2d", ["64", "48"], "0.6", "3", "2"),
                                           ("blobs3d", ["16", "16", "16"], "0.5", "2", "1")]:
    os.makedirs(name, exist_ok=True)
    g = run_blobs("--shape", *shape, "--porosity", porosity, "--sigma", sigma, "--seed", seed,
                  "--output", f"{name}/image.raw", "--scene", f"{name}.xml", "--json", f"{name}.json")
    done = subprocess.run([poresph, f"{name}.xml", "--output", f"{name}/run", "--overwrite",
                           "--set", "Run/Max Steps=5", "--set", "Run/Progress=never"], capture_output=True, text=True)
    print(done.stdout + done.stderr, end="")
    summary = json.load(open(f"{name}/run/summary.json")) if done.returncode == 0 else {}
    facts = json.load(open(f"{name}.json"))
    check(f"{name}: poresph runs the scene", done.returncode == 0 and summary.get("steps") == 5)
    check(f"{name}: poresph's porosity is the image's ({facts['porosity']})",
          abs(summary.get("porosity", -1) - facts["porosity"]) < 1e-12, str(summary.get("porosity")))

# An image whose pore space does not cross along x: blobs.py and PoreSPH say the same.
os.makedirs("closed", exist_ok=True)
g = run_blobs("--shape", "64", "48", "--porosity", "0.6", "--sigma", "3", "--seed", "1",
              "--output", "closed/image.raw", "--scene", "closed.xml")
done = subprocess.run([poresph, "closed.xml", "--output", "closed/run", "--overwrite", "--set", "Run/Max Steps=5"],
                      capture_output=True, text=True)
check("not percolating along x: blobs.py says so and poresph refuses the scene",
      "percolates along y (not along x)" in g.stdout and done.returncode != 0
      and "no pore path crosses the cell along x" in done.stderr, done.stderr)

print(f"{len(failures)} failed: {failures}" if failures else "blobs ok")
sys.exit(1 if failures else 0)
