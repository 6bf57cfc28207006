#!/usr/bin/python3
"""Capillary rise between two plates (input/two_phase/capillary_rise.xml) against Jurin's law.

Reads a run's parameters_used.xml and its final particles.csv (or, with --fields, every
fields_*.h5 with the `colour` field), finds on the vertical line through the middle of the gap
between the plates and through the middle of the gap outside them (across the periodic side)
the height where phi falls through 1/2 going up (the meniscus's lowest point), and compares
their difference with Jurin's for two gaps of widths w (inside) and W (outside):

    dh = (2 sigma cos(theta) / (rho |F|)) (1/w - 1/W)

theta through the liquid (phase 1, the driven one): 180 degrees less Phases/Contact Angle. That
form takes each meniscus for an arc of a circle, which holds for a gap narrow beside the capillary
length l_c = sqrt(sigma / (rho |F|)). Where a gap is not (the scene's outer gap is 3.5 l_c wide, and
its meniscus flattens in the middle), the menisci are the solutions of the Young-Laplace equation
with gravity, sigma u'' / (1 + u'^2)^(3/2) = rho |F| u (u the height over the level where the
liquid's pressure is the other phase's), level in each gap's middle and meeting its walls at theta;
the difference of their middles is the rest the run should reach. Both are printed; the law below
rests at the second.
The plates are read from the image: the solid columns of its middle row, and their lower end.

With --fields, each frame's heights are set beside the Lucas-Washburn law of the narrow gap with
gravity and the displaced fluid (Bosanquet's form, with the column's inertia): Poiseuille flow
between plates, whose pressure loss 12 v (mu_1 (h - b) + mu_0 (t - h)) / w^2 is that of the liquid
(phase 1) from the plates' lower end b to the meniscus h and of the other phase (phase 0) from
there to the plates' upper end t, driven by rho |F| (dh_rest - dh) and accelerating the gap's
column, rho (t - b) dv/dt (one density for both phases); the outer level falls by w / W of the
inner rise. Integrated from the first frame at rest. It leaves out the flow into the gap from
below and out of it above, and the contact lines' own resistance. Its difference dh over time
is the one to compare: the run's outer level falls by more than w / W of the inner rise (the
liquid also climbs the plates' outer faces), which the law does not follow, and each comes to
its own rest; so each frame also gives the run's time over the time the law takes to reach the
same fraction of its last difference (1: as fast as the law; above 1: slower).

    perf/capillary_rise.py RUN_DIR [--fields] [--json]
"""
import argparse
import csv
import glob
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np

from run_parameters import numbers, parameter
import run_parameters


