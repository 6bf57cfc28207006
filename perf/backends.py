#!/usr/bin/python3
"""Backend comparison: problems I and III at dx = 0.005 and 0.0025 of the
cell side on Kokkos Serial, OpenMP with 1 and 2 threads, and MPI with 2
ranks x 1 thread, each repeated; and, as the ceiling any parallel run can
reach on the machine, an independent Serial run on every core at once.

    perf/backends.py [--build build-openmp] [--steps 100] [--repeats 5]

Needs a build with an OpenMP Kokkos (scripts/build-trilinos-openmp.sh,
cmake --preset openmp). Writes backends.csv into --out and the bar chart
docs/figures/backends.png of particle-steps per second per core (median,
with the min-max range as error bars), and prints the Markdown table.
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from poresph_runs import CORES, ROOT, moving_particles, openmp_env, poresph_command, read_summary, run_poresph  # noqa: E402

CEILING = "2 Serial runs at once (ceiling)"
CONFIGS = [  # label, ranks, backend, threads
    ("Serial", 1, "serial", 1),
    ("OpenMP 1 thread", 1, "openmp", 1),
    ("OpenMP 2 threads", 1, "openmp", 2),
    ("MPI 2 ranks x 1 thread", 2, "serial", 1),
    (CEILING, 0, "serial", 1),  # one independent run per core
]
SCENES = {"I": "problem1/problem1.xml", "III": "problem3/problem3.xml"}


def settings(args, dx, backend, threads):
    # Moving particles, as in the figures of docs/performance.md.
    return [f"Discretization/Particle Spacing={dx!r}", f"Run/Max Steps={args.steps}",
            "Permeability/Steady Tolerance=0", f"Run/Backend={backend}", f"Run/Threads={threads}"] + \
        moving_particles(args.build)


def run(args, scene, dx, ranks, backend, threads, k):
    """One run; its particle-steps per second per core and its summary."""
    out = os.path.join(args.out, "runs", f"{os.path.basename(scene)}-{dx}-{ranks}-{backend}-{threads}-{k}")
    s = run_poresph(args.build, scene, out, settings(args, dx, backend, threads), ranks=ranks, threads=threads)
    return s["particle_steps_per_second"] / (ranks * threads), s


def run_one_per_core(args, scene, dx, k):
    """What the cores can give together: an independent Serial run on each
    core at once. No parallelisation can beat their summed rate, since the
    cores share what a run leans on (caches, memory, the host's core).
    Returns the mean rate per core and one summary."""
    outs = [os.path.join(args.out, "runs", f"{os.path.basename(scene)}-{dx}-ceiling-{core}-{k}") for core in range(CORES)]
    runs = [subprocess.Popen(["taskset", "-c", str(core)] + poresph_command(args.build, scene, out,
                                                                         settings(args, dx, "serial", 1)),
                             stdout=subprocess.DEVNULL, env=openmp_env(None, 1))
            for core, out in enumerate(outs)]
    for r in runs:
        if r.wait() != 0:
            raise subprocess.CalledProcessError(r.returncode, r.args)
    summaries = [read_summary(out) for out in outs]
    return statistics.mean(s["particle_steps_per_second"] for s in summaries), summaries[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build-openmp"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build-openmp", "backends"))
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--problems", nargs="+", default=list(SCENES), choices=list(SCENES))
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.0005, 0.00025])
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for problem, scene in ((p, SCENES[p]) for p in args.problems):
        for dx in args.spacings:
            # Repeats interleave the configurations, so that a slow spell of the
            # shared machine does not fall on one configuration only.
            samples = {c[0]: [] for c in CONFIGS}
            backend_seen = {}
            for k in range(args.repeats):
                for label, ranks, backend, threads in CONFIGS:
                    if label == CEILING:
                        per_core, s = run_one_per_core(args, scene, dx, k)
                    else:
                        per_core, s = run(args, scene, dx, ranks, backend, threads, k)
                    samples[label].append(per_core)
                    backend_seen[label] = (s["backend"], s["threads"], s["ranks"],
                                           s["fluid_particles"] + s["boundary_particles"])
            for label, ranks, backend, threads in CONFIGS:
                values = samples[label]
                cores = CORES if label == CEILING else ranks * threads
                rows.append(dict(problem=problem, dx_over_L=dx / 0.1, configuration=label, cores=cores,
                                 particles=backend_seen[label][3],
                                 per_core_median=statistics.median(values), per_core_min=min(values),
                                 per_core_max=max(values), backend=backend_seen[label][0]))
                print(f"problem {problem} dx {dx / 0.1:g}L {label}: {statistics.median(values):.3g} per core",
                      file=sys.stderr, flush=True)
    with open(os.path.join(args.out, "backends.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    groups = sorted({(r["problem"], r["dx_over_L"]) for r in rows}, key=lambda g: (g[0], -g[1]))
    fig, ax = plt.subplots(figsize=(10, 4.5))
    width = 0.8 / len(CONFIGS)
    for i, (label, *_rest) in enumerate(CONFIGS):
        sel = [next(r for r in rows if (r["problem"], r["dx_over_L"]) == g and r["configuration"] == label) for g in groups]
        x = [j + i * width for j in range(len(groups))]
        med = [r["per_core_median"] for r in sel]
        err = [[m - r["per_core_min"] for m, r in zip(med, sel)], [r["per_core_max"] - m for m, r in zip(med, sel)]]
        ax.bar(x, med, width, yerr=err, capsize=3, label=label)
    ax.set_xticks([j + 0.4 - width / 2 for j in range(len(groups))])
    ax.set_xticklabels([f"problem {p}, dx = {d:g} L" for p, d in groups])
    ax.set_ylabel("particle-steps per second per core")
    ax.set_title(f"median of {args.repeats} runs of {args.steps} steps (bars: min-max)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "figures", "backends.png"), dpi=120)

    print("| problem | dx/L | configuration | cores | particle-steps/s per core (median, min-max) | vs Serial (whole run) |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        serial = next(q for q in rows if q["problem"] == r["problem"] and q["dx_over_L"] == r["dx_over_L"]
                      and q["configuration"] == "Serial")
        speedup = r["per_core_median"] * r["cores"] / serial["per_core_median"]
        print(f"| {r['problem']} | {r['dx_over_L']:g} | {r['configuration']} | {r['cores']} | "
              f"{r['per_core_median']:.3g} ({r['per_core_min']:.3g}-{r['per_core_max']:.3g}) | {speedup:.2f} |")


if __name__ == "__main__":
    main()
