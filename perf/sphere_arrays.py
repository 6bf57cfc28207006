#!/usr/bin/python3
"""Cubic arrays of spheres against a reference drag: simple cubic (SC),
body-centred (BCC) and face-centred cubic (FCC) arrays at several solid
fractions and resolutions (particles per side of the cubic cell), each run
until k is steady (input/3d/simple_cubic.xml, bcc.xml, fcc.xml; the radius
and centres are set here for each fraction). The SC reference is Zick &
Homsy's table (1982); the BCC and FCC ones are computed by
perf/periodic_stokes_spheres.py, which reproduces that table (`DRAG`).

    perf/sphere_arrays.py [--lattice sc] [--per-side 20 30 40] [--fractions 0.027 0.064 ...]
                          [--build build] [--out build/sphere-arrays] [--ranks N]

Writes sphere_arrays_<lattice>.csv into --out and prints the Markdown table
for docs/validation.md: k/a^2 (a the sphere radius), the reference
2 / (9 phi K), the relative error, the observed order between successive
resolutions, steps, wall time and particles. A run the scene checks refuse
(a throat under one spacing) is listed as refused, with the reason.
Runs one after the other, on one process unless --ranks.
"""
import argparse
import math
import os
import subprocess
import sys

from poresph_runs import ROOT, poresph_command, openmp_env, read_summary, write_csv

L = 0.1
# Zick & Homsy (1982), Table 2, simple cubic: K = F / (6 pi mu a U), U the
# superficial velocity; k / a^2 = 2 / (9 phi K) (../shared/METHOD.md).
DRAG = {
    "sc": {0.027: 2.008, 0.064: 2.810, 0.125: 4.292, 0.216: 7.442, 0.343: 15.4, 0.45: 28.1},
    # BCC and FCC: the same K computed by perf/periodic_stokes_spheres.py at
    # degree 24 (changes from degree 16 at most 4e-6), the method that gives
    # the SC row above to its four digits; phi = 0.6 at degree 32 (changes
    # from degree 24: BCC 1.7e-3, FCC 1.9e-4); docs/validation.md section 4.
    "bcc": {0.054: 2.66041, 0.125: 4.44638, 0.216: 7.73878, 0.343: 16.3350, 0.45: 31.6882, 0.6: 88.828},
    "fcc": {0.054: 2.65992, 0.125: 4.44572, 0.216: 7.75768, 0.343: 16.6390, 0.45: 33.4898, 0.6: 107.656},
}
# Sphere centres in units of the cell side: one, two or four spheres per cube.
CENTRES = {
    "sc": [(0.5, 0.5, 0.5)],
    # One sphere across the cell's corners (its eight pieces at the corners) and one at the centre.
    "bcc": [(0.0, 0.0, 0.0), (0.5, 0.5, 0.5)],
    # Corners and face centres: pieces across every edge and corner of the cell.
    "fcc": [(0.0, 0.0, 0.0), (0.0, 0.5, 0.5), (0.5, 0.0, 0.5), (0.5, 0.5, 0.0)],
}
SCENE = {"sc": "3d/simple_cubic.xml", "bcc": "3d/bcc.xml", "fcc": "3d/fcc.xml"}


def radius(lattice, phi):
    return L * (3 * phi / (4 * math.pi * len(CENTRES[lattice]))) ** (1 / 3)


