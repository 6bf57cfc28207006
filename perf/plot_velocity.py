#!/usr/bin/python3
"""Velocity magnitude of a final state written with Output/Final Particles CSV.

    perf/plot_velocity.py RUN_DIR/particles.csv OUT.png [--title TEXT]

Fluid particles are coloured by |v| (interpolated onto the plane with
Gouraud shading over a Delaunay triangulation of the fluid particles, so
no triangle crosses a grain), boundary particles drawn in grey.
"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("particles")
    parser.add_argument("figure")
    parser.add_argument("--title", default="")
    args = parser.parse_args()
    d = np.genfromtxt(args.particles, delimiter=",", names=True)
    fluid, solid = d[d["kind"] == 0], d[d["kind"] != 0]
    speed = np.hypot(fluid["vx"], fluid["vy"])
    tri = mtri.Triangulation(fluid["x"], fluid["y"])
    # Drop triangles with an edge much longer than the typical one (about the
    # particle spacing): they would bridge a grain or the periodic seam.
    pts = np.stack([fluid["x"], fluid["y"]], axis=1)[tri.triangles]
    edges = np.linalg.norm(pts - np.roll(pts, 1, axis=1), axis=2)
    tri.set_mask(edges.max(axis=1) > 2.5 * np.median(edges))
    fig, ax = plt.subplots(figsize=(7, 6))
    shade = ax.tripcolor(tri, speed * 1e6, shading="gouraud", cmap="viridis")
    ax.scatter(solid["x"], solid["y"], s=0.5, c="0.6")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(args.title, fontsize=9)
    fig.colorbar(shade, ax=ax, label="|v| (µm/s)")
    fig.tight_layout()
    fig.savefig(args.figure, dpi=130)


if __name__ == "__main__":
    main()
