#!/usr/bin/python3
"""The hard cases of input/hard/ (and the lowest-porosity square arrays),
with PoreSPH's default (fixed particles, docs/method.md) and, where they
tell something, with moving particles as in the paper and the remedies
those need: particle shifting (Discretization/Particle Shifting) and
density re-summation (Discretization/Density Resummation Interval).

    perf/hard_cases.py [--build build] [--out build/hard-cases] [--quick] [--only TEXT] [--ranks N]

Writes hard_cases.csv into --out and prints the Markdown table for
docs/hard_cases.md: what ran, the largest density variation, fluid particles
found inside grains (and how many were put back on a surface), k against its
reference, steps, wall time and how the run ended. --quick leaves out the
throat and touching-grain runs (the throat at 4 dx takes about an hour).
"""
import argparse
import os
import sys

from poresph_runs import ROOT, run_poresph, write_csv

L = 0.1
SANGANI_ACRIVOS = {0.2: 1 / 51.53, 0.6: 1 / 1763, 0.7: 1 / 13520}
# Steady Navier-Stokes k/L^2 of hard/high_force.xml from finite elements
# (perf/stokes_reference.py --equations navier-stokes --grain 0.05 0.05
# 0.0252313252202016 --force 7.5e-8 --segments 50 100 200, extrapolated;
# docs/validation.md): inertia lowers it 0.07 % below the Stokes value.
HIGH_FORCE_NAVIER_STOKES = 0.019394

# k/L^2 along the force (kyy) of the throat scenes from finite elements,
# Richardson-extrapolated from meshes of 4, 2 and 1 mm whose grain
# boundaries are 4 times finer (docs/hard_cases.md):
#   perf/stokes_reference.py --grains GRAINS --drive y --segments 25 50 100 --grain-refinement 4
# with GRAINS the two grains of input/hard/throat.xml. A mesh cannot close a
# gap, so the touching grains' value is the one for gaps of 2e-5 m
# (2.33531e-3), extrapolated to a zero gap with the change from 4e-5 m to
# 2e-5 m at the 2 mm mesh (-0.25 %).
FINITE_ELEMENT = {"throat": 2.63760e-3, "touching": 2.32940e-3}

# Moving particles as in the paper, with or without the remedies they need.
MOVING = ["Discretization/Particle Motion=lagrangian", "Discretization/Wall Pressure=continuity"]
SHIFTING = ["Discretization/Particle Shifting=4"]
RESUM = ["Discretization/Density Resummation Interval=20"]


