#!/usr/bin/python3
"""Periodic arrays of grains settling under gravity (Grains/Motion = free)
against the speed the same array's drag gives when held still.

In the grains' frame a settling array is the array held still with the
fluid driven by f = g + s / rho0 per unit mass (s the cell's support,
docs/method.md "Grains that move"), and the cell's momentum stays zero; so
the settling speed is U = -q / (phi (1 + M_s / M_f)), q the superficial
velocity through the held array under f. Both runs here use moving fluid
particles, the same sound speed and time step, and end at the same time;
the held run's q is read from its summary.json, the settling speed from
grains_history.csv (the mean over the run's last fifth, and its spread).
The scenes are the shipped square array c = 0.2 and simple cubic array,
with the settings below.
The speed from the published drag (Sangani & Acrivos 1982 for the square
array, Zick & Homsy 1982 for the simple cubic one, through k) is given too.

    perf/settling_arrays.py [--arrays square simple_cubic] [--spacings 0.002 0.001]
        [--build build] [--out build/settling]
"""
import argparse
import csv
import math
import os
import sys
import time

from poresph_runs import ROOT, run_poresph

RHO = 1000.0
NU = 1e-6
SOLID_DENSITY = 2000.0
GRAVITY = 5e-8  # m/s^2, along -y: creeping flow (Re ~ 0.1)
CELL = 0.1
# name: (scene file under input/, dimension, solid fraction, k / L^2 of the published drag, End Time in s)
ARRAYS = {
    "square": ("square_array/square_array_c20.xml", 2, 0.2, 1 / 51.53, 2000.0),  # Sangani & Acrivos 1982
    # Zick & Homsy 1982, c = 0.125: K = 4.292, k / a^2 = 2 / (9 c K)
    "simple_cubic": ("3d/simple_cubic.xml", 3, 0.125,
                     2 * (3 * 0.125 / (4 * math.pi)) ** (2 / 3) / (9 * 0.125 * 4.292), 4000.0),
}


def settings(spacing, end_time, sound_speed):
    """What both runs of an array set on its scene file: moving fluid, the sound speed, no steady stop."""
    return [f"Discretization/Particle Spacing={spacing!r}", "Discretization/Particle Motion=lagrangian",
            f"Fluid/Sound Speed={sound_speed!r}", "Permeability/Steady Tolerance=0", f"Run/End Time={end_time!r}"]


def vector(values):
    return "{" + ", ".join(repr(v) for v in values) + "}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--arrays", nargs="+", default=["square"], choices=list(ARRAYS))
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.002, 0.001])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"), help="build directory holding poresph")
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "settling"))
    args = parser.parse_args()
    rows = []
    for name in args.arrays:
        scene, dim, solid_fraction, k_published, end_time = ARRAYS[name]
        cell_volume = CELL**dim
        radius = (solid_fraction * cell_volume / (math.pi if dim == 2 else 4 / 3 * math.pi)) ** (1 / dim)
        grain_volume = math.pi * radius**2 if dim == 2 else 4 / 3 * math.pi * radius**3
        grain_mass = SOLID_DENSITY * grain_volume
        for spacing in args.spacings:
            # One sound speed for both runs: the rule's for the settling scene (docs/method.md).
            force = GRAVITY * max(1.0, SOLID_DENSITY / RHO)
            velocity = force * CELL**2 / (8 * NU)
            sound_speed = math.sqrt(max(velocity**2, NU * velocity / CELL, force * CELL) / 0.01)
            directory = os.path.join(args.out, f"{name}_{spacing:g}")
            common = settings(spacing, end_time, sound_speed)
            gravity = [0.0, -GRAVITY] + ([0.0] if dim == 3 else [])
            start = time.monotonic()
            free = run_poresph(args.build, scene, os.path.join(directory, "free"), common + [
                f"Fluid/Body Force={vector([0.0] * dim)}", "Grains/Motion=free",
                f"Grains/Density={SOLID_DENSITY!r}", f"Grains/Gravity={vector(gravity)}"])
            free_seconds = time.monotonic() - start
            fluid_mass = free["fluid_particles"] * RHO * spacing**dim
            # The fluid's force per unit mass, f = g + s / rho0 (physics/RigidGrains.hpp): g_y = -G and
            # the support s_y = (M_f + M_s) G / (M_f / rho0 + V_s).
            f_y = -GRAVITY + (fluid_mass + grain_mass) * GRAVITY / ((fluid_mass / RHO + grain_volume) * RHO)
            start = time.monotonic()
            held = run_poresph(args.build, scene, os.path.join(directory, "held"),
                               common + [f"Fluid/Body Force={vector([0.0, f_y] + ([0.0] if dim == 3 else []))}"])
            held_seconds = time.monotonic() - start
            q = held["superficial_velocity"]["y"]
            phi = fluid_mass / (RHO * cell_volume)
            predicted = -q / (phi * (1 + grain_mass / fluid_mass))
            published = -(k_published * CELL**2) * f_y / NU / (phi * (1 + grain_mass / fluid_mass))
            with open(os.path.join(directory, "free", "grains_history.csv")) as f:
                history = [(float(r["time"]), float(r["velocity_y"])) for r in csv.DictReader(f)]
            late = [u for t, u in history if t >= 0.8 * end_time]
            mean = sum(late) / len(late)
            row = dict(array=name, spacing=spacing, particles_across=round(CELL / spacing), settling=mean,
                       spread=(max(late) - min(late)) / abs(mean), held_prediction=predicted,
                       ratio=mean / predicted, published_prediction=published, ratio_published=mean / published,
                       free_seconds=round(free_seconds, 1), held_seconds=round(held_seconds, 1))
            rows.append(row)
            print(f"{name} at {spacing:g}: settling {mean:.5e} m/s, held array's drag gives {predicted:.5e} "
                  f"(ratio {mean / predicted:.4f}), published drag {published:.5e}", file=sys.stderr)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "settling.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("| array | particles across | settling speed (m/s) | spread, last fifth | held array's drag gives "
          "| ratio | published drag gives | ratio | wall s (free, held) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['array']} | {r['particles_across']} | {r['settling']:.5e} | {r['spread'] * 100:.2f} % "
              f"| {r['held_prediction']:.5e} | {r['ratio']:.4f} | {r['published_prediction']:.5e} "
              f"| {r['ratio_published']:.4f} | {r['free_seconds']}, {r['held_seconds']} |")


if __name__ == "__main__":
    main()
