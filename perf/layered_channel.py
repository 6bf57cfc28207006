#!/usr/bin/python3
"""Layered two-phase Poiseuille flow (input/two_phase/layered_poiseuille.xml):
phase 0 below y = L/2, phase 1 above it at viscosity ratios 0.1, 1 and 10,
at 20, 40 and 80 particles across, against the piecewise-parabolic solution
(src/diagnostics/LayeredChannel.hpp, the same formulas), solved for the
steady state; with --driven 0 or 1 the force on that layer alone (the
other dragged along across the interface).

    perf/layered_channel.py [--build build] [--out build/layered-channel] [--driven both|0|1]
                            [--set "Solver/Method=explicit" ...]

Prints the Markdown table of docs/validation.md: per ratio and resolution
the largest |v_x - u| / u_max over the fluid particles, each phase's k_r
from summary.json against its closed form, and the run's wall time.
"""
import argparse
import csv
import os

from poresph_runs import run_poresph  # noqa: E402

H, NU, RHO, F = 1e-3, 1e-6, 1000.0, 2e-4


def layered(mu_lower, mu_upper, shares=(1.0, 1.0), a=H / 2, G=RHO * F):
    """u(y), the profile's peak speed and both layers' closed-form k_r, the
    force G on the layers in the given shares (Phases/Driven Phase)."""
    GA, GB, b = shares[0] * G, shares[1] * G, H - a
    CA = (GA * a * a / (2 * mu_lower) + (GB * (H * H - a * a) / 2 - (GB - GA) * a * b) / mu_upper) / \
        (a / mu_lower + b / mu_upper)
    CB = CA + (GB - GA) * a

    def u(y):
        if y < a:
            return (CA * y - GA * y * y / 2) / mu_lower
        return (CB * (y - H) - GB * (y * y - H * H) / 2) / mu_upper
    candidates = [a] + ([CA / GA] if GA and 0 < CA / GA < a else []) + ([CB / GB] if GB and a <= CB / GB < H else [])
    peak = max(abs(u(y)) for y in candidates)
    flux = ((CA * a * a / 2 - GA * a ** 3 / 6) / mu_lower, ((GB * H - CB) * b * b / 2 - GB * b ** 3 / 6) / mu_upper)
    kr = (12 * flux[0] * mu_lower / (G * H ** 3), 12 * flux[1] * mu_upper / (G * H ** 3))
    return u, peak, kr


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="build/layered-channel")
    parser.add_argument("--set", action="append", default=[], help="more --set settings for every run")
    parser.add_argument("--force", type=float, default=F,
                        help="Fluid/Body Force along x (m/s^2); smaller keeps Re low at ratios well below 1")
    parser.add_argument("--ratios", type=float, nargs="+", default=[0.1, 1.0, 10.0], help="nu_1 / nu_0")
    parser.add_argument("--across", type=int, nargs="+", default=[20, 40, 80], help="particles across the channel")
    parser.add_argument("--driven", default="both", choices=("both", "0", "1"),
                        help="Phases/Driven Phase: the force on both layers, or on the lower (0) or upper (1) alone")
    args = parser.parse_args()
    shares = (0.0 if args.driven == "1" else 1.0, 0.0 if args.driven == "0" else 1.0)
    print("| nu_1/nu_0 | across | max abs(v_x - u)/u_max (%) | k_r,0 (closed form) | k_r,1 (closed form) | wall s |")
    print("|---|---|---|---|---|---|")
    for ratio in args.ratios:
        u, peak, kr = layered(RHO * NU, RHO * NU * ratio, shares, G=RHO * args.force)
        for across in args.across:
            directory = os.path.join(args.out, f"ratio{ratio:g}-{across}-driven-{args.driven}")
            summary = run_poresph(args.build, "two_phase/layered_poiseuille.xml", directory,
                                  [f"Phases/Phase 1/Kinematic Viscosity={NU * ratio!r}",
                                   f"Discretization/Particle Spacing={H / across!r}",
                                   f"Phases/Driven Phase={args.driven}",
                                   f"Fluid/Body Force={{{args.force!r}, 0.0}}"] + args.set)
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