def cases(quick):
    """(case, scene, settings, reference k/L^2 or the name of a computed one, what the reference is)"""
    c20 = SANGANI_ACRIVOS[0.2]
    nse = HIGH_FORCE_NAVIER_STOKES
    rows = [
        ("grain across the corner", "hard/corner_grain.xml", [], "centred", "the centred grain, same dx"),
        ("grain across the corner, moving particles, shifting", "hard/corner_grain.xml", MOVING + SHIFTING,
         "centred-moving", "the centred grain, same dx and scheme"),
        ("Re about 1 (F x 5)", "hard/high_force.xml", [], nse, "Navier-Stokes FE"),
        ("Re about 1 (F x 5), moving particles, shifting", "hard/high_force.xml", MOVING + SHIFTING, nse,
         "Navier-Stokes FE"),
        ("Re about 1 (F x 5), moving particles, no shifting", "hard/high_force.xml", MOVING, nse, "Navier-Stokes FE"),
        ("long run, 1e5 steps", "hard/long_run.xml", [], c20, "Sangani-Acrivos"),
        ("long run, 1e5 steps, moving particles, shifting, re-summation every 20", "hard/long_run.xml",
         MOVING + SHIFTING + RESUM, c20, "Sangani-Acrivos"),
        ("long run, 1e5 steps, moving particles, shifting, no re-summation", "hard/long_run.xml", MOVING + SHIFTING,
         c20, "Sangani-Acrivos"),
        ("solid fraction 0.6", "square_array/square_array_c60.xml", ["Discretization/Particle Spacing=0.001"],
         SANGANI_ACRIVOS[0.6], "Sangani-Acrivos"),
        ("solid fraction 0.7", "square_array/square_array_c70.xml", ["Discretization/Particle Spacing=0.001"],
         SANGANI_ACRIVOS[0.7], "Sangani-Acrivos"),
        ("solid fraction 0.7, moving particles, shifting", "square_array/square_array_c70.xml",
         ["Discretization/Particle Spacing=0.001"] + MOVING + SHIFTING, SANGANI_ACRIVOS[0.7], "Sangani-Acrivos"),
    ]
    if not quick:
        rows += [
            ("throat 0.01 L = 2 dx", "hard/throat.xml", [], FINITE_ELEMENT["throat"], "finite elements"),
            ("touching grains (throat closed), dx = 0.005 L", "hard/touching.xml", [], FINITE_ELEMENT["touching"],
             "finite elements, extrapolated to zero gap"),
            ("throat 0.01 L = 4 dx", "hard/throat.xml", ["Discretization/Particle Spacing=0.00025"],
             FINITE_ELEMENT["throat"], "finite elements"),
        ]
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "hard-cases"))
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--ranks", type=int, default=None, help="run each case on this many MPI ranks")
    parser.add_argument("--only", default=None, help="run only the cases whose name contains this text")
    parser.add_argument("--csv", default="hard_cases.csv", help="file name of the CSV in --out")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    # References that are themselves runs.
    computed = {}
    computed["centred"] = run_poresph(args.build, "square_array/square_array_c20.xml", os.path.join(args.out, "centred"),
                                      ["Discretization/Particle Spacing=0.002"], ranks=args.ranks)
    computed["centred-moving"] = run_poresph(args.build, "square_array/square_array_c20.xml",
                                             os.path.join(args.out, "centred-moving"),
                                             ["Discretization/Particle Spacing=0.002"] + MOVING + SHIFTING,
                                             ranks=args.ranks)

    rows = []
    for number, (name, scene, settings, reference, reference_name) in enumerate(cases(args.quick)):
        if args.only and args.only not in name:
            continue
        s = run_poresph(args.build, scene, os.path.join(args.out, f"case{number:02d}"), settings, ranks=args.ranks,
                        allow_failure=True)
        # k along the force: kxx for F along x, kyy for F along y.
        measured = s.get("permeability", {})
        k = measured.get("kxx") if "kxx" in measured else measured.get("kyy")
        if isinstance(reference, str):
            ref_summary = computed.get(reference)
            reference = ref_summary["permeability"]["kxx"] / L**2 if ref_summary else None
        row = dict(case=name, scene=scene, settings=" ".join(settings), stopped_by=s["stopped_by"],
                   steps=s["steps"], wall_seconds=s["wall_seconds"],
                   max_density_variation=s["max_density_variation"],
                   max_density_drift=s.get("max_density_drift"),
                   particles_inside_grains=s.get("particles_inside_grains", 0),
                   grain_surface_corrections=s.get("grain_surface_corrections", 0),
                   k_over_L2=k / L**2 if k is not None else None, reference=reference,
                   reference_is=reference_name, reynolds=s.get("reynolds_number"),
                   failure=s.get("failure", ""), warnings=" | ".join(s.get("warnings", [])))
        row["relative_error"] = (row["k_over_L2"] / reference - 1) if reference and row["k_over_L2"] else None
        rows.append(row)
        print(f"{name}: {s['stopped_by']}, k/L^2 {row['k_over_L2']}, {s['wall_seconds']:.0f} s", file=sys.stderr,
              flush=True)
        write_csv(os.path.join(args.out, args.csv), rows)

    print("| case | ended by | max drho/rho | mean drift | inside grains (put back) | k/L^2 | reference | error % | Re | steps | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        k = f"{r['k_over_L2']:.5g}" if r["k_over_L2"] is not None else "-"
        ref = f"{r['reference']:.5g} ({r['reference_is']})" if r["reference"] else r["reference_is"]
        err = f"{100 * r['relative_error']:+.2f}" if r["relative_error"] is not None else "-"
        re = f"{r['reynolds']:.2f}" if r["reynolds"] is not None else "-"
        drift = f"{r['max_density_drift']:.4f}" if r["max_density_drift"] is not None else "-"
        print(f"| {r['case']} | {r['stopped_by']} | {r['max_density_variation']:.4f} | {drift} | "
              f"{r['particles_inside_grains']} ({r['grain_surface_corrections']}) | {k} | {ref} | {err} | {re} | "
              f"{r['steps']} | {r['wall_seconds']:.0f} |")


if __name__ == "__main__":
    main()
