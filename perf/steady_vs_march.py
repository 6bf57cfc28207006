#!/usr/bin/env python3
"""The steady solver against the march on the shipped scenes: each scene at
its own resolution, once marched to a steady k (Permeability/Steady
Tolerance = 1e-4 unless --march-tolerance says otherwise) and once solved
(Solver/Method = steady, the shipped defaults), one process, one thread.

    perf/steady_vs_march.py [--build build] [--out build/steady-vs-march] [--march-from CSV]
                            [--set PATH=VALUE ...] [SCENE ...]

SCENE: paths under input/ (default: every grain, 3D and image scene).
Writes steady_vs_march.csv and steady_vs_march.md (a table) into --out:
per scene the diagonal k of both runs (every driven axis of a tensor
scene), their largest relative difference, the march's steps and wall
seconds, the solve's iterations, evaluations and wall seconds. A solve
that did not converge is listed as such, with the k it stopped at.
--march-from takes the march's columns from an earlier steady_vs_march.csv
(the march does not change when the solver does) and runs the solves only;
--set adds settings to the solves (e.g. Solver/Tolerance=1e-4)."""
import argparse
import csv
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from poresph_runs import ROOT, read_summary, run_poresph, write_csv  # noqa: E402

SCENES = [
    "problem2/problem2.xml",
    "problem3/problem3.xml",
    "square_array/square_array_c05.xml",
    "square_array/square_array_c10.xml",
    "square_array/square_array_c20.xml",
    "square_array/square_array_c30.xml",
    "square_array/square_array_c40.xml",
    "square_array/square_array_c50.xml",
    "square_array/square_array_c60.xml",
    "square_array/square_array_c70.xml",
    "hard/corner_grain.xml",
    "hard/high_force.xml",
    "hard/throat.xml",
    "hard/touching.xml",
    "3d/simple_cubic.xml",
    "3d/bcc.xml",
    "3d/fcc.xml",
    "image/sphere_pack.xml",
    "3d/random_pack.xml",
]
SERIAL = ["Run/Backend=serial", "Convergence/Levels=1"]


def diagonal(summary):
    """k_ii of every driven axis the run measured, by name."""
    k = summary.get("permeability", {})
    return {name: value for name, value in k.items() if len(name) == 3 and name[1] == name[2]}


def earlier_march(row):
    """The march's part of a summary, from a row of an earlier CSV: its k in
    the order of the axes' names (matched to the solve's below)."""
    return {"fluid_particles": int(row["fluid_particles"]), "steps": int(row["march_steps"]),
            "wall_seconds": float(row["march_seconds"]), "k_in_order": [float(k) for k in row["k_march"].split()]}


def compare(build, scene, out, march_tolerance, marched=None, solve_settings=()):
    name = scene.replace("/", "_").replace(".xml", "")
    if marched is not None:
        march = marched
    else:
        march = run_poresph(build, scene, os.path.join(out, name + "_march"),
                            SERIAL + [f"Permeability/Steady Tolerance={march_tolerance}", "Run/End Time=1e12",
                                      "Run/Max Steps=0"])
    solve_dir = os.path.join(out, name + "_steady")
    try:
        solve = run_poresph(build, scene, solve_dir, SERIAL + ["Solver/Method=steady"] + list(solve_settings))
    except subprocess.CalledProcessError as error:
        if error.returncode != 4:  # 4: not converged, and the summary says where it stopped
            raise
        solve = read_summary(solve_dir)
    k_solve = diagonal(solve)
    if "k_in_order" in march:
        if len(march["k_in_order"]) != len(k_solve):
            sys.exit(f"{scene}: the earlier march measured {len(march['k_in_order'])} axes, the solve {len(k_solve)}")
        k_march = dict(zip(sorted(k_solve), march["k_in_order"]))
    else:
        k_march = diagonal(march)
    difference = max(abs(k_solve[c] / k_march[c] - 1) for c in k_march)
    solver = solve["solver"]
    return dict(scene=scene, fluid_particles=march["fluid_particles"],
                k_march=" ".join(f"{k_march[c]:.8g}" for c in sorted(k_march)),
                k_steady=" ".join(f"{k_solve[c]:.8g}" for c in sorted(k_solve)),
                relative_difference=difference, march_steps=march["steps"], march_seconds=march["wall_seconds"],
                converged=solver["converged"], nonlinear_iterations=solver["nonlinear_iterations"],
                linear_iterations=solver["linear_iterations"], rate_evaluations=solver["rate_evaluations"],
                partial_rate_evaluations=solver.get("partial_rate_evaluations", 0),
                steady_seconds=solve["wall_seconds"])


def write_table(path, rows):
    with open(path, "w") as f:
        f.write("| scene | fluid particles | k march | k steady | difference | march: steps, s | "
                "steady: Newton, linear, evaluations (all / one term), s |\n|---|---|---|---|---|---|---|\n")
        for r in rows:
            status = "" if r["converged"] else " (not converged)"
            f.write(f"| {r['scene']} | {r['fluid_particles']:,} | {r['k_march']} | {r['k_steady']}{status} | "
                    f"{r['relative_difference'] * 100:.3f} % | {r['march_steps']:,}, {r['march_seconds']:.1f} | "
                    f"{r['nonlinear_iterations']}, {r['linear_iterations']}, {r['rate_evaluations']:,} / "
                    f"{r['partial_rate_evaluations']:,}, {r['steady_seconds']:.1f} |\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", default=SCENES)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "steady-vs-march"))
    parser.add_argument("--march-tolerance", type=float, default=1e-4)
    parser.add_argument("--march-from", help="an earlier steady_vs_march.csv: its marches, not run again")
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                        help="a setting of the solves (repeatable)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    marches = {}
    if args.march_from:
        with open(args.march_from, newline="") as f:
            marches = {row["scene"]: earlier_march(row) for row in csv.DictReader(f)}
    rows = []
    for scene in args.scenes:
        if args.march_from and scene not in marches:
            sys.exit(f"{scene}: not in {args.march_from}")
        rows.append(compare(os.path.abspath(args.build), scene, args.out, args.march_tolerance, marches.get(scene),
                            args.set))
        r = rows[-1]
        print(f"{scene}: difference {r['relative_difference'] * 100:.3f} %, march {r['march_seconds']:.1f} s, "
              f"steady {r['steady_seconds']:.1f} s{'' if r['converged'] else ' (not converged)'}", flush=True)
        write_csv(os.path.join(args.out, "steady_vs_march.csv"), rows)
        write_table(os.path.join(args.out, "steady_vs_march.md"), rows)


if __name__ == "__main__":
    main()
