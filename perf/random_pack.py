#!/usr/bin/python3
"""The random sphere pack of input/3d/random_pack.xml (issue 15): its full
permeability tensor (x, y and z driven in turn, each to a steady k), how
symmetric it is, the wall time, and a Kozeny-Carman estimate beside it for
context, k_KC = eps^3 d^2 / (180 (1 - eps)^2) with eps the porosity the run
measured and d the Sauter mean diameter of the spheres it used
(sum d^3 / sum d^2, from grains_used.txt).

    perf/random_pack.py [--build build] [--out build/random-pack] [--ranks 2] [--set "Sublist/Name=value" ...]

Prints a Markdown table for docs/validation.md and writes random_pack.csv
into --out.
"""
import argparse
import os
import sys

from poresph_runs import ROOT, run_poresph, write_csv


def sauter_diameter(grains_file):
    """sum d^3 / sum d^2 over the spheres of a grain file (cx cy cz r per
    line), and how many spheres there are."""
    cubes = squares = 0.0
    spheres = 0
    with open(grains_file) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            d = 2 * float(line.replace(",", " ").split()[3])
            cubes += d**3
            squares += d**2
            spheres += 1
    return cubes / squares, spheres


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "random-pack"))
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--set", action="append", default=[], help="extra settings, as poresph's --set")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    directory = os.path.join(args.out, "run")
    summary = run_poresph(args.build, "3d/random_pack.xml", directory, args.set, ranks=args.ranks)

    k = summary["permeability"]
    axes = "xyz"
    tensor = [[k[f"k{axes[i]}{axes[j]}"] for j in range(3)] for i in range(3)]
    diagonal = sum(tensor[i][i] for i in range(3)) / 3
    asymmetry = max(abs(tensor[i][j] - tensor[j][i]) for i in range(3) for j in range(3)) / diagonal
    eps = summary["porosity"]
    d, spheres = sauter_diameter(os.path.join(directory, "grains_used.txt"))
    kozeny_carman = eps**3 * d**2 / (180 * (1 - eps) ** 2)
    row = dict(spheres=spheres, porosity=eps, sauter_diameter=d, kxx=tensor[0][0], kyy=tensor[1][1],
               kzz=tensor[2][2], kxy=tensor[0][1], kyx=tensor[1][0], kxz=tensor[0][2], kzx=tensor[2][0],
               kyz=tensor[1][2], kzy=tensor[2][1], asymmetry=asymmetry, kozeny_carman=kozeny_carman,
               steady=summary["steady"], steps=summary["steps"], wall_seconds=summary["wall_seconds"],
               setup_seconds=summary.get("setup_seconds"), ranks=summary["ranks"],
               particles=summary["fluid_particles"] + summary["boundary_particles"],
               reynolds=summary.get("reynolds_number"), warnings=" | ".join(summary.get("warnings", [])))
    write_csv(os.path.join(args.out, "random_pack.csv"), [row])

    print(f"{spheres} spheres, porosity {eps:.4f}, Sauter diameter {d:.5g} m ({d / 0.0025:.1f} spacings at "
          f"0.0025 m), {row['particles']} particles, {summary['ranks']} ranks", file=sys.stderr)
    print("| | x | y | z |")
    print("|---|---|---|---|")
    for i in range(3):
        print(f"| k{axes[i]}. (m^2) | " + " | ".join(f"{tensor[i][j]:.4e}" for j in range(3)) + " |")
    print()
    print(f"| spheres | porosity | mean diagonal k (m^2) | largest asymmetry / mean diagonal | Kozeny-Carman (m^2) | "
          f"SPH / KC | steps | wall s | ranks |")
    print("|---|---|---|---|---|---|---|---|---|")
    print(f"| {spheres} | {eps:.4f} | {diagonal:.4e} | {asymmetry:.2e} | {kozeny_carman:.4e} | "
          f"{diagonal / kozeny_carman:.2f} | {summary['steps']} | {summary['wall_seconds']:.0f} | {summary['ranks']} |")


if __name__ == "__main__":
    main()
