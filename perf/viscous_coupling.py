#!/usr/bin/python3
"""Viscous coupling of two phases on drained problem III
(input/two_phase/drainage_problem3.xml: the non-wetting phase 1, twice as
viscous, placed by drainage at S_nw >= 0.75): the body force on both
phases, on the wetting phase 0 alone and on the non-wetting phase 1 alone
(Phases/Driven Phase), at 0.02, 0.01 and 0.005 L, each solved for its
steady state. With --saturation, SCENE is a scene of one fluid: each
spacing first runs it alone for its k, and then with phase 1 placed by
drainage at that target (Phases/Phase 1/Drainage/Saturation), MU_RATIO
times as viscous.

    perf/viscous_coupling.py [--build build] [--out build/viscous-coupling] [--spacings 0.002 0.001 0.0005]
    perf/viscous_coupling.py --scene 3d/random_pack.xml --length 0.09 --spacings 0.0025 0.001875 \
        --saturation 0.5 --set ...        # a one-fluid scene: its phases added, k from a run of one fluid

Prints the Markdown table of docs/validation.md (section 10): per spacing
the saturation, the four coupling coefficients k_r,ij (phase i's k_r with
the force on phase j alone), how far k_r,i0 + k_r,i1 is from k_r,i of the
run with both driven (linearity), and how far k_r,10 / mu_1 is from
k_r,01 / mu_0 (reciprocity).
"""
import argparse
import os

from poresph_runs import run_poresph  # noqa: E402

SCENE = "two_phase/drainage_problem3.xml"
MU_RATIO = 2.0  # the non-wetting phase's viscosity over the wetting phase's, as in SCENE
NU = 1e-6  # phase 0's, the scenes' Fluid/Kinematic Viscosity


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="build/viscous-coupling")
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.002, 0.001, 0.0005])
    parser.add_argument("--scene", default=SCENE)
    parser.add_argument("--length", type=float, default=0.1, help="the cell's side L (m)")
    parser.add_argument("--saturation", type=float, default=None,
                        help="add the phases to a scene of one fluid, phase 1 drained to this target")
    parser.add_argument("--set", action="append", default=[], help="more --set settings for every run")
    args = parser.parse_args()
    print("| spacing (L) | S_nw | k_r,ww | k_r,w,nw | k_r,nw,w | k_r,nw,nw | linearity w, nw | "
          "k_r,nw,w / (2 k_r,w,nw) - 1 | wall s (3 runs) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for dx in args.spacings:
        kr, seconds = {}, 0.0
        common = [f"Discretization/Particle Spacing={dx!r}"] + args.set
        if args.saturation is not None:
            single = run_poresph(args.build, args.scene, os.path.join(args.out, f"dx{dx:g}-single"),
                                 common + ["Solver/Method=steady"])
            common += ["Solver/Method=steady", "Phases/Count=2",
                       f"Phases/Phase 1/Kinematic Viscosity={NU * MU_RATIO!r}",
                       f"Phases/Phase 1/Drainage/Saturation={args.saturation!r}",
                       f"Phases/Single Phase Permeability={single['permeability']['kxx']!r}"]
        for driven in ("both", "0", "1"):
            summary = run_poresph(args.build, args.scene, os.path.join(args.out, f"dx{dx:g}-driven-{driven}"),
                                  common + [f"Phases/Driven Phase={driven}"])
            assert summary["stopped_by"] == "steady_state", summary["stopped_by"]
            kr[driven] = [p["relative_permeability"] for p in summary["phases"]]
            saturation = summary["phases"][1]["saturation"]
            seconds += summary["wall_seconds"] + summary["setup_seconds"]
        linearity = [(kr["0"][i] + kr["1"][i]) / kr["both"][i] - 1 for i in range(2)]
        reciprocity = kr["0"][1] / MU_RATIO / kr["1"][0] - 1
        print(f"| {dx / args.length:g} | {saturation:.4f} | {kr['0'][0]:.5f} | {kr['1'][0]:.5f} | {kr['0'][1]:.5f} | "
              f"{kr['1'][1]:.5f} | {linearity[0]:.1e}, {linearity[1]:.1e} | {reciprocity:.2e} | {seconds:.1f} |")


if __name__ == "__main__":
    main()
