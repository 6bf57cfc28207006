#!/usr/bin/python3
"""The contact angle of a drop on the wall y = 0 (2D or 3D), from a run's final particles.

Reads particles.csv of a run with Phases/Interface = moving (its phi column),
finds where phi crosses 1/2 between neighbouring lattice points, fits a circle
(2D) or a sphere (3D) to the crossings more than --skip spacings above the
wall (a least-squares fit of |x|^2 + a . x + c = 0), and reports the angle it
makes with the wall: through the drop (phase 1) and through phase 0, as
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
    centre, radius = fit_sphere(above)
    drop = math.degrees(math.acos(max(-1.0, min(1.0, -centre[1] / radius))))
    spread = np.sqrt(np.sum((above - centre) ** 2, axis=1)) - radius
    result = {"drop_angle": drop, "contact_angle_phase_0": 180 - drop, "radius": radius, "centre": centre.tolist(),
              "points": int(len(above)), "fit_rms_spacings": float(np.sqrt(np.mean(spread ** 2)) / dx)}
    if args.json:
        print(json.dumps(result))
    else:
        print(f"angle through the drop {drop:.2f} deg (through phase 0 {180 - drop:.2f}), radius {radius:.4g} m, "
              f"{len(above)} points, rms off the {'circle' if above.shape[1] == 2 else 'sphere'} "
              f"{result['fit_rms_spacings']:.3f} spacings")


if __name__ == "__main__":
    main()
