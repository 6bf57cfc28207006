#!/usr/bin/env python3
"""What a second fluid costs a march: one scene with one fluid and with two
(phase 1 placed by drainage, its own viscosity), interleaved on one core,
a fixed number of steps each. With --interface moving the two fluids'
interface moves (Phases/Interface = moving: the phase field, with surface
tension and wetting at 60 degrees).

    perf/two_phase_cost.py [--scene input/problem3/problem3.xml] [--interface fixed|moving] \\
        [--set "Discretization/Particle Spacing=0.0005"] [--steps 2000] [--repeats 3] [--out DIR]

Runs one fluid, two fluids, one fluid, ... (--repeats each; taskset -c
CORE, Run/Backend = serial, Solver/Method = explicit) and prints per case
the median time per particle-step of the time loop (summary.json's
particle_steps_per_second) and the median of the per-pair ratios two / one.
"""
import argparse
import json
import os
import statistics
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TWO_FLUIDS = ["Phases/Count=2", "Phases/Phase 1/Kinematic Viscosity=2e-6", "Phases/Phase 1/Drainage/Saturation=0.75"]
MOVING = ["Phases/Interface=moving", "Phases/Surface Tension=1e-6", "Phases/Contact Angle=60"]


def run(build, scene, sets, directory, core):
    cmd = ["taskset", "-c", str(core), os.path.join(build, "poresph"), scene, "--output", directory, "--overwrite",
           "--set", "Run/Backend=serial", "--set", "Solver/Method=explicit", "--set", "Run/Progress=never"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--scene", default=os.path.join(ROOT, "input", "problem3", "problem3.xml"))
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--core", type=int, default=1)
    parser.add_argument("--out", default="/tmp/two-phase-cost")
    parser.add_argument("--interface", choices=("fixed", "moving"), default="fixed")
    args = parser.parse_args()
    two_fluids = TWO_FLUIDS + (MOVING if args.interface == "moving" else [])
    common = args.set + [f"Run/Max Steps={args.steps}", "Permeability/Steady Tolerance=0"]
    seconds = {"one": [], "two": []}
    for r in range(args.repeats):
        for case, extra in (("one", []), ("two", two_fluids)):
            s = run(args.build, args.scene, common + extra, os.path.join(args.out, f"{case}-{r}"), args.core)
            seconds[case].append(1.0 / s["particle_steps_per_second"])
    ratios = [t / o for o, t in zip(seconds["one"], seconds["two"])]
    for case in ("one", "two"):
        print(f"{case} fluid(s): median {1e9 * statistics.median(seconds[case]):.1f} ns a particle-step "
              f"({', '.join(f'{1e9 * t:.1f}' for t in seconds[case])})")
    print(f"two / one: median of the pairs' ratios {statistics.median(ratios):.3f} "
          f"({', '.join(f'{x:.3f}' for x in ratios)})")


if __name__ == "__main__":
    main()
