#!/usr/bin/python3
"""An image read in pieces runs as the whole image does: a 3D blobs image
(perf/blobs.py) as raw on one process and as HDF5 on two and four, and a
mirrored 2D one on one and three, give the same particles, porosity and k;
and a volume whose walls do not fit one process under an address-space
limit is refused there and runs on two, each holding its piece.

    check_image_pieces.py POREPSH_EXECUTABLE MPIEXEC SOURCE_DIR WORK_DIR

Prints "image pieces ok" when every check passes; exits 77 (skipped)
without numpy or h5py.
"""
import json
import os
import re
import resource
import shutil
import subprocess
import sys

for module in ("numpy", "h5py"):
    try:
        __import__(module)
    except ImportError:
        print(f"check_image_pieces.py: Python module {module} is missing: skipped")
        sys.exit(77)
import numpy as np  # noqa: E402

poresph, mpiexec, source, work = sys.argv[1:5]
sys.path.insert(0, os.path.join(source, "perf"))
import blobs  # noqa: E402

failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what}{': ' + detail if detail and not ok else ''}")
    if not ok:
        failures.append(what)


def run(ranks, scene, out, *sets, preexec=None):
    command = [poresph, scene, "--output", out, "--overwrite", "--set", "Run/Progress=never"]
    for s in sets:
        command += ["--set", s]
    if ranks > 1:
        command = [mpiexec, "-n", str(ranks), "--oversubscribe", "--allow-run-as-root"] + command
    done = subprocess.run(command, capture_output=True, text=True, preexec_fn=preexec)
    print(f"$ {' '.join(command)}\n{done.stdout}{done.stderr}", end="")
    summary = {}
    if done.returncode == 0:
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
    return done, summary


shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
os.chdir(work)

# The same voxels as raw and as an HDF5 dataset, and a scene for each.
solid, _ = blobs.blobs((40, 32, 24), 0.45, 2.0, 3)
blobs.write(solid, "blobs.raw")
blobs.write(solid, "blobs.h5", dataset="/scan/segmented")
for image, dataset in (("blobs.raw", "/image"), ("blobs.h5", "/scan/segmented")):
    with open(image + ".xml", "w") as f:
        f.write(blobs.scene_xml(image, image + ".xml", [40, 32, 24], 1e-3, 1e-3, "pieces", dataset))
keys = ("fluid_particles", "boundary_particles", "porosity", "warnings")


def same(key, a, b):
    """The summaries agree on key; warnings name the file, which differs between the raw and HDF5 scenes."""
    if key not in a or key not in b:
        return False
    if key == "warnings":
        return [re.sub(r"Image/File '[^']*'", "Image/File", w) for w in a[key]] == \
               [re.sub(r"Image/File '[^']*'", "Image/File", w) for w in b[key]]
    return a[key] == b[key]


steps = ["Run/Max Steps=30", "Permeability/Steady Tolerance=0"]
done, whole = run(1, "blobs.raw.xml", "whole", *steps)
check("3D raw on one process runs", done.returncode == 0 and whole.get("steps") == 30)
for ranks in (2, 4):
    done, pieces = run(ranks, "blobs.h5.xml", f"pieces-{ranks}", *steps)
    check(f"3D HDF5 on {ranks} processes runs", done.returncode == 0 and pieces.get("steps") == 30)
    for key in keys:
        check(f"3D on {ranks} processes: {key} as on one ({whole.get(key)})",
              same(key, pieces, whole), str(pieces.get(key)))
    k, k_whole = pieces.get("permeability", {}).get("kxx"), whole.get("permeability", {}).get("kxx")
    check(f"3D on {ranks} processes: kxx after 30 steps as on one to 1e-12 ({k_whole})",
          k is not None and k_whole is not None and abs(k - k_whole) <= 1e-12 * abs(k_whole), str(k))

# A 2D image mirrored along the flow, on one and three processes.
plane, _ = blobs.blobs((48, 40), 0.7, 2.5, 5)
blobs.write(plane, "plane.raw")
with open("plane.xml", "w") as f:
    f.write(blobs.scene_xml("plane.raw", "plane.xml", [48, 40], 1e-3, 1e-3, "plane"))
mirrored = steps + ["Image/Mirror=true", "Domain/Cell Size={0.096, 0.04}"]
done, whole = run(1, "plane.xml", "plane-whole", *mirrored)
check("2D mirrored on one process runs", done.returncode == 0 and whole.get("steps") == 30)
done, pieces = run(3, "plane.xml", "plane-pieces", *mirrored)
check("2D mirrored on three processes runs", done.returncode == 0 and pieces.get("steps") == 30)
for key in keys:
    check(f"2D mirrored on three processes: {key} as on one ({whole.get(key)})",
          same(key, pieces, whole), str(pieces.get(key)))
# k is a sum over the processes' particles, added in another order on another count of them.
k, k_whole = pieces.get("permeability", {}), whole.get("permeability", {})
check(f"2D mirrored on three processes: k after 30 steps as on one to 1e-12 of kxx ({k_whole})",
      bool(k) and k.keys() == k_whole.keys() and
      all(abs(k[c] - k_whole[c]) <= 1e-12 * abs(k_whole["kxx"]) for c in k_whole), str(k))

