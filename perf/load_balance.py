#!/usr/bin/python3
"""The dynamic load balance (Parallel/Rebalance Threshold) on a load that
moves and on a process that is slower than the others.

column: input/moving/settling_column.xml (six discs settling onto the floor
    of a tall column) on --ranks processes, held to the first division of
    the cell and divided anew whenever the slowest process's computing time
    passes --threshold times the mean. Both runs record the balance every
    --interval steps (balance_history.csv); the table gives the time a step
    and the imbalance over the run, the figure both against time.
slowed: the same scene on 2 processes, one a core (taskset), with a third
    program that only computes sharing the first process's core, as another
    user's job would (the paper's case of processors whose speed changes):
    held and balanced. The balance is by measured time, so the process on
    the shared core is given fewer particles.
shared: the same scene on 3 processes, processes 0 and 1 sharing core 0
    and process 2 alone on core 1 (this machine's two cores; the layout
    "two sharing a core beside two alone" needs four). Whether the two on
    one core show up as slower depends on whether they compute at once
    (each at half speed) or take turns (each at full speed while the other
    waits in an exchange): the balance sees only the first. (Four
    processes on two cores, two a core, are alike and show nothing.)

The runs of one comparison go one after the other on the same machine; the
figures are wall-clock times and move with the machine's other load.

    perf/load_balance.py [--case column slowed shared] [--ranks 4] [--end-time 20] [--figure PNG]
        [--threshold 1.1] [--interval 200] [--spacing DX] [--build build] [--out build/load_balance]
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys
import time

from poresph_runs import MPI_ENV, ROOT

SCENE = os.path.join(ROOT, "input", "moving", "settling_column.xml")


def run(build, directory, ranks, settings, layout):
    """One run into DIRECTORY; returns its wall seconds. layout: None (processes where the system
    puts them), "hog" (process r on core r, a busy loop on core 0) or "shared" (the last process on
    core 1, the others on core 0)."""
    program = [os.path.join(build, "poresph"), SCENE, "--output", directory, "--overwrite",
               "--set", "Run/Progress=never"]
    for s in settings:
        program += ["--set", s]
    hog = None
    if layout == "hog":
        command = ["mpiexec", "-n", str(ranks), "--bind-to", "core"] + program
        hog = subprocess.Popen(["taskset", "-c", "0", sys.executable, "-c", "while True: pass"])
    elif layout == "shared":
        last = str(ranks - 1)
        pin = f'exec taskset -c "$([ "$OMPI_COMM_WORLD_RANK" = {last} ] && echo 1 || echo 0)" "$@"'
        command = ["mpiexec", "-n", str(ranks), "--bind-to", "none", "--oversubscribe", "sh", "-c", pin, "sh"] + program
    else:
        command = ["mpiexec", "-n", str(ranks), "--bind-to", "none"] + program
    start = time.time()
    try:
        done = subprocess.run(command, env=MPI_ENV, capture_output=True, text=True)
    finally:
        if hog:
            hog.kill()
    seconds = time.time() - start
    if done.returncode != 0:
        sys.exit(f"run into {directory} failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return seconds


def history(directory):
    with open(os.path.join(directory, "balance_history.csv")) as f:
        return list(csv.DictReader(f))


LAYOUTS = {None: "", "hog": " (process 0 shares its core with a busy loop)",
           "shared": " (all but the last on core 0, the last on core 1)"}


def compare(case, build, out, ranks, settings, threshold, interval, layout):
    results = {}
    for label, extra in (("held", []), ("balanced", [f"Parallel/Rebalance Threshold={threshold}"])):
        directory = os.path.join(out, f"{case}-{label}")
        seconds = run(build, directory, ranks, settings + [f"Parallel/Rebalance Interval={interval}"] + extra, layout)
        results[label] = (seconds, history(directory))
    print(f"\n{case}: {ranks} processes{LAYOUTS[layout]}, threshold {threshold}, every {interval} steps")
    print(f"{'run':>9} {'wall s':>8} {'s/step median':>14} {'imbalance median':>17} {'max':>6} "
          f"{'divided anew':>13} {'particles min-max (last)':>25}")
    for label, (seconds, rows) in results.items():
        per_step = statistics.median(float(r["seconds_per_step"]) for r in rows)
        imbalance = [float(r["imbalance"]) for r in rows]
        divided = sum(r["rebalanced"] == "1" for r in rows)
        last = rows[-1]
        print(f"{label:>9} {seconds:8.1f} {per_step:14.3e} {statistics.median(imbalance):17.3f} "
              f"{max(imbalance):6.3f} {divided:13d} {last['particles_min'] + '-' + last['particles_max']:>25}")
    held, balanced = results["held"][0], results["balanced"][0]
    print(f"wall time balanced / held: {balanced / held:.3f}")
    return results


def plot(all_results, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: no figure")
        return
    fig, axes = plt.subplots(2, len(all_results), figsize=(5.5 * len(all_results), 6), squeeze=False)
    for column, (case, results) in enumerate(all_results.items()):
        for label, (seconds, rows) in results.items():
            t = [float(r["time"]) for r in rows]
            axes[0][column].plot(t, [1e3 * float(r["seconds_per_step"]) for r in rows], label=f"{label} ({seconds:.0f} s)")
            axes[1][column].plot(t, [float(r["imbalance"]) for r in rows], label=label)
        axes[0][column].set_title(case)
        axes[0][column].set_ylabel("wall ms a step")
        axes[1][column].set_ylabel("slowest / mean working time")
        axes[1][column].set_xlabel("simulated time (s)")
        for a in axes[:, column]:
            a.legend()
            a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", nargs="+", default=["column", "slowed"],
                        choices=["column", "slowed", "shared"])
    parser.add_argument("--ranks", type=int, default=4)
    parser.add_argument("--end-time", type=float, default=20.0)
    parser.add_argument("--slowed-end-time", type=float, default=6.0)
    parser.add_argument("--threshold", type=float, default=1.1)
    parser.add_argument("--interval", type=int, default=200)
    parser.add_argument("--spacing", type=float, default=None,
                        help="Discretization/Particle Spacing (the scene's 0.025 m if not given): a finer one "
                             "gives each step more work than the scheduler's time slice")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "load_balance"))
    parser.add_argument("--figure", default=os.path.join(ROOT, "docs", "figures", "load_balance.png"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    spacing = [] if args.spacing is None else [f"Discretization/Particle Spacing={args.spacing}"]
    all_results = {}
    if "column" in args.case:
        all_results[f"settling column, {args.ranks} processes"] = compare(
            "column", args.build, args.out, args.ranks, [f"Run/End Time={args.end_time}"] + spacing, args.threshold,
            args.interval, None)
    if "slowed" in args.case:
        all_results["2 processes, process 0 sharing its core"] = compare(
            "slowed", args.build, args.out, 2, [f"Run/End Time={args.slowed_end_time}"] + spacing, args.threshold,
            args.interval, "hog")
    if "shared" in args.case:
        all_results["3 processes, 0 and 1 sharing core 0"] = compare(
            "shared", args.build, args.out, 3, [f"Run/End Time={args.slowed_end_time}"] + spacing, args.threshold,
            args.interval, "shared")
    plot(all_results, args.figure)


if __name__ == "__main__":
    main()
