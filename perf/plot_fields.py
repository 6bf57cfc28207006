#!/usr/bin/python3
"""Velocity magnitude of a run's final state from its gridded view: the last
fields_*.h5 of an output directory written with Output/Field Interval and
Output/Grid Points. Solid grid points (inside grains) are drawn grey. A 3D
grid is shown as one slice normal to z: the layer nearest --slice-z (a
fraction of the cell, default the middle).

    perf/plot_fields.py OUTPUT_DIR PNG [--title TITLE] [--slice-z 0.5]
"""
import argparse
import glob
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output_dir")
    parser.add_argument("png")
    parser.add_argument("--title", default=None)
    parser.add_argument("--slice-z", type=float, default=0.5, help="3D: the slice's z as a fraction of the cell")
    args = parser.parse_args()
    files = sorted(f for f in glob.glob(os.path.join(args.output_dir, "fields*.h5")))
    if not files:
        raise SystemExit(f"no fields*.h5 in {args.output_dir} (run with Output/Field Interval > 0)")
    with h5py.File(files[-1], "r") as f:
        if "grid_velocity" not in f:
            raise SystemExit(f"{files[-1]} has no grid (run with Output/Grid Points)")
        layers = f["grid_velocity"].shape[0]  # 1 in 2D
        layer = min(layers - 1, int(args.slice_z * layers))
        velocity = f["grid_velocity"][layer]  # (ny, nx, 3)
        solid = f["grid_solid"][layer] > 0.5
        time = float(f.attrs["time"][0])
    speed = np.linalg.norm(velocity, axis=-1)
    ny, nx = speed.shape
    fig, ax = plt.subplots(figsize=(6, 5.2))
    shown = np.ma.masked_where(solid, speed)
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("0.6")
    image = ax.imshow(shown, origin="lower", extent=(0, 1, 0, ny / nx), cmap=cmap)
    fig.colorbar(image, ax=ax, label="|v| (m/s)")
    ax.set_xlabel("x / L")
    ax.set_ylabel("y / L")
    where = f", slice z = {(layer + 0.5) / layers:.2f} of the cell" if layers > 1 else ""
    ax.set_title(args.title or f"|v| at t = {time:g} s ({nx} x {ny} grid{where})")
    fig.tight_layout()
    fig.savefig(args.png, dpi=130)
    print(f"wrote {args.png} from {files[-1]}")


if __name__ == "__main__":
    main()
