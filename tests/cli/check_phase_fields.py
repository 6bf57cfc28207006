"""check_phase_fields.py DIR: the `phase` field of a two-fluid run's field files (Output/Fields
with `phase`): in every frame, -1 exactly on the boundary particles, 0 or 1 on the fluid; phase 1's
share of the fluid particles is summary.json's saturation of phase 1 (fixed particles of one
volume); particles.xmf names the array, and check_xdmf.py's checks hold for it."""
import glob
import json
import os
import subprocess
import sys

import h5py
import numpy as np

directory = sys.argv[1]
summary = json.load(open(os.path.join(directory, "summary.json")))
saturation = next(p["saturation"] for p in summary["phases"] if p["index"] == 1)
frames = sorted(glob.glob(os.path.join(directory, "fields_*.h5")))
assert len(frames) >= 2, frames
for name in frames:
    with h5py.File(name, "r") as f:
        phase, kind = np.asarray(f["phase"]), np.asarray(f["kind"])
    assert phase.shape == kind.shape, (phase.shape, kind.shape)
    assert np.all((phase == -1) == (kind != 0)), f"{name}: -1 is not exactly the boundary particles"
    fluid = phase[kind == 0]
    assert set(np.unique(fluid)) <= {0, 1}, np.unique(fluid)
    share = np.count_nonzero(fluid == 1) / fluid.size
    assert abs(share - saturation) < 1e-12, (name, share, saturation)
xmf = os.path.join(directory, "particles.xmf")
assert 'Name="phase"' in open(xmf).read(), "particles.xmf does not name phase"
subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "check_xdmf.py"), xmf], check=True)
print(f"phase fields as the phases are: {len(frames)} frames, phase 1 on {share:.4f} of the fluid")
