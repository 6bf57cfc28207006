#!/usr/bin/env python3
"""The march and the steady solve on grain cells that are not in input/:
random periodic cells of discs (2D) or spheres (3D), made from a seed, each
run with the shipped defaults three ways, one process, one thread:

  - marched to a steady k (Permeability/Steady Tolerance = --march-tolerance,
    1e-4 unless said otherwise), as a user's run would stop;
  - solved (Solver/Method = steady, the solver's defaults);
  - with --long T, marched on to t = T s without a stop: where the march
    itself goes, to tell which of the first two is nearer its limit.

    perf/unseen_cells.py --dimension 3 --seeds 101 102 103 --long 300000 --out DIR
    perf/unseen_cells.py --dimension 2 --seeds 11 12 13 14 --out DIR

A cell: side 0.1 m (one side 0.05 to 0.12 m in three cells of ten, a whole
number of spacings), one to six grains in 2D and one to four in 3D, radii
0.06 to 0.3 of the shorter side, no two surfaces closer than 0.06 of it
(about a spacing at the default 3D spacing: some throats are refused as
narrower than one spacing, and so skipped, some are one to three spacings
wide, and warned of), water (nu = 1e-6 m^2/s) driven by 1e-8 m/s^2 along x
or y. The spacing is 0.1 m over --across (50 in 2D, 16 in 3D).

Writes unseen_cells.csv and unseen_cells.md (a table) into --out: per
cell the driven k of each run, the narrowest throat in spacings, the
march's steps, its predicted remaining change at the stop
(steady_remaining_change), and each run's wall seconds. Needs the poresph
of --build only."""
import argparse
import csv
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from poresph_runs import run_poresph  # noqa: E402

SCENE = """<ParameterList name="PoreSPH">
  <ParameterList name="Scene"><Parameter name="Name" type="string" value="{name}"/></ParameterList>
  <ParameterList name="Domain"><Parameter name="Cell Size" type="Array(double)" value="{cell}"/></ParameterList>
  <ParameterList name="Fluid">
    <Parameter name="Density" type="double" value="1000.0"/>
    <Parameter name="Kinematic Viscosity" type="double" value="1.0e-6"/>
    <Parameter name="Body Force" type="Array(double)" value="{force}"/>
  </ParameterList>
  <ParameterList name="Discretization"><Parameter name="Particle Spacing" type="double" value="{spacing!r}"/></ParameterList>
  <ParameterList name="Grains"><Parameter name="File" type="string" value="grains.txt"/></ParameterList>
  <ParameterList name="Run"><Parameter name="End Time" type="double" value="1.0e7"/></ParameterList>
</ParameterList>
"""


def array(values):
    return "{" + ", ".join(repr(float(v)) for v in values) + "}"


def periodic_distance(a, b, cell):
    return math.sqrt(sum(min(abs(x - y), side - abs(x - y)) ** 2 for x, y, side in zip(a, b, cell)))


def random_cell(seed, dimension, spacing):
    """The cell's sides (whole multiples of the spacing), its grains [centre..., radius] and the driven axis,
    from the seed."""
    rng = random.Random(seed)
    cell = [0.1] * dimension
    if rng.random() < 0.3:
        cell[1] = spacing * round(0.1 * rng.choice([0.5, 0.6, 0.8, 1.2]) / spacing)
    shorter = min(cell)
    count = rng.randint(1, 6 if dimension == 2 else 4)
    grains = []
    for _ in range(2000):
        if len(grains) == count:
            break
        radius = rng.uniform(0.06, 0.3) * shorter
        centre = [rng.uniform(0, side) for side in cell]
        apart = all(periodic_distance(centre, g[:-1], cell) >= radius + g[-1] + 0.06 * shorter for g in grains)
        if apart and 2 * radius < shorter - 0.06 * shorter:
            grains.append(centre + [radius])
    axis = rng.choice([0, 0, 1])
    return cell, grains, axis


