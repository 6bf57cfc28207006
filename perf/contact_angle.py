#!/usr/bin/python3
"""The contact angle of a 2D drop on the wall y = 0, from a run's final particles.

Reads particles.csv of a run with Phases/Interface = moving (its phi column),
finds where phi crosses 1/2 between neighbouring lattice points, fits a circle
to the crossings more than --skip spacings above the wall (a least-squares fit
of x^2 + y^2 + a x + b y + c = 0), and reports the angle the circle makes with
the wall: through the drop (phase 1) and through phase 0, as
Phases/Contact Angle is given.

    perf/contact_angle.py RUN_DIR [--skip 3] [--json]
"""
import argparse
import csv
import json
import math
import sys

import numpy as np


def interface_points(path):
    """The phi = 1/2 crossings between lattice neighbours along x and y, and the spacing."""
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            if int(r["kind"]) != 0:
                continue
            rows.append((float(r["x"]), float(r["y"]), float(r["phi"])))
    if not rows:
        sys.exit(f"{path}: no fluid particle")
    xs = np.array(sorted({r[0] for r in rows}))
    dx = float(np.min(np.diff(xs)))
    lattice = {(round(x / dx - 0.5), round(y / dx - 0.5)): phi for x, y, phi in rows}
    points = []
    for (i, j), phi in lattice.items():
        for di, dj in ((1, 0), (0, 1)):
            other = lattice.get((i + di, j + dj))
            if other is None or (phi - 0.5) * (other - 0.5) > 0 or phi == other:
                continue
            t = (0.5 - phi) / (other - phi)
            points.append(((i + 0.5 + t * di) * dx, (j + 0.5 + t * dj) * dx))
    return np.array(points), dx


def fit_circle(points):
    x, y = points[:, 0], points[:, 1]
    A = np.column_stack([x, y, np.ones_like(x)])
    a, b, c = np.linalg.lstsq(A, -(x * x + y * y), rcond=None)[0]
    xc, yc = -a / 2, -b / 2
    return xc, yc, math.sqrt(xc * xc + yc * yc - c)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="the run's output directory (with particles.csv)")
    parser.add_argument("--skip", type=float, default=3.0,
                        help="crossings closer than this many spacings to the wall are left out of the fit")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()
    points, dx = interface_points(args.run + "/particles.csv")
    above = points[points[:, 1] > args.skip * dx]
    if len(above) < 5:
        sys.exit(f"{args.run}: {len(above)} interface points above the wall: no drop to fit")
    xc, yc, radius = fit_circle(above)
    drop = math.degrees(math.acos(max(-1.0, min(1.0, -yc / radius))))
    spread = np.sqrt((above[:, 0] - xc) ** 2 + (above[:, 1] - yc) ** 2) - radius
    result = {"drop_angle": drop, "contact_angle_phase_0": 180 - drop, "radius": radius, "centre": [xc, yc],
              "points": int(len(above)), "fit_rms_spacings": float(np.sqrt(np.mean(spread ** 2)) / dx)}
    if args.json:
        print(json.dumps(result))
    else:
        print(f"angle through the drop {drop:.2f} deg (through phase 0 {180 - drop:.2f}), radius {radius:.4g} m, "
              f"{len(above)} points, rms off the circle {result['fit_rms_spacings']:.3f} spacings")


if __name__ == "__main__":
    main()
