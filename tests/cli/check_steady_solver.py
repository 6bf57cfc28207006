#!/usr/bin/python3
"""Solver/Method = steady from the command line (docs/steady_solver.md):

- the square array c = 0.2 at dx = 0.04 L, solved with the default
  Solver/Tolerance: its residual below it, and k within 0.1 % of the march's
  (Permeability/Steady Tolerance 1e-4, as the issue asks), with and without convection;
- solved to Solver/Tolerance 1e-6 (below, TIGHT), 1, 2 and 4 processes
  agree on k to 1e-5 (not bits: the sums go in another order);
- a solve held to 2 linear iterations does not converge: exit status 4, a
  warning, "converged": false, "steady": false, stopped_by not_converged,
  and a checkpoint from which --restart then converges to the same k; its
  warning names Solver/Max Inner Iterations only when the inner solves
  were near it (held to 1 iteration);
- a residual below Solver/Tolerance is not enough: k must have settled
  (its last Newton step's change, steady_relative_change, below Solver/
  Permeability Tolerance), else exit status 4 and a warning that says so;
- a linear solve that stalls with its inner solves at their cap raises
  the cap (Solver/Raised Inner Iterations; with Solver/DG Preconditioner =
  lattice, since auto switches the DG solves to local solves instead), and
  converges in far fewer linear iterations than with the cap held;
- the ladder, the tensor and the linearity check run with it;
- a channel solves to its k without a start-up profile check (a transient);
- moving particles are refused (exit 2, nothing written).

    check_steady_solver.py PORESPH_BINARY INPUT_DIR WORK_DIR
"""
import json
import os
import subprocess
import sys

poresph, inputs, work = sys.argv[1:4]
DEFAULT_TOLERANCE = 1e-4  # Solver/Tolerance's default (io/Parameters.cpp)
TIGHT = "Solver/Tolerance=1e-6"
scene = os.path.join(inputs, "square_array", "square_array_c20.xml")
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")
failures = 0


def check(ok, what):
    global failures
    failures += not ok
    print(f"{'ok' if ok else 'FAILED'}: {what}")


def run(name, settings, ranks=1, restart=None):
    out = os.path.join(work, name)
    command = (["mpiexec", "-n", str(ranks)] if ranks > 1 else []) + [poresph, scene]
    for setting in ["Discretization/Particle Spacing=0.004", "Run/Progress=never"] + settings:
        command += ["--set", setting]
    command += ["--output", out, "--overwrite"]
    if restart:
        command += ["--restart", restart]
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    summary = None
    if os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
    return done, summary, out


def kxx(summary):
    return summary["permeability"]["kxx"]


# The same answer as the march.
for convection in ("true", "false"):
    _, marched, _ = run(f"steady-march-{convection}", [f"Fluid/Convection={convection}",
                                                        "Permeability/Steady Tolerance=1e-4",
                                                        "Run/End Time=100000"])
    done, solved, _ = run(f"steady-solve-{convection}", [f"Fluid/Convection={convection}", "Solver/Method=steady"])
    solver = solved["solver"]
    check(done.returncode == 0 and solver["converged"] and solved["steady"] and solved["stopped_by"] == "steady_state",
          f"convection {convection}: converged in {solver['nonlinear_iterations']} Newton and "
          f"{solver['linear_iterations']} linear iterations, residual {solver['residual']:.2e}")
    keys = {"method", "converged", "nonlinear_iterations", "linear_iterations", "residual", "setup_seconds",
            "solve_seconds", "bytes_per_particle"}
    check(keys <= set(solver) and solver["method"] == "steady" and solver["residual"] <= DEFAULT_TOLERANCE
          and solver["bytes_per_particle"] > 0, f"solver keys {sorted(keys)}")
    change = kxx(solved) / kxx(marched) - 1
    check(abs(change) < 1e-3 and marched["steady"],
          f"convection {convection}: k solved {kxx(solved):.8e}, marched {kxx(marched):.8e} ({change:+.1e})")
    check(marched["solver"] == {"method": "explicit"}, "the march says it marched")
    check(0 < solved["steady_relative_change"] < 1e-3,
          f"convection {convection}: the last Newton step moved k by {solved['steady_relative_change']:.1e}")

# Ranks agree to the tolerance.
_, one, _ = run("steady-ranks-1", ["Solver/Method=steady", TIGHT])
for ranks in (2, 4):
    done, many, _ = run(f"steady-ranks-{ranks}", ["Solver/Method=steady", TIGHT], ranks)
    change = kxx(many) / kxx(one) - 1
    check(done.returncode == 0 and many["solver"]["converged"] and abs(change) < 1e-5,
          f"{ranks} ranks: k {kxx(many):.10e} against {kxx(one):.10e} ({change:+.1e})")

# A solve that cannot converge says so, and leaves its state for a restart.
done, capped, out = run("steady-capped", ["Solver/Method=steady", TIGHT, "Solver/Max Linear Iterations=2",
                                          "Solver/Max Nonlinear Iterations=1"])
check(done.returncode == 4, f"capped solve: exit status {done.returncode} (4 expected)")
check("did not converge" in done.stderr and any("did not converge" in w for w in capped["warnings"]),
      "capped solve: warning on stderr and in summary.json")
check(capped["solver"]["converged"] is False and capped["steady"] is False
      and capped["stopped_by"] == "not_converged" and capped["solver"]["linear_iterations"] == 2,
      f"capped solve: converged false, steady false, stopped_by {capped['stopped_by']}")
check(not any("Max Inner Iterations" in w for w in capped["warnings"]),
      "capped solve: its inner solves were far from their cap, and the warning does not name it")
