#!/usr/bin/python3
"""Single-core speed against the LAMMPS SPH yardstick, measured in one run
on the same machine.

    perf/single_core.py [--build build] [--baseline OTHER_BUILD ...] [--repeats 5]

Each repeat runs, back to back on one core: the LAMMPS yardstick of issue 5
(perf/lammps_yardstick.sh, 48,000 particles of 2D Poiseuille flow, which
builds LAMMPS with its SPH package once per machine), then PoreSPH on
problem I at dx = 0.0025 L (160,000 particles, Kokkos Serial) with each
build given. Interleaving puts a slow spell of the shared machine on every
program alike; the ratio is the median of the per-repeat ratios.

Prints a Markdown table: particle-steps per second (median, min-max), the
ratio to LAMMPS, and for PoreSPH the time per particle-step and per pair
interaction (a pair within the 3h support, evaluated once for both ends:
14 per particle at h = dx). Writes single_core.csv into --out.
"""
import argparse
import math
import os
import re
import statistics
import subprocess
import sys

from poresph_runs import ROOT, moving_particles, run_poresph, write_csv

SCENE = "problem1/problem1.xml"
SPACING = 0.00025


def pairs_per_particle(support_over_dx):
    """Pairs within the support per particle at the lattice's number
    density: pi R^2 / dx^2 neighbours (28 for R = 3 dx), halved because one
    evaluation serves both ends. (The lattice itself has 24 neighbours
    strictly inside 3 dx and 4 on the circle, where W' = 0.)"""
    return math.pi * support_over_dx ** 2 / 2


def lammps_rate(steps):
    """One run of the yardstick; its particle-steps per second."""
    done = subprocess.run([os.path.join(ROOT, "perf", "lammps_yardstick.sh"), "--repeats", "1", "--steps", str(steps)],
                          check=True, capture_output=True, text=True)
    match = re.search(r"median ([0-9.eE+]+) particle-steps/s", done.stdout)
    if not match:
        sys.exit("single_core: no rate in the yardstick's output:\n" + done.stdout + done.stderr)
    return float(match.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--baseline", nargs="*", default=[], help="other PoreSPH builds to time alongside")
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "single_core"))
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--steps", type=int, default=300, help="PoreSPH steps per run")
    parser.add_argument("--lammps-steps", type=int, default=1000)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    builds = [args.build] + args.baseline
    labels = ["LAMMPS SPH"] + [f"PoreSPH ({os.path.relpath(b, ROOT) if b.startswith(ROOT) else b})" for b in builds]
    rates = {label: [] for label in labels}
    pairs = None
    ratios = {label: [] for label in labels[1:]}
    # LAMMPS moves its particles: so does PoreSPH here, the same scene.
    motion = {build: moving_particles(build) for build in builds}
    for k in range(args.repeats):
        lammps = lammps_rate(args.lammps_steps)
        rates[labels[0]].append(lammps)
        for index, (label, build) in enumerate(zip(labels[1:], builds)):
            summary = run_poresph(build, SCENE, os.path.join(args.out, f"run-{k}-{index}"),
                                  [f"Discretization/Particle Spacing={SPACING!r}", f"Run/Max Steps={args.steps}",
                                   "Run/Backend=serial"] + motion[build])
            rate = summary["particle_steps_per_second"]
            pairs = pairs_per_particle(3 * summary["smoothing_length"] / SPACING)
            rates[label].append(rate)
            ratios[label].append(rate / lammps)
        print(f"repeat {k + 1}: " + ", ".join(f"{label} {rates[label][-1]:.3g}" for label in labels),
              file=sys.stderr, flush=True)

    rows = []
    for label in labels:
        median = statistics.median(rates[label])
        row = dict(program=label, particle_steps_per_second=median, min=min(rates[label]), max=max(rates[label]),
                   ratio_to_lammps=statistics.median(ratios[label]) if label in ratios else 1.0,
                   ns_per_particle_step=1e9 / median)
        row["ns_per_pair"] = row["ns_per_particle_step"] / pairs if label in ratios else float("nan")
        rows.append(row)
    write_csv(os.path.join(args.out, "single_core.csv"), rows)
    print(f"| program | particle-steps/s, median (min-max) of {args.repeats} | vs LAMMPS (median of ratios) "
          "| ns per particle-step | ns per pair |")
    print("|---|---|---|---|---|")
    for r in rows:
        pair = f"{r['ns_per_pair']:.1f}" if r["ns_per_pair"] == r["ns_per_pair"] else ""
        print(f"| {r['program']} | {r['particle_steps_per_second']:.3g} ({r['min']:.3g}-{r['max']:.3g}) "
              f"| {r['ratio_to_lammps']:.2f} | {r['ns_per_particle_step']:.0f} | {pair} |")


if __name__ == "__main__":
    main()
