#!/usr/bin/python3
"""Entry of a non-wetting phase into a throat (input/two_phase/throat_entry.xml) against the entry pressure.

Reads a run's parameters_used.xml, its image, and every fields_*.h5 with the `colour` field. The cell is
periodic along x, the body force drives both phases along x, and the image narrows the channel (width W
between the plane walls) to a throat of width w: the columns where the fewest voxels are fluid. Phase 1
(phi >= 1/2) is one slug across the channel. On the row through the throat's middle, each frame gives the
slug's front (where phi falls through 1/2 going along x) and its rear (where it rises), and a circle fitted
to the rear meniscus's crossings on every row of the channel gives the rear's capillary pressure,
Pc(rear) = sigma / R. At rest each phase's pressure rises by rho |F| L along the cell (L its length), so
the front holds

    Pc(front) = Pc(rear) + rho |F| L,

and enters the throat when that exceeds the throat's entry pressure 2 sigma cos(theta) / w (theta the
contact angle through phase 0, the wetting phase). The run's verdict at its last frame:

- entered: the front is past the throat's middle;
- arrested: the front is before the throat's middle and moved less than half a spacing over the last
  quarter of the run's frames;
- neither (still on its way in): said as such.

    perf/throat_entry.py RUN_DIR [RUN_DIR ...] [--json]

With runs at forces on both sides of F* = 2 sigma cos(theta) (1/w - 1/W) / (rho L) (the scene's comment
derives it), the entry pressure lies between the largest Pc(front) of an arrested run and the smallest of
a run that entered.
"""
import argparse
import glob
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

from run_parameters import numbers, parameter
import run_parameters


def image(run, root):
    """The solid image (ny, nx) as booleans, and its voxel size."""
    values, solid, voxel = run_parameters.scene_image(run, root)
    return np.isin(values, list(solid)), voxel


class Scene:
    def __init__(self, run):
        root = ET.parse(os.path.join(run, "parameters_used.xml")).getroot()
        self.run = run
        self.dx = float(parameter(root, "Discretization/Particle Spacing"))
        self.cell = numbers(parameter(root, "Domain/Cell Size"))
        self.sigma = float(parameter(root, "Phases/Surface Tension"))
        self.theta = math.radians(float(parameter(root, "Phases/Contact Angle")))
        self.rho = float(parameter(root, "Fluid/Density"))
        self.force = numbers(parameter(root, "Fluid/Body Force"))[0]
        solid, voxel = image(run, root)
        fluid_per_column = (~solid).sum(axis=0)
        throat = np.flatnonzero(fluid_per_column == fluid_per_column.min())
        self.w = fluid_per_column.min() * voxel
        self.W = fluid_per_column.max() * voxel
        self.mouth = throat[0] * voxel
        self.middle = 0.5 * (throat[0] + throat[-1] + 1) * voxel
        rows = np.flatnonzero(~solid[:, throat[0]])
        self.centre_line = 0.5 * (rows[0] + rows[-1] + 1) * voxel
        self.entry_pressure = 2 * self.sigma * math.cos(self.theta) / self.w
        self.lift = self.rho * self.force * self.cell[0]  # rho |F| L

    def lattice(self, fields):
        """phi on the particles' lattice, (ny, nx), NaN off the fluid."""
        nx, ny = (int(round(c / self.dx)) for c in self.cell[:2])
        grid = np.full((ny, nx), np.nan)
        x, kind, colour = fields["position"][:], fields["kind"][:], fields["colour"][:]
        fluid = kind == 0
        i = np.floor(x[fluid, 0] / self.dx).astype(int) % nx
        j = np.floor(x[fluid, 1] / self.dx).astype(int)
        inside = (j >= 0) & (j < ny)
        grid[j[inside], i[inside]] = colour[fluid][inside]
        return grid

    def crossings(self, row, falling):
        """x of each crossing of phi through 1/2 along a row (periodic), falling or rising."""
        found = []
        n = len(row)
        for i in range(n):
            a, b = row[i], row[(i + 1) % n]
            if np.isnan(a) or np.isnan(b):
                continue
            if (falling and a >= 0.5 > b) or (not falling and a < 0.5 <= b):
                found.append((i + 0.5 + (0.5 - a) / (b - a)) * self.dx)
        return found

    def frame(self, name):
        with h5py.File(name, "r") as f:
            grid = self.lattice(f)
        # The throat's middle row: the mean of the two rows about the centre line if it falls between.
        y = self.centre_line / self.dx - 0.5
        lo, hi = int(math.floor(y)), int(math.ceil(y))
        row = 0.5 * (grid[lo] + grid[hi])
        fronts, rears = self.crossings(row, True), self.crossings(row, False)
        if len(fronts) != 1 or len(rears) != 1:
            return None  # not one slug across the channel
        front, rear = fronts[0], rears[0]
        # The rear meniscus: its crossing on every row of the channel whose ends are fluid, nearest the apex.
        points = []
        for j in range(grid.shape[0]):
            xs = self.crossings(grid[j], False)
            if xs:
                nearest = min(xs, key=lambda x: abs((x - rear + self.cell[0] / 2) % self.cell[0] - self.cell[0] / 2))
                points.append((nearest, (j + 0.5) * self.dx))
        points = np.array(points)
        if len(points) > 6:
            points = points[2:-2]  # not the rows beside the walls
        # Unwrap across the periodic side to the apex's side.
        points[:, 0] = rear + (points[:, 0] - rear + self.cell[0] / 2) % self.cell[0] - self.cell[0] / 2
        A = np.c_[2 * points, np.ones(len(points))]
        c = np.linalg.lstsq(A, (points ** 2).sum(axis=1), rcond=None)[0]
        radius = math.sqrt(c[2] + c[0] ** 2 + c[1] ** 2)
        return {"front": front, "rear": rear, "rear_radius": radius, "rear_pressure": self.sigma / radius}


