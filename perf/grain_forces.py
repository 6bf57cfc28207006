#!/usr/bin/python3
"""The fluid's force and torque on each grain of a 2D periodic cell
(problem III by default): PoreSPH's (surface_forces.csv, the steady solve)
against finite elements (Taylor-Hood, FreeFem++, the stress on each grain's
boundary; perf/stokes_reference.py's mesh and solve) in Stokes flow.

    perf/grain_forces.py [--scene input/problem3/problem3.xml] [--grains input/problem3/grains.txt]
        [--spacings 0.001 0.0005 0.00025] [--segments 100 200 400] [--method steady|explicit]
        [--poresph build/poresph] [--out build/grain-forces] [--reuse]

Each force is given as a share of the body force on the whole fluid (the
fluid's mass times the body force, which the grains hold up at a steady
state): grain i's (Fx, Fy) / (rho F A_fluid), and its torque over
(rho F A_fluid) times its radius. The finite-element reference is the
finest mesh's, its change from the mesh before shown beside it; the scene's
fluid properties and body force (along x) are read from the finite-element
run's arguments: --nu and --force must match the scene's (problem III's by
default). Writes grain_forces.csv into --out and prints a Markdown table.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

from poresph_runs import ROOT
import stokes_reference


def fem_forces(grains, cell, segments, nu, force, out):
    """Per mesh: {segments: (porosity, [(fx, fy, torque) per grain])}, per unit density."""
    x0 = stokes_reference.free_edge([(cx - r, cx + r) for cx, _, r in grains], cell)
    y0 = stokes_reference.free_edge([(cy - r, cy + r) for _, cy, r in grains], cell)
    if x0 is None or y0 is None:
        sys.exit("the grains cross every line of the cell: no translate to mesh")
    results = {}
    for n in segments:
        script = os.path.join(out, f"stokes_forces_n{n}.edp")
        with open(script, "w") as f:
            f.write(stokes_reference.edp(grains, cell, x0, y0, n, nu, force, "x", 1.0))
        start = time.monotonic()
        done = subprocess.run(["FreeFem++-nw", "-v", "0", script], capture_output=True, text=True)
        lines = done.stdout.splitlines()
        result = [line.split() for line in lines if line.startswith("RESULT")]
        rows = [line.split() for line in lines if line.startswith("GRAIN")]
        if done.returncode != 0 or not result or len(rows) != len(grains):
            sys.exit(f"FreeFem++ failed on {script}:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
        if not float(result[-1][3]) > 0:  # FreeFem++ reports some failed solves (memory) only by a zero solution
            sys.exit(f"FreeFem++ gave kxx = {result[-1][3]} on {script}: the solve failed (too fine a mesh?)")
        porosity = float(result[-1][5])
        results[n] = (porosity, [tuple(float(v) for v in row[2:5]) for row in rows])
        print(f"finite elements, {n} segments a side: {time.monotonic() - start:.1f} s", file=sys.stderr)
    return results


def poresph_forces(binary, scene, spacing, method, out, reuse):
    """PoreSPH's grain rows of surface_forces.csv and its body_force_on_fluid row."""
    directory = os.path.join(out, f"poresph_{spacing:g}")
    command = [binary, scene, "--output", directory, "--overwrite", "--set", f"Discretization/Particle Spacing={spacing!r}",
               "--set", f"Solver/Method={method}"]
    start = time.monotonic()
    if not (reuse and os.path.exists(os.path.join(directory, "surface_forces.csv"))):
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"{' '.join(command)} failed:\n{done.stderr[-2000:]}")
    grains, held = [], None
    with open(os.path.join(directory, "surface_forces.csv")) as f:
        for row in csv.DictReader(f):
            if row["surface"] == "grain":
                grains.append((float(row["force_x"]), float(row["force_y"]), float(row["torque"])))
            elif row["surface"] == "body_force_on_fluid":
                held = float(row["force_x"])
    print(f"PoreSPH at {spacing:g}: {time.monotonic() - start:.1f} s", file=sys.stderr)
    return grains, held


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", default=os.path.join(ROOT, "input", "problem3", "problem3.xml"))
    parser.add_argument("--grains", default=os.path.join(ROOT, "input", "problem3", "grains.txt"))
    parser.add_argument("--cell", type=float, default=0.1, help="side of the square cell (m)")
    parser.add_argument("--nu", type=float, default=1e-6, help="the scene's kinematic viscosity (m^2/s)")
    parser.add_argument("--force", type=float, default=1.5e-8, help="the scene's body force along x (m/s^2)")
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.001, 0.0005, 0.00025])
    parser.add_argument("--segments", type=int, nargs="+", default=[100, 200, 300])
    parser.add_argument("--method", choices=["steady", "explicit"], default="steady")
    parser.add_argument("--poresph", default=os.path.join(ROOT, "build", "poresph"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "grain-forces"))
    parser.add_argument("--reuse", action="store_true", help="read PoreSPH runs already in --out instead of running them")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    grains = stokes_reference.read_grains(args.grains)
    fem = fem_forces(grains, args.cell, args.segments, args.nu, args.force, args.out)
    finest, before = args.segments[-1], args.segments[-2] if len(args.segments) > 1 else None
    porosity = fem[finest][0]
    held = args.force * porosity * args.cell**2  # per unit density: what the grains hold up

    def shares(forces, total):
        return [(fx / total, fy / total, t / (total * r)) for (fx, fy, t), (_, _, r) in zip(forces, grains)]

    reference = shares(fem[finest][1], held)
    coarser = shares(fem[before][1], held) if before else None
    runs = {}
    for spacing in args.spacings:
        forces, poresph_held = poresph_forces(args.poresph, args.scene, spacing, args.method, args.out, args.reuse)
        if len(forces) != len(grains):
            sys.exit(f"PoreSPH reported {len(forces)} grains, the grains file has {len(grains)}")
        runs[spacing] = (shares(forces, poresph_held), sum(f[0] for f in forces) / poresph_held - 1)
    rows = []
    for i, (cx, cy, r) in enumerate(grains):
        row = dict(grain=i, cx=cx, cy=cy, radius=r)
        for name, k in (("fx", 0), ("fy", 1), ("torque", 2)):
            row[f"fem_{name}"] = reference[i][k]
            if coarser:
                row[f"fem_{name}_change"] = reference[i][k] - coarser[i][k]
            for spacing, (s, _) in runs.items():
                row[f"poresph_{spacing:g}_{name}"] = s[i][k]
        rows.append(row)
    with open(os.path.join(args.out, "grain_forces.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"Shares of the body force on the fluid (rho F A_fluid); torque over rho F A_fluid R. Finite elements: "
          f"{finest} segments a side (change from {before} in brackets); PoreSPH: Solver/Method = {args.method}.\n")
    header = "| grain | R (m) | quantity | finite elements |" + "".join(f" PoreSPH {s:g} m |" for s in runs)
    print(header)
    print("|---" * (4 + len(runs)) + "|")
    for i, row in enumerate(rows):
        for name, label in (("fx", "Fx"), ("fy", "Fy"), ("torque", "T / R")):
            fem_text = f"{row[f'fem_{name}']:+.4f}"
            if coarser:
                fem_text += f" ({row[f'fem_{name}_change']:+.1e})"
            cells = "".join(f" {row[f'poresph_{s:g}_{name}']:+.4f} |" for s in runs)
            print(f"| {i} | {grains[i][2]:.4g} | {label} | {fem_text} |{cells}")
    print()
    for spacing, (s, balance) in runs.items():
        worst = max(max(abs(s[i][k] - reference[i][k]) for k in range(3)) for i in range(len(grains)))
        print(f"PoreSPH at {spacing:g} m: largest difference from finite elements {worst:.4f} of the held force; "
              f"its grains' drag over the body force on its fluid - 1 = {balance:+.2e}")
    fem_sum = sum(f[0] for f in fem[finest][1]) / held - 1
    print(f"finite elements: the grains' drag over F A_fluid - 1 = {fem_sum:+.2e} (the boundary stress's error)")


if __name__ == "__main__":
    main()