checkpoint = os.path.join(out, "checkpoint.h5")
check(os.path.exists(checkpoint), "capped solve: checkpoint.h5 written")
# Inner solves held to one iteration: the warning names that cap.
done, inner, _ = run("steady-inner-capped", ["Solver/Method=steady", TIGHT, "Solver/Max Linear Iterations=2",
                                             "Solver/Max Nonlinear Iterations=1", "Solver/Max Inner Iterations=1"])
named = "Solver/Max Inner Iterations = 1 (raised when the solve stalls"
check(done.returncode == 4 and any(named in w for w in inner["warnings"]),
      "inner solves held to 1 iteration: exit status 4, the warning names Solver/Max Inner Iterations")
# k must have settled too: held to a change of 1e-12 a Newton step, three
# steps end with a residual far below the tolerance and k still moving.
done, unsettled, _ = run("steady-unsettled", ["Solver/Method=steady", "Solver/Permeability Tolerance=1e-12",
                                              "Solver/Max Nonlinear Iterations=3"])
check(done.returncode == 4 and unsettled["solver"]["converged"] is False and unsettled["steady"] is False
      and unsettled["solver"]["residual"] <= DEFAULT_TOLERANCE and unsettled["steady_relative_change"] > 1e-12
      and any("Solver/Permeability Tolerance" in w for w in unsettled["warnings"]),
      f"k not settled: exit status {done.returncode}, residual {unsettled['solver']['residual']:.1e}, the last "
      f"step moved k by {unsettled['steady_relative_change']:.1e}, the warning names Solver/Permeability Tolerance")
# A linear solve that stalls with its DG solves at the cap raises the cap
# (x4 at a time, at most to Solver/Raised Inner Iterations) where the DG
# solves keep the lattice cycle (auto, the default, switches them to local
# solves instead): with the cap fixed at 1 a linear iteration takes at
# most 3 inner ones (two DG solves, one of the velocity block), so more a
# linear iteration means it rose.
stalled = {}
for raised in (1, 1600):
    done, stalled[raised], _ = run(f"steady-raised-{raised}", ["Solver/Method=steady", "Solver/Max Inner Iterations=1",
                                                              "Solver/DG Preconditioner=lattice",
                                                              f"Solver/Raised Inner Iterations={raised}",
                                                              "Solver/Max Linear Iterations=300"])
fixed, raised = stalled[1]["solver"], stalled[1600]["solver"]
check(fixed["inner_iterations"] <= 3 * fixed["linear_iterations"], f"cap held at 1: {fixed['inner_iterations']} inner "
      f"in {fixed['linear_iterations']} linear iterations")
check(raised["converged"] and raised["inner_iterations"] > 3 * raised["linear_iterations"]
      and 2 * raised["linear_iterations"] < fixed["linear_iterations"],
      f"cap raised from 1: converged in {raised['linear_iterations']} linear iterations ({raised['inner_iterations']} "
      f"inner) against {fixed['linear_iterations']} with the cap held")
done, resumed, _ = run("steady-resumed", ["Solver/Method=steady", TIGHT], restart=checkpoint)
check(done.returncode == 0 and resumed["solver"]["converged"] and abs(kxx(resumed) / kxx(one) - 1) < 1e-5,
      f"restart of the capped solve: converged, k {kxx(resumed):.10e}")

# The ladder, the tensor, the linearity check.
done, ladder, _ = run("steady-ladder", ["Solver/Method=steady", TIGHT, "Convergence/Levels=2",
                                        "Permeability/Tensor=true", "Permeability/Linearity Check=true"])
check(done.returncode == 0 and ladder["solver"]["converged"] and len(ladder["convergence"]) == 2
      and "kyy" in ladder["permeability"] and "darcy_linearity" in ladder
      and abs(ladder["permeability"]["kxx"] / ladder["permeability"]["kyy"] - 1) < 1e-6
      and abs(ladder["darcy_linearity"]["kxx"]) < 1e-2,
      f"ladder, tensor, linearity: kxx {ladder['permeability']['kxx']:.8e}, kyy {ladder['permeability']['kyy']:.8e}, "
      f"darcy_linearity {ladder['darcy_linearity']['kxx']:+.1e}")

# A channel: its k, and no start-up profile check (a transient) reported for a solve.
poiseuille = os.path.join(inputs, "poiseuille.xml")
out = os.path.join(work, "steady-channel")
done = subprocess.run([poresph, poiseuille, "--set", "Solver/Method=steady", "--set", "Run/Progress=never",
                       "--output", out, "--overwrite"], env=env, capture_output=True, text=True)
with open(os.path.join(out, "summary.json")) as f:
    channel = json.load(f)
check(done.returncode == 0 and channel["solver"]["converged"] and "profile_error" not in channel
      and not os.path.exists(os.path.join(out, "profiles.csv")) and channel["permeability"]["kxx"] > 0,
      f"channel: converged, k {channel['permeability']['kxx']:.6e}, no profile_error, no profiles.csv")

# Moving particles have no steady state to solve for.
done, refused, out = run("steady-lagrangian", ["Solver/Method=steady", "Discretization/Particle Motion=lagrangian"])
check(done.returncode == 2 and "Solver/Method = steady" in done.stderr and not os.path.exists(out),
      "lagrangian particles refused, nothing written")
# Nor has an inviscid driven flow.
done, refused, out = run("steady-inviscid", ["Solver/Method=steady", "Fluid/Kinematic Viscosity=0"])
check(done.returncode == 2 and "Fluid/Kinematic Viscosity > 0" in done.stderr and not os.path.exists(out),
      "no viscosity refused, nothing written")

print("steady solver ok" if failures == 0 else f"{failures} checks failed")
sys.exit(1 if failures else 0)
