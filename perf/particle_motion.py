#!/usr/bin/python3
"""Fixed against moving particles (issue 14): the same scenes with
PoreSPH's default (fixed particles, wall pressure from the fluid, exact
wall drag), with moving (Lagrangian) particles as in the paper plus
particle shifting, and optionally with an earlier PoreSPH binary (its own
defaults of that time), each run until it stops by itself at a steady k.
Then the time per step of each, in short runs interleaved R times on one
core (medians), on problem III at dx = 0.005 L.

    perf/particle_motion.py [--build build] [--baseline DIR_WITH_OLD_poresph] [--out build/particle-motion]
        [--repeats 5] [--timing-steps 400] [--skip-steady]

The baseline is a poresph built from an earlier commit (the one of
docs/method.md's tables is 57d5985, whose particles move: `git worktree
add /tmp/base 57d5985`, then configure and build there as
docs/building.md says); it is given the settings its scenes had then
(Particle Shifting 4, Steady Tolerance 3e-3), which the scene files do
not carry. Prints two Markdown tables for docs/method.md and
writes particle_motion.csv into --out.
"""
import argparse
import os
import statistics
import sys

from poresph_runs import ROOT, run_poresph, write_csv

L = 0.1
# (name, scene, settings, reference k/L^2, what the reference is)
SCENES = [
    ("lattice of cylinders, Re 2.2 (PySPH's case)", "square_array/square_array_c20.xml",
     ["Grains/Inline={0.05, 0.05, 0.02}", "Fluid/Body Force={1.5e-7, 0.0}"], 0.032669, "Navier-Stokes FE"),
    ("square array c = 0.2, Re 1 (hard/high_force)", "hard/high_force.xml", [], 0.019394, "Navier-Stokes FE"),
    ("square array c = 0.2, dx = 0.01 L", "square_array/square_array_c20.xml", [], 1 / 51.53, "Sangani-Acrivos"),
    ("square array c = 0.5, dx = 0.01 L", "square_array/square_array_c50.xml", [], 1 / 532.55, "Sangani-Acrivos"),
    ("problem III, dx = 0.01 L", "problem3/problem3.xml", [], 9.638e-4, "Stokes FE"),
]
MOVING = ["Discretization/Particle Motion=lagrangian", "Discretization/Particle Shifting=4",
          "Discretization/Wall Pressure=continuity"]
BASELINE = ["Discretization/Particle Shifting=4", "Permeability/Steady Tolerance=3e-3"]


def variants(args):
    """(label, build directory, settings) of each way of running a scene."""
    out = [("fixed (default)", args.build, []),
           ("moving, shifting A = 4, wall by continuity", args.build, MOVING)]
    if args.baseline:
        out.append(("baseline binary (moving, shifting A = 4)", args.baseline, BASELINE))
    return out


def steady_runs(args):
    rows = []
    for name, scene, settings, reference, what in SCENES:
        for label, build, extra in variants(args):
            tag = f"{len(rows):02d}"
            s = run_poresph(build, scene, os.path.join(args.out, f"steady-{tag}"), settings + extra,
                            allow_failure=True)
            k = s["permeability"]["kxx"] / L**2 if "permeability" in s else float("nan")
            rows.append(dict(scene=name, variant=label, k_over_L2=k, reference=reference, reference_kind=what,
                             relative_error=k / reference - 1, stopped_by=s["stopped_by"],
                             simulated_time=s["simulated_time"], steps=s["steps"], wall_seconds=s["wall_seconds"],
                             corrections=s.get("grain_surface_corrections", 0),
                             remaining=s.get("steady_remaining_change", "")))
            print(f"{name} / {label}: {100 * rows[-1]['relative_error']:+.2f} % in {s['steps']} steps, "
                  f"{s['wall_seconds']:.0f} s ({s['stopped_by']})", file=sys.stderr, flush=True)
            write_csv(os.path.join(args.out, "particle_motion.csv"), rows)
    return rows


def timing_runs(args):
    """Median ns per particle-step of each variant, runs interleaved."""
    times = {label: [] for label, _, _ in variants(args)}
    for repeat in range(args.repeats):
        for label, build, extra in variants(args):
            s = run_poresph(build, "problem3/problem3.xml", os.path.join(args.out, "timing"),
                            ["Discretization/Particle Spacing=0.0005", f"Run/Max Steps={args.timing_steps}",
                             "Permeability/Steady Tolerance=0"] + extra)
            times[label].append(1e9 / s["particle_steps_per_second"])
            print(f"timing {repeat + 1}/{args.repeats} {label}: {times[label][-1]:.0f} ns per particle-step",
                  file=sys.stderr, flush=True)
    return {label: statistics.median(t) for label, t in times.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--baseline", help="directory holding an earlier poresph binary")
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "particle-motion"))
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--timing-steps", type=int, default=400)
    parser.add_argument("--skip-steady", action="store_true", help="only the timing runs")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    if not args.skip_steady:
        rows = steady_runs(args)
        print("| scene | variant | k/L^2 | reference | error % | stopped by | t (s) | steps | wall s | put back on a grain |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['scene']} | {r['variant']} | {r['k_over_L2']:.5g} | {r['reference']:.5g} ({r['reference_kind']}) "
                  f"| {100 * r['relative_error']:+.2f} | {r['stopped_by']} | {r['simulated_time']:.0f} | {r['steps']} "
                  f"| {r['wall_seconds']:.0f} | {r['corrections']} |")
        print()
    medians = timing_runs(args)
    first = next(iter(medians.values()))
    print("| variant | ns per particle-step (median) | relative to the default |")
    print("|---|---|---|")
    for label, t in medians.items():
        print(f"| {label} | {t:.0f} | {t / first:.2f} |")


if __name__ == "__main__":
    main()
