#!/usr/bin/python3
"""PySPH's own lattice_cylinders example against PoreSPH on the same scene,
one after the other on one core of this machine.

    perf/pysph_lattice_cylinders.py [--build build] [--out build/pysph-lattice] [--pysph-tf SECONDS]
                                    [--skip-pysph] [--skip-poresph]

The scene is PySPH's pysph/examples/lattice_cylinders.py (Debian's
python3-pysph, PySPH 1.0b1): one cylinder of radius 0.02 m at the centre of
a periodic square cell L = 0.1 m, nu = 1e-6 m^2/s, body force 1.5e-7 m/s^2
along x, the transport-velocity formulation (Adami, Hu & Adams 2013), 100
particles across, to t = 1000 s. PySPH runs that example unchanged through
/usr/bin/python3 (the system Python, which has Debian's packages), with
OMP_NUM_THREADS=1 and no --openmp; its scheme settings are read from the
example module. Its first run on a machine compiles the generated Cython
(into ~/.pysph); that setup is outside its time loop ("Run took"), and so
outside the table's wall seconds. PoreSPH runs
input/square_array/square_array_c20.xml with the grain and the force set to
the same, on one thread, until its k is steady.

k/L^2 = nu <u_x> / (F L^2), <u_x> the superficial velocity. PySPH reports
no permeability: it is computed from each of its output files (every 100
steps) as the sum of u_x dx^2 over the fluid particles over L^2. The
reference is the steady Navier-Stokes finite-element k/L^2 = 0.032669
(perf/stokes_reference.py --equations navier-stokes; Stokes 0.032948).

The example's end time, 1000 s, is short of a steady flow (k is still
rising there, by about 1.3 % in its last 50 s): --pysph-tf runs it longer (--tf),
e.g. to PoreSPH's steady time. The table gives both programs' k at PySPH's
end time too, so that the spin-ups can be compared at the same time.

Prints a Markdown table (program, particles fluid + solid, steps, dt, end
time, wall seconds of the time loop, CPU seconds of the whole process (the
machine is shared: wall time counts other jobs, CPU time does not),
particle-steps per second over the time loop, k/L^2 at the end, its error,
the change of k over the last 10 % of the run, the time from which k stays
within 0.5 % of its final value, and k/L^2 at PySPH's end time) and writes
pysph_lattice_cylinders.csv and both runs' k histories into --out.
"""
import argparse
import csv
import glob
import json
import os
import re
import resource
import subprocess
import sys
import time

from poresph_runs import ROOT, run_poresph, write_csv

SYSTEM_PYTHON = "/usr/bin/python3"
EXAMPLE = "pysph.examples.lattice_cylinders"
REFERENCE = 0.032669  # k / L^2, steady Navier-Stokes finite elements
STOKES = 0.032948
L = 0.1
SCENE = "square_array/square_array_c20.xml"
SETTINGS = ["Grains/Inline={0.05, 0.05, 0.02}", "Fluid/Body Force={1.5e-7, 0.0}"]
SETTLED = 0.005  # "k within 0.5 % of its final value"


def settled_at(history, tolerance=SETTLED):
    """The first (step, time) from which every later k is within tolerance
    of the last one."""
    final = history[-1][2]
    at = history[-1][:2]
    for step, t, k in reversed(history):
        if abs(k / final - 1) > tolerance:
            break
        at = (step, t)
    return at


def k_at(history, t):
    """k/L^2 at time t, linear between the samples (None beyond them)."""
    for (_, t0, k0), (_, t1, k1) in zip(history, history[1:]):
        if t0 <= t <= t1:
            return k0 + (k1 - k0) * (t - t0) / (t1 - t0)
    return None


