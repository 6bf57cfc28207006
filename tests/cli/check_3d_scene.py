"""A 3D scene end to end, on 1, 2 and 4 ranks (Zoltan2 RCB boxes): the
simple cubic array of input/3d with the full permeability tensor, field
files and a 20^3 grid, 150 steps per driven direction.

usage: check_3d_scene.py PORESPH MPIEXEC INPUT_DIR OUT_DIR

Checks: summary.json gives all nine components of k, equal on every rank
count to 1e-9 of kxx; the cubic cell's k is isotropic (kyy = kzz = kxx to
1e-9) with off-diagonals below 1e-6 kxx; the XDMF descriptions match their
HDF5 arrays (check_xdmf.py); the particles fill the cube (z spans it); the
grid is 20 x 20 x 20 with the sphere's solid fraction, 0.125, to the grid's
resolution, and in the frame driven along x the flow is along x.
"""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

from check_xdmf import check

poresph, mpiexec, inputs, out = sys.argv[1:5]
scene = os.path.join(inputs, "3d", "simple_cubic.xml")
settings = ["Permeability/Tensor=true", "Run/Max Steps=150", "Output/Field Interval=100",
            "Output/Grid Points={20, 20, 20}", "Run/Progress=never"]
results = {}
for ranks in (1, 2, 4):
    directory = os.path.join(out, f"ranks-{ranks}")
    cmd = [mpiexec, "-n", str(ranks), "--oversubscribe", poresph, scene, "--output", directory, "--overwrite"]
    for s in settings:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    assert summary["dimension"] == 3 and summary["ranks"] == ranks, summary
    k = summary["permeability"]
    names = [f"k{i}{j}" for j in "xyz" for i in "xyz"]
    assert sorted(k) == sorted(names), f"{ranks} ranks: permeability keys {sorted(k)}"
    results[ranks] = (k, summary["fluid_particles"], summary["boundary_particles"], summary["steps"])
    for axis in "xyz":
        for kind in ("particles", "grid"):
            frames = check(os.path.join(directory, f"{kind}_{axis}.xmf"))
            assert frames >= 2, f"{kind}_{axis}.xmf: {frames} frames"
    # The last frame of the x-driven run: particles in 3D, the grid's solid and flow.
    last = sorted(f for f in os.listdir(directory) if f.startswith("fields_x_") and f.endswith(".h5"))[-1]
    with h5py.File(os.path.join(directory, last), "r") as f:
        z = f["position"][:, 2]
        assert z.min() < 0.01 and z.max() > 0.09, f"positions span z {z.min()} .. {z.max()}"
        assert f["grid_solid"].shape == (20, 20, 20), f["grid_solid"].shape
        solid = float(np.mean(f["grid_solid"][...]))
        assert abs(solid - 0.125) < 0.02, f"solid fraction of the grid {solid}"
        v = f["grid_velocity"][...]
        assert v.shape == (20, 20, 20, 3)
        mean = v.reshape(-1, 3).mean(axis=0)
        assert mean[0] > 0 and abs(mean[1]) < 1e-6 * mean[0] and abs(mean[2]) < 1e-6 * mean[0], mean
    print(f"{ranks} ranks: kxx {k['kxx']:.9e} kyy {k['kyy']:.9e} kzz {k['kzz']:.9e} kyx {k['kyx']:.2e}, "
          f"{summary['fluid_particles']} fluid + {summary['boundary_particles']} boundary particles, fields ok")

k1, fluid, boundary, steps = results[1]
kxx = k1["kxx"]
assert kxx > 0
for name in ("kyy", "kzz"):
    assert abs(k1[name] - kxx) < 1e-9 * kxx, f"{name} = {k1[name]}, kxx = {kxx}"
for name, value in k1.items():
    if name[1] != name[2]:
        assert abs(value) < 1e-6 * kxx, f"{name} = {value}"
for ranks in (2, 4):
    k, f_n, b_n, s_n = results[ranks]
    assert (f_n, b_n, s_n) == (fluid, boundary, steps), (ranks, f_n, b_n, s_n)
    worst = max(abs(k[n] - k1[n]) for n in k1) / kxx
    assert worst < 1e-9, f"{ranks} ranks differ from 1 by {worst:.2e} of kxx"
    print(f"{ranks} ranks against 1: largest difference {worst:.2e} of kxx")
print("3d scene ok")
