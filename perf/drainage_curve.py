#!/usr/bin/python3
"""Quasi-static drainage of a grain cell (Phases/Phase 1/Drainage, the
morphological rule of src/scene/Drainage.hpp) at several spacings: the
capillary pressure-saturation curve of each spacing (drainage.csv), and at
a few target saturations the co-current flow of both phases through the
placed distribution, solved for its steady state, with each phase's
relative permeability against the single-phase k of the same spacing.

    perf/drainage_curve.py --scene problem3/problem3.xml --length 0.1 \\
        --spacings 0.002 0.001 0.0005 --saturations 0.65 0.75 0.85 0.95 \\
        [--viscosity-ratio 2] [--set "Permeability/Tensor=false" ...] [--out build/drainage] [--figure F.png] \
        [--pictures P.png] [--trapping]

With --pressures (values of Pc L / sigma) each point is instead placed at
that capillary pressure (Drainage/Capillary Pressure, sigma = 0.072 N/m)
and run as a resolution ladder over --spacings (Convergence/Levels, the
spacings a constant ratio apart, the finest last): each level's S_nw and
k_r, and each phase's k_r extrapolated with its uncertainty, over the
single-phase k extrapolated by the same ladder.

    perf/drainage_curve.py --pressures 7 9 12 15 20 --out build/drainage-ladder [--figure F.png]

The capillary pressure is given as L kappa = L (dim - 1) cos(theta) / r
(theta = 0): Pc L / sigma, the cell's side L over the balls' radius. Phase 1
is the non-wetting phase, entering from the cell's faces across x. Prints
the Markdown tables of docs/validation.md; --figure draws the curves and
the k_r points, --pictures the phases at each saturation of the finest
spacing (in 3D on the slice through the cell's middle across z).
"""
import argparse
import csv
import os
import time

from poresph_runs import run_poresph  # noqa: E402