def plates(run, root):
    """The solid columns of the image's middle row, grouped into the plates' x extents (voxels)."""
    grid, solid, _ = run_parameters.scene_image(run, root)
    shape = (grid.shape[1], grid.shape[0])
    row = grid[shape[1] // 2]
    columns = [i for i in range(shape[0]) if int(row[i]) in solid]
    groups = []
    for i in columns:
        if groups and i == groups[-1][1]:
            groups[-1][1] = i + 1
        else:
            groups.append([i, i + 1])
    if len(groups) != 2:
        sys.exit(f"{run}: the image's middle row holds {len(groups)} solid runs, not two plates")
    rows = [j for j in range(shape[1]) if int(grid[j, groups[0][0]]) in solid]
    return groups, shape[0], min(rows), max(rows) + 1


def meniscus(column):
    """The height (in spacings) where phi falls through 1/2 going up, the highest such crossing."""
    js = sorted(column)
    height = None
    for a, b in zip(js, js[1:]):
        if b == a + 1 and column[a] >= 0.5 > column[b]:
            height = a + 0.5 + (column[a] - 0.5) / (column[a] - column[b])
    return height


def heights(x, y, phi, dx, inner, outer):
    columns = {inner: {}, outer: {}}
    for xi, yi, p in zip(x, y, phi):
        i, j = round(xi / dx - 0.5), round(yi / dx - 0.5)
        if i in columns:
            columns[i][j] = p
    return meniscus(columns[inner]), meniscus(columns[outer])


def meniscus_middle(gap, capillary_length_sq, theta):
    """The height over the level of equal pressures of a 2D meniscus's middle in a gap (lengths in one
    unit): u'' = (u / l_c^2) (1 + u'^2)^(3/2) from the middle (u' = 0) to a wall, where u' must be
    cot(theta). Shooting on the middle's height, RK4 and bisection."""
    target = abs(1 / math.tan(theta))

    def slope_at_wall(middle):
        steps = 2000
        h, u, du = gap / 2 / steps, middle, 0.0
        f = lambda u, du: (du, u / capillary_length_sq * (1 + du * du) ** 1.5)
        for _ in range(steps):
            k1 = f(u, du)
            k2 = f(u + h / 2 * k1[0], du + h / 2 * k1[1])
            k3 = f(u + h / 2 * k2[0], du + h / 2 * k2[1])
            k4 = f(u + h * k3[0], du + h * k3[1])
            u += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            du += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            if du > 1e3 * (1 + target):
                return math.inf
        return du

    low, high = 0.0, 2 * capillary_length_sq * abs(math.cos(theta)) / gap  # the arc's middle: gravity lowers it
    for _ in range(100):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if slope_at_wall(middle) < target else (low, middle)
    return math.copysign(0.5 * (low + high), math.cos(theta))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("--fields", action="store_true", help="every field file's heights over time")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    root = ET.parse(os.path.join(args.run, "parameters_used.xml")).getroot()
    dx = float(parameter(root, "Discretization/Particle Spacing"))
    sigma = float(parameter(root, "Phases/Surface Tension"))
    theta = math.radians(180 - float(parameter(root, "Phases/Contact Angle")))
    rho = float(parameter(root, "Fluid/Density"))
    force = math.hypot(*numbers(parameter(root, "Fluid/Body Force")))
    ((a0, a1), (b0, b1)), n, bottom, top = plates(args.run, root)
    w, W = (b0 - a1), n - (b1 - a0)
    inner, outer = (a1 + b0) // 2, ((b1 + a0 + n) // 2) % n
    jurin = 2 * sigma * math.cos(theta) / (rho * force) * (1 / (w * dx) - 1 / (W * dx)) / dx
    capillary_length_sq = sigma / (rho * force) / dx**2  # in spacings^2
    rest = meniscus_middle(w, capillary_length_sq, theta) - meniscus_middle(W, capillary_length_sq, theta)
    mu_liquid = rho * float(parameter(root, "Phases/Phase 1/Kinematic Viscosity"))
    mu_other = rho * float(parameter(root, "Fluid/Kinematic Viscosity"))
    result = {"gap": w, "outer_gap": W, "jurin_difference": jurin, "meniscus_difference": rest,
              "capillary_length": math.sqrt(capillary_length_sq), "rows": []}
    if args.fields:
        import h5py
        for name in sorted(glob.glob(os.path.join(args.run, "fields_*.h5")),
                           key=lambda f: int(os.path.basename(f)[7:-3])):
            with h5py.File(name, "r") as f:
                pos, phi, kind = np.asarray(f["position"]), np.asarray(f["colour"]), np.asarray(f["kind"])
                time = float(f.attrs["time"])
            fluid = kind == 0
            hi, ho = heights(pos[fluid, 0], pos[fluid, 1], phi[fluid], dx, inner, outer)
            result["rows"].append({"time": time, "inner": hi, "outer": ho})
        # Lucas-Washburn-Bosanquet with gravity, from the first frame at rest; heights in spacings,
        # the balance in SI units (v in m/s).
        first = result["rows"][0]
        h, t, v = first["inner"], first["time"], 0.0
        for row in result["rows"]:
            while t < row["time"] - 1e-12:
                step = min(1e-6, row["time"] - t)
                outer = first["outer"] - (w / W) * (h - first["inner"])
                drive = rho * force * (rest - (h - outer)) * dx
                loss = 12 * v * (mu_liquid * (h - bottom) + mu_other * (top - h)) * dx / (w * dx) ** 2
                v += step * (drive - loss) / (rho * (top - bottom) * dx)
                h += step * v / dx
                t += step
            row["washburn_inner"] = h
            row["washburn_difference"] = h - (first["outer"] - (w / W) * (h - first["inner"]))
        # How much slower the run is than the law: the time the law takes to reach the fraction of
        # its last difference that the run's difference is of the run's last, against the run's time.
        rows = result["rows"]
        run_rest = rows[-1]["inner"] - rows[-1]["outer"]
        law_times = [r["time"] for r in rows]
        law_fractions = [r["washburn_difference"] / rows[-1]["washburn_difference"] for r in rows]
        for row in rows[1:]:
            fraction = (row["inner"] - row["outer"]) / run_rest
            if fraction < max(law_fractions) and all(b > a for a, b in zip(law_fractions, law_fractions[1:])):
                row["time_over_law"] = row["time"] / float(np.interp(fraction, law_fractions, law_times))
    else:
        x, y, phi = [], [], []
        with open(os.path.join(args.run, "particles.csv")) as f:
            for r in csv.DictReader(f):
                if r["kind"] == "0":
                    x.append(float(r["x"])), y.append(float(r["y"])), phi.append(float(r["phi"]))
        hi, ho = heights(x, y, phi, dx, inner, outer)
        result["rows"].append({"time": None, "inner": hi, "outer": ho})
    if args.json:
        print(json.dumps(result))
        return
    print(f"gaps {w} and {W} spacings, capillary length {math.sqrt(capillary_length_sq):.2f}; Jurin's difference "
          f"{jurin:.2f} spacings (arcs), the menisci's with gravity {rest:.2f}")
    for r in result["rows"]:
        when = "end" if r["time"] is None else f"t = {r['time']:.4g} s"
        d = r["inner"] - r["outer"]
        washburn = (f"; Lucas-Washburn's inner {r['washburn_inner']:.2f}, difference {r['washburn_difference']:.2f}"
                    if "washburn_inner" in r else "")
        if "time_over_law" in r:
            washburn += f", time over the law's to the same fraction of rest {r['time_over_law']:.2f}"
        print(f"{when}: inner {r['inner']:.2f}, outer {r['outer']:.2f}, difference {d:.2f} "
              f"({100 * (d / jurin - 1):+.1f} % of Jurin's arcs, {100 * (d / rest - 1):+.1f} % of the menisci's)"
              f"{washburn}")


if __name__ == "__main__":
    main()
