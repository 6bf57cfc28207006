#!/usr/bin/python3
"""Fines carried through a pack: problem III's six grains held still
(Grains/Held), and small free grains ("fines") placed in its pores, driven
through the periodic cell by a body force on the fluid (the flow rate) and
pulled across the flow by gravity (the fines' weight less their buoyancy;
the cell rests on the held grains). A fine that settles onto a grain, or is
strained in a throat narrower than itself, stops: it is counted trapped.

    perf/fines_in_pack.py [--forces 0.5 1 2 4 8] [--fines 30] [--traverses 1]
        [--build build] [--out build/fines-in-pack] [--reuse] [--frames FORCE]

Each run is problem III at 0.01 of the cell side (0.001 m), moving
particles, nu = 1e-6 m^2/s, fines of radius 2 mm (two spacings; 4 mm
across: about a fifth of the main throats between the grains, larger than
the four narrow gaps of 3.3-4.2 mm) and density 2500 kg/m^3, gravity
G = 4e-6 m/s^2 along -y. The body force is F = FORCE x 1e-5 m/s^2 along x;
each run lasts TRAVERSES times the time the fluid takes to cross the cell
at its mean velocity q = k F / nu (k = 9.6e-4 L^2, problem III's), so that
a fine falls (rho_s / rho0 - 1) G a^2 / (4 nu) / q of the cell's side
per crossing: more at low flow rates. A fine is trapped when it moved less
than its own diameter over the run's last quarter. --frames FORCE writes
field files (particles.xmf, grains.xmf) for that run, and the figure
docs/figures/fines_in_pack.png shows the fines' paths at the lowest and
highest force.
"""
import argparse
import csv
import json
import math
import os
import random

from poresph_runs import ROOT, run_poresph

L = 0.1
DX = 0.001
FINE_RADIUS = 0.002
FINE_DENSITY = 2500.0
GRAVITY = 4e-6
FORCE_UNIT = 1e-5
NU = 1e-6


def held_grains():
    with open(os.path.join(ROOT, "input", "problem3", "grains.txt")) as f:
        return [tuple(float(v) for v in line.split()) for line in f if line.strip() and not line.startswith("#")]


def periodic_distance(a, b):
    dx = [abs(a[d] - b[d]) % L for d in range(2)]
    return math.hypot(*(min(x, L - x) for x in dx))


def place_fines(count, seed=7):
    """Fines at random in the pores, three spacings clear of every grain and of one another."""
    rng = random.Random(seed)
    grains, fines = held_grains(), []
    while len(fines) < count:
        c = (rng.uniform(0, L), rng.uniform(0, L))
        clear = all(periodic_distance(c, g) > g[2] + FINE_RADIUS + 3 * DX for g in grains) and all(
            periodic_distance(c, f) > 2 * FINE_RADIUS + 3 * DX for f in fines)
        if clear:
            fines.append(c)
    return grains, fines


def run(build, out, force, fines, end_time, frames, reuse):
    directory = os.path.join(out, f"force_{force:g}")
    if reuse and os.path.exists(os.path.join(directory, "summary.json")):
        return directory
    grains, centres = place_fines(fines)
    values = [v for g in grains for v in g] + [v for c in centres for v in (c[0], c[1], FINE_RADIUS)]
    inline = "{" + ", ".join(f"{v!r}" for v in values) + "}"
    held = "{" + ", ".join(str(i) for i in range(len(grains))) + "}"
    settings = [
        f"Discretization/Particle Spacing={DX!r}", "Discretization/Particle Motion=lagrangian",
        "Grains/File=", f"Grains/Inline={inline}", f"Grains/Held={held}", "Grains/Motion=free",
        f"Grains/Density={FINE_DENSITY!r}", f"Grains/Gravity={{0.0, {-GRAVITY!r}}}",
        f"Fluid/Body Force={{{force * FORCE_UNIT!r}, 0.0}}", f"Fluid/Velocity Scale={velocity_scale(force)!r}",
        f"Run/End Time={end_time!r}", "Permeability/Steady Tolerance=0"]
    if frames:
        settings.append(f"Output/Field Interval={end_time / 40!r}")
    run_poresph(build, "problem3/problem3.xml", directory, settings)
    return directory


def mean_velocity(force):
    # problem III's k F / nu, k = 9.6e-4 L^2 (docs/validation.md)
    return 9.6e-4 * L * L * force * FORCE_UNIT / NU


def velocity_scale(force):
    # the fastest fluid, in the narrow throats: about 12 times the mean (the sound-speed rule also
    # counts gravity, docs/method.md)
    return 12 * mean_velocity(force)


