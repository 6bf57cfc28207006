#!/usr/bin/python3
"""Laplace's law (input/two_phase/laplace_drop.xml): a drop of radius
R = 2e-4 m at rest in a periodic cell four radii wide, at R = 10, 20 and 40
particle spacings, with each colour function of the surface tension
(Phases/Colour), solved for the steady state; in 2D (a disc, jump sigma/R)
or with --dim 3 (a sphere, jump 2 sigma/R).

    taskset -c 1 perf/laplace_drop.py [--build build] [--out build/laplace-drop] [--dim 3] [--radii 10 20]
                                      [--colours "volume fraction"] [--set "Solver/Method=explicit" ...]

Prints the Markdown table of docs/validation.md: per radius and colour the
pressure jump's error against Laplace's law, the largest speed left as
max |v| mu / sigma, whether each phase's mass is its particles' count times
rho0 dx^Dim, and the run's set-up and solve times.
"""
import argparse
import os

from poresph_runs import run_poresph  # noqa: E402

R, RHO = 2e-4, 1000.0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="build/laplace-drop")
    parser.add_argument("--dim", type=int, default=2, choices=(2, 3))
    parser.add_argument("--radii", type=int, nargs="+", default=[10, 20, 40], help="R in particle spacings")
    parser.add_argument("--colours", nargs="+", default=["volume fraction", "phase"])
    parser.add_argument("--set", action="append", default=[], help="more --set settings for every run")
    args = parser.parse_args()
    print("| Dim | R / dx | colour | jump / Laplace - 1 (%) | max abs(v) mu / sigma | masses exact | set-up s | solve s |")
    print("|---|---|---|---|---|---|---|---|")
    side = 4 * R
    for spacings in args.radii:
        dx = R / spacings
        for colour in args.colours:
            settings = [f"Discretization/Particle Spacing={dx!r}", f"Phases/Colour={colour}"]
            if args.dim == 3:
                settings += [f"Domain/Cell Size={{{side!r}, {side!r}, {side!r}}}",
                             f"Phases/Phase 1/Region Centre={{{side / 2!r}, {side / 2!r}, {side / 2!r}}}"]
            directory = os.path.join(args.out, f"{args.dim}d-R{spacings}-{colour.replace(' ', '-')}")
            summary = run_poresph(args.build, "two_phase/laplace_drop.xml", directory, settings + args.set)
            c = summary["capillary"]
            # Fixed particles keep their phase and mass: each phase's mass is
            # a whole number of particles of mass rho0 dx^Dim (to the round-off
            # of summing them, 1e-10 of the count), and all of them are the
            # lattice's.
            particle = RHO * dx ** args.dim
            counts = [p["mass"] / particle for p in summary["phases"]]
            exact = all(abs(n - round(n)) < 1e-10 * n for n in counts) and \
                round(sum(counts)) == round((side / dx) ** args.dim)
            print(f"| {args.dim} | {spacings} | {colour} | {100 * (c['pressure_jump'] / c['laplace_pressure'] - 1):+.2f} | "
                  f"{c['capillary_number']:.2e} | {'yes' if exact else 'NO'} | {summary['setup_seconds']:.2f} | "
                  f"{summary['wall_seconds']:.2f} |", flush=True)


if __name__ == "__main__":
    main()
