#!/usr/bin/python3
"""Speed against error: the relative error of k against the wall time it
took, for the square arrays of solid fraction 0.2 and 0.5 (reference:
Sangani & Acrivos 1982) and problem III (reference: the finite-element
value of perf/stokes_reference.py, or else the finest PoreSPH run), at
several resolutions, each with PoreSPH's default (fixed particles,
docs/method.md) and with moving particles as in the paper plus particle
shifting (the paper's method); at the middle resolution also the
moving particles with the raised sound speed and the fixed ones without
the convective term. Every run stops by itself when k is steady.

    perf/speed_vs_error.py [--build build] [--out build/speed-vs-error]
        [--problem3-runs DIR...] [--problem3-reference K_M2]
        [--square-arrays-csv build/square-arrays/square_arrays.csv]
    perf/speed_vs_error.py --replot build/speed-vs-error/speed_vs_error.csv
    perf/speed_vs_error.py --add-steady docs/figures/speed_vs_error.csv --problem3-reference K_M2

--add-steady runs the steady solver (Solver/Method = steady, its defaults)
on the square arrays at the three spacings and problem III at 0.02, 0.01,
0.005 and 0.0025 L, and adds its rows to those of an earlier CSV (replacing
earlier steady rows): the figure and the table then show both.

Problem III at dx = 0.005 L and 0.0025 L takes minutes to hours; such runs
are made once (input/problem3/problem3.xml with Discretization/Particle
Spacing set) and their output directories given with --problem3-runs (the
spacing and the particle motion are read from their parameters_used.xml);
the script runs dx = 0.02 and 0.01 L itself when problem III has a
reference.
Writes speed_vs_error.csv into --out (and, once all runs are done, into
docs/figures beside the plot), docs/figures/speed_vs_error.png,
and prints the table for docs/speed_vs_error.md, with what the steady-state
stop saved against running to the scene's End Time.
"""
import argparse
import csv
import os
import sys
import xml.etree.ElementTree as ElementTree

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from poresph_runs import ROOT, read_summary, run_poresph, write_csv  # noqa: E402

L = 0.1
SANGANI_ACRIVOS = {20: 1 / 51.53, 50: 1 / 532.55}
DEFAULT = "fixed (default)"
LADDER = "ladder, 3 levels"
STEADY = "steady solve"  # Solver/Method = steady: no pseudo-time, no steps
MOVING = "moving, shifting"  # the paper's moving particles, with particle shifting
MOVING_SETTINGS = ["Discretization/Particle Motion=lagrangian", "Discretization/Wall Pressure=continuity",
                   "Discretization/Particle Shifting=4"]
END_TIME = 8000.0  # of the scenes below: what a run without the steady-state stop would simulate


def row(scene, variant, dx, summary, reference, ranks):
    measured = summary["permeability"]
    k = measured["kxx"] / L**2
    steps_to_end = END_TIME / summary["time_step"]
    return dict(scene=scene, variant=variant, dx_over_L=dx / L, k_over_L2=k, reference=reference,
                relative_error=k / reference - 1 if reference else None, steady=summary["steady"],
                steps=summary["steps"], wall_seconds=summary["wall_seconds"], ranks=ranks,
                wall_seconds_to_end_time=summary["wall_seconds"] * steps_to_end / summary["steps"], uncertainty=None)


def read_rows(path):
    """The rows of an earlier speed_vs_error.csv, numbers as numbers."""
    def value(text):
        if text in ("", "None"):
            return None
        if text in ("True", "False"):
            return text == "True"
        try:
            return int(text)
        except ValueError:
            try:
                return float(text)
            except ValueError:
                return text
    with open(path) as f:
        return [{key: value(text) for key, text in r.items()} for r in csv.DictReader(f)]