def trapped(directory, grains):
    """The count of fines that moved less than their diameter over the run's last quarter, of those
    the ones touching two surfaces or more at the end (strained in a throat; the others rest on
    one grain), the count of fines, and their paths."""
    with open(os.path.join(directory, "grains_history.csv")) as f:
        rows = [r for r in csv.DictReader(f) if int(r["grain"]) >= grains]
    end = max(float(r["time"]) for r in rows)
    paths, contacts = {}, {}
    for r in rows:
        paths.setdefault(int(r["grain"]), []).append((float(r["time"]), float(r["centre_x"]), float(r["centre_y"])))
        contacts[int(r["grain"])] = int(r["contacts"])  # at the last row
    stopped = strained = 0
    for fine, path in paths.items():
        late = [p for p in path if p[0] >= 0.75 * end]
        # centres are unwrapped along the run: the distance is the path's, not the cell's
        if math.hypot(late[-1][1] - late[0][1], late[-1][2] - late[0][2]) < 2 * FINE_RADIUS:
            stopped += 1
            strained += contacts[fine] >= 2
    return stopped, strained, len(paths), paths


def figure(out, runs, grains):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle
    fig, axes = plt.subplots(1, len(runs), figsize=(5 * len(runs), 5))
    for ax, (force, directory) in zip(axes, runs):
        for g in held_grains():
            for sx in (-L, 0, L):
                for sy in (-L, 0, L):
                    ax.add_patch(Circle((g[0] + sx, g[1] + sy), g[2], color="0.6"))
        stopped, _, count, paths = trapped(directory, grains)
        for path in paths.values():
            xs = [p[1] % L for p in path]
            ys = [p[2] % L for p in path]
            # break the line where the path wraps across the periodic cell
            segments, current = [], [(xs[0], ys[0])]
            for x, y in zip(xs[1:], ys[1:]):
                if abs(x - current[-1][0]) > L / 2 or abs(y - current[-1][1]) > L / 2:
                    segments.append(current)
                    current = []
                current.append((x, y))
            segments.append(current)
            for s in segments:
                ax.plot([p[0] for p in s], [p[1] for p in s], lw=0.8)
            ax.add_patch(Circle((xs[-1], ys[-1]), FINE_RADIUS, color="k"))
        ax.set_xlim(0, L)
        ax.set_ylim(0, L)
        ax.set_aspect("equal")
        ax.set_title(f"F = {force:g} x {FORCE_UNIT:g} m/s^2: {stopped} of {count} fines trapped")
    fig.tight_layout()
    path = os.path.join(ROOT, "docs", "figures", "fines_in_pack.png")
    fig.savefig(path, dpi=110)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--forces", type=float, nargs="+", default=[0.5, 1, 2, 4, 8],
                        help="body forces, in units of 1e-5 m/s^2")
    parser.add_argument("--fines", type=int, default=30)
    parser.add_argument("--traverses", type=float, default=1.0,
                        help="run length in crossings of the cell at the run's mean velocity")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "fines-in-pack"))
    parser.add_argument("--frames", type=float, default=None, help="write field files for this force")
    parser.add_argument("--reuse", action="store_true", help="read runs already in --out")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    grains = len(held_grains())
    fall = (FINE_DENSITY / 1000 - 1) * GRAVITY * FINE_RADIUS ** 2 / (4 * NU)
    print(f"{args.fines} fines of radius {FINE_RADIUS} m falling at about {fall:.2g} m/s; "
          f"{args.traverses:g} crossing(s) of the cell a run\n")
    print("| body force (m/s^2) | mean velocity q (m/s) | fall over q | fines trapped | of them strained "
          "| steps | time per step (ms) | particle-steps/s | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")
    runs = []
    for force in args.forces:
        end_time = args.traverses * L / mean_velocity(force)
        directory = run(args.build, args.out, force, args.fines, end_time, force == args.frames, args.reuse)
        with open(os.path.join(directory, "summary.json")) as f:
            summary = json.load(f)
        stopped, strained, count, _ = trapped(directory, grains)
        per_step = summary["wall_seconds"] / summary["steps"] * 1e3
        print(f"| {force * FORCE_UNIT:.3g} | {mean_velocity(force):.3g} | {fall / mean_velocity(force):.3g} "
              f"| {stopped} of {count} | {strained} | {summary['steps']} | {per_step:.2f} "
              f"| {summary['particle_steps_per_second']:.3g} | {summary['wall_seconds']:.0f} |")
        runs.append((force, directory))
    print("\nfigure:", figure(args.out, [runs[0], runs[-1]], grains))


if __name__ == "__main__":
    main()
