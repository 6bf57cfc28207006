#!/usr/bin/python3
"""Channel-flow validation: Poiseuille and Couette start-up at 20, 40 and 80
particles across, against the series solutions.

    perf/channel_validation.py [--build build] [--out build/channel-validation]

Writes channel_validation.csv (one row per scene, resolution and sample time)
into --out, the comparison plot docs/figures/channel_profiles.png from the
40-across runs, and prints the Markdown tables for docs/validation.md.
"""
import argparse
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from poresph_runs import ROOT, run_poresph  # noqa: E402

WIDTH = 1e-3


def run(build, scene, across, out):
    dx = WIDTH / across
    return run_poresph(build, f"{scene}.xml", os.path.join(out, f"{scene}-{across}"),
                       [f"Discretization/Particle Spacing={dx!r}"])


def plot(out, figure):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, scene, title in zip(axes, ["poiseuille", "couette"], ["Poiseuille", "Couette"]):
        data = np.genfromtxt(os.path.join(out, f"{scene}-40", "profiles.csv"), delimiter=",", names=True)
        for k, t in enumerate(np.unique(data["sample_time"])):
            s = data[data["sample_time"] == t]
            order = np.argsort(s["y"])
            colour = f"C{k}"
            label = f"t = {t:g} s" if t < 0.99 else "t = 1 s (steady)"
            ax.plot(s["v_x_series"][order] * 1e6, s["y"][order] * 1e3, "-", color=colour, lw=1.2)
            # one point per lattice row: every particle of a row has the same v_x to round-off
            rows, first = np.unique(np.round(s["y"] / (WIDTH / 40)), return_index=True)
            ax.plot(s["v_x"][first] * 1e6, s["y"][first] * 1e3, "o", ms=3.5, color=colour, label=label)
        ax.set_xlabel("v_x (µm/s)")
        ax.set_ylabel("y (mm)")
        ax.set_title(f"{title} start-up, 40 particles across: SPH (points), series (lines)")
        ax.legend(fontsize=8)
        ax.title.set_fontsize(9)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "channel-validation"))
    parser.add_argument("--figure", default=os.path.join(ROOT, "docs", "figures", "channel_profiles.png"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    rows = []
    for scene in ["poiseuille", "couette"]:
        for across in [20, 40, 80]:
            summary = run(args.build, scene, across, args.out)
            for s in summary["profile_samples"]:
                rows.append(dict(scene=scene, across=across, sample_time=s["sample_time"], error=s["error"],
                                 steps=summary["steps"], particles=summary["fluid_particles"] + summary["boundary_particles"],
                                 wall_seconds=summary["wall_seconds"],
                                 max_density_variation=summary["max_density_variation"]))
            print(f"{scene} {across}: profile_error {summary['profile_error']:.2e} in {summary['wall_seconds']:.1f} s",
                  file=sys.stderr)
    with open(os.path.join(args.out, "channel_validation.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(args.out, args.figure)

    times = sorted({r["sample_time"] for r in rows})
    for scene in ["poiseuille", "couette"]:
        print(f"\n{scene}: max |v_x - series| / v_max (%)\n")
        print("| across | " + " | ".join(f"t = {t:g} s" for t in times) + " | steps | particles | wall s |")
        print("|---" * (len(times) + 4) + "|")
        for across in [20, 40, 80]:
            sel = [r for r in rows if r["scene"] == scene and r["across"] == across]
            errors = {r["sample_time"]: r["error"] for r in sel}
            print(f"| {across} | " + " | ".join(f"{100 * errors[t]:.3f}" for t in times) +
                  f" | {sel[0]['steps']} | {sel[0]['particles']} | {sel[0]['wall_seconds']:.1f} |")


if __name__ == "__main__":
    main()