def child_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def read_pysph_output(directory):
    """Runs under /usr/bin/python3 (--read-pysph-output): the example's
    settings and k/L^2 of each output file, as JSON on stdout."""
    import importlib
    from pysph.solver.utils import load

    ex = importlib.import_module(EXAMPLE)
    files = glob.glob(os.path.join(directory, "lattice_cylinders_*.hdf5")) + \
        glob.glob(os.path.join(directory, "lattice_cylinders_*.npz"))
    history = []
    fluid = solid = 0
    for name in sorted(files, key=lambda f: int(re.search(r"_(\d+)\.\w+$", f).group(1))):
        data = load(name)
        f = data["arrays"]["fluid"]
        real = f.tag == 0
        superficial = float(f.u[real].sum()) * ex.dx ** 2 / ex.L ** 2
        history.append((int(data["solver_data"]["count"]), float(data["solver_data"]["t"]),
                        ex.nu * superficial / (ex.fx * ex.L ** 2)))
        fluid, solid = int(real.sum()), data["arrays"]["solid"].get_number_of_particles()
    settings = dict(nx=ex.nx, dx=ex.dx, hdx=ex.hdx, h=ex.h0, c0=ex.c0, nu=ex.nu, fx=ex.fx, dt=ex.dt, tf=ex.tf,
                    pb=ex.p0, kernel="QuinticSpline (TVFScheme's default)", integrator="PECIntegrator")
    json.dump(dict(settings=settings, fluid=fluid, solid=solid, history=history), sys.stdout)


def pysph_installed():
    done = subprocess.run([SYSTEM_PYTHON, "-c", f"import {EXAMPLE}"], capture_output=True, text=True) \
        if os.path.exists(SYSTEM_PYTHON) else None
    return done is not None and done.returncode == 0


def run_pysph(out, tf=None):
    """Runs the example to its end time (or tf) on one thread; its figures."""
    directory = os.path.join(out, "pysph")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for stale in glob.glob(os.path.join(directory, "lattice_cylinders_*")):  # a previous run's output files
        os.remove(stale)
    cmd = [SYSTEM_PYTHON, "-m", EXAMPLE, "-d", directory] + (["--tf", repr(tf)] if tf else [])
    start, cpu = time.perf_counter(), child_cpu_seconds()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    total, cpu = time.perf_counter() - start, child_cpu_seconds() - cpu
    with open(os.path.join(out, "pysph.log"), "w") as f:
        f.write(done.stdout + done.stderr)
    if done.returncode != 0:
        sys.exit(f"pysph_lattice_cylinders: PySPH failed (exit status {done.returncode}), see {out}/pysph.log")
    loop = float(re.search(r"Run took: ([0-9.eE+-]+) secs", done.stdout).group(1))
    setup = float(re.search(r"Setup took: ([0-9.eE+-]+) secs", done.stdout).group(1))
    read = subprocess.run([SYSTEM_PYTHON, os.path.abspath(__file__), "--read-pysph-output", directory],
                          check=True, capture_output=True, text=True)
    result = json.loads(read.stdout)
    history = result["history"]
    steps = history[-1][0]
    particles = result["fluid"] + result["solid"]
    return dict(program="PySPH 1.0b1 (TVF)", fluid=result["fluid"], solid=result["solid"], steps=steps,
                dt=result["settings"]["dt"], end_time=history[-1][1], wall_seconds=loop, setup_seconds=setup,
                process_seconds=total, cpu_seconds=cpu, particle_steps_per_second=particles * steps / loop,
                k_over_L2=history[-1][2], history=history, settings=result["settings"])


