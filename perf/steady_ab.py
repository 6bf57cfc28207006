#!/usr/bin/env python3
"""Two builds of poresph on one steady solve, interleaved: solve seconds,
iterations and k of each, and whether k is the same to the bit.

    perf/steady_ab.py --reference OLD_BUILD_DIR --candidate build \\
        --scene input/problem3/problem3.xml \\
        --set "Discretization/Particle Spacing=0.0005" --repeats 3 --out DIR

Runs reference, candidate, reference, candidate, ... (--repeats each) on one
core (taskset -c CORE, Run/Backend = serial, Solver/Method = steady unless
--set says otherwise), or with --ranks N under mpirun -np N --bind-to core,
and prints, per build, the median solve seconds
(summary.json's solver.solve_seconds), the median of the per-pair ratios
candidate / reference, the Newton, linear and inner iterations and the
permeability. --candidate-set gives the candidate settings of its own, so
that one build against itself measures a parameter. Iterations and k that
differ between the builds are printed as such: a change meant to leave the
arithmetic alone must leave them equal. A solve that ends unconverged (exit
status 4) is measured like the others, its iterations marked "not converged".
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(build, scene, sets, directory, core, ranks=0):
    launch = (["mpirun", "-np", str(ranks), "--bind-to", "core"] + (["--oversubscribe"] if ranks > 2 else [])
              if ranks > 0 else ["taskset", "-c", str(core)])
    cmd = launch + [os.path.join(build, "poresph"), scene, "--output", directory, "--overwrite",
                    "--set", "Run/Backend=serial", "--set", "Solver/Method=steady"]
    for s in sets:
        cmd += ["--set", s]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    # Exit status 4: the solve ended unconverged (k not settled, or a cap) and
    # said so; its time and iterations still compare. Any other failure stops.
    status = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env).returncode
    if status not in (0, 4):
        raise subprocess.CalledProcessError(status, cmd)
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    solver = summary["solver"]
    counts = (solver["nonlinear_iterations"], solver["linear_iterations"], solver["inner_iterations"])
    if not solver["converged"]:
        counts += ("not converged",)
    return solver["solve_seconds"], counts, summary.get("permeability", {})


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reference", required=True, help="build directory (holding poresph) of the code before")
    parser.add_argument("--candidate", required=True, help="build directory of the code after")
    parser.add_argument("--scene", required=True, help="scene XML")
    parser.add_argument("--set", action="append", default=[], help="PATH=VALUE, passed to both builds")
    parser.add_argument("--candidate-set", action="append", default=[],
                        help="PATH=VALUE, passed to the candidate only (after --set): a parameter's A/B on one build")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--core", type=int, default=0)
    parser.add_argument("--ranks", type=int, default=0, help="processes under mpirun (0: one, pinned to --core)")
    parser.add_argument("--out", required=True, help="directory for the runs' outputs")
    args = parser.parse_args()

    builds = {"reference": args.reference, "candidate": args.candidate}
    seconds = {name: [] for name in builds}
    last = {}
    for r in range(args.repeats):
        for name, build in builds.items():
            directory = os.path.join(args.out, f"{name}_{r}")
            sets = args.set + (args.candidate_set if name == "candidate" else [])
            t, counts, k = run(build, args.scene, sets, directory, args.core, args.ranks)
            seconds[name].append(t)
            last[name] = (counts, k)
            print(f"{name} {r}: {t:.2f} s, Newton/linear/inner {counts}", flush=True)
    ratios = [c / r for r, c in zip(seconds["reference"], seconds["candidate"])]
    for name in builds:
        counts, k = last[name]
        print(f"{name}: median {statistics.median(seconds[name]):.2f} s, iterations {counts}, "
              f"k {json.dumps(k)}")
    print(f"candidate / reference: median of pairs {statistics.median(ratios):.3f} "
          f"({', '.join(f'{x:.3f}' for x in ratios)})")
    same_counts = last["reference"][0] == last["candidate"][0]
    same_k = last["reference"][1] == last["candidate"][1]
    print(f"iterations {'the same' if same_counts else 'DIFFER'}, k {'the same bits' if same_k else 'DIFFERS'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
