#!/usr/bin/env python3
"""Images against grains: the voxel error told apart from the particle error.

Each grain scene is run as given (Grains) and rasterised (perf/rasterise.py)
at 2, 4 and 8 voxels per particle spacing, run from the image, at each
spacing asked for. The table gives k/L^2 from the grains and from each
image, the image's difference from the grains at the same spacing (the
voxel error: same particles, same method, only the walls come from voxels)
and both against the reference (the particle error is the grains' own).
Writes image_validation.csv and prints the rows of docs/validation.md,
section 5.

  /usr/bin/python3 perf/image_validation.py --build build --out build/images
"""
import argparse
import os
import subprocess
import sys

from poresph_runs import ROOT, run_poresph, write_csv

L = 0.1
# (name, scene, reference k/L^2, what the reference is)
SCENES = [
    ("square array c = 0.2", "square_array/square_array_c20.xml", 1 / 51.53, "Sangani-Acrivos"),
    ("square array c = 0.5", "square_array/square_array_c50.xml", 1 / 532.55, "Sangani-Acrivos"),
    ("problem III", "problem3/problem3.xml", 9.638e-4, "Stokes FE"),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "images"))
    parser.add_argument("--spacings", default="0.002,0.001", help="particle spacings (m), comma-separated")
    parser.add_argument("--voxels", default="2,4,8", help="voxels per particle spacing, comma-separated")
    parser.add_argument("--format", default="raw", choices=["raw", "png", "tif"])
    parser.add_argument("--only", default=None, help="only the scenes whose name contains this text")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name, scene, reference, source in SCENES:
        if args.only and args.only not in name:
            continue
        for dx in [float(v) for v in args.spacings.split(",")]:
            tag = f"{os.path.basename(scene)[:-4]}-{dx:g}"
            grains = run_poresph(args.build, scene, os.path.join(args.out, f"grains-{tag}"),
                                 [f"Discretization/Particle Spacing={dx!r}"])
            k_grains = grains["permeability"]["kxx"] / L**2
            row = dict(scene=name, dx_over_L=dx / L, reference=reference, reference_source=source,
                       grains=k_grains, grains_error=k_grains / reference - 1, grains_steps=grains["steps"])
            for n in [int(v) for v in args.voxels.split(",")]:
                folder = os.path.join(args.out, f"image-{tag}-{n}")
                subprocess.run([sys.executable, os.path.join(ROOT, "perf", "rasterise.py"),
                                os.path.join(ROOT, "input", scene), "--spacing", repr(dx),
                                "--voxels-per-spacing", str(n), "--format", args.format, "--output", folder],
                               check=True, stdout=subprocess.DEVNULL)
                image = run_poresph(args.build, os.path.join(folder, "image.xml"), os.path.join(folder, "run"))
                k_image = image["permeability"]["kxx"] / L**2
                row[f"image_{n}"] = k_image
                row[f"image_{n}_vs_grains"] = k_image / k_grains - 1
                row[f"image_{n}_error"] = k_image / reference - 1
                row[f"image_{n}_steps"] = image["steps"]
            rows.append(row)
            cells = " | ".join(f"{row[f'image_{n}']:.5g} ({100 * row[f'image_{n}_vs_grains']:+.2f} %, "
                               f"{100 * row[f'image_{n}_error']:+.2f} %)" for n in args.voxels.split(","))
            print(f"| {name} | {dx / L:g} | {reference:.5g} | {k_grains:.5g} ({100 * row['grains_error']:+.2f} %) | "
                  f"{cells} |", flush=True)
    write_csv(os.path.join(args.out, "image_validation.csv"), rows)


if __name__ == "__main__":
    main()
