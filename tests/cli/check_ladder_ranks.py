#!/usr/bin/python3
"""The resolution ladder on 1, 2 and 4 processes (issue 17): the square
array c = 0.5 with three levels ending at dx = 0.01 L, from its grain and
from an image of it (perf/rasterise.py, four voxels a spacing of the finest
level), and the simple cubic array of spheres (input/3d) with two levels
ending at 16 particles per side, from its grain and from a 64^3 raw image. Every level's k and step count must agree
with one process's: to 1e-10 (sums in another order) and exactly.

    check_ladder_ranks.py POREPSH_BINARY INPUT_DIR WORK_DIR
"""
import json
import os
import subprocess
import sys

poresph, inputs, work = sys.argv[1:4]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")
# The image of the square array, beside the other runs' directories.
image_dir = os.path.join(work, "ladder-image")
subprocess.run([sys.executable, os.path.join(os.path.dirname(inputs), "perf", "rasterise.py"),
                os.path.join(inputs, "square_array", "square_array_c50.xml"), "--voxels-per-spacing", "4",
                "--format", "raw", "--output", image_dir], check=True, stdout=subprocess.DEVNULL)
sphere_dir = os.path.join(work, "ladder-sphere-image")
subprocess.run([sys.executable, os.path.join(os.path.dirname(inputs), "perf", "rasterise.py"),
                os.path.join(inputs, "3d", "simple_cubic.xml"), "--spacing", "0.00625", "--voxels-per-spacing", "4",
                "--format", "raw", "--output", sphere_dir], check=True, stdout=subprocess.DEVNULL)
CASES = [
    ("square array c = 0.5", ["square_array", "square_array_c50.xml"], ["Convergence/Levels=3"], 3),
    ("square array c = 0.5, image", [image_dir, "image.xml"], ["Convergence/Levels=3"], 3),
    ("simple cubic, 3D", ["3d", "simple_cubic.xml"],
     ["Convergence/Levels=2", "Discretization/Particle Spacing=0.00625"], 2),
    ("simple cubic, 3D, image", [sphere_dir, "image.xml"], ["Convergence/Levels=2"], 2),
]
failures = 0
for name, scene, settings, count in CASES:
    levels = {}
    for ranks in (1, 2, 4):
        out = os.path.join(work, f"ladder-{os.path.basename(scene[0])}-{ranks}")
        command = ["mpiexec", "-n", str(ranks), poresph, os.path.join(inputs, *scene)]
        for setting in settings + ["Run/Progress=never"]:
            command += ["--set", setting]
        subprocess.run(command + ["--output", out, "--overwrite"], check=True, env=env, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            levels[ranks] = json.load(f)["convergence"]
        if len(levels[ranks]) != count:
            failures += 1
            print(f"{name}, {ranks} ranks: {len(levels[ranks])} levels, not {count}")
    for ranks in (2, 4):
        for l, (one, many) in enumerate(zip(levels[1], levels[ranks])):
            k1, kn = one["permeability"]["kxx"], many["permeability"]["kxx"]
            ok = abs(kn / k1 - 1) < 1e-10 and one["steps"] == many["steps"] and many["warm_started"] == (l > 0)
            failures += not ok
            print(f"{name}, {ranks} ranks, level {l}: kxx {kn:.15g} against {k1:.15g}, steps {many['steps']} "
                  f"against {one['steps']}: {'ok' if ok else 'DIFFERENT'}")
print("ladder ranks ok" if failures == 0 else f"{failures} differ")
sys.exit(1 if failures else 0)
