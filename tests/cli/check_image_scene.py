"""A segmented image end to end (issue 16): the square array c = 0.2 drawn in
voxels (perf/rasterise.py, four to a spacing of 0.04 L) and run from the
image, against the same grain run from Grains/Inline.

usage: check_image_scene.py PORESPH INPUT_DIR OUT_DIR

Checks:
- k from the image is within 1 % of k from the grain (measured: +0.75 %;
  docs/validation.md, section 5, has the finer table);
- Image/Mirror along x makes the cell twice as long and, the array being
  symmetric, leaves k within 0.5 % (the mirrored voxels are the same circle
  drawn the other way round);
- Discretization/Spacings Across Throat = 12 takes the image's bottleneck
  (the gap between the circle and its image, 0.0495 m, read from voxel
  centres as 0.049) over 12 and makes it fit the cell: 25 spacings;
- a restart from this image's checkpoint with another image is refused;
- moving particles (Particle Motion = lagrangian) with an image are warned
  of: they measure the no-slip distances from tangent planes;
- the grid output's solid flag covers the image's solid fraction;
- a sphere drawn as a 3D raw volume and as a TIFF stack gives the same k.
"""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

poresph, inputs, out = sys.argv[1:4]
grain_scene = os.path.join(inputs, "square_array", "square_array_c20.xml")
image_dir = os.path.join(out, "image")
subprocess.run([sys.executable, os.path.join(os.path.dirname(inputs), "perf", "rasterise.py"), grain_scene,
                "--spacing", "0.004", "--voxels-per-spacing", "4", "--format", "raw", "--output", image_dir],
               check=True, stdout=subprocess.DEVNULL)
image_scene = os.path.join(image_dir, "image.xml")


def run(scene, name, *settings):
    directory = os.path.join(out, name)
    cmd = [poresph, scene, "--output", directory, "--overwrite", "--set", "Run/Progress=never"]
    for s in settings:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


grains = run(grain_scene, "grains", "Discretization/Particle Spacing=0.004")
image = run(image_scene, "from-image", "Output/Grid Points={50, 50}", "Output/Field Interval=1000")
k_grains, k_image = grains["permeability"]["kxx"], image["permeability"]["kxx"]
change = k_image / k_grains - 1
print(f"kxx from the image {k_image:.6e}, from the grain {k_grains:.6e}: {100 * change:+.2f} %")
assert abs(change) < 0.01, change
assert abs(image["porosity"] - 0.8008) < 1e-12, image["porosity"]  # the image's pore voxels: 8008 of 10^4

mirrored = run(image_scene, "mirrored", "Image/Mirror=true", "Domain/Cell Size={0.2, 0.1}")
change = mirrored["permeability"]["kxx"] / k_image - 1
print(f"kxx mirrored along x {mirrored['permeability']['kxx']:.6e}: {100 * change:+.2f} % against unmirrored")
assert abs(change) < 0.005, change

across = run(image_scene, "across-throat", "Discretization/Particle Spacing=0",
             "Discretization/Spacings Across Throat=12")
print(f"Spacings Across Throat = 12: spacing {across['particle_spacing']}")
assert abs(across["particle_spacing"] - 0.004) < 1e-12, across["particle_spacing"]

moving = run(image_scene, "moving", "Discretization/Particle Motion=lagrangian", "Run/Max Steps=5")
assert any("tangent planes" in w for w in moving["warnings"]), moving["warnings"]
print("moving particles with an image: warned")

# Another image (one pore voxel made solid) is another solid: a restart
# from the first image's checkpoint is refused, naming the image.
voxels = np.fromfile(os.path.join(image_dir, "image.raw"), dtype=np.uint8)
voxels[0] = 1 - voxels[0]
other_dir = os.path.join(out, "other-image")
os.makedirs(other_dir, exist_ok=True)
voxels.tofile(os.path.join(other_dir, "image.raw"))
with open(image_scene) as f:
    text = f.read()
with open(os.path.join(other_dir, "image.xml"), "w") as f:
    f.write(text)
refused = subprocess.run([poresph, os.path.join(other_dir, "image.xml"), "--restart",
                          os.path.join(out, "from-image", "checkpoint.h5"), "--output", os.path.join(out, "restart"),
                          "--overwrite"], capture_output=True, text=True)
assert refused.returncode == 2 and "Image:" in refused.stderr, (refused.returncode, refused.stderr)
print("restart with another image: refused")

frames = sorted(f for f in os.listdir(os.path.join(out, "from-image")) if f.startswith("fields") and f.endswith(".h5"))
with h5py.File(os.path.join(out, "from-image", frames[-1]), "r") as f:
    solid = float(np.mean(f["grid_solid"][...]))
print(f"grid solid fraction {solid:.4f}")
assert abs(solid - 0.2) < 0.02, solid
# The same sphere as a 3D raw volume and as a TIFF stack (one page per z):
# the same voxels, so the same k to every digit.
sphere = os.path.join(inputs, "3d", "simple_cubic.xml")
k_of = {}
for fmt in ("raw", "tif"):
    folder = os.path.join(out, f"sphere-{fmt}")
    subprocess.run([sys.executable, os.path.join(os.path.dirname(inputs), "perf", "rasterise.py"), sphere,
                    "--spacing", "0.01", "--voxels-per-spacing", "2", "--format", fmt, "--output", folder],
                   check=True, stdout=subprocess.DEVNULL)
    k_of[fmt] = run(os.path.join(folder, "image.xml"), f"sphere-{fmt}-run", "Run/Max Steps=100")["permeability"]["kxx"]
print(f"sphere as raw volume kxx {k_of['raw']!r}, as TIFF stack {k_of['tif']!r}")
assert k_of["raw"] == k_of["tif"] and k_of["raw"] > 0, k_of

print("image scene ok")