def measure(run):
    scene = Scene(run)
    frames = []
    for name in sorted(glob.glob(os.path.join(run, "fields_*.h5"))):
        with h5py.File(name, "r") as f:
            if "colour" not in f:
                sys.exit(f"throat_entry: {name} has no colour field (Output/Fields must name 'colour')")
            time = float(f.attrs["time"][0]) if "time" in f.attrs else None
        m = scene.frame(name)
        if m is not None:
            m["file"] = os.path.basename(name)
            m["time"] = time
            frames.append(m)
    if len(frames) < 3:
        sys.exit(f"throat_entry: {run}: fewer than 3 frames with one slug across the channel")
    last, quarter = frames[-1], frames[(3 * len(frames)) // 4]
    front_pressure = last["rear_pressure"] + scene.lift
    if last["front"] > scene.middle:
        verdict = "entered"
    elif abs(last["front"] - quarter["front"]) < 0.5 * scene.dx:
        verdict = "arrested"
    else:
        verdict = "on its way"
    return {
        "run": run,
        "body_force": scene.force,
        "spacing": scene.dx,
        "throat_width": scene.w,
        "channel_width": scene.W,
        "throat_mouth": scene.mouth,
        "throat_middle": scene.middle,
        "entry_pressure": scene.entry_pressure,
        "lift": scene.lift,
        "rear_pressure": last["rear_pressure"],
        "front_pressure": front_pressure,
        "front_over_entry": front_pressure / scene.entry_pressure,
        "front": [f["front"] for f in frames],
        "times": [f["time"] for f in frames],
        "verdict": verdict,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    results = [measure(run) for run in args.runs]
    if args.json:
        print(json.dumps(results, indent=1))
        return
    for r in results:
        dx = r["spacing"]
        print(f"{r['run']}: |F| = {r['body_force']:.4g} m/s^2, w = {r['throat_width'] / dx:.0f} spacings, "
              f"mouth at {r['throat_mouth'] / dx:.1f}, middle at {r['throat_middle'] / dx:.1f}")
        print("  front along the throat's middle row (spacings): " +
              " ".join(f"{x / dx:.2f}" for x in r["front"]))
        print(f"  Pc(rear) {r['rear_pressure']:.4f} Pa + rho|F|L {r['lift']:.4f} Pa = Pc(front) "
              f"{r['front_pressure']:.4f} Pa, {r['front_over_entry']:.4f} of the entry pressure "
              f"{r['entry_pressure']:.4f} Pa: {r['verdict']}")
    arrested = [r["front_pressure"] for r in results if r["verdict"] == "arrested"]
    entered = [r["front_pressure"] for r in results if r["verdict"] == "entered"]
    if arrested and entered:
        entry = results[0]["entry_pressure"]
        lo, hi = max(arrested), min(entered)
        print(f"entry pressure between {lo:.4f} and {hi:.4f} Pa ({lo / entry - 1:+.2%} and {hi / entry - 1:+.2%} "
              f"of 2 sigma cos(theta) / w = {entry:.4f} Pa)")


if __name__ == "__main__":
    main()
