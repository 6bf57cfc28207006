#!/usr/bin/python3
"""Layered two-phase Poiseuille flow (input/two_phase/layered_poiseuille.xml):
phase 0 below y = L/2, phase 1 above it at viscosity ratios 0.1, 1 and 10,
at 20, 40 and 80 particles across, against the piecewise-parabolic solution
(src/diagnostics/LayeredChannel.hpp, the same formulas), solved for the
steady state.

    perf/layered_channel.py [--build build] [--out build/layered-channel] [--set "Solver/Method=explicit" ...]

Prints the Markdown table of docs/validation.md: per ratio and resolution
the largest |v_x - u| / u_max over the fluid particles, each phase's k_r
from summary.json against its closed form, and the run's wall time.
"""
import argparse
import csv
import os

from poresph_runs import run_poresph  # noqa: E402

H, NU, RHO, F = 1e-3, 1e-6, 1000.0, 2e-4


def layered(mu_lower, mu_upper, a=H / 2, G=RHO * F):
    """u(y), the zero-stress point y0 and both layers' closed-form k_r."""
    y0 = (a * a / mu_lower + (H * H - a * a) / mu_upper) / (2 * (a / mu_lower + (H - a) / mu_upper))

    def u(y):
        if y < a:
            return G * (y0 * y - y * y / 2) / mu_lower
        return G * (y0 * (y - H) - (y * y - H * H) / 2) / mu_upper
    b = H - a
    kr = (12 * (y0 * a * a / 2 - a ** 3 / 6) / H ** 3, 12 * ((H - y0) * b * b / 2 - b ** 3 / 6) / H ** 3)
    return u, y0, kr


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="build/layered-channel")
    parser.add_argument("--set", action="append", default=[], help="more --set settings for every run")
    args = parser.parse_args()
    print("| nu_1/nu_0 | across | max abs(v_x - u)/u_max (%) | k_r,0 (closed form) | k_r,1 (closed form) | wall s |")
    print("|---|---|---|---|---|---|")
    for ratio in (0.1, 1.0, 10.0):
        u, y0, kr = layered(RHO * NU, RHO * NU * ratio)
        peak = u(y0)
        for across in (20, 40, 80):
            directory = os.path.join(args.out, f"ratio{ratio:g}-{across}")
            summary = run_poresph(args.build, "two_phase/layered_poiseuille.xml", directory,
                                  [f"Phases/Phase 1/Kinematic Viscosity={NU * ratio!r}",
                                   f"Discretization/Particle Spacing={H / across!r}"] + args.set)
            worst = 0.0
            with open(os.path.join(directory, "particles.csv")) as rows:
                for row in csv.DictReader(rows):
                    if int(row["kind"]) == 0:
                        worst = max(worst, abs(float(row["vx"]) - u(float(row["y"]))) / peak)
            phases = summary["phases"]
            seconds = summary["wall_seconds"] + summary["setup_seconds"]
            print(f"| {ratio:g} | {across} | {100 * worst:.3f} | "
                  f"{phases[0]['relative_permeability']:.4f} ({kr[0]:.4f}) | "
                  f"{phases[1]['relative_permeability']:.4f} ({kr[1]:.4f}) | {seconds:.2f} |")


if __name__ == "__main__":
    main()