def narrowest_throat(grains, cell):
    """The smallest surface-to-surface gap between two grains (inf with one grain)."""
    gaps = [periodic_distance(a[:-1], b[:-1], cell) - a[-1] - b[-1]
            for i, a in enumerate(grains) for b in grains[i + 1:]]
    return min(gaps, default=math.inf)


def driven_k(summary, axis):
    name = "k" + "xyz"[axis] * 2
    return summary.get("permeability", {}).get(name)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="build/unseen-cells")
    parser.add_argument("--dimension", type=int, choices=(2, 3), default=2)
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(1, 11)))
    parser.add_argument("--across", type=int, help="spacings across the shorter side (50 in 2D, 16 in 3D)")
    parser.add_argument("--march-tolerance", type=float, default=1e-4)
    parser.add_argument("--long", type=float, default=0.0, help="also march to this time (s) without a stop")
    args = parser.parse_args()
    build = os.path.abspath(args.build)
    across = args.across or (50 if args.dimension == 2 else 16)
    rows = []
    for seed in args.seeds:
        spacing = 0.1 / across
        cell, grains, axis = random_cell(seed, args.dimension, spacing)
        folder = os.path.abspath(os.path.join(args.out, f"cell{args.dimension}d_{seed}"))
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "grains.txt"), "w") as f:
            f.writelines(" ".join(repr(v) for v in g) + "\n" for g in grains)
        force = [0.0] * args.dimension
        force[axis] = 1e-8
        scene = os.path.join(folder, "scene.xml")
        with open(scene, "w") as f:
            f.write(SCENE.format(name=f"cell{args.dimension}d_{seed}", cell=array(cell), force=array(force),
                                 spacing=spacing))
        serial = ["Run/Backend=serial"]
        row = {"seed": seed, "grains": len(grains), "axis": "xyz"[axis],
               "narrowest_throat_spacings": narrowest_throat(grains, cell) / spacing}
        runs = {"march": serial + ["Solver/Method=explicit",
                                   f"Permeability/Steady Tolerance={args.march_tolerance!r}"],
                "steady": serial + ["Solver/Method=steady"]}
        if args.long > 0:
            runs["long"] = serial + ["Solver/Method=explicit", "Permeability/Steady Tolerance=0",
                                     f"Run/End Time={args.long!r}"]
        for name, settings in runs.items():
            try:
                summary = run_poresph(build, scene, os.path.join(folder, name), settings)
            except Exception as error:  # a cell refused (a throat narrower than one spacing) or failed
                row[f"k_{name}"] = f"refused or failed: {error}"
                break
            row[f"k_{name}"] = driven_k(summary, axis)
            row[f"seconds_{name}"] = summary["wall_seconds"]
            if name == "march":
                row["march_steps"] = summary["steps"]
                row["march_remaining_change"] = summary.get("steady_remaining_change")
        if isinstance(row.get("k_steady"), float) and isinstance(row.get("k_march"), float):
            row["march_over_steady"] = row["k_march"] / row["k_steady"] - 1
            if isinstance(row.get("k_long"), float):
                row["long_over_steady"] = row["k_long"] / row["k_steady"] - 1
        rows.append(row)
        print(row, flush=True)
    columns = ["seed", "grains", "axis", "narrowest_throat_spacings", "k_march", "k_steady", "k_long",
               "march_over_steady", "long_over_steady", "march_remaining_change", "march_steps",
               "seconds_march", "seconds_steady", "seconds_long"]

    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "unseen_cells.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns, restval="", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)

    def cell_text(value):
        if isinstance(value, float):
            return f"{value:.4g}"
        return "" if value is None else str(value)

    with open(os.path.join(args.out, "unseen_cells.md"), "w") as f:
        f.write("| " + " | ".join(columns) + " |\n|" + "---|" * len(columns) + "\n")
        for row in rows:
            f.write("| " + " | ".join(cell_text(row.get(c)) for c in columns) + " |\n")


if __name__ == "__main__":
    main()