NU = 1e-6


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--scene", default="problem3/problem3.xml")
    parser.add_argument("--length", type=float, default=0.1, help="the cell's side L (m)")
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.002, 0.001, 0.0005])
    parser.add_argument("--saturations", type=float, nargs="+", default=[0.65, 0.75, 0.85, 0.95])
    parser.add_argument("--viscosity-ratio", type=float, default=2.0, help="phase 1's viscosity over phase 0's")
    parser.add_argument("--set", action="append", default=[], help="more --set settings for every run")
    parser.add_argument("--ranks", type=int, default=None)
    parser.add_argument("--out", default="build/drainage")
    parser.add_argument("--trapping", action="store_true", help="Drainage/Trapping = true")
    parser.add_argument("--figure", default=None)
    parser.add_argument("--pictures", default=None)
    parser.add_argument("--pressures", type=float, nargs="+", default=None,
                        help="Pc L / sigma of each point, each run as a ladder over --spacings")
    args = parser.parse_args()
    if args.pressures:
        return ladder_points(args)
    common = ["Solver/Method=steady"] + args.set
    rule = ["Phases/Phase 1/Drainage/Trapping=true"] if args.trapping else []
    curves, points = {}, []
    for dx in args.spacings:
        spacing = [f"Discretization/Particle Spacing={dx!r}"]
        single = run_poresph(args.build, args.scene, os.path.join(args.out, f"single-{dx:g}"), common + spacing,
                             ranks=args.ranks)
        k = single["permeability"]["kxx"]
        for target in args.saturations:
            directory = os.path.join(args.out, f"dx{dx:g}-s{target:g}")
            start = time.monotonic()
            summary = run_poresph(args.build, args.scene, directory, common + spacing + [
                "Phases/Count=2", f"Phases/Phase 1/Kinematic Viscosity={NU * args.viscosity_ratio!r}",
                f"Phases/Phase 1/Drainage/Saturation={target!r}", f"Phases/Single Phase Permeability={k!r}",
                "Output/Final Particles CSV=true"] + rule,
                ranks=args.ranks)
            seconds = time.monotonic() - start
            if dx not in curves:
                with open(os.path.join(directory, "drainage.csv")) as f:
                    curves[dx] = [(float(r["saturation"]), float(r["curvature"]) * args.length)
                                  for r in csv.DictReader(f)]
            drainage, phases = summary["drainage"], summary["phases"]
            points.append(dict(dx=dx, target=target, saturation=drainage["saturation"],
                               pc=drainage["curvature"] * args.length, radius=drainage["radius"] / dx,
                               krw=phases[0]["relative_permeability"], krn=phases[1]["relative_permeability"],
                               k=k, seconds=seconds, converged=summary["solver"]["converged"]))
    print(f"| spacing (L) | target S_nw | S_nw | Pc L / sigma | r (spacings) | k_r,w | k_r,nw | k (m^2) | s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for p in points:
        print(f"| {p['dx'] / args.length:g} | {p['target']:g} | {p['saturation']:.4f} | {p['pc']:.2f} | "
              f"{p['radius']:.2f} | {p['krw']:.4f} | {p['krn']:.4f} | {p['k']:.4e} | {p['seconds']:.1f}"
              f"{'' if p['converged'] else ' (not converged)'} |")
    print()
    print("| spacing (L) | breakthrough Pc L / sigma | S_nw there | Pc L / sigma at S_nw = 0.9 | largest S_nw |")
    print("|---|---|---|---|---|")
    for dx, curve in curves.items():
        entered = next((s, pc) for s, pc in curve if s > 0)
        at_90 = next((pc for s, pc in curve if s >= 0.9), float("nan"))
        print(f"| {dx / args.length:g} | {entered[1]:.2f} | {entered[0]:.4f} | {at_90:.2f} | {curve[-1][0]:.4f} |")
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
        for dx, curve in curves.items():
            tag = f"dx = {dx / args.length:g} L"
            left.step([s for s, _ in curve], [pc for _, pc in curve], where="post", label=tag)
            mine = [p for p in points if p["dx"] == dx]
            saturations = [p["saturation"] for p in mine]
            right.plot(saturations, [p["krw"] for p in mine], "o-", label=f"k_r,w {tag}")
            right.plot(saturations, [p["krn"] for p in mine], "s--", label=f"k_r,nw {tag}")
        left.set_xlabel("non-wetting saturation S_nw")
        left.set_ylabel("Pc L / sigma")
        left.set_yscale("log")
        left.legend()
        right.set_xlabel("non-wetting saturation S_nw")
        right.set_ylabel("relative permeability (fixed distribution)")
        right.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=100)
    if args.pictures:
        draw_phases(args, points)


SIGMA = 0.072


