#!/usr/bin/python3
"""The contact angle of a drop on the wall y = 0 (2D or 3D), or of drops side by side on y = floor, from a run's
final particles.

Reads particles.csv of a run with Phases/Interface = moving (its phi column),
finds where phi crosses 1/2 between neighbouring lattice points, fits a circle
(2D) or a sphere (3D) to the crossings more than --skip spacings above the
wall (a least-squares fit of |x|^2 + a . x + c = 0), and reports the angle it
makes with the wall: through the drop (phase 1) and through phase 0, as
Phases/Contact Angle is given.

With --drops N the crossings are split into N drops at the widest gaps along x, and each is fitted.

    perf/contact_angle.py RUN_DIR [--skip 3] [--floor Y] [--drops N] [--json]
"""
import argparse
import csv
import json
import math
import sys

import numpy as np


def interface_points(path):
    """The phi = 1/2 crossings between lattice neighbours along each axis, and the spacing."""
    rows = []
    with open(path) as f:
        reader = csv.DictReader(f)
        axes = [a for a in ("x", "y", "z") if a in reader.fieldnames]
        for r in reader:
            if int(r["kind"]) != 0:
                continue
            rows.append((tuple(float(r[a]) for a in axes), float(r["phi"])))
    if not rows:
        sys.exit(f"{path}: no fluid particle")
    xs = np.array(sorted({r[0][0] for r in rows}))
    dx = float(np.min(np.diff(xs)))
    lattice = {tuple(round(c / dx - 0.5) for c in at): phi for at, phi in rows}
    dim = len(axes)
    points = []
    for i, phi in lattice.items():
        for d in range(dim):
            j = tuple(i[e] + (1 if e == d else 0) for e in range(dim))
            other = lattice.get(j)
            if other is None or (phi - 0.5) * (other - 0.5) > 0 or phi == other:
                continue
            t = (0.5 - phi) / (other - phi)
            points.append(tuple((i[e] + 0.5 + (t if e == d else 0)) * dx for e in range(dim)))
    return np.array(points), dx


def fit_sphere(points):
    """The circle (2D) or sphere (3D) |x - c|^2 = r^2 closest to the points by least squares."""
    A = np.column_stack([points, np.ones(len(points))])
    solution = np.linalg.lstsq(A, -np.sum(points * points, axis=1), rcond=None)[0]
    centre = -solution[:-1] / 2
    return centre, math.sqrt(float(centre @ centre) - solution[-1])


def drops(points, count):
    """The points split into `count` drops along x, at the count - 1 widest gaps between them."""
    order = np.argsort(points[:, 0])
    x = points[order, 0]
    cuts = sorted(np.argsort(np.diff(x))[len(x) - count:] + 1) if count > 1 else []
    return [points[part] for part in np.split(order, cuts)]


def measure(points, dx, floor, skip):
    """A drop's angle with the wall y = floor from its interface points above floor + skip spacings."""
    above = points[points[:, 1] > floor + skip * dx]
    if len(above) < 5:
        sys.exit(f"{len(above)} interface points above the wall: no drop to fit")
    centre, radius = fit_sphere(above)
    drop = math.degrees(math.acos(max(-1.0, min(1.0, -(centre[1] - floor) / radius))))
    spread = np.sqrt(np.sum((above - centre) ** 2, axis=1)) - radius
    return {"drop_angle": drop, "contact_angle_phase_0": 180 - drop, "radius": radius, "centre": centre.tolist(),
            "points": int(len(above)), "fit_rms_spacings": float(np.sqrt(np.mean(spread ** 2)) / dx)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="the run's output directory (with particles.csv)")
    parser.add_argument("--skip", type=float, default=3.0,
                        help="crossings closer than this many spacings to the wall are left out of the fit")
    parser.add_argument("--floor", type=float, default=0.0, help="the wall's height y (m), 0: the cell's lower side")
    parser.add_argument("--drops", type=int, default=1, help="drops on the wall, each measured (2D: side by side)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (a list with --drops)")
    args = parser.parse_args()
    points, dx = interface_points(args.run + "/particles.csv")
    results = [measure(drop, dx, args.floor, args.skip) for drop in drops(points, args.drops)]
    if args.json:
        print(json.dumps(results if args.drops > 1 else results[0]))
        return
    for r in results:
        shape = "circle" if points.shape[1] == 2 else "sphere"
        print(f"angle through the drop {r['drop_angle']:.2f} deg (through phase 0 {r['contact_angle_phase_0']:.2f}), "
              f"centre x {r['centre'][0]:.4g} m, radius {r['radius']:.4g} m, {r['points']} points, rms off the "
              f"{shape} {r['fit_rms_spacings']:.3f} spacings")


if __name__ == "__main__":
    main()
