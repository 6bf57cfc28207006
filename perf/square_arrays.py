#!/usr/bin/python3
"""Square arrays of cylinders against Sangani & Acrivos (1982): every solid
fraction of METHOD.md's table at three resolutions, each run until k is
steady (input/square_array/square_array_cNN.xml).

    perf/square_arrays.py [--build build] [--out build/square-arrays] [--spacings 0.004 0.002 0.001]

Writes square_arrays.csv into --out and prints the Markdown table for
docs/validation.md: k/L^2, reference, relative error, observed order of
convergence between successive resolutions, steps and wall time.
"""
import argparse
import math
import os
import sys

from poresph_runs import ROOT, run_poresph, write_csv

DRAG = {5: 15.56, 10: 24.83, 20: 51.53, 30: 102.90, 40: 217.89, 50: 532.55, 60: 1763, 70: 13520}
L = 0.1


def run(build, fraction, dx, out):
    return run_poresph(build, f"square_array/square_array_c{fraction:02d}.xml",
                       os.path.join(out, f"c{fraction:02d}-dx{dx:g}"), [f"Discretization/Particle Spacing={dx!r}"])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "square-arrays"))
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.004, 0.002, 0.001])
    parser.add_argument("--fractions", type=int, nargs="+", default=sorted(DRAG))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    rows = []
    for fraction in args.fractions:
        for dx in args.spacings:
            s = run(args.build, fraction, dx, args.out)
            k = s["permeability"]["kxx"] / L**2
            ref = 1 / DRAG[fraction]
            rows.append(dict(solid_fraction=fraction / 100, dx_over_L=dx / L, k_over_L2=k, reference=ref,
                             relative_error=k / ref - 1, steady=s["steady"], stopped_by=s["stopped_by"],
                             simulated_time=s["simulated_time"], steps=s["steps"], wall_seconds=s["wall_seconds"],
                             particles=s["fluid_particles"] + s["boundary_particles"],
                             max_density_variation=s["max_density_variation"],
                             particles_inside_grains=s["particles_inside_grains"], reynolds=s["reynolds_number"]))
            print(f"c = {fraction / 100:.2f} dx = {dx:g}: error {100 * rows[-1]['relative_error']:+.2f} % "
                  f"({s['stopped_by']}, {s['wall_seconds']:.0f} s)", file=sys.stderr, flush=True)
            write_csv(os.path.join(args.out, "square_arrays.csv"), rows)

    print("| c | dx/L | k/L^2 SPH | k/L^2 Sangani-Acrivos | error % | order | steady | steps | wall s | max drho/rho | inside |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for fraction in args.fractions:
        sel = [r for r in rows if round(r["solid_fraction"] * 100) == fraction]
        for i, r in enumerate(sel):
            order = ""
            if i > 0 and r["relative_error"] != 0 and sel[i - 1]["relative_error"] != 0:
                ratio = abs(sel[i - 1]["relative_error"] / r["relative_error"])
                order = f"{math.log(ratio) / math.log(sel[i - 1]['dx_over_L'] / r['dx_over_L']):.2f}"
            print(f"| {r['solid_fraction']:.2f} | {r['dx_over_L']:g} | {r['k_over_L2']:.5g} | {r['reference']:.5g} | "
                  f"{100 * r['relative_error']:+.2f} | {order} | {'yes' if r['steady'] else 'no'} | {r['steps']} | "
                  f"{r['wall_seconds']:.0f} | {r['max_density_variation']:.4f} | {r['particles_inside_grains']} |")


if __name__ == "__main__":
    main()