def run_poresph_scene(build, out):
    directory = os.path.join(out, "poresph")
    start, cpu = time.perf_counter(), child_cpu_seconds()
    s = run_poresph(build, SCENE, directory, SETTINGS)
    total, cpu = time.perf_counter() - start, child_cpu_seconds() - cpu
    with open(os.path.join(directory, "permeability_history.csv")) as f:
        history = [(int(r["step"]), float(r["time"]), float(r["kxx"]) / L ** 2) for r in csv.DictReader(f)]
    return dict(program="PoreSPH", fluid=s["fluid_particles"], solid=s["boundary_particles"], steps=s["steps"],
                dt=s["time_step"], end_time=s["simulated_time"], wall_seconds=s["wall_seconds"],
                setup_seconds=s.get("setup_seconds", float("nan")), process_seconds=total, cpu_seconds=cpu,
                particle_steps_per_second=s["particle_steps_per_second"], k_over_L2=s["permeability"]["kxx"] / L ** 2,
                history=history, settings=dict(h=s["smoothing_length"], c0=s["sound_speed"],
                                               stopped_by=s["stopped_by"]))


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--read-pysph-output":
        read_pysph_output(sys.argv[2])
        return
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "pysph-lattice"))
    parser.add_argument("--pysph-tf", type=float, help="PySPH's end time (default: the example's, 1000 s)")
    parser.add_argument("--skip-pysph", action="store_true")
    parser.add_argument("--skip-poresph", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    rows = []
    if not args.skip_pysph:
        if pysph_installed():
            rows.append(run_pysph(args.out, args.pysph_tf))
            print(f"PySPH: settings {rows[-1]['settings']}", file=sys.stderr, flush=True)
        else:
            print(f"pysph_lattice_cylinders: PySPH is NOT installed: {SYSTEM_PYTHON} cannot import {EXAMPLE} "
                  "(apt-get install -y --no-install-recommends python3-pysph); PySPH is left out",
                  file=sys.stderr, flush=True)
            rows.append(dict(program="PySPH: not installed"))
    if not args.skip_poresph:
        rows.append(run_poresph_scene(args.build, args.out))

    compare_at = next((r["end_time"] for r in rows if r["program"].startswith("PySPH") and "end_time" in r),
                      args.pysph_tf or 1000.0)
    for r in rows:
        if "history" in r:
            r["settled_step"], r["settled_time"] = settled_at(r["history"])
            r["relative_error"] = r["k_over_L2"] / REFERENCE - 1
            r["last_tenth_change"] = r["k_over_L2"] / k_at(r["history"], 0.9 * r["history"][-1][1]) - 1
            r["k_at_compare_time"] = k_at(r["history"], compare_at)
            name = "pysph" if r["program"].startswith("PySPH") else "poresph"
            write_csv(os.path.join(args.out, f"k_history_{name}.csv"),
                      [dict(step=s, time=t, k_over_L2=k) for s, t, k in r.pop("history")])
    measured = [r for r in rows if "steps" in r]
    if measured:
        columns = [c for c in measured[0] if c != "settings"]
        write_csv(os.path.join(args.out, "pysph_lattice_cylinders.csv"),
                  [{c: r.get(c) for c in columns} for r in measured])

    print(f"| program | particles (fluid + solid) | steps | dt s | end time s | wall s (time loop) | CPU s (process) "
          f"| particle-steps/s | k/L^2 | error vs {REFERENCE} | change over last 10 % | within 0.5 % of final from "
          f"| k/L^2 at t = {compare_at:g} s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "steps" not in r:
            print(f"| {r['program']} |" + " |" * 12)
            continue
        at = f"{r['k_at_compare_time']:.5f}" if r["k_at_compare_time"] is not None else "(not reached)"
        print(f"| {r['program']} | {r['fluid'] + r['solid']} ({r['fluid']} + {r['solid']}) | {r['steps']} "
              f"| {r['dt']:.4g} | {r['end_time']:.4g} | {r['wall_seconds']:.1f} | {r['cpu_seconds']:.1f} "
              f"| {r['particle_steps_per_second']:.3g} | {r['k_over_L2']:.5f} | {100 * r['relative_error']:+.2f} % "
              f"| {100 * r['last_tenth_change']:+.2f} % | t = {r['settled_time']:.4g} s (step {r['settled_step']}) "
              f"| {at} |")
    print(f"\nStokes k/L^2 = {STOKES}. Particles: PoreSPH counts its boundary particles (those within the kernel "
          "support of the fluid), PySPH every particle of the filled disc; particle-steps/s are over both.")


if __name__ == "__main__":
    main()