def run(args, lattice, phi, per_side):
    a = radius(lattice, phi)
    grains = ", ".join(f"{c[0] * L!r}, {c[1] * L!r}, {c[2] * L!r}, {a!r}" for c in CENTRES[lattice])
    directory = os.path.join(args.out, f"{lattice}-phi{phi:g}-n{per_side}")
    settings = [f"Discretization/Particle Spacing={L / per_side!r}", f"Grains/Inline={{{grains}}}"]
    cmd = poresph_command(args.build, SCENE[lattice], directory, settings, args.ranks)
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          env=openmp_env(args.ranks, 1))
    if done.returncode == 2:  # refused by the scene checks: say why
        reason = done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "refused"
        return None, reason
    if done.returncode != 0:
        raise subprocess.CalledProcessError(done.returncode, cmd, stderr=done.stderr)
    return read_summary(directory), a


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "sphere-arrays"))
    parser.add_argument("--lattice", choices=sorted(CENTRES), default="sc")
    parser.add_argument("--per-side", type=int, nargs="+", default=[20, 30, 40])
    parser.add_argument("--fractions", type=float, nargs="+")
    parser.add_argument("--ranks", type=int, default=None)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    fractions = args.fractions or sorted(DRAG[args.lattice])

    rows = []
    for per_side in args.per_side:
        for phi in fractions:
            summary, detail = run(args, args.lattice, phi, per_side)
            drag = DRAG[args.lattice].get(phi)
            ref = 2 / (9 * phi * drag) if drag else float("nan")
            if summary is None:
                rows.append(dict(lattice=args.lattice, solid_fraction=phi, per_side=per_side, k_over_a2="",
                                 reference=ref, relative_error="", steady="", stopped_by="refused", steps="",
                                 simulated_time="", wall_seconds="", particles="", max_density_variation="",
                                 porosity="", reynolds="", kyx="", kzx="", note=detail))
                print(f"{args.lattice} phi = {phi:g} n = {per_side}: refused: {detail}", file=sys.stderr, flush=True)
            else:
                a = detail
                k = summary["permeability"]
                rows.append(dict(lattice=args.lattice, solid_fraction=phi, per_side=per_side,
                                 k_over_a2=k["kxx"] / a**2, reference=ref, relative_error=k["kxx"] / a**2 / ref - 1,
                                 steady=summary["steady"], stopped_by=summary["stopped_by"], steps=summary["steps"],
                                 simulated_time=summary["simulated_time"], wall_seconds=summary["wall_seconds"],
                                 particles=summary["fluid_particles"] + summary["boundary_particles"],
                                 max_density_variation=summary["max_density_variation"],
                                 porosity=summary["porosity"], reynolds=summary["reynolds_number"],
                                 kyx=k["kyx"] / k["kxx"], kzx=k["kzx"] / k["kxx"], note=""))
                print(f"{args.lattice} phi = {phi:g} n = {per_side}: error {100 * rows[-1]['relative_error']:+.2f} % "
                      f"({summary['stopped_by']}, {summary['wall_seconds']:.0f} s)", file=sys.stderr, flush=True)
            write_csv(os.path.join(args.out, f"sphere_arrays_{args.lattice}.csv"), rows)

    print("| phi | per side | a/dx | k/a^2 SPH | k/a^2 reference | error % | order | steady | steps | wall s | particles |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for phi in fractions:
        sel = [r for r in rows if r["solid_fraction"] == phi]
        for i, r in enumerate(sel):
            a_dx = radius(args.lattice, phi) * r["per_side"] / L
            if r["stopped_by"] == "refused":
                print(f"| {phi:g} | {r['per_side']} | {a_dx:.2f} | refused: {r['note']} | | | | | | | |")
                continue
            order = ""
            prev = sel[i - 1] if i > 0 else None
            if prev and prev["relative_error"] not in ("", 0) and r["relative_error"] != 0:
                ratio = abs(prev["relative_error"] / r["relative_error"])
                order = f"{math.log(ratio) / math.log(r['per_side'] / prev['per_side']):.2f}"
            print(f"| {phi:g} | {r['per_side']} | {a_dx:.2f} | {r['k_over_a2']:.5g} | {r['reference']:.5g} | "
                  f"{100 * r['relative_error']:+.2f} | {order} | {'yes' if r['steady'] else 'no'} | {r['steps']} | "
                  f"{r['wall_seconds']:.0f} | {r['particles']} |")


if __name__ == "__main__":
    main()
