#!/usr/bin/python3
"""The resolution ladder (Convergence/Levels, issue 17) against cold runs of
its finest level: problem III with three levels ending at dx = 0.005 L, the
square arrays c = 0.2 and 0.5 with three levels ending at 0.01 L. For each:
the steps and wall time of every level, the finest level's steps against a
cold start's at the same tolerance, the whole ladder's wall time against the
cold finest run's, and the extrapolated k with its band (the grid
convergence index) against the reference.

    perf/ladder.py [--build build] [--out build/ladder] [--ranks N] [--only TEXT]

Writes ladder.csv into --out (perf/speed_vs_error.py --ladder-csv puts the
ladder's points in the speed-against-error figure) and prints the Markdown
table for docs/speed_vs_error.md.
"""
import argparse
import os
import sys

from poresph_runs import ROOT, run_poresph, write_csv

L = 0.1
# (name, scene, settings, reference k/L^2, what the reference is)
SCENES = [
    ("problem III", "problem3/problem3.xml", ["Discretization/Particle Spacing=0.0005"], 9.638e-4, "Stokes FE"),
    ("square array c = 0.2", "square_array/square_array_c20.xml", [], 1 / 51.53, "Sangani-Acrivos"),
    ("square array c = 0.5", "square_array/square_array_c50.xml", [], 1 / 532.55, "Sangani-Acrivos"),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "ladder"))
    parser.add_argument("--ranks", type=int, default=None, help="MPI ranks of every run (default: one process)")
    parser.add_argument("--levels", type=int, default=3)
    parser.add_argument("--only", default=None, help="only the scenes whose name contains this text")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name, scene, settings, reference, what in SCENES:
        if args.only and args.only not in name:
            continue
        tag = name.replace(" ", "_").replace("=", "").replace(".", "")
        cold = run_poresph(args.build, scene, os.path.join(args.out, f"{tag}-cold"), settings, ranks=args.ranks)
        ladder = run_poresph(args.build, scene, os.path.join(args.out, f"{tag}-ladder"),
                             settings + [f"Convergence/Levels={args.levels}"], ranks=args.ranks)
        levels = ladder["convergence"]
        k = ladder["permeability"]["kxx"] / L**2
        band = ladder["permeability_uncertainty"]["kxx"]
        extrapolated = ladder["permeability_extrapolated"]["kxx"] / L**2
        row = dict(scene=name, reference=reference, reference_kind=what, ranks=ladder["ranks"],
                   cold_k=cold["permeability"]["kxx"] / L**2, cold_steps=cold["steps"],
                   cold_wall=cold["wall_seconds"], k=k, extrapolated=extrapolated, uncertainty=band,
                   observed_order=ladder["observed_order"], ladder_wall=ladder["wall_seconds"],
                   finest_steps=levels[-1]["steps"], covered=abs(k - reference) <= band * k,
                   warnings=" | ".join(ladder["warnings"]),
                   levels=" ; ".join(f"{l['spacing'] / L:g} L: k/L^2 {l['permeability']['kxx'] / L**2:.5g}, "
                                     f"{l['steps']} steps, {l['wall_seconds']:.1f} s" for l in levels))
        rows.append(row)
        print(f"{name}: finest {row['finest_steps']} steps warm against {row['cold_steps']} cold; ladder "
              f"{row['ladder_wall']:.1f} s against {row['cold_wall']:.1f} s", file=sys.stderr, flush=True)
        write_csv(os.path.join(args.out, "ladder.csv"), rows)

    print("| scene | levels (dx: k/L^2, steps, wall s) | finest steps, warm / cold | ladder wall s / cold finest | "
          "k/L^2 finest | band (GCI) | extrapolated | observed order | reference | covered |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        order = f"{r['observed_order']:.2f}" if r["observed_order"] is not None else "-"
        print(f"| {r['scene']} | {r['levels']} | {r['finest_steps']} / {r['cold_steps']} = "
              f"{r['finest_steps'] / r['cold_steps']:.2f} | {r['ladder_wall']:.1f} / {r['cold_wall']:.1f} | "
              f"{r['k']:.5g} ({100 * (r['k'] / r['reference'] - 1):+.2f} %) | +-{100 * r['uncertainty']:.2f} % | "
              f"{r['extrapolated']:.5g} ({100 * (r['extrapolated'] / r['reference'] - 1):+.2f} %) | {order} | "
              f"{r['reference']:.5g} ({r['reference_kind']}) | {'yes' if r['covered'] else 'NO'} |")


if __name__ == "__main__":
    main()