# A segmented image of the solid and two fluids (Phases/Phase 1/Image Values): the 3D blobs' pore
# voxels in blocks of 4 alternately of value 0 and 2, on one process and on four, give every particle
# the same phase.
i, j, k = np.indices(solid.shape)
labels = np.where(solid, 1, np.where((i // 4 + j // 4 + k // 4) % 2 == 1, 2, 0)).astype(np.uint8)
np.ascontiguousarray(labels.transpose((2, 1, 0))).tofile("labels.raw")
with open("labels.xml", "w") as f:
    f.write(blobs.scene_xml("labels.raw", "labels.xml", [40, 32, 24], 1e-3, 1e-3, "labels"))
two_fluids = ["Run/Max Steps=2", "Permeability/Steady Tolerance=0", "Phases/Count=2",
              "Phases/Phase 1/Kinematic Viscosity=2e-6", "Phases/Phase 1/Image Values={2}",
              "Output/Final Particles CSV=true"]


def particle_phases(out):
    rows = np.genfromtxt(os.path.join(out, "particles.csv"), delimiter=",", names=True)
    return dict(zip(rows["id"].astype(int), rows["phase"].astype(int)))


done, whole = run(1, "labels.xml", "labels-whole", *two_fluids)
done4, pieces = run(4, "labels.xml", "labels-pieces", *two_fluids)
check("labelled phases on one and four processes run", done.returncode == 0 and done4.returncode == 0)
if done.returncode == 0 and done4.returncode == 0:
    a, b = particle_phases("labels-whole"), particle_phases("labels-pieces")
    share = whole["phases"][1]["saturation"]
    check(f"labelled phases on four processes as on one (phase 1 on {share:.3f} of the fluid)",
          a == b and 0.3 < share < 0.7, f"{sum(a[n] != b.get(n) for n in a)} particles differ")
    pore = labels != 1
    voxel_share = np.count_nonzero(labels == 2) / np.count_nonzero(pore)
    check(f"phase 1's saturation near its voxels' share of the pore ({voxel_share:.3f})",
          abs(share - voxel_share) < 0.03, str(share))

# A volume whose walls need more than one process's address space holds, and its pieces less:
# 384 x 192 x 192 voxels (14 M), 40 bytes a voxel to make the walls, about 570 MB on one
# process; at 8 voxels a spacing (27,648 lattice points) each of two processes reads
# 192 + 2 x 44 layers of x, 73 % of it.
big, _ = blobs.blobs((384, 192, 192), 0.45, 4.0, 1)
blobs.write(big, "big.raw")
with open("big.xml", "w") as f:
    f.write(blobs.scene_xml("big.raw", "big.xml", [384, 192, 192], 1e-3, 1e-3, "big"))
coarse = ["Run/Max Steps=2", "Permeability/Steady Tolerance=0", "Discretization/Particle Spacing=0.008"]


def address_space(limit):
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    return apply


def stated(pattern, text):
    found = re.search(pattern, text)
    return float(found.group(1)) * 1e9 if found else None


# What the image needs on one process, and what a process maps before it (its libraries): from the
# refusals of Run/Memory Limit, and of a sparse volume of 8 GB under a 2 GB address-space limit.
done, _ = run(1, "big.xml", "big-probe", *coarse, "Run/Memory Limit=0.001")
whole_bytes = stated(r"making its walls takes about ([0-9.e+-]+) GB", done.stderr)
with open("sparse.raw", "wb") as f:
    f.truncate(2000 ** 3)
done, _ = run(1, "big.xml", "sparse-probe", *coarse, "Image/File=sparse.raw", "Image/Shape={2000, 2000, 2000}",
              "Domain/Cell Size={2, 2, 2}", preexec=address_space(2 << 30))
left = stated(r"and ([0-9.e+-]+) GB are available \(what is left of the process's address-space limit", done.stderr)
os.remove("sparse.raw")
check("the image's set-up need and the address space left are stated", whole_bytes and left, done.stderr[-400:])
if whole_bytes and left:
    mapped = (2 << 30) - left
    limit = int(mapped + 0.95 * whole_bytes)  # room for a piece, not for the whole
    done, _ = run(1, "big.xml", "big-one", *coarse, preexec=address_space(limit))
    check(f"one process under {limit / 1e9:.2f} GB of address space is refused for the image's walls "
          f"({whole_bytes / 1e9:.2f} GB), naming ulimit -v",
          done.returncode == 2 and "making its walls" in done.stderr and "ulimit -v" in done.stderr,
          done.stderr[-600:])
    done, pieces = run(2, "big.xml", "big-two", *coarse,
                       preexec=address_space(limit))
    check("two processes under the same limit run, each with its piece", done.returncode == 0 and
          pieces.get("steps") == 2, done.stderr[-600:])

print("image pieces ok" if not failures else f"image pieces: {len(failures)} failed: {failures}")
sys.exit(1 if failures else 0)
