#!/usr/bin/python3
"""Growth: wall time to a steady k against the particle count, the steady
solve (Solver/Method = steady, its defaults) beside the march
(Permeability/Steady Tolerance = 1e-4), one process, Kokkos Serial, on two
series: problem III at dx = 0.01, 0.005, 0.0025 (and 0.00125) L, and the
simple cubic array at 20, 40, 80 (and 120) particles a side.

    perf/steady_growth.py run --out DIR [--series problem3 simple_cubic] [--method steady march]
                              [--sizes N ...]
    perf/steady_growth.py add DIR/steady_growth.csv RUN_DIR ...
    perf/steady_growth.py plot DIR/steady_growth.csv [--png docs/figures/steady_growth.png]

`run` runs the series (--sizes: points per cell side; default 100, 200,
400 for problem III and 20, 40, 80 for the simple cubic array) and adds a
row per run to DIR/steady_growth.csv. The finest runs take hours: start
them by hand (input/problem3/problem3.xml or input/3d/simple_cubic.xml
with Discretization/Particle Spacing set) and give their output
directories to `add`, which reads each run's parameters_used.xml and
summary.json. `plot` fits time = a N^b on each method's points of a series
(N: fluid particles; least squares in log-log), prints the table for
docs/steady_solver.md and draws the figure.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

from poresph_runs import ROOT, read_summary, run_poresph, write_csv  # noqa: E402

SERIES = {  # scene under input/, cell side (m), default points per side
    "problem3": ("problem3/problem3.xml", 0.1, [100, 200, 400]),
    "simple_cubic": ("3d/simple_cubic.xml", 0.1, [20, 40, 80]),
}
METHODS = {
    "steady": ["Solver/Method=steady"],
    "march": ["Permeability/Steady Tolerance=1e-4", "Run/End Time=1e12", "Run/Max Steps=0"],
}
SERIAL = ["Run/Backend=serial", "Convergence/Levels=1"]


def row_of(directory):
    """The row of an output directory, from its summary.json: its series
    from the scene's name, its method, its lattice and what it measured."""
    summary = read_summary(directory)
    name = summary["scene"]
    series = "problem3" if name.startswith("problem3") else "simple_cubic" if name.startswith("simple-cubic") else None
    if series is None:
        sys.exit(f"{directory}: scene {name} is in neither series")
    method = "steady" if summary["solver"]["method"] == "steady" else "march"
    side = SERIES[series][1]
    converged = summary["solver"]["converged"] if method == "steady" else summary.get("steady", False)
    return dict(series=series, method=method, points_per_side=round(side / summary["particle_spacing"]),
                fluid_particles=summary["fluid_particles"], wall_seconds=summary["wall_seconds"],
                kxx=summary["permeability"]["kxx"], converged=converged, run=os.path.abspath(directory))


def read_rows(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def add_rows(path, rows):
    """Adds rows, replacing an earlier row of the same series, method and size."""
    key = lambda r: (r["series"], r["method"], int(r["points_per_side"]))  # noqa: E731
    merged = {key(r): r for r in read_rows(path)}
    merged.update({key(r): r for r in rows})
    write_csv(path, sorted(merged.values(), key=key))


def fit(points):
    """b and a of time = a N^b by least squares in log-log."""
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return b, math.exp(my - b * mx)


def plot(path, png):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in read_rows(path) if r["converged"] in ("True", "true", "1")]
    figure, axes = plt.subplots(figsize=(6.4, 4.8))
    print("| series | method | points per side | fluid particles | wall s | fitted exponent |\n|---|---|---|---|---|---|")
    for (series, method), marker in zip([(s, m) for s in SERIES for m in METHODS], "osd^"):
        mine = sorted((r for r in rows if r["series"] == series and r["method"] == method),
                      key=lambda r: int(r["fluid_particles"]))
        if not mine:
            continue
        points = [(int(r["fluid_particles"]), float(r["wall_seconds"])) for r in mine]
        exponent = f"{fit(points)[0]:.2f}" if len(points) > 1 else ""
        for r in mine:
            print(f"| {series} | {method} | {r['points_per_side']} | {int(r['fluid_particles']):,} | "
                  f"{float(r['wall_seconds']):.1f} | {exponent} |")
        label = f"{series.replace('_', ' ')}, {method}" + (f": N^{exponent}" if exponent else "")
        axes.loglog(*zip(*points), marker=marker, linestyle="-" if method == "steady" else "--", label=label)
    axes.set_xlabel("fluid particles N")
    axes.set_ylabel("wall seconds to a steady k (one core)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(png, dpi=120)
    print(f"figure: {png}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True)
    run = commands.add_parser("run")
    run.add_argument("--out", required=True)
    run.add_argument("--build", default=os.path.join(ROOT, "build"))
    run.add_argument("--series", nargs="+", choices=sorted(SERIES), default=sorted(SERIES))
    run.add_argument("--method", nargs="+", choices=sorted(METHODS), default=sorted(METHODS))
    run.add_argument("--sizes", nargs="+", type=int, help="points per cell side (default: the series' own)")
    add = commands.add_parser("add")
    add.add_argument("csv")
    add.add_argument("runs", nargs="+")
    draw = commands.add_parser("plot")
    draw.add_argument("csv")
    draw.add_argument("--png", default=os.path.join(ROOT, "docs", "figures", "steady_growth.png"))
    args = parser.parse_args()
    if args.command == "run":
        os.makedirs(args.out, exist_ok=True)
        for series in args.series:
            scene, side, sizes = SERIES[series]
            for n in args.sizes or sizes:
                for method in args.method:
                    directory = os.path.join(args.out, f"{series}_{n}_{method}")
                    settings = SERIAL + METHODS[method] + [f"Discretization/Particle Spacing={side / n:.10g}"]
                    try:
                        run_poresph(os.path.abspath(args.build), scene, directory, settings)
                    except subprocess.CalledProcessError as error:
                        if error.returncode != 4:  # 4: not converged; its row says so
                            raise
                        print(f"{directory}: not converged", file=sys.stderr)
                    add_rows(os.path.join(args.out, "steady_growth.csv"), [row_of(directory)])
                    print(f"{series} {n} {method}: done", flush=True)
    elif args.command == "add":
        add_rows(args.csv, [row_of(d) for d in args.runs])
    else:
        plot(args.csv, args.png)


if __name__ == "__main__":
    main()