def ladder_points(args):
    """Each capillary pressure's point as a resolution ladder (see the top)."""
    spacings = sorted(args.spacings, reverse=True)
    ratios = [a / b for a, b in zip(spacings, spacings[1:])]
    if len(spacings) < 3 or max(ratios) - min(ratios) > 1e-9 * max(ratios):
        raise SystemExit("--pressures needs three or more spacings a constant ratio apart")
    ladder = [f"Discretization/Particle Spacing={spacings[-1]!r}", f"Convergence/Levels={len(spacings)}",
              f"Convergence/Refinement Ratio={ratios[0]!r}"]
    common = ["Solver/Method=steady"] + args.set + ladder
    single = run_poresph(args.build, args.scene, os.path.join(args.out, "single"), common, ranks=args.ranks)
    k = single["permeability_extrapolated"]["kxx"]
    print(f"single-phase k: {k:.5e} m^2 +- {100 * single['permeability_uncertainty']['kxx']:.2g} % "
          f"(levels {', '.join(format(lv['permeability']['kxx'], '.5e') for lv in single['convergence'])})")
    rows = []
    for pc in args.pressures:
        directory = os.path.join(args.out, f"pc{pc:g}")
        start = time.monotonic()
        summary = run_poresph(args.build, args.scene, directory, common + [
            "Phases/Count=2", f"Phases/Phase 1/Kinematic Viscosity={NU * args.viscosity_ratio!r}",
            f"Phases/Phase 1/Drainage/Capillary Pressure={pc * SIGMA / args.length!r}",
            f"Phases/Phase 1/Drainage/Surface Tension={SIGMA!r}", f"Phases/Single Phase Permeability={k!r}"],
            ranks=args.ranks)
        phases = summary["phases"]
        rows.append(dict(pc=pc, seconds=time.monotonic() - start,
                         levels=[lv["phases"] for lv in summary["convergence"]],
                         kr=[(p["relative_permeability_extrapolated"], p["relative_permeability_uncertainty"])
                             for p in phases]))
    tags = ", ".join(f"{dx / args.length:g}" for dx in spacings)
    print(f"| Pc L / sigma | S_nw at {tags} L | k_r,w at {tags} L | extrapolated k_r,w | "
          f"k_r,nw at {tags} L | extrapolated k_r,nw | s |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        s_nw = ", ".join(f"{lv[1]['saturation']:.4f}" for lv in r["levels"])
        krw = ", ".join(f"{lv[0]['relative_permeability']:.4f}" for lv in r["levels"])
        krn = ", ".join(f"{lv[1]['relative_permeability']:.4f}" for lv in r["levels"])
        (w, uw), (n, un) = r["kr"]
        print(f"| {r['pc']:g} | {s_nw} | {krw} | {w:.4f} +- {100 * uw:.2g} % | {krn} | {n:.4f} +- {100 * un:.2g} % | "
              f"{r['seconds']:.1f} |")
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5.5, 4))
        s_fine = [r["levels"][-1][1]["saturation"] for r in rows]
        for phase, (marker, name, colour) in enumerate([("o", "k_r,w", "C0"), ("s", "k_r,nw", "C2")]):
            values = [r["kr"][phase][0] for r in rows]
            ax.errorbar(s_fine, values, yerr=[v * r["kr"][phase][1] for v, r in zip(values, rows)], fmt=marker + "-",
                        color=colour, capsize=3, label=f"{name}, extrapolated (error bar: the ladder's uncertainty)")
            ax.plot(s_fine, [r["levels"][-1][phase]["relative_permeability"] for r in rows], marker, color=colour,
                    mfc="none", ms=9, label=f"{name} at {spacings[-1] / args.length:g} L")
        ax.set_xlabel("non-wetting saturation S_nw (finest level)")
        ax.set_ylabel("relative permeability (fixed distribution)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=100)
    return 0


def draw_phases(args, points):
    """The phases of the finest spacing's runs, one panel a saturation."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    dx = min(args.spacings)
    mine = [p for p in points if p["dx"] == dx]
    fig, axes = plt.subplots(1, len(mine), figsize=(3.2 * len(mine), 3.4))
    for ax, p in zip(np.atleast_1d(axes), mine):
        rows = np.genfromtxt(os.path.join(args.out, f"dx{dx:g}-s{p['target']:g}", "particles.csv"), delimiter=",",
                             names=True)
        if "z" in rows.dtype.names:
            rows = rows[np.abs(rows["z"] - args.length / 2) < 0.5 * dx + 1e-12]
        colour = np.where(rows["kind"] != 0, 2, rows["phase"])
        ax.scatter(rows["x"], rows["y"], c=colour, s=max(0.5, 0.05 * args.length / dx), marker="s",
                   cmap="viridis", vmin=0, vmax=2, linewidths=0)
        ax.set_aspect("equal")
        ax.set_xticks([]), ax.set_yticks([])
        ax.set_title(f"S_nw = {p['saturation']:.2f}, Pc L/sigma = {p['pc']:.1f}", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.pictures, dpi=100)


if __name__ == "__main__":
    main()
