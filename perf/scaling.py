#!/usr/bin/python3
"""Strong and weak scaling over MPI ranks, as in Morris, Zhu & Fox (1999).

    perf/scaling.py strong [--problems 1 2 3 3d] [--spacings 0.001 0.0005 0.00025] [--spacings-3d 0.005 0.0025]
                           [--ranks 1 2 4] [--steps 100] [--repeats 3]
    perf/scaling.py weak   [--spacing 0.0005] [--ranks 1 2 4] [--steps 100] [--repeats 3]

Strong: a fixed problem (the paper's problems I-III at its three
resolutions, and with `3d` the simple cubic array of spheres of
input/3d at 20 and 40 particles per side) on 1..N ranks. Weak: problem I with the cell stretched along x
so that every rank holds the same number of particles. Each point is the
median of --repeats runs of --steps steps (time loop only, from
summary.json), repeats interleaved across configurations. Writes scaling_strong.csv / scaling_weak.csv into --out and
PNG plots of T per step and of the normalised time T* = T Nproc / (T0 Npart)
(T0: time per particle per step of the largest problem-I run on one rank;
constant T* = perfect scaling) into docs/figures. Runs with more ranks than
cores are marked oversubscribed.
"""
import argparse
import csv
import os
import statistics
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from poresph_runs import CORES, ROOT, moving_particles, run_poresph  # noqa: E402

SCENES = {"1": "problem1/problem1.xml", "2": "problem2/problem2.xml", "3": "problem3/problem3.xml",
          "3d": "3d/simple_cubic.xml"}
def run(build, out, scene, ranks, steps, settings):
    directory = os.path.join(out, "runs", f"{os.path.basename(scene)}-{ranks}-{'-'.join(settings)}".replace("/", "_"))
    # Moving particles, as in the figures of docs/performance.md (and as LAMMPS moves them).
    return run_poresph(build, scene, directory, [f"Run/Max Steps={steps}", "Permeability/Steady Tolerance=0", *settings,
                                                 *moving_particles(build)], ranks=ranks)


def measure_all(args, configs):
    """configs: (key, scene, ranks, settings). Repeats are interleaved (every
    configuration once, then again), so that a slow or quiet spell of the
    shared machine does not fall on one configuration only."""
    times = {c[0]: [] for c in configs}
    summaries = {}
    for _ in range(args.repeats):
        for key, scene, ranks, settings in configs:
            summary = run(args.build, args.out, scene, ranks, args.steps, settings)
            times[key].append(summary["wall_seconds"] / summary["steps"])
            summaries[key] = summary
    rows = {}
    for key, scene, ranks, settings in configs:
        s = summaries[key]
        rows[key] = dict(ranks=ranks, particles=s["fluid_particles"] + s["boundary_particles"],
                         seconds_per_step=statistics.median(times[key]), min_seconds_per_step=min(times[key]),
                         max_seconds_per_step=max(times[key]), oversubscribed=ranks > CORES)
    return rows


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def plot(rows, key, label, figure, title):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for name in sorted({r[key] for r in rows}):
        sel = sorted((r for r in rows if r[key] == name), key=lambda r: r["ranks"])
        n = [r["ranks"] for r in sel]
        axes[0].plot(n, [r["seconds_per_step"] for r in sel], "o-", label=f"{label} {name}")
        axes[1].plot(n, [r["t_star"] for r in sel], "o-", label=f"{label} {name}")
        for r in sel:
            if r["oversubscribed"]:
                for ax, y in ((axes[0], r["seconds_per_step"]), (axes[1], r["t_star"])):
                    ax.plot(r["ranks"], y, "x", color="k", ms=9)
    axes[0].set_yscale("log")
    axes[0].set_ylabel("T, seconds per step")
    axes[1].set_ylabel("T* = T Nproc / (T0 Npart)")
    for ax in axes:
        ax.set_xlabel(f"MPI ranks (x: more ranks than the {CORES} cores)")
        ax.set_xticks(sorted({r["ranks"] for r in rows}))
        ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["strong", "weak"])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "scaling"))
    parser.add_argument("--problems", nargs="+", choices=sorted(SCENES), default=["1", "2", "3"])
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.001, 0.0005, 0.00025])
    parser.add_argument("--spacings-3d", type=float, nargs="+", default=[0.005, 0.0025])
    parser.add_argument("--spacing", type=float, default=0.0005)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    if args.mode == "strong":
        configs = [((problem, dx, ranks), SCENES[problem], ranks, [f"Discretization/Particle Spacing={dx!r}"])
                   for problem in args.problems
                   for dx in (args.spacings_3d if problem == "3d" else args.spacings) for ranks in args.ranks]
        measured = measure_all(args, configs)
        for (problem, dx, ranks), *_ in configs:
            row = measured[(problem, dx, ranks)]
            row.update(problem=problem, dx_over_L=dx / 0.1, series=f"{problem} dx={dx / 0.1:g}L")
            rows.append(row)
            print(f"problem {problem} dx {dx:g} ranks {ranks}: {row['seconds_per_step'] * 1e3:.2f} ms/step "
                  f"({row['particles']} particles)", file=sys.stderr, flush=True)
        base = [r for r in rows if r["problem"] == min(args.problems) and r["ranks"] == 1]
        largest = max(base, key=lambda r: r["particles"])
    else:
        configs = [(ranks, SCENES["1"], ranks, [f"Discretization/Particle Spacing={args.spacing!r}",
                                               f"Domain/Cell Size={{{0.1 * ranks!r}, 0.1}}"]) for ranks in args.ranks]
        measured = measure_all(args, configs)
        for ranks in args.ranks:
            row = measured[ranks]
            row.update(series=f"problem I, {row['particles'] // ranks} particles per rank")
            rows.append(row)
            print(f"weak ranks {ranks}: {row['seconds_per_step'] * 1e3:.2f} ms/step", file=sys.stderr, flush=True)
        largest = rows[0]
    t0 = largest["seconds_per_step"] / largest["particles"]
    for r in rows:
        r["t_star"] = r["seconds_per_step"] * r["ranks"] / (t0 * r["particles"])
    write_csv(rows, os.path.join(args.out, f"scaling_{args.mode}.csv"))
    plot(rows, "series", "problem" if args.mode == "strong" else "", os.path.join(ROOT, "docs", "figures", f"scaling_{args.mode}.png"),
         f"{args.mode} scaling, median of {args.repeats} runs of {args.steps} steps, Kokkos Serial, one thread per rank")
    print("| series | ranks | particles | ms per step (median, min-max) | speed-up | T* | oversubscribed |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        one = [q for q in rows if q["series"] == r["series"] and q["ranks"] == 1]
        speedup = one[0]["seconds_per_step"] / r["seconds_per_step"] if one and args.mode == "strong" else float("nan")
        print(f"| {r['series']} | {r['ranks']} | {r['particles']} | {r['seconds_per_step'] * 1e3:.2f} "
              f"({r['min_seconds_per_step'] * 1e3:.2f}-{r['max_seconds_per_step'] * 1e3:.2f}) | {speedup:.2f} | "
              f"{r['t_star']:.2f} | {'yes' if r['oversubscribed'] else ''} |")


if __name__ == "__main__":
    main()