def report(rows):
    """The plot docs/figures/speed_vs_error.png and the Markdown table."""
    # The plot: |error| against wall time, one curve per scene and sound-speed
    # choice (solid: the paper's rule, dashed: raised c), other variants as markers.
    fig, ax = plt.subplots(figsize=(10, 5.5))
    for scene, colour in [("square array c = 0.2", "C0"), ("square array c = 0.5", "C1"), ("problem III", "C2")]:
        for curve, style in [(DEFAULT, "o-"), (MOVING, "D--")]:
            sel = sorted((r for r in rows if r["scene"] == scene and r["variant"] == curve and r["relative_error"]),
                         key=lambda r: r["wall_seconds"] * r["ranks"])
            if not sel:
                continue
            ax.loglog([r["wall_seconds"] * r["ranks"] for r in sel], [abs(r["relative_error"]) for r in sel], style,
                      color=colour, label=f"{scene}, {curve}")
            for r in sel:
                ax.annotate(f"{r['dx_over_L']:g}L", (r["wall_seconds"] * r["ranks"], abs(r["relative_error"])),
                            fontsize=7, textcoords="offset points", xytext=(4, 4 if curve == DEFAULT else -9))
        # The ladder: its finest k with the band of the grid convergence index,
        # at the whole ladder's wall time.
        for r in (r for r in rows if r["scene"] == scene and r["variant"] == LADDER):
            cost = r["wall_seconds"] * r["ranks"]
            ax.errorbar([cost], [abs(r["relative_error"])], yerr=[[0], [r["uncertainty"]]], fmt="*", ms=11,
                        color=colour, capsize=3, label=f"{scene}, ladder (band: GCI)")
        sel = sorted((r for r in rows if r["scene"] == scene and r["variant"] == STEADY and r["relative_error"]),
                     key=lambda r: r["wall_seconds"])
        if sel:
            ax.loglog([r["wall_seconds"] for r in sel], [abs(r["relative_error"]) for r in sel], "s-.",
                      color=colour, mfc="none", label=f"{scene}, {STEADY}")
            for r in sel:
                ax.annotate(f"{r['dx_over_L']:g}L", (r["wall_seconds"], abs(r["relative_error"])), fontsize=7,
                            textcoords="offset points", xytext=(4, -9))
        for marker, variant in [("^", "moving, shifting, raised c"), ("v", "fixed, no convection")]:
            sel = [r for r in rows if r["scene"] == scene and r["variant"] == variant]
            if sel:
                ax.loglog([r["wall_seconds"] for r in sel], [abs(r["relative_error"]) for r in sel], marker,
                          color=colour, mfc="none", label=f"{scene}, {variant} (dx = 0.02 L)")
    for level in [0.05, 0.02, 0.01]:
        ax.axhline(level, color="grey", lw=0.5, ls=":")
    ax.set_xlabel("wall time to a steady k (core-seconds)")
    ax.set_ylabel("|relative error of k|")
    ax.set_title("PoreSPH: speed against error (steady-state stop, this machine)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    figure = os.path.join(ROOT, "docs", "figures", "speed_vs_error.png")
    fig.savefig(figure, dpi=130)
    print(f"wrote {figure}", file=sys.stderr)

    print("| scene | variant | dx/L | k/L^2 | reference | error % | steps | wall s | ranks | wall s to End Time | saved |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        err = f"{100 * r['relative_error']:+.2f}" if r["relative_error"] is not None else "(reference)"
        ref = f"{r['reference']:.5g}" if r["reference"] is not None else "-"
        if r["variant"] == LADDER:  # no single spacing or End Time: the band instead
            print(f"| {r['scene']} | {r['variant']} | 3 levels | {r['k_over_L2']:.5g} | {ref} | {err} "
                  f"(band +-{100 * r['uncertainty']:.2f}) | | {r['wall_seconds']:.0f} | {r['ranks']} | | |")
            continue
        if r["variant"] == STEADY:  # no steps, no End Time
            print(f"| {r['scene']} | {r['variant']} | {r['dx_over_L']:g} | {r['k_over_L2']:.5g} | {ref} | {err} | "
                  f"| {r['wall_seconds']:.1f} | {r['ranks']} | | |")
            continue
        print(f"| {r['scene']} | {r['variant']} | {r['dx_over_L']:g} | {r['k_over_L2']:.5g} | {ref} | "
              f"{err} | {r['steps']} | {r['wall_seconds']:.0f} | {r['ranks']} | {r['wall_seconds_to_end_time']:.0f} | "
              f"{r['wall_seconds_to_end_time'] / r['wall_seconds']:.1f}x |")


def steady_row(scene, dx, summary, reference):
    k = summary["permeability"]["kxx"] / L**2
    return dict(scene=scene, variant=STEADY, dx_over_L=dx / L, k_over_L2=k, reference=reference,
                relative_error=k / reference - 1, steady=summary["solver"]["converged"], steps=None,
                wall_seconds=summary["wall_seconds"], ranks=1, wall_seconds_to_end_time=None, uncertainty=None)


def add_steady(args):
    """The steady solver's rows, added to those of an earlier CSV."""
    if not args.problem3_reference:
        sys.exit("--add-steady needs --problem3-reference")
    rows = [r for r in read_rows(args.add_steady) if r["variant"] != STEADY]
    runs = [(f"square array c = 0.{fraction // 10}", f"square_array/square_array_c{fraction}.xml", dx, reference)
            for fraction, reference in SANGANI_ACRIVOS.items() for dx in [0.004, 0.002, 0.001]]
    runs += [("problem III", "problem3/problem3.xml", dx, args.problem3_reference / L**2)
             for dx in [0.002, 0.001, 0.0005, 0.00025]]
    for scene, path, dx, reference in runs:
        out = os.path.join(args.out, f"{os.path.basename(path)[:-4]}-dx{dx}-steady")
        s = run_poresph(args.build, path, out, [f"Discretization/Particle Spacing={dx!r}", "Solver/Method=steady"])
        rows.append(steady_row(scene, dx, s, reference))
        print(rows[-1], file=sys.stderr, flush=True)
    write_csv(os.path.join(args.out, "speed_vs_error.csv"), rows)
    write_csv(os.path.join(ROOT, "docs", "figures", "speed_vs_error.csv"), rows)
    report(rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "speed-vs-error"))
    parser.add_argument("--problem3-runs", nargs="+", default=[], metavar="DIR",
                        help="output directories of earlier problem III runs")
    parser.add_argument("--problem3-reference", type=float, default=None, metavar="K_M2",
                        help="kxx of problem III (m^2) to measure against; default: the finest --problem3-runs run")
    parser.add_argument("--square-arrays-csv", default=None,
                        help="take the default runs of c = 0.2 and 0.5 from perf/square_arrays.py's CSV "
                             "instead of running them again")
    parser.add_argument("--ladder-csv", default=None,
                        help="perf/ladder.py's ladder.csv: the ladders' points, with their bands")
    parser.add_argument("--add-steady", default=None, metavar="CSV",
                        help="run the steady solver's rows and add them to those of an earlier speed_vs_error.csv")
    parser.add_argument("--replot", default=None, metavar="CSV",
                        help="make the plot and the table from an earlier speed_vs_error.csv, running nothing")
    args = parser.parse_args()
    if args.replot:
        report(read_rows(args.replot))
        return
    os.makedirs(args.out, exist_ok=True)
    if args.add_steady:
        add_steady(args)
        return
    rows = []

    def save():
        write_csv(os.path.join(args.out, "speed_vs_error.csv"), rows)

    moving = (MOVING, MOVING_SETTINGS)
    variants = [(DEFAULT, []), moving]
    middle_variants = [("moving, shifting, raised c", MOVING_SETTINGS + ["Fluid/Raise Sound Speed=true"]),
                       ("fixed, no convection", ["Fluid/Convection=false"])]
    earlier = []
    if args.square_arrays_csv:
        with open(args.square_arrays_csv) as f:
            earlier = list(csv.DictReader(f))
    for fraction, reference in SANGANI_ACRIVOS.items():
        scene = f"square_array/square_array_c{fraction}.xml"
        for dx in [0.004, 0.002, 0.001]:
            done = [r for r in earlier if round(float(r["solid_fraction"]) * 100) == fraction
                    and abs(float(r["dx_over_L"]) - dx / L) < 1e-9]
            if done:
                r = done[0]
                k = float(r["k_over_L2"])
                steps, wall = int(r["steps"]), float(r["wall_seconds"])
                rows.append(dict(scene=f"square array c = 0.{fraction // 10}", variant=DEFAULT, dx_over_L=dx / L,
                                 k_over_L2=k, reference=reference, relative_error=k / reference - 1,
                                 steady=r["steady"], steps=steps, wall_seconds=wall, ranks=1,
                                 wall_seconds_to_end_time=wall * (END_TIME / float(r["simulated_time"])),
                                 uncertainty=None))
            todo = variants if not done else [moving]
            for variant, settings in todo + (middle_variants if dx == 0.002 else []):
                out = os.path.join(args.out, f"c{fraction}-dx{dx}-{variant.replace(' ', '_')}")
                s = run_poresph(args.build, scene, out, [f"Discretization/Particle Spacing={dx!r}"] + settings)
                rows.append(row(f"square array c = 0.{fraction // 10}", variant, dx, s, reference, 1))
                print(rows[-1], file=sys.stderr, flush=True)
                save()

    # Problem III: the finite-element reference, or else the finest run.
    def given_run(directory):
        """(spacing, variant, summary) of an earlier problem III run, from its parameters_used.xml."""
        parameters = {p.get("name"): p.get("value") for p in
                      ElementTree.parse(os.path.join(directory, "parameters_used.xml")).iter("Parameter")}
        if "Particle Spacing" not in parameters:
            sys.exit(f"{directory}/parameters_used.xml has no Particle Spacing")
        variant = MOVING if parameters.get("Particle Motion") == "lagrangian" else DEFAULT
        return float(parameters["Particle Spacing"]), variant, read_summary(directory)

    given = sorted((given_run(d) for d in args.problem3_runs), key=lambda run: run[0])
    reference = args.problem3_reference / L**2 if args.problem3_reference else None
    reference_run = None
    if reference is None and given:
        reference_run = given[0][2]
        reference = reference_run["permeability"]["kxx"] / L**2
    if reference is None:
        print("problem III left out: no --problem3-reference and no --problem3-runs", file=sys.stderr)
    for dx in [0.002, 0.001] if reference else []:
        for variant, settings in variants:
            out = os.path.join(args.out, f"problem3-dx{dx}-{variant.replace(' ', '_')}")
            s = run_poresph(args.build, "problem3/problem3.xml", out,
                            [f"Discretization/Particle Spacing={dx!r}"] + settings)
            rows.append(row("problem III", variant, dx, s, reference, 1))
            print(rows[-1], file=sys.stderr, flush=True)
    for dx, variant, s in given:
        rows.append(row("problem III", variant, dx, s, None if s is reference_run else reference, s["ranks"]))
    if args.ladder_csv:
        with open(args.ladder_csv) as f:
            for r in csv.DictReader(f):
                k, ref = float(r["k"]), float(r["reference"])
                rows.append(dict(scene=r["scene"], variant=LADDER, dx_over_L=None, k_over_L2=k, reference=ref,
                                 relative_error=k / ref - 1, steady=True, steps=None,
                                 wall_seconds=float(r["ladder_wall"]), ranks=int(r["ranks"]),
                                 wall_seconds_to_end_time=None, uncertainty=float(r["uncertainty"])))
    save()

    write_csv(os.path.join(ROOT, "docs", "figures", "speed_vs_error.csv"), rows)
    report(rows)


if __name__ == "__main__":
    main()
