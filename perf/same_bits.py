#!/usr/bin/env python3
"""Whether two builds of poresph give the same results bit for bit, and how
fast each runs its time loop.

    perf/same_bits.py --reference OLD_BUILD_DIR --candidate build --out DIR
    perf/same_bits.py ... --timing problem3 --repeats 5

Each scene of SCENES runs once with each build (short runs, --set
overrides below), with the final particles written (Output/Final Particles
CSV); then summary.json (all but the timings), every history file and
particles.csv of the two must be equal byte for byte (.csv files that
only the candidate writes are new outputs, not compared). The scenes cover
every compiled variant of the pair loop: fixed particles with channel
walls, grains (2D and 3D) and an image; moving particles with and without
surfaces, with shifting, with the paper's wall continuity.

--timing SCENE runs that scene alternately with each build (A B A B ...,
--repeats times each, one core), and prints particle-steps per second of
the time loop (summary.json), their medians, the median of the per-pair
ratios candidate / reference, and the fastest run of each (the least
disturbed by other work on the machine)."""
import argparse
import filecmp
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMINGS = {"wall_seconds", "setup_seconds", "particle_steps_per_second"}

# name: (scene file under input/, --set overrides)
SCENES = {
    "channel": ("poiseuille.xml", ["Run/Max Steps=3000"]),
    "channel_wall_continuity": ("poiseuille.xml", ["Run/Max Steps=1000", "Discretization/Wall Pressure=continuity"]),
    "problem3": ("problem3/problem3.xml", ["Run/Max Steps=1500"]),
    "simple_cubic": ("3d/simple_cubic.xml", ["Run/Max Steps=200"]),
    "simple_cubic_40": ("3d/simple_cubic.xml", ["Run/Max Steps=100", "Discretization/Particle Spacing=0.0025"]),
    "image_pack": ("image/sphere_pack.xml", ["Run/Max Steps=200"]),
    "box_40": ("problem1/problem1.xml", [
        "Run/Max Steps=100", "Domain/Cell Size={0.1, 0.1, 0.1}", "Discretization/Particle Spacing=0.0025"]),
    "problem3_moving_shifting": ("problem3/problem3.xml", [
        "Run/Max Steps=600", "Discretization/Particle Motion=lagrangian", "Discretization/Particle Shifting=0.5"]),
    "problem1_moving": ("problem1/problem1.xml", ["Run/Max Steps=600", "Discretization/Particle Motion=lagrangian"]),
}
# For --timing: longer runs of the same scenes.
TIMING_STEPS = {"channel": 6000, "problem3": 3000, "simple_cubic": 300, "simple_cubic_40": 150, "image_pack": 300,
                "box_40": 150,
                "problem3_moving_shifting": 1500, "problem1_moving": 1500}


def run(build, name, directory, extra=(), steps=None):
    """Runs SCENES[name] (with `steps` instead of its Run/Max Steps if given)."""
    scene, settings = SCENES[name]
    if steps is not None:
        settings = [s for s in settings if not s.startswith("Run/Max Steps=")] + [f"Run/Max Steps={steps}"]
    cmd = [os.path.join(build, "poresph"), os.path.join(ROOT, "input", scene), "--output", directory, "--overwrite"]
    for s in list(settings) + list(extra):
        cmd += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false", KOKKOS_DISABLE_WARNINGS="1")
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def summary_of(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def compare(a_dir, b_dir):
    """The differences between two runs' results, as text lines (none: equal)."""
    problems = []
    with open(os.path.join(a_dir, "summary.json")) as f:
        a = json.load(f)
    with open(os.path.join(b_dir, "summary.json")) as f:
        b = json.load(f)
    # A key only the candidate reports is a new output, not a changed result (main() lists them).
    for key in sorted(set(a) | set(b)):
        if key in TIMINGS or key not in a:
            continue
        if a.get(key) != b.get(key):
            problems.append(f"summary.json {key}: {a.get(key)!r} != {b.get(key)!r}")
    files = sorted(f for f in os.listdir(a_dir) if f.endswith(".csv"))
    # A file only the candidate writes is a new output, not a changed result.
    missing = sorted(set(files) - {f for f in os.listdir(b_dir) if f.endswith(".csv")})
    if missing:
        problems.append("not written by the candidate: " + ", ".join(missing))
        files = [f for f in files if f not in missing]
    for name in files:
        if not filecmp.cmp(os.path.join(a_dir, name), os.path.join(b_dir, name), shallow=False):
            problems.append(f"{name} differs")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reference", required=True, help="build directory (or a directory holding poresph) of the reference")
    parser.add_argument("--candidate", required=True, help="build directory of the build to check")
    parser.add_argument("--out", required=True, help="where the runs go")
    parser.add_argument("--scenes", nargs="*", default=list(SCENES), choices=list(SCENES))
    parser.add_argument("--timing", choices=list(TIMING_STEPS))
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.timing:
        extra = ["Permeability/Steady Tolerance=0"]
        rates = {"reference": [], "candidate": []}
        for repeat in range(args.repeats):
            for which in ("reference", "candidate"):
                build = getattr(args, which)
                s = run(build, args.timing, os.path.join(args.out, f"timing-{args.timing}-{which}"), extra,
                        TIMING_STEPS[args.timing])
                rates[which].append(s["particle_steps_per_second"])
                print(f"{args.timing} repeat {repeat} {which}: {s['particle_steps_per_second']:.4g} particle-steps/s",
                      flush=True)
        ratios = [c / r for r, c in zip(rates["reference"], rates["candidate"])]
        print(f"{args.timing}: reference median {statistics.median(rates['reference']):.4g}, candidate median "
              f"{statistics.median(rates['candidate']):.4g}, candidate/reference median {statistics.median(ratios):.3f} "
              f"({min(ratios):.3f}-{max(ratios):.3f}, {args.repeats} pairs); fastest runs {max(rates['reference']):.4g} "
              f"and {max(rates['candidate']):.4g}, ratio {max(rates['candidate']) / max(rates['reference']):.3f}")
        return 0
    failed = 0
    for name in args.scenes:
        dirs = {}
        for which in ("reference", "candidate"):
            dirs[which] = os.path.join(args.out, f"{name}-{which}")
            if which == "reference" and os.path.exists(os.path.join(dirs[which], "summary.json")):
                continue  # the reference's runs are kept between checks
            run(getattr(args, which), name, dirs[which], ["Output/Final Particles CSV=true"])
        problems = compare(dirs["reference"], dirs["candidate"])
        new_keys = sorted(set(summary_of(dirs["candidate"])) - set(summary_of(dirs["reference"])))
        print(f"{name}: {'same bits' if not problems else 'DIFFERENT'}"
              + (f" (new in summary.json: {', '.join(new_keys)})" if new_keys else ""), flush=True)
        for p in problems:
            print("   ", p)
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
