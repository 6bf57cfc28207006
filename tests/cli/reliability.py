#!/usr/bin/python3
"""Hostile input and faults, one class of failure per call (docs/reliability.md):

    reliability.py CLASS POREESPH WORK_DIR MPIEXEC

Every case runs the executable as a user would and asserts three things: the
exit status, the message, and the state of the output directory afterwards
(nothing written, nothing overwritten, nothing mixed). A case prints "ok" or
what failed; the script fails if any case did.
"""
import csv
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

CLASS, POREESPH, WORK, MPIEXEC = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
HERE = os.path.dirname(os.path.abspath(__file__))
TINY = os.path.join(HERE, "tiny.xml")
INPUT = os.path.join(os.path.dirname(os.path.dirname(HERE)), "input")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")
failures = []


def path(*parts):
    return os.path.join(WORK, *parts)


def fresh(name):
    """An empty work directory of this class; returns where a run's output goes inside it."""
    base = path(name)
    shutil.rmtree(base, ignore_errors=True)
    os.makedirs(base)
    return os.path.join(base, "out")


def write(file, text):
    with open(file, "w") as f:
        f.write(text)
    return file


def snapshot(directory):
    """Every file below directory, by relative name, with the hash of its bytes; None if there is no directory."""
    if not os.path.exists(directory):
        return None
    state = {}
    for root, _, files in os.walk(directory):
        for name in files:
            full = os.path.join(root, name)
            if not os.path.isfile(full):  # a link to a device (/dev/full) is recorded, not read
                state[os.path.relpath(full, directory)] = "-> " + os.path.realpath(full)
                continue
            with open(full, "rb") as f:
                state[os.path.relpath(full, directory)] = hashlib.sha256(f.read()).hexdigest()
    return state


def run(args, env=None, mpi=0, timeout=600, preexec=None):
    cmd = ([MPIEXEC, "-n", str(mpi)] if mpi else []) + [POREESPH] + args
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env or ENV,
                          timeout=timeout, preexec_fn=preexec)
    return done.returncode, done.stdout


def good_run(out, *settings):
    """A short valid run of tiny.xml into out (which must end well)."""
    args = [TINY, "--output", out, "--set", "Run/Max Steps=20"]
    for s in settings:
        args += ["--set", s]
    status, output = run(args)
    assert status == 0, f"the preparatory run into {out} failed ({status}):\n{output}"


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


# What the output directory must look like afterwards: each returns "" or what is wrong.
def absent(directory):
    return lambda: "" if not os.path.exists(directory) else f"{directory} exists: {sorted(os.listdir(directory))}"


def unchanged(directory):
    before = snapshot(directory)
    def test():
        after = snapshot(directory)
        if after == before:
            return ""
        if before is None or after is None:
            return f"{directory}: {'created' if before is None else 'removed'}"
        changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
        return f"{directory}: changed {changed}"
    return test


def case(name, args, status, message, after, **run_options):
    """Runs poresph ARGS and checks exit status, output against the regex `message`, and after()."""
    try:
        got, output = run(args, **run_options)
        problems = []
        if got != status:
            problems.append(f"exit status {got}, expected {status}")
        if not re.search(message, output, re.S):
            problems.append(f"output does not match /{message}/")
        state = after() if after else ""
        if state:
            problems.append(state)
    except Exception as e:  # a case that cannot even run is a failed case, not a crashed script
        problems, output = [f"{type(e).__name__}: {e}"], ""
    report(name, problems, output)


def report(name, problems, output=""):
    if problems:
        failures.append(name)
        print(f"FAILED {name}: {'; '.join(problems)}\n--- output ---\n{output}--------------")
    else:
        print(f"ok     {name}")


def both(*checks):
    def test():
        return "; ".join(p for p in (c() for c in checks) if p)
    return test


# ---------------------------------------------------------------------------------------------------
def class_1_counts():
    """Counts in checked arithmetic; particles and memory estimated before allocating; no fluid refused."""
    out = fresh("steps")
    case("End Time / dt beyond 2^62 steps is refused, not wrapped to one step",
         [TINY, "--output", out, "--set", "Run/End Time=1e300"], 2,
         r"Run/End Time = 1e\+300 s at a time step of .* steps: more than PoreSPH counts", absent(out))
    out = fresh("steps-limited")
    case("the same end time with Run/Max Steps runs to the limit",
         [TINY, "--output", out, "--set", "Run/End Time=1e300", "--set", "Run/Max Steps=7"], 0, r"7 steps",
         lambda: "" if (summary(out)["steps"], summary(out)["stopped_by"]) == (7, "max_steps")
         else f"summary says {summary(out)['steps']} steps, stopped by {summary(out)['stopped_by']}")
    out = fresh("lattice-wraps")
    case("a lattice count beyond an int is refused, not wrapped to no particles",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=1e-12"], 2,
         r"Cell Size\[0\] / Discretization/Particle Spacing = 1 / 1e-12 = 1e\+12 lattice points across", absent(out))
    out = fresh("memory")
    case("a run that cannot fit in memory is refused naming particles and memory",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=1e-6"], 2,
         r"needs about 1000000000000 particles \(lattice 1000000 x 1000000.*\) and about [0-9.]+ TB of memory", absent(out))
    out = fresh("memory-limit")
    case("Run/Memory Limit refuses a run that would exceed it",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.001", "--set", "Run/Memory Limit=0.05"], 2,
         r"needs about 1000000 particles .* and about [0-9.]+ MB of memory .* but it has 50 MB \(Run/Memory Limit\)",
         absent(out))
    out = fresh("memory-steady")
    case("the steady solver's vectors are counted: a run that fits marching is refused solving",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.002", "--set", "Run/Memory Limit=0.4",
          "--set", "Solver/Method=steady"], 2,
         r"needs about 250000 particles .*; the steady solver's vectors alone need [0-9.]+ MB .*, but it has 400 MB",
         absent(out))
    out = fresh("grid")
    case("a grid of Output/Grid Points that needs too much memory is refused before allocating",
         [TINY, "--output", out, "--set", "Output/Grid Points={1000000, 1000000}", "--set", "Output/Field Interval=1"], 2,
         r"the grid of Output/Grid Points alone \(1000000000000 nodes\) needs [0-9.]+ TB", absent(out))
    out = fresh("no-fluid")
    case("a scene without a fluid particle is refused",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.25", "--set", "Grains/Allow Overlap=true",
          "--set", "Grains/Inline={0.5, 0.5, 0.5, 0, 0, 0.5}"], 2, r"the scene has no fluid particle", absent(out))
    case("--help-parameters says that a run that does not fit is refused",
         ["--help-parameters"], 0, r"Memory Limit : double = 0.*refused, naming both", None)


def class_2_xml():
    """The XML is read as strictly as --set, by the same parser; a name given twice is refused."""
    tiny = open(TINY).read()
    base = fresh("xml")
    def variant(name, old, new):
        assert old in tiny, old
        return write(os.path.join(os.path.dirname(base), name), tiny.replace(old, new, 1))
    bad = variant("trailing.xml", 'value="0.05"', 'value="0.05abc"')
    case("a number with trailing text in the XML is refused", [bad, "--output", base], 2,
         r"trailing.xml: Discretization/Particle Spacing: '0.05abc' is not a number", absent(base))
    case("the same text through --set gets the same message",
         [TINY, "--output", base, "--set", "Discretization/Particle Spacing=0.05abc"], 2,
         r"--set Discretization/Particle Spacing: '0.05abc' is not a number", absent(base))
    bad = variant("nan.xml", '"Kinematic Viscosity" type="double" value="0.01"',
                  '"Kinematic Viscosity" type="double" value="nan"')
    case("NaN in the XML is refused", [bad, "--output", base], 2,
         r"Fluid/Kinematic Viscosity: 'nan' is not a finite number", absent(base))
    bad = variant("array.xml", 'value="{1.0, 1.0}"', 'value="{1.0, 1.0x}"')
    case("an array element with trailing text is refused", [bad, "--output", base], 2,
         r"Domain/Cell Size: '\{1.0, 1.0x\}' has element 2 '1.0x' that is not a number", absent(base))
    bad = variant("twice.xml", '<Parameter name="Kinematic Viscosity" type="double" value="0.01"/>',
                  '<Parameter name="Kinematic Viscosity" type="double" value="0.01"/>'
                  '<Parameter name="Kinematic Viscosity" type="double" value="0.02"/>')
    case("a parameter given twice in one sublist is refused", [bad, "--output", base], 2,
         r"Fluid/Kinematic Viscosity is given twice in group Fluid", absent(base))
    bad = variant("sublist-twice.xml", '<ParameterList name="Run">',
                  '<ParameterList name="Run"><Parameter name="Max Steps" type="int" value="5"/></ParameterList>'
                  '<ParameterList name="Run">')
    case("a sublist given twice is refused", [bad, "--output", base], 2, r"Run is given twice at the top level",
         absent(base))
    bad = variant("int.xml", '<Parameter name="End Time" type="double" value="10.0"/>',
                  '<Parameter name="End Time" type="double" value="10.0"/><Parameter name="Max Steps" type="int" value="12.5"/>')
    case("a fractional integer is refused, not truncated", [bad, "--output", base], 2,
         r"Run/Max Steps: '12.5' is not an integer", absent(base))
    bad = variant("misspelt.xml", '"Kinematic Viscosity"', '"Kinematic Viscocity"')
    case("a misspelt name is refused with the likely one", [bad, "--output", base], 2,
         r"unknown parameter Fluid/Kinematic Viscocity; did you mean 'Kinematic Viscosity'", absent(base))
    # What PoreSPH writes, Teuchos's own XML with its extra attributes and validators, reads back.
    out = fresh("xml-roundtrip")
    good_run(out)
    again = fresh("xml-roundtrip-again")
    case("parameters_used.xml of a run is a scene that reads back",
         [os.path.join(out, "parameters_used.xml"), "--output", again, "--set", "Run/Max Steps=20"], 0, r"summary in",
         lambda: "" if summary(again)["fluid_particles"] == summary(out)["fluid_particles"] else "another scene")


def class_3_grains():
    """Grain files that are not what they seem are refused, naming file and line."""
    base = fresh("grains")
    files = os.path.dirname(base)
    cases = [
        ("an empty grain file", write(os.path.join(files, "empty.txt"), ""), r"empty.txt' holds no grain"),
        ("a grain file of comments only", write(os.path.join(files, "comments.txt"), "# cx cy r\n\n"),
         r"comments.txt' holds no grain"),
        ("a directory as grain file", files, r"it is a directory, not a grain file"),
        ("a device as grain file", "/dev/null", r"'/dev/null': it is not a regular file"),
        ("a NaN coordinate", write(os.path.join(files, "nan.txt"), "0.5 0.5 0.1\n0.2 nan 0.1\n"),
         r"nan.txt:2: 'nan' is not a finite number"),
        ("an infinite radius", write(os.path.join(files, "inf.txt"), "# c r\n0.5 0.5 inf\n"),
         r"inf.txt:2: 'inf' is not a finite number"),
        ("a number with trailing text", write(os.path.join(files, "trailing.txt"), "0.5 0.5x 0.1\n"),
         r"trailing.txt:1: '0.5x' is not a number"),
        ("a column more without a header naming it", write(os.path.join(files, "extra.txt"), "0.5 0.5 0.1 2000\n"),
         r"extra.txt:1: expected 3 numbers \(cx cy r\), found 4 \(as a file of 3D grains has\); a density column "
         r"needs a first line naming"),
        ("a grain without the density its header names",
         write(os.path.join(files, "no-density.txt"), "cx cy r density\n0.3 0.5 0.1 2000\n0.7 0.5 0.1\n"),
         r"no-density.txt:3: expected 4 numbers \(cx cy r density, as the header names them\), found 3"),
    ]
    for name, grain_file, message in cases:
        case(name + " is refused", [TINY, "--output", base, "--set", f"Grains/File={grain_file}"], 2, message,
             absent(base))
    # Grains that move: what they need, said before anything runs.
    grain = "Grains/Inline={0.5, 0.5, 0.2}"
    two_grains = "Grains/Inline={0.3, 0.5, 0.1, 0.7, 0.5, 0.1}"
    lagrangian = "Discretization/Particle Motion=lagrangian"
    densities = "Grains/File=" + write(os.path.join(files, "densities.txt"),
                                       "cx cy r density\n0.3 0.5 0.1 2000\n0.7 0.5 0.1 3000\n")
    motion_cases = [
        ("grain densities in the file and grains without in Grains/Inline",
         [densities, grain, "Grains/Motion=free", lagrangian],
         r"Grains/File gives each grain a density and Grains/Inline gives grains without one"),
        ("grain densities both in the file and in Grains/Density",
         [densities, "Grains/Motion=free", "Grains/Density=2000", lagrangian],
         r"Grains/Density and the grain file's density column both give the grains' density: give it one way"),
        ("moving grains in a fixed fluid", [grain, "Grains/Motion=free", "Grains/Density=2000"],
         r"Grains/Motion = free needs a fluid that moves with them: set Discretization/Particle Motion = lagrangian"),
        ("moving grains without a density", [grain, "Grains/Motion=rotating", lagrangian],
         r"Grains/Motion = rotating needs Grains/Density"),
        ("moving grains without grains", ["Grains/Motion=free", "Grains/Density=2000", lagrangian],
         r"Grains/Motion = free moves grains, and the scene has none"),
        ("gravity on grains that hold still", [grain, "Grains/Gravity={0, -9.81}"],
         r"Grains/Gravity acts on moving grains"),
        ("gravity of the wrong dimension", [grain, "Grains/Motion=free", "Grains/Density=2000", lagrangian,
                                            "Grains/Gravity={0, 0, -9.81}"],
         r"Grains/Gravity must have one value per direction \(2\)"),
        ("a negative grain density", [grain, "Grains/Density=-1"], r"Grains/Density"),
        ("a start velocity for grains that hold still", [grain, "Grains/Initial Velocity={0.1, 0}"],
         r"Grains/Initial Velocity sets moving grains going: with Grains/Motion = fixed"),
        ("a start velocity for grains that only turn", [grain, "Grains/Motion=rotating", "Grains/Density=2000",
                                                        lagrangian, "Grains/Initial Velocity={0.1, 0}"],
         r"with Grains/Motion = rotating they are held"),
        ("a start velocity of the wrong count", [grain, "Grains/Motion=free", "Grains/Density=2000", lagrangian,
                                                 "Grains/Initial Velocity={0.1, 0, 0}"],
         r"Grains/Initial Velocity has 3 values: give 2 \(every grain alike\) or 2"),
        ("a contact that restitutes nothing", [grain, "Grains/Contact/Restitution=0"], r"Restitution"),
        ("a contact that restitutes more than it got", [grain, "Grains/Contact/Restitution=1.5"], r"Restitution"),
        ("a negative Young's modulus", [grain, "Grains/Contact/Young Modulus=-1"], r"Young Modulus"),
        ("a held grain that is not there", [grain, "Grains/Motion=free", "Grains/Density=2000", lagrangian,
                                            "Grains/Held={3}"],
         r"Grains/Held names grain 3, and the scene has 1"),
        ("held grains where all hold still", [grain, "Grains/Held={0}"],
         r"Grains/Held names grains that hold still while the others move: with Grains/Motion = fixed"),
        ("every grain held", [grain, "Grains/Motion=free", "Grains/Density=2000", lagrangian, "Grains/Held={0}"],
         r"Grains/Held holds every grain: nothing moves"),
        ("a start spin for grains that hold still", [grain, "Grains/Initial Spin={0.1}"],
         r"Grains/Initial Spin sets moving grains going: with Grains/Motion = fixed"),
        ("a start spin of the wrong count", [grain, "Grains/Motion=rotating", "Grains/Density=2000", lagrangian,
                                             "Grains/Initial Spin={0.1, 0.2, 0.3}"],
         r"Grains/Initial Spin has 3 values: give 1 \(every grain alike\) or 1"),
        ("a prescribed grain where all hold still", [grain, "Grains/Prescribed={0}"],
         r"Grains/Prescribed names grains that keep their initial velocity and spin: with Grains/Motion = fixed"),
        ("a prescribed grain of grains that only turn", [grain, "Grains/Motion=rotating", "Grains/Density=2000",
                                                         lagrangian, "Grains/Prescribed={0}"],
         r"Grains/Prescribed moves grains at their initial velocity: with Grains/Motion = rotating"),
        ("a prescribed grain that is not there", [two_grains, "Grains/Motion=free", "Grains/Density=2000",
                                                  lagrangian, "Grains/Prescribed={2}"],
         r"Grains/Prescribed names grain 2, and the scene has 2"),
        ("a grain both held and prescribed", [two_grains, "Grains/Motion=free", "Grains/Density=2000", lagrangian,
                                              "Grains/Held={0}", "Grains/Prescribed={0}"],
         r"Grains/Held holds grain 0 still, and Grains/Prescribed moves it as set"),
        ("every grain held or prescribed", [two_grains, "Grains/Motion=free", "Grains/Density=2000", lagrangian,
                                            "Grains/Held={0}", "Grains/Prescribed={1}"],
         r"Grains/Held and Grains/Prescribed set the motion of every grain"),
        ("a rebalance threshold under 1", [lagrangian, "Parallel/Rebalance Threshold=0.5"],
         r"Parallel/Rebalance Threshold = 0.5.*: the slowest process's time over the mean is at least 1"),
        ("a rebalance of the process grid", [lagrangian, "Parallel/Rebalance Threshold=1.2",
                                             "Parallel/Decomposition=grid"],
         r"divides the cell anew by Zoltan2's RCB: not with Parallel/Decomposition = grid"),
        ("a rebalance of fixed particles", ["Parallel/Rebalance Threshold=1.2"],
         r"Parallel/Rebalance Threshold follows a load that moves: fixed particles"),
    ]
    for name, settings, message in motion_cases:
        case(name + " is refused", [TINY, "--output", base] + sets(*settings), 2, message, absent(base))
    # Two grains thrown at each other meet and touch, and the contact throws
    # them back: the contacts go to grains_history.csv.
    colliding = fresh("colliding-grains")
    def met_and_parted():
        with open(os.path.join(colliding, "grains_history.csv")) as f:
            rows = [r for r in csv.DictReader(f) if r["grain"] == "0"]
        touching = [r["step"] for r in rows if int(r["contacts"]) > 0]
        if not touching:
            return "no row of grains_history.csv shows a contact"
        if min(float(r["velocity_x"]) for r in rows) >= 0:
            return f"grain 0 never turned back: {rows}"
        return ""
    def grains_described():
        # grains.xmf: a frame per field file, the two grains as points with vectors
        import xml.etree.ElementTree as ElementTree
        problem = met_and_parted() or frames_consistent(colliding)
        path = os.path.join(colliding, "grains.xmf")
        if problem or not os.path.exists(path):
            return problem or "no grains.xmf"
        frames = [g for g in ElementTree.parse(path).iter("Grid") if g.get("GridType") == "Uniform"]
        fields = [f for f in os.listdir(colliding) if f.startswith("fields_") and f.endswith(".h5")]
        if len(frames) != len(fields) or len(fields) < 3:
            return f"grains.xmf has {len(frames)} frames for {len(fields)} field files"
        for frame in frames:
            points = frame.find("Topology").get("NumberOfElements")
            named = {a.get("Name") for a in frame.iter("Attribute")}
            if points != "2" or not {"velocity", "spin", "radius", "fluid_force", "contact_force"} <= named:
                return f"a frame of grains.xmf has {points} points and attributes {sorted(named)}"
        return ""
    case("two grains thrown at each other touch and bounce back, described frame by frame in grains.xmf",
         [TINY, "--output", colliding] + sets("Grains/Inline={0.3, 0.5, 0.15, 0.7, 0.5, 0.15}", "Grains/Motion=free",
                                              "Grains/Density=2500", lagrangian, "Fluid/Velocity Scale=0.1",
                                              "Fluid/Kinematic Viscosity=0.001", "Run/Max Steps=300",
                                              "Grains/Initial Velocity={0.05, 0, -0.05, 0}",
                                              "Output/Field Interval=1"),
         0, r"summary in", grains_described)
    light = fresh("light-grains")
    case("grains far lighter than the fluid are warned of",
         [TINY, "--output", light] + sets(grain, "Grains/Motion=free", "Grains/Density=100", lagrangian,
                                          "Run/Max Steps=5"),
         0, r"warning: Grains/Density = 100 kg/m\^3 is 0.1 of the fluid's: .*added mass", None)
    # Grains that move, stopped half way and continued: the same grains,
    # forces and particles to the last digit as the run in one go.
    colliding_scene = sets("Grains/Inline={0.3, 0.5, 0.15, 0.7, 0.5, 0.15}", "Grains/Motion=free",
                           "Grains/Density=2500", lagrangian, "Fluid/Velocity Scale=0.1",
                           "Fluid/Kinematic Viscosity=0.001", "Grains/Initial Velocity={0.05, 0, -0.05, 0}",
                           "Run/End Time=5", "Output/Final Particles CSV=true", "Output/Field Interval=1")
    whole, cut = fresh("moving-grains-whole"), fresh("moving-grains-continued")
    run([TINY, "--output", whole] + colliding_scene)
    run([TINY, "--output", cut] + colliding_scene + sets("Run/Max Steps=230"))
    def same_files():
        return "; ".join(f"{name} differs from the run in one go" for name in
                         ("grains_history.csv", "surface_forces.csv", "particles.csv", "grains.xmf")
                         if not os.path.exists(os.path.join(cut, name)) or
                         open(os.path.join(whole, name)).read() != open(os.path.join(cut, name)).read())
    case("moving grains stopped at step 230 of 400 and continued go on bit for bit",
         [TINY, "--output", cut, "--restart", os.path.join(cut, "checkpoint.h5")] + colliding_scene, 0,
         r"400 steps to t = 5 s", same_files)
    moving = fresh("moving-grains")
    moving_scene = [grain, "Grains/Motion=free", "Grains/Density=2000", lagrangian]
    good_run(moving, *moving_scene)
    case("a restart of moving grains with another density is refused",
         [TINY, "--output", moving + "-restarted", "--restart", os.path.join(moving, "checkpoint.h5")]
         + sets(*moving_scene, "Grains/Density=3000"), 2,
         r"Grains/Density.*2000.*3000", absent(moving + "-restarted"))


def class_5_output_directories():
    """A refused run writes nothing; results of another run are not replaced or mixed without --overwrite."""
    out = fresh("outdir")
    good_run(out)
    case("a refused run into a directory with results changes nothing",
         [TINY, "--output", out, "--set", "Fluid/Kinematic Viscosity=-1"], 2, r"Kinematic Viscosity", unchanged(out))
    case("a run refused during set-up (no fluid) changes nothing",
         [TINY, "--output", out, "--overwrite", "--set", "Discretization/Particle Spacing=0.25",
          "--set", "Grains/Allow Overlap=true", "--set", "Grains/Inline={0.5, 0.5, 0.5, 0, 0, 0.5}"], 2,
         r"no fluid particle", unchanged(out))
    case("a second run into the directory is refused without --overwrite",
         [TINY, "--output", out, "--set", "Run/Max Steps=5"], 2,
         r"holds the results of another run \(checkpoint.h5, parameters_used.xml, .*--overwrite", unchanged(out))

    out = fresh("overwrite")
    good_run(out, "Output/Field Interval=0.5")
    write(os.path.join(out, "notes.txt"), "the user's own file\n")
    old_fields = sorted(f for f in os.listdir(out) if f.startswith("fields_"))
    def replaced():
        names = sorted(os.listdir(out))
        problems = []
        if any(f.startswith("fields_") or f.endswith(".xmf") for f in names):
            problems.append(f"the old run's field files are still there: {names}")
        if "notes.txt" not in names:
            problems.append("the user's notes.txt was removed")
        if summary(out)["steps"] != 3:
            problems.append("summary.json is not the new run's")
        return "; ".join(problems)
    case("--overwrite removes the old run's files (%d field files) first" % len(old_fields),
         [TINY, "--output", out, "--overwrite", "--set", "Run/Max Steps=3"], 0, r"summary in", replaced)

    case("Scene/Name with a path separator is refused", [TINY, "--set", "Scene/Name=../escaped"], 2,
         r"Scene/Name '../escaped' contains a path separator",
         lambda: "" if not os.path.exists(os.path.join(WORK, "escaped")) and not os.path.exists("poresph-..")
         else "a directory outside was created")

    base = fresh("is-a-file")
    os.makedirs(os.path.dirname(base), exist_ok=True)
    write(base, "not a directory\n")
    case("--output naming a file is refused", [TINY, "--output", base], 2, r"it exists and is not a directory",
         unchanged(os.path.dirname(base)))

    out = fresh("restart-in-place")
    good_run(out)
    case("--overwrite with the directory's own checkpoint is refused",
         [TINY, "--output", out, "--overwrite", "--restart", os.path.join(out, "checkpoint.h5"),
          "--set", "Run/Max Steps=30"], 2, r"--overwrite would remove .*checkpoint.h5", unchanged(out))
    other = fresh("restart-elsewhere")
    good_run(other)
    case("a restart from another directory's checkpoint into one with results is refused",
         [TINY, "--output", other, "--restart", os.path.join(out, "checkpoint.h5"), "--set", "Run/Max Steps=30"], 2,
         r"holds the results of another run", unchanged(other))
    case("a restart from the directory's own checkpoint continues there",
         [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5"), "--set", "Run/Max Steps=30"], 0,
         r"30 steps", lambda: "" if summary(out)["restarted_from_step"] == 20 else "not continued")


def h5(path, mode="r"):
    import h5py  # Debian's python3-h5py, as the other checks of the files
    return h5py.File(path, mode)


def zero_bytes(path, dataset, count=256):
    """Zeroes `count` bytes in the middle of a dataset's storage, as a damaged disk block would."""
    with h5(path) as f:
        offset, size = f[dataset].id.get_offset(), f[dataset].id.get_storage_size()
    with open(path, "r+b") as g:
        g.seek(offset + size // 3)
        g.write(b"\0" * min(count, size // 2))


def class_4_restart():
    """A checkpoint of other physics or damaged is refused naming what differs; a restart continues exactly."""
    base = fresh("restart")
    first = os.path.join(os.path.dirname(base), "first")
    good_run(first, "Output/Field Interval=0.7")
    checkpoint = os.path.join(first, "checkpoint.h5")
    out = base
    for name, settings, message in [
        ("another spacing", ["Discretization/Particle Spacing=0.025"],
         r"Discretization/Particle Spacing: 0.05 in the checkpoint, 0.025 here.*time step: "),
        ("other grains", ["Grains/Inline={0.5, 0.5, 0.1}"], r"Grains: 0 grains, checksum [0-9a-f]+ in the checkpoint, "
                                                            r"1 grains, checksum [0-9a-f]+ here"),
        ("another fluid", ["Fluid/Kinematic Viscosity=0.02"], r"Fluid/Kinematic Viscosity: 0.01 in the checkpoint, 0.02 here"),
        ("another dimension", ["Domain/Cell Size={1, 1, 1}", "Fluid/Body Force={0.001, 0, 0}"],
         r"dimension: 2 in the checkpoint, 3 here"),
        ("a tensor run from a single-axis checkpoint", ["Permeability/Tensor=true"],
         r"Permeability/Tensor: false in the checkpoint, true here")]:
        args = [TINY, "--output", out, "--restart", checkpoint, "--set", "Run/Max Steps=40"]
        for setting in settings:
            args += ["--set", setting]
        case(f"a checkpoint of {name} is refused, naming the difference", args, 2,
             r"the checkpoint is of other physics than this scene.*" + message, both(absent(out), unchanged(first)))

    for dataset in ["v", "rho", "run/fingerprint"]:
        damaged = path("restart", f"damaged-{dataset.replace('/', '-')}.h5")
        shutil.copy(checkpoint, damaged)
        zero_bytes(damaged, dataset)
        case(f"a checkpoint with a zeroed block in {dataset} is refused", [TINY, "--output", out, "--restart", damaged,
             "--set", "Run/Max Steps=40"], 2, rf"the data of '{dataset}' do not match their checksum", absent(out))
    # Cut short (its rows fewer than the rank record says) or missing: damaged, said so, exit 2.
    for dataset, cut in [("v", True), ("rho", False)]:
        damaged = path("restart", f"{'short' if cut else 'missing'}-{dataset}.h5")
        shutil.copy(checkpoint, damaged)
        with h5(damaged, "r+") as f:
            data, attributes = f[dataset][...], dict(f[dataset].attrs)
            del f[dataset]
            if cut:
                f.create_dataset(dataset, data=data[: len(data) // 2])
                for key, value in attributes.items():
                    f[dataset].attrs[key] = value
        message = (rf"'{dataset}' holds {len(data) // 2} rows, fewer than the checkpoint records: the checkpoint is "
                   r"damaged" if cut else rf"has no field '{dataset}'.*or the file is damaged")
        case(f"a checkpoint whose {dataset} is {'cut short' if cut else 'missing'} is refused as damaged",
             [TINY, "--output", out, "--restart", damaged, "--set", "Run/Max Steps=40"], 2, message, None)
    old = path("restart", "format-1.h5")
    shutil.copy(checkpoint, old)
    import numpy
    with h5(old, "r+") as f:
        del f.attrs["format"]
        f.attrs["format"] = numpy.bytes_(b"poresph checkpoint 1")
    case("a checkpoint of the format before fingerprints is refused, not trusted",
         [TINY, "--output", out, "--restart", old], 2, r"earlier PoreSPH .* cannot be checked", absent(out))

    # Exact continuation: a run that stopped at step 130 (its last checkpoint at 100, as if killed)
    # and one that ended at 110, each continued to 200, against 200 steps in one go: the same
    # history rows, the same field files, the same XDMF description.
    fields = ["--set", "Output/Field Interval=0.7", "--set", "Run/Max Steps=200"]
    whole = fresh("whole")
    run([TINY, "--output", whole] + fields)
    for name, stop in [("killed after its last checkpoint", ["Run/Max Steps=130", "Output/Checkpoint Interval=50",
                                                              "Output/Final Checkpoint=false"]),
                       ("continued past its end", ["Run/Max Steps=110"])]:
        out = fresh("continued-" + name.split()[0])
        args = [TINY, "--output", out, "--set", "Output/Field Interval=0.7"]
        for setting in stop:
            args += ["--set", setting]
        run(args)
        def same_as_whole():
            problems = []
            for file in ["permeability_history.csv", "particles.xmf"]:
                if open(os.path.join(out, file)).read() != open(os.path.join(whole, file)).read():
                    problems.append(f"{file} differs from the uninterrupted run's")
            steps = [line.split(",")[0] for line in open(os.path.join(out, "permeability_history.csv"))][1:]
            if len(steps) != len(set(steps)):
                problems.append("a history row is there twice")
            ours, theirs = sorted(os.listdir(out)), sorted(os.listdir(whole))
            if ours != theirs:
                problems.append(f"files {sorted(set(ours) ^ set(theirs))} differ")
            return "; ".join(problems)
        case(f"a run {name} continues its history and field frames exactly",
             [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] + fields, 0, r"200 steps",
             same_as_whole)


def class_6_results_kept():
    """Large metadata in datasets; summary.json at every ending; a full disk named, earlier files kept."""
    out = fresh("long-parameters")
    grains = ", ".join(f"{(a + 0.5) * 0.025:.4f}, {(b + 0.5) * 0.025:.4f}, 0.004" for a in range(40) for b in range(40))
    def checkpoint_holds_everything():
        with h5(os.path.join(out, "checkpoint.h5")) as f:
            parameters = bytes(f["run/parameters"][()]).decode()
        s = summary(out)
        return "" if "Inline" in parameters and s["stopped_by"] == "max_steps" and s["steps"] == 2 else "incomplete"
    case("1,600 inline grains: the parameter list is a dataset and every checkpoint is written",
         [TINY, "--output", out, "--set", "Grains/Inline={" + grains + "}", "--set", "Discretization/Particle Spacing=0.004",
          "--set", "Run/Max Steps=2", "--set", "Output/Checkpoint Interval=1"], 0, r"summary in",
         checkpoint_holds_everything)

    # A checkpoint that cannot be written in the time loop: the device /dev/full behind
    # checkpoint.h5.tmp (a run continued in place keeps what is in its directory).
    out = fresh("failed-write")
    good_run(out, "Output/Checkpoint Interval=10")
    os.symlink("/dev/full", os.path.join(out, "checkpoint.h5.tmp"))
    before = snapshot(out)["checkpoint.h5"]
    def recorded():
        problems = []
        s = summary(out)
        if s["stopped_by"] != "error" or "checkpoint.h5.tmp" not in s.get("failure", ""):
            problems.append(f"summary.json says {s['stopped_by']}, {s.get('failure')}")
        if snapshot(out)["checkpoint.h5"] != before:
            problems.append("the earlier checkpoint.h5 was changed")
        return "; ".join(problems)
    case("a checkpoint that cannot be written: exit 1, the reason, summary.json written, the earlier checkpoint kept",
         [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5"), "--set", "Run/Max Steps=40",
          "--set", "Output/Checkpoint Interval=10"], 1, r"checkpoint.h5.tmp: cannot (create the file|write dataset)", recorded)

    # summary.json itself cannot be written (/dev/full: "No space left on device"): the earlier one
    # is removed, not left to be taken for this run's.
    out = fresh("summary-fails")
    good_run(out)
    os.symlink("/dev/full", os.path.join(out, "summary.json.tmp"))
    case("a summary.json that cannot be written says why and leaves no stale one",
         [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5"), "--set", "Run/Max Steps=40"], 1,
         r"cannot write .*summary.json: writing .*No space left on device; the earlier summary.json was removed",
         lambda: "" if not os.path.exists(os.path.join(out, "summary.json")) else "summary.json is still there")

    # A full disk, when a small file system can be mounted (root in a container that allows it).
    disk = path("full-disk")
    os.makedirs(disk, exist_ok=True)
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", disk], capture_output=True).returncode == 0
    if not mounted:
        print("skip   a full disk (cannot mount a small tmpfs here)")
        return
    try:
        out = os.path.join(disk, "out")
        kept = {}
        def after_full_disk():
            problems = []
            names = os.listdir(out)
            if any(n.endswith(".tmp") for n in names):
                problems.append(f"temporary files left: {names}")
            with h5(os.path.join(out, "checkpoint.h5")) as f:
                if f.attrs["step"] != 50:
                    problems.append(f"checkpoint.h5 is of step {f.attrs['step']}, not the last good one (50)")
            s = summary(out)
            if s["stopped_by"] != "error" or "the disk is full" not in s["failure"]:
                problems.append(f"summary.json: {s['stopped_by']}, {s.get('failure')}")
            return "; ".join(problems)
        case("a full disk: exit 1, 'the disk is full', the last good checkpoint kept, no .tmp, summary.json says so",
             [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.02", "--set", "Run/Max Steps=200",
              "--set", "Output/Checkpoint Interval=50", "--set", "Output/Field Interval=0.1"], 1,
             r"cannot write dataset .*the disk is full", after_full_disk)
    finally:
        subprocess.run(["umount", disk])


def class_7_messages():
    """Messages that say what is wrong, and nothing lost or buried."""
    out = fresh("messages")
    case("a body force whose magnitude overflows is named, not 'no flow scale'",
         [TINY, "--output", out, "--set", "Fluid/Body Force={1e200, 1e200}"], 2,
         r"Fluid/Body Force = \(1e\+200, 1e\+200\) has no finite magnitude", absent(out))
    case("a directory given as the scene is named as one", [HERE, "--output", out], 2,
         r"cannot read scene file .*: it is a directory, not an XML file", absent(out))
    empty = write(os.path.join(WORK, "empty.xml"), "\n")
    case("an empty scene file is named as one", [empty, "--output", out], 2, r"the file is empty", absent(out))
    for ranks in (0, 2):
        name = "--restart with a directory gives one line, no MPI I/O noise" + (f" ({ranks} ranks)" if ranks else "")
        try:
            status, output = run([TINY, "--output", out, "--restart", WORK], mpi=ranks)
            # Ours, up to mpiexec's own notice that a process exited with a non-zero status.
            lines = [l for l in output.split("-" * 20)[0].splitlines() if l.strip()]
            problems = []
            if status != 2:
                problems.append(f"exit status {status}")
            if len(lines) != 1 or not re.search(r"--restart .*: it is a directory, not a file", lines[0]):
                problems.append(f"{len(lines)} lines of output before mpiexec's notice")
            problems += [p for p in [absent(out)()] if p]
        except Exception as e:
            problems, output = [str(e)], ""
        report(name, problems, output)
    case("the run's output options cannot be given twice", [TINY, "--output", out, "--output", out + "2"], 2,
         r"--output given twice", both(absent(out), absent(out + "2")))

    # setup_seconds counts the whole set-up (reading, checks, lattice), not the last part of it.
    out = fresh("setup-seconds")
    start = time.monotonic()
    status, output = run([TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.001",
                          "--set", "Run/Max Steps=2", "--set", "Output/Final Checkpoint=false"])
    elapsed = time.monotonic() - start
    problems = [] if status == 0 else [f"exit status {status}"]
    if status == 0:
        s = summary(out)
        # All but the loop, MPI start-up and the final writes is set-up: most of the process's time.
        if not s["setup_seconds"] > 0.5 * (elapsed - s["wall_seconds"]) - 1.0:
            problems.append(f"setup_seconds {s['setup_seconds']:.3f} of {elapsed:.2f} s outside the time loop")
    report("setup_seconds covers the set-up", problems, output)


def class_8_setup_time():
    """Set-up grows linearly with the number of grains: 40,000 grains are checked in seconds (86 s before)."""
    base = fresh("many-grains")
    files = os.path.dirname(base)
    import random
    rng = random.Random(3)
    lines = [f"{(a + 0.5) * 0.005 + rng.uniform(-5e-4, 5e-4):.9f} {(b + 0.5) * 0.005 + rng.uniform(-5e-4, 5e-4):.9f} 0.0015"
             for a in range(200) for b in range(200)]
    grains = write(os.path.join(files, "grains40k.txt"), "\n".join(lines) + "\n")
    for name, settings, message in [
        ("40,000 grains are read and checked, then the run refused for memory",
         ["Discretization/Particle Spacing=0.0002", "Run/Memory Limit=1e-6"], r"needs about 25000000 particles"),
        ("40,000 grains at a spacing coarser than their gaps: refused naming the narrowest throat",
         ["Discretization/Particle Spacing=0.005"], r"narrower than one spacing.*\([0-9]+ throats are narrower")]:
        args = [TINY, "--output", base, "--set", f"Grains/File={grains}"]
        for setting in settings:
            args += ["--set", setting]
        start = time.monotonic()
        case(name, args, 2, message, absent(base))
        elapsed = time.monotonic() - start
        report(f"  ... in {elapsed:.1f} s (limit 30 s)", [] if elapsed < 30 else [f"took {elapsed:.1f} s"])


def class_9_tests_stay():
    """A test of an optional tool is always registered, and skips (status 77) only when the tool is absent now."""
    listed = subprocess.run([os.environ["CTEST"], "-N"], cwd=os.environ["BUILD_DIR"], capture_output=True,
                            text=True).stdout
    for test in ["stokes_reference_square_arrays", "navier_stokes_reference_lattice", "cli_xdmf_paraview"]:
        report(f"{test} is in CTest's list", [] if re.search(rf"Test +#[0-9]+: {test}\n", listed) else ["not listed"])
    skip = os.environ["SKIP_WITHOUT"]
    no_tools = dict(ENV, PATH="/nonexistent")
    done = subprocess.run(["/bin/bash", skip, "FreeFem++-nw", "--", "/bin/true"], env=no_tools, capture_output=True,
                          text=True)
    report("without FreeFem++ on PATH the test reports 77 (skipped) and why",
           [] if done.returncode == 77 and "FreeFem++-nw is not on PATH" in done.stdout
           else [f"status {done.returncode}: {done.stdout}"])
    # A tool that is there runs the test, and its failure is a failure, not a skip.
    for command, status in [("/bin/true", 0), ("/bin/false", 1)]:
        done = subprocess.run([skip, "sh", "--", command], capture_output=True, text=True)
        report(f"with the tool on PATH the test runs ({command} gives {status})",
               [] if done.returncode == status else [f"status {done.returncode}"])


# ---------------------------------------------------------------------------------------------------
# Issue 30: nothing lost, nothing misreported.

GRAIN = "Grains/Inline={0.5, 0.5, 0.25}"
# Two grains one above the other: flow along y finds open lanes, along x it squeezes between them, so
# the y axis of a tensor run takes longer to settle than the x axis (a run cut by Run/Max Steps in its
# last stage only, for the restart cases).
TWO_GRAINS = "Grains/Inline={0.5, 0.25, 0.18, 0.5, 0.75, 0.18}"
STEADY = ["Permeability/Steady Tolerance=1e-3", "Run/End Time=1000"]


def sets(*settings):
    args = []
    for setting in settings:
        args += ["--set", setting]
    return args


def names(directory):
    return sorted(os.listdir(directory)) if os.path.isdir(directory) else None


def frames_consistent(out):
    """Every .xmf names exactly the field files of its stage that are there: none missing, none stale."""
    import xml.etree.ElementTree as ElementTree
    problems = []
    present = {f for f in os.listdir(out) if f.startswith("fields") and f.endswith(".h5")}
    described = set()
    for xmf in sorted(f for f in os.listdir(out) if f.endswith(".xmf")):
        suffix = re.sub(r"^(particles|grid|grains)", "", xmf[:-4])
        files = set()
        for item in ElementTree.parse(os.path.join(out, xmf)).iter("DataItem"):
            if item.get("Format") == "HDF":
                files.add(item.text.split(":")[0])
        missing = sorted(f for f in files if f not in present)
        if missing:
            problems.append(f"{xmf} names frames that are not there: {missing}")
        own = {f for f in present if re.fullmatch(rf"fields{re.escape(suffix)}_[0-9]+\.h5", f)}
        if own - files:
            problems.append(f"{xmf} leaves out frames that are there: {sorted(own - files)}")
        described |= files
    if present - described:
        problems.append(f"frames no description names: {sorted(present - described)}")
    return "; ".join(problems)


def comparable(s):
    """A summary without what may differ between a run in one go and one continued: wall times, restarts."""
    skip = {"wall_seconds", "setup_seconds", "particle_steps_per_second", "restarted_from_step"}
    if isinstance(s, dict):
        return {k: comparable(v) for k, v in s.items() if k not in skip}
    if isinstance(s, list):
        return [comparable(v) for v in s]
    return s


def same_summary(out, reference):
    """'' if out's summary.json equals reference's key for key (wall times and restarts aside)."""
    ours, theirs = comparable(summary(out)), comparable(summary(reference))
    differing = [k for k in sorted(set(ours) | set(theirs)) if ours.get(k) != theirs.get(k)]
    return "" if not differing else "summary.json differs from the run in one go in " + ", ".join(
        f"{k} ({ours.get(k)!r} against {theirs.get(k)!r})" for k in differing)


def last_history_step(out, suffix=""):
    with open(os.path.join(out, f"permeability_history{suffix}.csv")) as f:
        return int(list(f)[-1].split(",")[0])


def start(args, **options):
    return subprocess.Popen([POREESPH] + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=ENV,
                            **options)


def wait_for(condition, timeout=120, poll=0.002):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(poll)
    return False


def handler_installed(pid, signal_number):
    """Whether the process catches the signal (SigCgt in /proc): it is past MPI_Init."""
    try:
        with open(f"/proc/{pid}/status") as status:
            caught = int(next(l for l in status if l.startswith("SigCgt:")).split()[1], 16)
        return bool(caught & (1 << (signal_number - 1)))
    except (OSError, StopIteration):
        return False


def history_rows(out, suffix=""):
    try:
        with open(os.path.join(out, f"permeability_history{suffix}.csv")) as f:
            return sum(1 for _ in f) - 1
    except OSError:
        return 0


def checkpoint_step(out):
    with h5(os.path.join(out, "checkpoint.h5")) as f:
        return int(f.attrs["step"])


def class_10_run_files():
    """Every file of a multi-part run (ladder levels, half force, tensor axes with levels) is known as run output."""
    plain = fresh("plain")
    good_run(plain, "Output/Field Interval=0.5")
    plain_files = names(plain)
    fields = ["Output/Field Interval=0.5", "Output/Grid Points={8, 8}", "Output/Final Particles CSV=true",
              "Run/Max Steps=20", "Run/Progress=never"]
    for label, settings in [
        ("a 3-level ladder with the linearity check", ["Convergence/Levels=3", "Permeability/Linearity Check=true"]),
        ("a tensor run with the linearity check", ["Permeability/Tensor=true", "Permeability/Linearity Check=true"]),
        ("a tensor run of a 3-level ladder", ["Permeability/Tensor=true", "Convergence/Levels=3"]),
        ("a tensor run of a 2-level ladder with the linearity check",
         ["Permeability/Tensor=true", "Convergence/Levels=2", "Permeability/Linearity Check=true"])]:
        out = fresh("multi-" + re.sub(r"[^a-z0-9]+", "-", label))
        status, output = run([TINY, "--output", out] + sets(GRAIN, *fields, *settings))
        if status != 0:
            report(f"{label}: the run", [f"exit status {status}"], output)
            continue
        written = names(out)
        write(os.path.join(out, "notes.txt"), "the user's own file\n")
        case(f"{label}: a second run without --overwrite is refused, counting all {len(written)} files",
             [TINY, "--output", out, "--set", "Run/Max Steps=5"], 2,
             rf"holds the results of another run \(.*\({len(written)} files\)\)", unchanged(out))
        def only_the_new_run():
            left = sorted(set(names(out)) - set(plain_files) - {"notes.txt"})
            problems = [f"{len(left)} files of the first run are left: {left}"] if left else []
            if "notes.txt" not in names(out):
                problems.append("the user's notes.txt was removed")
            return "; ".join(problems + [p for p in [frames_consistent(out)] if p])
        case(f"{label}: --overwrite with a plain run leaves none of its files",
             [TINY, "--output", out, "--overwrite", "--set", "Output/Field Interval=0.5", "--set", "Run/Max Steps=20"],
             0, r"summary in", only_the_new_run)

    # A restart in place from a checkpoint of an earlier stage removes what the stages after it had
    # written: here the half-force stage's files, written after the last checkpoint (of the full force:
    # no checkpoint falls in the shorter half-force stage), and the run continued with other frames.
    out = fresh("later-stages")
    status, output = run([TINY, "--output", out] + sets(
        GRAIN, *STEADY, "Permeability/Linearity Check=true", "Output/Checkpoint Interval=500",
        "Output/Final Checkpoint=false", "Output/Field Interval=2"))
    stage_steps = [last_history_step(out), last_history_step(out, "_half_force")] if status == 0 else []
    if status != 0 or not (stage_steps[1] < 500 <= stage_steps[0]):
        report("later stages: the run to continue", [f"exit {status}, stages of {stage_steps} steps"], output)
    else:
        half_before = sorted(f for f in names(out) if f.startswith("fields_half_force_"))
        def later_stage_rewritten():
            # The continued stage writes its frames at the new interval; one of the first attempt's left
            # beside them is a frame its description leaves out.
            problems = [p for p in [frames_consistent(out)] if p]
            half = sorted(f for f in names(out) if f.startswith("fields_half_force_"))
            if half == half_before:
                problems.append("the half-force stage's frames are the first attempt's")
            return "; ".join(problems)
        case(f"a restart in place from an earlier stage's checkpoint removes the later stages' files "
             f"({len(half_before)} frames)",
             [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] + sets(
                 GRAIN, *STEADY, "Permeability/Linearity Check=true", "Output/Field Interval=1.3"), 0, r"summary in",
             later_stage_rewritten)


def class_11_claim():
    """One run per output directory: runs started together into it are refused, and touch nothing."""
    reference = fresh("reference")
    long_run = sets("Discretization/Particle Spacing=0.01", "Run/Max Steps=100", "Run/Progress=never")
    status, output = run([TINY, "--output", reference] + long_run)
    assert status == 0, output
    expected = names(reference)
    for label, existing in [("a new directory", False), ("an empty directory made beforehand", True)]:
        for repeat in range(3):
            out = fresh(f"together-{existing}-{repeat}")
            if existing:
                os.makedirs(out)
            runs = [start([TINY, "--output", out] + long_run) for _ in range(8)]
            outputs = [r.communicate(timeout=600)[0] for r in runs]
            statuses = [r.returncode for r in runs]
            problems = []
            if sorted(statuses) != [0] + [2] * 7:
                problems.append(f"exit statuses {statuses}")
            refused = [o for r, o in zip(runs, outputs) if r.returncode == 2]
            unclear = [o for o in refused if not re.search(r"is in use by another run( \(process [0-9]+ on .*since "
                                                           r".*\))?; wait|holds the results of another run", o)]
            if unclear:
                problems.append(f"{len(unclear)} refusals do not say the directory is taken")
            if names(out) != expected:
                problems.append(f"the directory holds {names(out)}, not one run's {expected}")
            elif summary(out)["steps"] != 100 or frames_consistent(out):
                problems.append("its summary is not a whole run's")
            report(f"8 runs started together into {label} (try {repeat + 1}): one runs, 7 are refused with exit 2",
                   problems, "\n".join(outputs))

    # A run into a directory in use, with --overwrite or as a restart in place, is refused; the run goes on.
    out = fresh("in-use")
    first = start([TINY, "--output", out] + sets("Discretization/Particle Spacing=0.005", "Run/Max Steps=400",
                                                 "Run/Progress=never", "Output/Checkpoint Interval=20"))
    if not wait_for(lambda: os.path.exists(os.path.join(out, "checkpoint.h5")), timeout=120):
        report("a run into a directory in use: the first run", ["did not start"], first.communicate()[0])
        return
    case("a run with --overwrite into a directory in use is refused, naming the run that holds it",
         [TINY, "--output", out, "--overwrite", "--set", "Run/Max Steps=5"], 2,
         r"is in use by another run \(process [0-9]+ on .*\); wait until it has ended", None)
    case("a restart in place while the run goes on is refused", [TINY, "--output", out, "--restart",
         os.path.join(out, "checkpoint.h5"), "--set", "Discretization/Particle Spacing=0.005"], 2,
         r"is in use by another run", None)
    first_output = first.communicate(timeout=600)[0]
    report("the run that held the directory ended as it would have",
           [] if first.returncode == 0 and summary(out)["steps"] == 400 and
           not os.path.exists(os.path.join(out, ".poresph.lock")) else [f"exit {first.returncode}"], first_output)

    # The lock is the system's: a lock file left by a run that was killed holds nothing.
    out = fresh("stale-lock")
    os.makedirs(out)
    write(os.path.join(out, ".poresph.lock"), "process 1 on elsewhere, since long ago\n")
    case("a lock file left by a killed run does not hold the directory", [TINY, "--output", out, "--set",
         "Run/Max Steps=5"], 0, r"summary in",
         lambda: "" if not os.path.exists(os.path.join(out, ".poresph.lock")) else "the lock file is still there")
    out = fresh("killed")
    victim = start([TINY, "--output", out] + sets("Discretization/Particle Spacing=0.005", "Run/Max Steps=100000",
                                                  "Output/Checkpoint Interval=20"))
    wait_for(lambda: os.path.exists(os.path.join(out, "checkpoint.h5")), timeout=120)
    victim.kill()
    victim.communicate()
    step = checkpoint_step(out)
    case("after a run killed with SIGKILL, whose lock file stays, a restart in place goes on",
         [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] +
         sets("Discretization/Particle Spacing=0.005", f"Run/Max Steps={step + 10}"), 0, r"summary in",
         lambda: "" if summary(out).get("restarted_from_step") == step and
         not os.path.exists(os.path.join(out, ".poresph.lock")) else "not continued, or the lock file left")

    # A run refused after its claim (here: more processes than the cell can be split for, found when the
    # run decomposes it) gives the directory back as it found it: not there.
    out = fresh("refused-after-claim")
    too_many = sets("Discretization/Particle Spacing=0.25", "Run/Max Steps=2")
    case("a run refused during its set-up leaves no directory behind", [TINY, "--output", out] + too_many, 2,
         r"cannot be split into 5 sub-domains", absent(out), mpi=5)
    deep = os.path.join(fresh("refused-deep"), "a", "b")
    case("... nor the parent directories the claim made for it", [TINY, "--output", deep] + too_many, 2,
         r"cannot be split into 5 sub-domains", absent(os.path.dirname(os.path.dirname(deep))), mpi=5)
    existing = fresh("refused-existing")
    os.makedirs(existing)
    write(os.path.join(existing, "notes.txt"), "the user's own file\n")
    case("... and in a directory that was there, it leaves what was there", [TINY, "--output", existing] + too_many, 2,
         r"cannot be split into 5 sub-domains", unchanged(existing), mpi=5)


def class_12_restart_no_step_left():
    """A restart with no step left keeps its frames' descriptions to the frames that are there."""
    # A frame every 25 steps (dt = 0.03125 s) falls on the checkpoint's step, so the run continued writes
    # no frame of its own that would rewrite the descriptions; every 16, it does.
    for label, settings, suffix in [
        ("a run", ["Output/Field Interval=0.78125"], ""),
        ("a run with a frame due after the checkpoint", ["Output/Field Interval=0.5"], ""),
        ("a run with a grid", ["Output/Field Interval=0.78125", "Output/Grid Points={8, 8}"], ""),
        ("a tensor run's second axis", ["Output/Field Interval=0.78125", "Permeability/Tensor=true"], "_y")]:
        common = [GRAIN] + settings
        # Killed between its last frame and its last checkpoint: frames up to step 130, checkpoint at 100.
        out = fresh("no-step-" + re.sub(r"[^a-z0-9]+", "-", label))
        status, output = run([TINY, "--output", out] + sets(*common, "Run/Max Steps=130", "Output/Checkpoint Interval=50",
                                                            "Output/Final Checkpoint=false"))
        if status != 0:
            report(f"{label}: the run to continue", [f"exit {status}"], output)
            continue
        stale = sorted(f for f in names(out) if re.fullmatch(rf"fields{suffix}_[0-9]+\.h5", f) and int(f[-12:-3]) > 100)
        # What a run to step 100 in one go leaves.
        whole = fresh("no-step-whole-" + re.sub(r"[^a-z0-9]+", "-", label))
        run([TINY, "--output", whole] + sets(*common, "Run/Max Steps=100"))
        def as_in_one_go():
            # The stage continued (a tensor run's x axis ran to its own end, 130, before y began) has
            # the files and descriptions of a run to step 100 in one go.
            problems = [p for p in [frames_consistent(out)] if p]
            stage = lambda files: sorted(f for f in files if suffix in f and f.endswith((".xmf", ".h5")))
            for xmf in [f for f in stage(names(whole)) if f.endswith(".xmf")]:
                if open(os.path.join(out, xmf)).read() != open(os.path.join(whole, xmf)).read():
                    problems.append(f"{xmf} differs from the run to step 100 in one go")
            if stage(names(out)) != stage(names(whole)):
                problems.append(f"files {sorted(set(stage(names(out))) ^ set(stage(names(whole))))} differ")
            return "; ".join(problems)
        case(f"{label}: continued with no step left after its checkpoint ({len(stale)} frames past it), "
             "its descriptions name only the frames there",
             [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] + sets(*common, "Run/Max Steps=100"),
             0, r"summary in", as_in_one_go)


def signal_case(label, args, signal_number, when, out, continue_args, expect_step=None):
    """Runs poresph ARGS, sends the signal once `when(proc)` holds, and checks exit status 128 + signal,
    the message, summary.json (stopped_by signal) and a checkpoint that a restart continues from
    (continue_args(step): the arguments of the continued run, the checkpoint's step given)."""
    problems, output = [], ""
    try:
        proc = start(args)
        if not wait_for(lambda: when(proc) or proc.poll() is not None, timeout=300, poll=0.001):
            problems.append("the moment to send the signal never came")
        proc.send_signal(signal_number)
        output = proc.communicate(timeout=600)[0]
        name = signal.Signals(signal_number).name
        if proc.returncode != 128 + signal_number:
            problems.append(f"exit status {proc.returncode}, expected {128 + signal_number}")
        elif not re.search(rf"stopped by {name} at step [0-9]+, t = .*; the state is in .*checkpoint.h5", output):
            problems.append("no message naming the signal, the step and the checkpoint")
        else:
            s = summary(out)
            step = checkpoint_step(out)
            if s["stopped_by"] != "signal" or s["steps"] < step:
                problems.append(f"summary.json says {s['stopped_by']}, {s['steps']} steps")
            if expect_step is not None and not expect_step(step):
                problems.append(f"the checkpoint is of step {step}")
            if os.path.exists(os.path.join(out, ".poresph.lock")) or [f for f in names(out) if f.endswith(".tmp")]:
                problems.append(f"left behind: {names(out)}")
            status, more = run(continue_args(step) + ["--restart", os.path.join(out, "checkpoint.h5")])
            if status != 0 or summary(out).get("restarted_from_step") != step or summary(out)["steps"] <= step:
                problems.append(f"the checkpoint does not continue (exit {status})")
                output += more
    except Exception as e:
        problems.append(f"{type(e).__name__}: {e}")
    report(label, problems, output)


def class_13_signals():
    """SIGHUP, SIGPIPE, SIGINT, SIGTERM at set-up, in the loop and during a checkpoint write: a summary and a
    usable checkpoint each, and 128 + the signal as exit status (129, 141, 130, 143)."""
    signals = [signal.SIGHUP, signal.SIGPIPE, signal.SIGINT, signal.SIGTERM]
    for number in signals:
        name = signal.Signals(number).name
        # At set-up: once the handler is there, the set-up of a 250,000-point lattice has a while to go.
        out = fresh(f"setup-{name}")
        args = [TINY, "--output", out] + sets("Discretization/Particle Spacing=0.002", "Run/Max Steps=5",
                                              "Run/Progress=never")
        signal_case(f"{name} during set-up: checkpoint of step 0 and summary, exit {128 + number}", args, number,
                    lambda p, n=number: handler_installed(p.pid, n) and time.sleep(0.05) is None, out,
                    lambda step, o=out: [TINY, "--output", o] + sets("Discretization/Particle Spacing=0.002",
                                                                      f"Run/Max Steps={step + 2}"),
                    expect_step=lambda step: step == 0)
        # In the loop: once the history has rows.
        out = fresh(f"loop-{name}")
        args = [TINY, "--output", out] + sets("Discretization/Particle Spacing=0.01", "Run/Max Steps=1000000",
                                              "Run/End Time=1e6", "Output/Final Checkpoint=false")
        signal_case(f"{name} in the time loop: checkpoint and summary, exit {128 + number}", args, number,
                    lambda p, o=out: history_rows(o) >= 3, out,
                    lambda step, o=out: [TINY, "--output", o] + sets("Discretization/Particle Spacing=0.01",
                                                                      "Run/End Time=1e6", f"Run/Max Steps={step + 10}"),
                    expect_step=lambda step: step > 0 and step % 10 == 0)
        # During a checkpoint write: while checkpoint.h5.tmp is there.
        out = fresh(f"checkpoint-{name}")
        settings = ["Discretization/Particle Spacing=0.002", "Run/End Time=1e6", "Output/Checkpoint Interval=10"]
        args = [TINY, "--output", out] + sets(*settings, "Run/Max Steps=1000000")
        signal_case(f"{name} during a checkpoint write: checkpoint and summary, exit {128 + number}", args, number,
                    lambda p, o=out: os.path.exists(os.path.join(o, "checkpoint.h5.tmp")), out,
                    lambda step, o=out: [TINY, "--output", o] + sets(*settings, f"Run/Max Steps={step + 10}"),
                    expect_step=lambda step: step > 0 and step % 10 == 0)

    # While a random pack grows (set-up before any particle, 32,000 grains: minutes before the growth stops
    # at each sweep): the growth stops at once, nothing is written, exit 143.
    out = fresh("pack-SIGTERM")
    args = [os.path.join(INPUT, "problem3", "problem3.xml"), "--output", out] + sets(
        "Grains/File=", "Discretization/Particle Spacing=0.002", "Grains/Random Pack/Porosity=0.6",
        "Grains/Random Pack/Min Radius=2e-4", "Grains/Random Pack/Max Radius=2e-4")
    problems, output = [], ""
    try:
        proc = start(args)
        if not wait_for(lambda: handler_installed(proc.pid, signal.SIGTERM)):
            problems.append("no handler installed")
        time.sleep(0.5)  # into the growth
        sent = time.monotonic()
        proc.send_signal(signal.SIGTERM)
        output = proc.communicate(timeout=600)[0]
        waited = time.monotonic() - sent
        if proc.returncode != 128 + signal.SIGTERM:
            problems.append(f"exit status {proc.returncode}, expected 143")
        if waited > 10:
            problems.append(f"it took {waited:.1f} s to stop")
        if not re.search(r"stopped by SIGTERM while growing the random pack", output):
            problems.append("no message of the stop")
        problems += [p for p in [absent(out)()] if p]
    except Exception as e:
        problems.append(f"{type(e).__name__}: {e}")
    report("SIGTERM while a random pack grows stops it at once, writes nothing, exit 143", problems, output)

    # SIGPIPE as it comes: the reader of the output goes away (`poresph ... | head -1`). The random pack's
    # note is the first line; the progress line after it finds no reader.
    out = fresh("pipe")
    pack = sets("Grains/Random Pack/Porosity=0.6", "Grains/Random Pack/Min Radius=0.1",
                "Grains/Random Pack/Max Radius=0.1", "Discretization/Particle Spacing=0.01")
    args = [TINY, "--output", out] + pack + sets("Run/Progress=always", "Run/End Time=1e6", "Run/Max Steps=1000000")
    problems, output = [], ""
    try:
        proc = subprocess.Popen([POREESPH] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
        first_line = proc.stdout.readline().decode(errors="replace")
        proc.stdout.close()  # as head -1 does once it has its line
        output = first_line + proc.communicate(timeout=600)[1].decode(errors="replace")
        if proc.returncode != 128 + signal.SIGPIPE:
            problems.append(f"exit status {proc.returncode}, expected 141")
        elif summary(out)["stopped_by"] != "signal" or not re.search(r"stopped by SIGPIPE at step", output):
            problems.append("no summary or message of the stop")
        else:
            step = checkpoint_step(out)
            status, more = run([TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] + pack +
                               sets("Run/End Time=1e6", f"Run/Max Steps={step + 10}"))
            if status != 0:
                problems.append(f"the checkpoint does not continue (exit {status})")
                output += more
    except Exception as e:
        problems.append(f"{type(e).__name__}: {e}")
    report("the reader of the output goes away (| head -1): SIGPIPE stops the run with a checkpoint, exit 141",
           problems, output)
    # A run that has finished when its last line meets a closed pipe has finished: exit 0.
    for label, args in [("a run", [TINY, "--output", fresh("pipe-end"), "--set", "Run/Max Steps=20"]),
                        ("--help-parameters", ["--help-parameters"])]:
        proc = subprocess.Popen([POREESPH] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
        proc.stdout.close()
        errors = proc.communicate(timeout=600)[1].decode(errors="replace")
        report(f"{label} whose output has no reader left ends with exit 0, not 141",
               [] if proc.returncode == 0 else [f"exit status {proc.returncode}"], errors)


def class_14_continued_runs():
    """A run interrupted (by Run/Max Steps, by a signal) and continued reports what the run in one go
    reports: summary.json equal key for key, wall times and restarts aside."""
    scenes = [
        ("a single run", [GRAIN, *STEADY, "Discretization/Particle Spacing=0.025"], lambda out: [last_history_step(out)]),
        # To End Time: the finer level takes four times the steps (dt goes with the spacing squared).
        ("a ladder", [GRAIN, "Run/End Time=10", "Convergence/Levels=2", "Discretization/Particle Spacing=0.025"],
         lambda out: [level["steps"] for level in summary(out)["convergence"]]),
        ("a tensor run", [TWO_GRAINS, *STEADY, "Permeability/Tensor=true", "Discretization/Particle Spacing=0.025"],
         lambda out: [last_history_step(out, "_x"), last_history_step(out, "_y")]),
        ("a linearity check", [GRAIN, *STEADY, "Permeability/Linearity Check=true",
                               "Discretization/Particle Spacing=0.025"],
         lambda out: [last_history_step(out), last_history_step(out, "_half_force")]),
    ]
    for label, settings, stage_steps in scenes:
        key = re.sub(r"[^a-z0-9]+", "-", label)
        whole = fresh("whole-" + key)
        status, output = run([TINY, "--output", whole] + sets(*settings, "Output/Field Interval=3"))
        if status != 0:
            report(f"{label}: the run in one go", [f"exit {status}"], output)
            continue
        steps = stage_steps(whole)
        # Run/Max Steps applies to each stage: it cuts a run in its last stage alone when every stage
        # before it ended sooner (a continued run goes on with the stage of its checkpoint).
        if len(steps) == 1 or max(steps[:-1]) < steps[-1] - 20:
            cut = (max(steps[:-1], default=0) + steps[-1]) // 2
            out = fresh("max-steps-" + key)
            status, output = run([TINY, "--output", out] + sets(*settings, "Output/Field Interval=3",
                                                                f"Run/Max Steps={cut}"))
            first = summary(out) if status == 0 else {}
            case(f"{label} stopped by Run/Max Steps at {cut} (stages in one go: {steps}) and continued",
                 [TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] +
                 sets(*settings, "Output/Field Interval=3"), 0, r"summary in",
                 lambda o=out, w=whole, f=first: "; ".join(p for p in [
                     "" if f.get("stopped_by") == "max_steps" else f"the first part ended by {f.get('stopped_by')}",
                     same_summary(o, w), frames_consistent(o)] if p))
        else:
            print(f"note   {label}: its last stage ends first ({steps}); Run/Max Steps cannot cut it alone")
        # A signal, wherever it comes; the run continued from its checkpoint.
        for number in (signal.SIGTERM, signal.SIGHUP):
            out = fresh(f"signal-{number}-" + key)
            problems, output = [], ""
            proc = start([TINY, "--output", out] + sets(*settings, "Output/Field Interval=3", "Run/Progress=never"))
            # Half way through the run in one go, as its history files count their rows.
            rows = sum(history_rows(whole, f[len("permeability_history"):-4]) for f in names(whole)
                       if f.startswith("permeability_history"))
            wait_for(lambda: sum(history_rows(out, f[len("permeability_history"):-4]) for f in names(out) or []
                                 if f.startswith("permeability_history")) >= rows // 2 or proc.poll() is not None,
                     timeout=300, poll=0.001)
            proc.send_signal(number)
            output = proc.communicate(timeout=600)[0]
            where = ""
            if proc.returncode != 128 + number:
                problems.append(f"exit status {proc.returncode}")
            else:
                stopped = re.search(r"stopped by SIG[A-Z]+ at step [0-9]+", output)
                where = f" ({stopped.group(0)} of a stage)" if stopped else ""
                status, more = run([TINY, "--output", out, "--restart", os.path.join(out, "checkpoint.h5")] +
                                   sets(*settings, "Output/Field Interval=3"))
                output += more
                problems += [p for p in [f"exit status {status}" if status else "", same_summary(out, whole),
                                         frames_consistent(out)] if p]
            report(f"{label} stopped by {signal.Signals(number).name}{where} and continued", problems, output)


def class_15_scene_requests():
    """What a scene asks for must be what it gets: a force off the axes, a measurement without a force, a
    parameter given twice, options that do nothing are refused with a message that says what to do."""
    out = fresh("requests")
    for force in ["{0.001, 0.001}", "{0.001, -0.0005}"]:
        case(f"a body force {force} off the axes, without Permeability/Tensor, is refused",
             [TINY, "--output", out] + sets(f"Fluid/Body Force={force}", GRAIN), 2,
             r"Fluid/Body Force = \(.*\) does not lie along one axis.*Permeability/Tensor = true", absent(out))
    case("... in 3D too", [TINY, "--output", out] + sets("Domain/Cell Size={1, 1, 1}",
         "Fluid/Body Force={0.001, 0, 0.001}"), 2, r"does not lie along one axis", absent(out))
    tensor = fresh("oblique-tensor")
    case("the same force with Permeability/Tensor measures the tensor with its magnitude",
         [TINY, "--output", tensor] + sets("Fluid/Body Force={0.001, 0.001}", GRAIN, "Permeability/Tensor=true",
                                           "Run/Max Steps=20"), 0, r"summary in",
         lambda: "" if set(summary(tensor)["permeability"]) == {"kxx", "kyx", "kxy", "kyy"} else "no tensor")
    for settings, asked in [
        (["Permeability/Tensor=true"], "Permeability/Tensor asks"),
        (["Permeability/Steady Tolerance=0.01"], "Permeability/Steady Tolerance asks"),
        (["Permeability/Linearity Check=true", "Convergence/Levels=2"],
         "Permeability/Linearity Check and Convergence/Levels ask"),
        (["Permeability/Steady Window=5"], "Permeability/Steady Window asks")]:
        case(f"{', '.join(settings)} without a body force is refused",
             [TINY, "--output", out] + sets("Fluid/Body Force={0, 0}", "Fluid/Velocity Scale=0.01", GRAIN, *settings), 2,
             rf"{re.escape(asked)} for the permeability, which a body force measures, and Fluid/Body Force is zero",
             absent(out))
    channel = os.path.join(INPUT, "poiseuille.xml")
    for settings, asked in [(["Permeability/Steady Tolerance=0.0001"], "Permeability/Steady Tolerance"),
                            (["Solver/Method=steady"], "Solver/Method = steady")]:
        case(f"a force across a channel's walls with {', '.join(settings)} is refused: no flow crosses them",
             [channel, "--output", out] + sets("Fluid/Body Force={0, 1e-8}", *settings), 2,
             rf"drives along y, where the channel's walls close the cell: no flow crosses them, so k along y is "
             rf"zero and {re.escape(asked)} cannot measure it", absent(out))
    walled = fresh("walled-tensor")
    case("Permeability/Tensor in a channel drives along the walls only",
         [channel, "--output", walled] + sets("Permeability/Tensor=true", "Solver/Method=steady"), 0, r"converged",
         lambda: "" if set(summary(walled)["permeability"]) == {"kxx", "kyx"} else "a column across the walls")
    case("Diagnostics/Profile Sample Times without a channel is refused",
         [TINY, "--output", out] + sets("Diagnostics/Profile Sample Times={1}"), 2,
         r"Profile Sample Times compares a channel's velocity profile .* no channel", absent(out))
    case("Output/Grid Points without field files is refused", [TINY, "--output", out] + sets("Output/Grid Points={8, 8}"),
         2, r"Output/Grid Points is given, but .*Output/Field Interval is 0", absent(out))
    for first, second in [("Run/Max Steps=5", "Run/Max Steps=6"),
                          ("Fluid/Kinematic Viscosity=0.01", "Fluid/Kinematic Viscosity=0.01"),
                          ("Scene/Name=a", "Scene/Name=b")]:
        case(f"--set {first.split('=')[0]} given twice is refused, as the XML refuses it",
             [TINY, "--output", out, "--set", first, "--set", second], 2,
             rf"--set {re.escape(first.split('=')[0])} is given twice \('{re.escape(first)}' and '{re.escape(second)}'\)",
             absent(out))
    case("--inject-nan given twice is refused", [TINY, "--output", out, "--inject-nan", "3", "--inject-nan", "4"], 2,
         r"--inject-nan given twice", absent(out))


def class_16_messages():
    """Messages that say what to fix: no source paths of Teuchos, no suggestion of the very name typed."""
    out = fresh("messages")
    teuchos_noise = r"\.(cpp|hpp):[0-9]+|Throw number|Throw test"
    def clean(output):
        return "" if not re.search(teuchos_noise, output) else "Teuchos's source paths in the message"
    for settings, message in [
        (["Fluid/Kinematic Viscosity=-1"], r"Fluid/Kinematic Viscosity = -1 is out of range: it must be at least 0"),
        (["Walls/Type=chanel"], r"Walls/Type: 'chanel' is not one of its values, 'none', 'channel'; did you mean 'channel'"),
        (["Domain/Cell Size={1, -1}"], r"Domain/Cell Size: element 2 = -1 is out of range: it must be at least 0"),
        (["Convergence/Levels=11"], r"Convergence/Levels = 11 is out of range: it must be between 1 and 10"),
        (["Fluid/Density Variation=0.9"], r"Fluid/Density Variation = 0.9 is out of range: it must be between 1e-06 and 0.5")]:
        try:
            status, output = run([TINY, "--output", out] + sets(*settings))
            problems = [p for p in [f"exit status {status}" if status != 2 else "",
                                    "" if re.search(message, output) else f"output does not match /{message}/",
                                    clean(output), absent(out)()] if p]
        except Exception as e:
            problems, output = [str(e)], ""
        report(f"{settings[0]}: the range in the scene's terms", problems, output)
    tiny = open(TINY).read()
    base = os.path.dirname(out)
    for label, text, message in [
        ("a value where a group is expected",
         tiny.replace('<ParameterList name="Run">', '<Parameter name="Permeability" type="double" value="1"/>'
                      '<ParameterList name="Run">'),
         r"Permeability is a group of parameters, not a value: write it as <ParameterList name=\"Permeability\">"),
        ("a group where a value is expected",
         tiny.replace('<Parameter name="Kinematic Viscosity" type="double" value="0.01"/>',
                      '<ParameterList name="Kinematic Viscosity"><Parameter name="Value" type="double" value="0.01"/>'
                      '</ParameterList>'),
         r"Fluid/Kinematic Viscosity is a parameter, not a group of them: write it as <Parameter name=\"Kinematic "
         r"Viscosity\" type=\"double\""),
        ("XML that is not well-formed", tiny.replace("</ParameterList>\n</ParameterList>", "</ParameterList>\n"),
         r"it is not well-formed XML: XML parse error")]:
        scene = write(os.path.join(base, re.sub(r"[^a-z]+", "-", label) + ".xml"), text)
        status, output = run([scene, "--output", out])
        problems = [p for p in [f"exit status {status}" if status != 2 else "",
                                "" if re.search(message, output) else f"output does not match /{message}/",
                                clean(output), "it suggests the name typed" if "did you mean" in output else "",
                                absent(out)()] if p]
        report(f"{label}: said as such", problems, output)
    for setting, message in [("Fluid=1", r"--set Fluid: 'Fluid' is a group of parameters, not a value"),
                             ("Fluid/Density/Value=1", r"--set Fluid/Density/Value: 'Density' is a parameter, not a group")]:
        case(f"--set {setting}: said as such", [TINY, "--output", out, "--set", setting], 2, message, absent(out))
    case("a periodic cell narrower than the kernel's reach names the spacing that fits",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.5"], 2,
         r"Domain/Cell Size\[0\] = 1 is not wider than the kernel's reach at spacing 0.5.*smaller than 0.3333",
         absent(out))
    case("... and one as wide as the reach is refused without advising the spacing just given",
         [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.25", "--set",
          "Domain/Cell Size={0.75, 1.0}"], 2,
         r"Domain/Cell Size\[0\] = 0.75 is not wider than the kernel's reach at spacing 0.25, 0.75 .*smaller than 0.25",
         absent(out))
    for ranks, most in [(5, 4), (7, 6)]:
        case(f"{ranks} processes for a 4 x 4 lattice: refused, suggesting {most}",
             [TINY, "--output", out, "--set", "Discretization/Particle Spacing=0.25", "--set", "Run/Max Steps=2"], 2,
             rf"cannot be split into {ranks} sub-domains.*Run on at most {most} processes \(mpiexec -n {most}\)",
             absent(out), mpi=ranks)


def expat_parses(path):
    import xml.parsers.expat
    try:
        xml.parsers.expat.ParserCreate().Parse(open(path, "rb").read(), True)
        return ""
    except Exception as e:
        return f"{os.path.basename(path)} does not parse: {e}"


def class_17_names_and_encodings():
    """Names in any language reach every file as UTF-8; files in other encodings are named as such."""
    tiny = open(TINY).read()
    base = os.path.dirname(fresh("names"))
    def scene_named(label, value, encoding="utf-8", prefix=b""):
        text = tiny.replace('value="tiny"', f'value="{value}"')
        return write_bytes(os.path.join(base, label + ".xml"), prefix + text.encode(encoding))
    for label, value, expected in [
        ("decimal-reference", "caf&#233;", "café"), ("hex-reference", "caf&#xE9;", "café"),
        ("beyond-latin-1", "&#8364; &#x1F600;", "€ 😀"), ("utf-8", "Darcy–Forchheimer ø", "Darcy–Forchheimer ø"),
        ("markup", "a &lt;b&gt; &amp; &quot;c&quot;", 'a <b> & "c"')]:
        out = os.path.join(base, "out-" + label)
        shutil.rmtree(out, ignore_errors=True)
        scene = scene_named(label, value)
        def everywhere(out=out, expected=expected):
            problems = []
            if summary(out)["scene"] != expected:
                problems.append(f"summary.json says {summary(out)['scene']!r}")
            problems += [p for p in [expat_parses(os.path.join(out, "parameters_used.xml"))] if p]
            again = out + "-again"
            shutil.rmtree(again, ignore_errors=True)
            status, output = run([os.path.join(out, "parameters_used.xml"), "--output", again, "--set",
                                  "Run/Max Steps=2"])
            if status != 0 or summary(again)["scene"] != expected:
                problems.append(f"parameters_used.xml does not read back as the scene: {output}")
            return "; ".join(problems)
        case(f"Scene/Name {value!r} is {expected!r} in summary.json and parameters_used.xml, which parses",
             [scene, "--output", out, "--set", "Run/Max Steps=2"], 0, r"summary in", everywhere)
    out = os.path.join(base, "out-latin-1")
    shutil.rmtree(out, ignore_errors=True)
    declared = write_bytes(os.path.join(base, "declared-latin-1.xml"),
                           b'<?xml version="1.0" encoding="ISO-8859-1"?>\n' +
                           tiny.replace('value="tiny"', 'value="café"').encode("latin-1"))
    case("a file declared ISO-8859-1 is read as such", [declared, "--output", out, "--set", "Run/Max Steps=2"], 0,
         r"summary in", lambda: "" if summary(out)["scene"] == "café" else f"scene {summary(out)['scene']!r}")
    out = os.path.join(base, "out-refused")
    shutil.rmtree(out, ignore_errors=True)
    bom = scene_named("bom", "tiny", prefix=b"\xef\xbb\xbf")
    bom_out = os.path.join(base, "out-bom")
    shutil.rmtree(bom_out, ignore_errors=True)
    case("a UTF-8 file with a byte order mark is read", [bom, "--output", bom_out, "--set", "Run/Max Steps=2"], 0,
         r"summary in", None)
    for label, data, message in [
        ("UTF-16 with its byte order mark (little-endian)", b"\xff\xfe" + tiny.encode("utf-16-le"),
         r"the file is in UTF-16 \(it starts with that byte order mark\): save it as UTF-8"),
        ("UTF-16 with its byte order mark (big-endian)", b"\xfe\xff" + tiny.encode("utf-16-be"),
         r"the file is in UTF-16 \(it starts with that byte order mark\): save it as UTF-8"),
        ("UTF-16 without a byte order mark", tiny.encode("utf-16-le"), r"the file is in UTF-16 or UTF-32"),
        ("UTF-32", b"\xff\xfe\x00\x00" + tiny.encode("utf-32-le"), r"the file is in UTF-32"),
        ("Latin-1 without a declaration", tiny.replace('value="tiny"', 'value="café"').encode("latin-1"),
         r"line 2: the byte 0xE9 is not UTF-8 .*save it as UTF-8"),
        ("another declared encoding", b'<?xml version="1.0" encoding="Shift_JIS"?>\n' + tiny.encode(),
         r"its XML declaration says encoding \"shift_jis\": save it as UTF-8"),
        ("an entity XML does not define", tiny.replace('value="tiny"', 'value="caf&eacute;"').encode(),
         r"line 2: '&eacute;' is not an entity XML knows"),
        ("a reference to no character", tiny.replace('value="tiny"', 'value="a&#0;"').encode(),
         r"line 2: '&#0;' is not a character XML allows"),
        ("a tab in Scene/Name", tiny.replace('value="tiny"', 'value="a&#9;b"').encode(),
         r"Scene/Name contains a control character \(code 9\)")]:
        scene = write_bytes(os.path.join(base, re.sub(r"[^a-z0-9]+", "-", label.lower()) + ".xml"), data)
        case(f"{label}: refused as an encoding problem", [scene, "--output", out], 2, message, absent(out))
    case("--set with a value that is not UTF-8 is refused", [TINY, "--output", out, "--set",
         os.fsdecode(b"Scene/Name=caf\xe9")], 2, r"--set Scene/Name: the value holds the byte 0xE9, which is not UTF-8",
         absent(out))
    grains = write_bytes(os.path.join(base, "grains-bom.txt"), b"\xef\xbb\xbfx y r\n0.5 0.5 0.25\n")
    bom_grains = os.path.join(base, "out-grains-bom")
    shutil.rmtree(bom_grains, ignore_errors=True)
    case("a grain file with a byte order mark is read", [TINY, "--output", bom_grains, "--set", f"Grains/File={grains}",
         "--set", "Run/Max Steps=2"], 0, r"summary in",
         lambda: "" if open(os.path.join(bom_grains, "grains_used.txt")).read().count("\n") >= 1 else "no grains")
    grains = write_bytes(os.path.join(base, "grains-utf16.txt"), "0.5 0.5 0.25\n".encode("utf-16"))
    case("a grain file in UTF-16 is refused as such", [TINY, "--output", out, "--set", f"Grains/File={grains}"], 2,
         r"grains-utf16.txt':1: the file is not text in UTF-8 or ASCII", absent(out))


def write_bytes(file, data):
    with open(file, "wb") as f:
        f.write(data)
    return file


def class_18_image_sizes():
    """Images whose headers declare more voxels than the memory holds are refused by the estimate, before the
    voxels are allocated: under a 4 GB address-space limit, as a small machine has."""
    import resource
    import struct
    import zlib
    base = os.path.dirname(fresh("images"))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    def png(width, height, depth=8):
        header = struct.pack(">IIBBBBB", width, height, depth, 0, 0, 0, 0)
        return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"\0" * 16)) +
                chunk(b"IEND", b""))
    def tiff(width, height, pages=1, tile=None):
        """A little-endian TIFF of `pages` pages whose headers declare the size and hold no pixels."""
        data = bytearray(b"II*\x00" + struct.pack("<I", 8))
        for page in range(pages):
            entries = [(256, 4, width), (257, 4, height), (258, 3, 8), (259, 3, 1), (262, 3, 1), (277, 3, 1)]
            if tile:
                entries += [(322, 4, tile), (323, 4, tile), (324, 4, 0), (325, 4, 16)]
            else:
                entries += [(273, 4, 0), (278, 4, height), (279, 4, 16)]
            entries.sort()
            offset = len(data)
            ifd = struct.pack("<H", len(entries))
            for tag, kind, value in entries:
                ifd += struct.pack("<HHIHH", tag, kind, 1, value, 0) if kind == 3 else struct.pack("<HHII", tag, kind, 1, value)
            following = offset + len(ifd) + 4
            ifd += struct.pack("<I", following if page + 1 < pages else 0)
            data += ifd
        return bytes(data)
    huge = [("a 68-byte PNG declaring 100000 x 100000", "huge.png", png(100000, 100000), [], "100000 x 100000", "400"),
            ("a 16-bit PNG declaring 60000 x 60000", "huge16.png", png(60000, 60000, 16), [], "60000 x 60000", "144"),
            ("a TIFF declaring 100000 x 100000", "huge.tif", tiff(100000, 100000), [], "100000 x 100000", "400"),
            ("a TIFF stack of 3 pages of 30000 x 30000", "stack.tif", tiff(30000, 30000, 3),
             ["Domain/Cell Size={1, 1, 1}", "Fluid/Body Force={0.001, 0, 0}"], "30000 x 30000 x 3", "108"),
            ("a tiled TIFF declaring 80000 x 80000", "tiled.tif", tiff(80000, 80000, tile=256), [], "80000 x 80000",
             "256")]
    out = os.path.join(base, "out")
    shutil.rmtree(out, ignore_errors=True)
    def four_gigabytes():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    for label, name, data, settings, shape, gigabytes in huge:
        image = write_bytes(os.path.join(base, name), data)
        case(f"{label}: refused by the memory estimate under ulimit -v 4 GB",
             [TINY, "--output", out] + sets(f"Image/File={image}", "Image/Solid Values={1}", "Image/Voxel Size=1e-5",
                                            *settings), 2,
             rf"Image/File '.*{re.escape(name)}' \({shape}\): making its walls takes about {gigabytes}[0-9.]* GB .*"
             rf"GB are available \(", absent(out), preexec=four_gigabytes)
    # Raw volumes whose size matches their shape: sparse files, no disk is used.
    for label, shape, kind, gigabytes in [("8 GB of uint8", "{2000, 2000, 2000}", "uint8", "320"),
                                          ("a 1.6 GB uint16 volume", "{1000, 1000, 800}", "uint16", "32"),
                                          ("120 MB, in most machines' memory but not in the limit",
                                           "{500, 500, 480}", "uint8", "4.8")]:
        voxels = 1
        for n in re.findall(r"[0-9]+", shape):
            voxels *= int(n)
        raw = os.path.join(base, f"volume-{voxels}-{kind}.raw")
        with open(raw, "wb") as f:
            f.truncate(voxels * (2 if kind == "uint16" else 1))
        case(f"a raw volume of {label}: refused by the memory estimate under ulimit -v 4 GB",
             [TINY, "--output", out] + sets(f"Image/File={raw}", f"Image/Shape={shape}", f"Image/Type={kind}",
                                            "Domain/Cell Size={1, 1, 1}", "Fluid/Body Force={0.001, 0, 0}",
                                            "Image/Solid Values={1}", "Image/Voxel Size=1e-5"), 2,
             rf"making its walls takes about {gigabytes}[0-9.]* GB for a moment .* GB are available \((what is left "
             rf"of the process's address-space limit \(ulimit -v\)|MemAvailable in /proc/meminfo)\)", absent(out),
             preexec=four_gigabytes)
        os.remove(raw)
    image = os.path.join(base, "huge.png")
    case("Run/Memory Limit below the image's needs: the same refusal, naming the limit",
         [TINY, "--output", out] + sets(f"Image/File={image}", "Image/Solid Values={1}", "Image/Voxel Size=1e-5",
                                        "Run/Memory Limit=2"), 2, r"2 GB are available \(Run/Memory Limit\)", absent(out),
         preexec=four_gigabytes)


def class_19_paths():
    """Paths that cannot work are found before any work, saying what to fix."""
    base = os.path.dirname(fresh("paths"))
    loop_a, loop_b = os.path.join(base, "loop-a"), os.path.join(base, "loop-b")
    os.symlink(loop_b, loop_a)
    os.symlink(loop_a, loop_b)
    dangling = os.path.join(base, "dangling")
    os.symlink(os.path.join(base, "nowhere", "dir"), dangling)
    a_file = write(os.path.join(base, "a-file"), "text\n")
    dangling_image = os.path.join(base, "image.png")
    os.symlink(os.path.join(base, "nowhere", "image.png"), dangling_image)
    out = os.path.join(base, "out")
    loop = r"its symbolic links lead in a loop"
    for label, args, message, after in [
        ("the scene is a symbolic link loop", [loop_a, "--output", out], "cannot read scene file .*: " + loop, absent(out)),
        ("the scene is a dangling symbolic link", [dangling, "--output", out],
         r"cannot read scene file .*: it is a symbolic link to '.*nowhere/dir', which does not exist", absent(out)),
        ("the scene's path runs through a file", [os.path.join(a_file, "scene.xml"), "--output", out],
         r"a part of the path before its last name is a file", absent(out)),
        ("Grains/File is a symbolic link loop", [TINY, "--output", out, "--set", f"Grains/File={loop_a}"],
         r"Grains/File: cannot open .*: " + loop, absent(out)),
        ("Image/File is a dangling symbolic link",
         [TINY, "--output", out] + sets(f"Image/File={dangling_image}", "Image/Solid Values={1}",
                                        "Image/Voxel Size=0.25"),
         r"Image/File .*image.png': it is a symbolic link to '.*nowhere/image.png', which does not exist", absent(out)),
        ("--restart is a symbolic link loop", [TINY, "--output", out, "--restart", loop_a], r"--restart .*: " + loop,
         absent(out)),
        ("--output is a symbolic link loop", [TINY, "--output", loop_a], r"--output .*loop-a: " + loop, None),
        ("--output is a dangling symbolic link", [TINY, "--output", dangling],
         r"--output .*dangling: it is a symbolic link to '.*nowhere/dir', which does not exist: create that directory",
         absent(os.path.join(base, "nowhere"))),
        ("--output under a file", [TINY, "--output", os.path.join(a_file, "out")],
         r"a part of the path is a file, not a directory", None),
        ("--output where no directory can be made", [TINY, "--output", "/proc/poresph-out"],
         r"--output /proc/poresph-out: cannot create '/proc/poresph-out'", absent("/proc/poresph-out")),
        ("--output with a name too long", [TINY, "--output", os.path.join(base, "x" * 300)],
         r"too long for the file system", None)]:
        case(f"{label}: exit 2 before any work, saying what is wrong", args, 2, message, after)
    dangling_parent = os.path.join(dangling, "run")
    case("--output inside a dangling symbolic link", [TINY, "--output", dangling_parent], 2,
         r"is a symbolic link to '.*nowhere/dir', which does not exist", absent(os.path.join(base, "nowhere")))
    target = os.path.join(base, "target")
    os.makedirs(target)
    link = os.path.join(base, "link")
    os.symlink(target, link)
    case("--output through a symbolic link to a directory writes there", [TINY, "--output", link, "--set",
         "Run/Max Steps=2"], 0, r"summary in", lambda: "" if "summary.json" in names(target) else "not in the target")
    # A file system mounted read-only, where one can be (root in a container that allows it).
    readonly = os.path.join(base, "read-only")
    os.makedirs(readonly, exist_ok=True)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=1m", "tmpfs", readonly], capture_output=True).returncode:
        print("skip   a read-only file system (cannot mount one here)")
        return
    try:
        case("--output on a read-only file system: exit 2 before any work",
             [TINY, "--output", os.path.join(readonly, "out")], 2, r"Read-only file system", None)
    finally:
        subprocess.run(["umount", readonly])


def class_20_durability():
    """Each file is on the disk before it takes its final name, and its directory after the rename: a
    power loss leaves the old file or the new, never an empty one under the name."""
    library = os.environ.get("IO_ORDER_LIBRARY", "")
    for label, settings, extra, status_expected in [
        ("a run with checkpoints and field files", ["Output/Checkpoint Interval=10", "Output/Field Interval=0.5"], [], 0),
        ("a run that fails", ["Output/Field Interval=0.5"], ["--inject-nan", "15"], 3)]:
        out = fresh("durable-" + re.sub(r"[^a-z]+", "-", label))
        log = os.path.join(os.path.dirname(out), "io.log")
        env = dict(ENV, LD_PRELOAD=library, PORESPH_IO_ORDER_LOG=log)
        status, output = run([TINY, "--output", out] + sets("Run/Max Steps=40", *settings) + extra, env=env)
        problems = [] if status == status_expected else [f"exit status {status}"]
        lines = [line.split() for line in open(log)] if os.path.exists(log) else []
        renames = [(k, l[1], l[2]) for k, l in enumerate(lines) if l[0] == "rename"]
        if not renames:
            problems.append("no rename was logged")
        directory = os.path.realpath(out)
        for k, old, new in renames:
            if not any(l == ["fsync", old] for l in lines[:k]):
                problems.append(f"{os.path.basename(new)}: renamed without an fsync of {os.path.basename(old)}")
            if not any(l == ["fsync", directory] for l in lines[k + 1:]):
                problems.append(f"{os.path.basename(new)}: its directory is not synced after the rename")
        kinds = sorted({re.sub(r"_[0-9]+\.h5$", "_N.h5", os.path.basename(new)) for _, _, new in renames})
        report(f"{label}: every rename ({len(renames)}: {', '.join(kinds)}) follows an fsync and precedes the "
               "directory's", problems[:5], output)

def class_21_results_as_asked():
    """A result means what its name says: k the same for a force either way, no k of a cell the grains close,
    grains the lattice cannot see named, a checkpoint of two fluids not continued as one."""
    channel = os.path.join(INPUT, "poiseuille.xml")
    short = ["Discretization/Particle Spacing=1e-4", "Run/Max Steps=200"]
    ks = {}
    for force in ["2e-4", "-2e-4"]:
        out = fresh(f"force{force}")
        case(f"a channel driven along {'-' if force[0] == '-' else '+'}x", [channel, "--output", out] +
             sets(*short, f"Fluid/Body Force={{{force}, 0}}"), 0, r"summary in",
             lambda o=out, f=force: ks.__setitem__(f, summary(o)["permeability"]["kxx"]) or "")
    report("a force along -x gives the k of one along +x, positive",
           [] if len(ks) == 2 and ks["2e-4"] > 0 and ks["-2e-4"] == ks["2e-4"] else [f"k {ks}"])
    grains = os.path.join(INPUT, "problem3", "problem3.xml")
    closed = fresh("closed")
    write(os.path.join(os.path.dirname(closed), "touching.txt"), "0.05 0.05 0.05\n")
    for method in ["explicit", "steady"]:
        case(f"a grain touching its periodic images closes the cell: refused ({method})",
             [grains, "--output", closed] + sets("Discretization/Particle Spacing=0.002",
                                                 "Grains/File=" + os.path.join(os.path.dirname(closed), "touching.txt"),
                                                 f"Solver/Method={method}"), 2,
             r"no pore path crosses the cell along x, the driven axis", absent(closed))
    small = fresh("small")
    write(os.path.join(os.path.dirname(small), "small.txt"), "0.05 0.05 0.0005\n0.02 0.02 0.01\n")
    case("a grain that holds no lattice point is named", [grains, "--output", small] +
         sets("Discretization/Particle Spacing=0.002", "Run/Max Steps=5",
              "Grains/File=" + os.path.join(os.path.dirname(small), "small.txt")), 0,
         r"1 grain \(.*small.txt:1, radius 0.0005\) holds no lattice point",
         lambda: "" if any("holds no lattice point" in w for w in summary(small)["warnings"])
         else "not in summary.json")
    two = fresh("two-fluids")
    layered = os.path.join(INPUT, "two_phase", "layered_poiseuille.xml")
    spacing = "Discretization/Particle Spacing=6.25e-5"
    case("a two-fluid run's checkpoint", [layered, "--output", two] +
         sets(spacing, "Solver/Method=explicit", "Run/Max Steps=20"), 0, r"summary in", None)
    one = fresh("one-fluid")
    step = summary(two)["time_step"] if os.path.exists(os.path.join(two, "summary.json")) else 0
    sound = summary(two)["sound_speed"] if step else 0
    case("... is not continued by a scene of one fluid with the same cell, spacing, c and step",
         [channel, "--output", one, "--restart", os.path.join(two, "checkpoint.h5")] +
         sets(spacing, "Domain/Cell Size={2.5e-4, 1e-3}", "Run/Max Steps=40", f"Fluid/Sound Speed={sound!r}",
              f"Discretization/Time Step={step!r}"), 2,
         r"other physics.*Phases/Count: 2 in the checkpoint, none here", absent(one))
    # An image of more values than solid and one pore: each unnamed value counted, all read as pore.
    labels = fresh("labels")
    folder = os.path.dirname(labels)
    values = bytearray(40 * 40)
    for j in range(10, 20):
        values[j * 40 + 10:j * 40 + 20] = bytes([1]) * 10
    for j in range(25, 30):
        values[j * 40 + 5:j * 40 + 35] = bytes([2]) * 30
    with open(os.path.join(folder, "labels.raw"), "wb") as f:
        f.write(bytes(values))
    image = sets("Grains/Inline={}", "Image/File=" + os.path.join(folder, "labels.raw"), "Image/Shape={40, 40}",
                 "Image/Voxel Size=0.025", "Discretization/Particle Spacing=0.025", "Run/Max Steps=3")
    case("an image with a value neither solid nor the pore's is warned of, with the voxels of each",
         [TINY, "--output", labels] + image + sets("Image/Solid Values={1}"), 0,
         r"holds 2 values that Image/Solid Values \{1\} does not name \(value: voxels 0: 1350, 2: 150\), all read as "
         r"pore", None)
    named = fresh("labels-named")
    case("... and not when every value but the pore's is named", [TINY, "--output", named] + image +
         sets("Image/Solid Values={1, 2}"), 0, r"summary in",
         lambda: "" if not any("does not name" in w for w in summary(named)["warnings"]) else "warned")
    column = fresh("column")
    case("a channel of settling grains has no profile against an empty channel's (no null in summary.json)",
         [os.path.join(INPUT, "moving", "settling_column.xml"), "--output", column, "--set", "Run/Max Steps=10"], 0,
         r"summary in", lambda: "" if "null" not in open(os.path.join(column, "summary.json")).read()
         and "profile_error" not in summary(column) else "a profile error, or null, in summary.json")
    across = fresh("across")
    case("a force across a channel's walls measures no k, and says so", [channel, "--output", across] +
         sets(*short, "Fluid/Body Force={0, 2e-4}", "Diagnostics/Profile Sample Times={}"), 0,
         r"drives along y, across the channel's walls: no flow crosses them, so no k is measured",
         lambda: "" if "permeability" not in summary(across) else "a k across the walls")
    profile = fresh("across-profile")
    case("... and comparing its profile with an empty channel's is refused", [channel, "--output", profile] +
         sets(*short, "Fluid/Body Force={0, 2e-4}"), 2,
         r"Profile Sample Times compares the velocity profile of an empty channel driven along x", absent(profile))
    inviscid = fresh("inviscid")
    case("no viscosity under a body force: no k, said so", [channel, "--output", inviscid] +
         sets(*short, "Fluid/Kinematic Viscosity=0"), 0, r"nothing resists the body force", None)
    case("an empty Scene/Name is refused", [TINY, "--output", fresh("unnamed"), "--set", "Scene/Name="], 2,
         r"Scene/Name is empty", None)
    for height, warned in [("3e-4", True), ("1e-3", False)]:
        narrow = fresh(f"channel-{height}")
        case(f"a channel {height} m high at a spacing of 1e-4 m {'is' if warned else 'is not'} warned of as narrow",
             [channel, "--output", narrow] + sets(*short, f"Domain/Cell Size={{5e-4, {height}}}",
                                                  "Diagnostics/Profile Sample Times={}"), 0, r"summary in",
             lambda o=narrow, w=warned: "" if any("particle spacings high" in x for x in summary(o)["warnings"]) == w
             else "warned" if not w else "not warned")
    ahead = fresh("ahead")
    good_run(ahead)
    past = fresh("past")
    case("a restart from a checkpoint past the run's Run/Max Steps says it makes no step",
         [TINY, "--output", past, "--restart", os.path.join(ahead, "checkpoint.h5"), "--set", "Run/Max Steps=5"], 0,
         r"--restart: the checkpoint is at step [0-9]+ .*past this run's last step 5 .*no step is made",
         lambda: "" if any("no step is made" in w for w in summary(past)["warnings"]) else "not in summary.json")
    # A steady solve's field file is its solved state (the start at rest shared its step and file).
    solved = fresh("solved-fields")
    def solved_frame():
        import h5py
        files = sorted(f for f in os.listdir(solved) if f.startswith("fields_"))
        if len(files) != 1:
            return f"field files {files}"
        with h5py.File(os.path.join(solved, files[0]), "r") as f:
            if not abs(f["velocity"][...]).max() > 0:
                return "the field file holds fluid at rest"
            solid = f["grid_solid"][...].reshape(-1)
        return "" if solid[len(solid) // 2] == 1 else "the grid node at the grain's centre is not solid"
    case("a steady solve writes its solved flow to the field files; a grid node at a grain's centre is solid",
         [TINY, "--output", solved] + sets(GRAIN, "Solver/Method=steady", "Output/Field Interval=1000",
                                           "Output/Grid Points={11, 11}"), 0, r"converged", solved_frame)
    # A tensor solve cut short, continued: the last axis is solved again, the others are not.
    cut = fresh("tensor-cut")
    case("a tensor solve capped at one Newton step", [TINY, "--output", cut] +
         sets(GRAIN, "Solver/Method=steady", "Permeability/Tensor=true", "Solver/Max Nonlinear Iterations=1",
              "Solver/Tolerance=1e-9"), 4, r"NOT converged", None)
    more = fresh("tensor-continued")
    case("... continued: still not converged, said so in stopped_by, the earlier axis to be run again",
         [TINY, "--output", more, "--restart", os.path.join(cut, "checkpoint.h5")] +
         sets(GRAIN, "Solver/Method=steady", "Permeability/Tensor=true", "Solver/Tolerance=1e-9"), 4,
         r"driven along x did not converge.*run the scene again: a restart continues its last stage only",
         lambda: "" if summary(more)["stopped_by"] == "not_converged" else f"stopped_by {summary(more)['stopped_by']}")
    case("Output/Fields without field files is refused", [TINY, "--output", fresh("fields")] +
         sets("Output/Fields=pressure"), 2, r"Output/Fields is given, but .*Output/Field Interval is 0", None)
    case("Discretization/Spacings Across Throat below 1 is refused", [TINY, "--output", fresh("across")] +
         sets(GRAIN, "Discretization/Particle Spacing=0", "Discretization/Spacings Across Throat=0.5"), 2,
         r"Spacings Across Throat = 0.5.* less than one spacing across the narrowest throat", None)
    case("grains set moving under a body force: k is said not to be a fixed pack's",
         [TINY, "--output", fresh("moving")] + sets("Grains/Inline={0.5, 0.5, 0.15}", "Grains/Motion=free",
                                                    "Grains/Density=2000", "Run/Max Steps=5",
                                                    "Discretization/Particle Motion=lagrangian"), 0,
         r"Grains/Motion moves grains while Fluid/Body Force drives the fluid", None)
    threads = fresh("threads")
    status, output = run([TINY, "--output", threads] + sets("Run/Threads=2", "Run/Max Steps=3"))
    serial = status == 0 and summary(threads)["backend"] == "Serial"
    report("Run/Threads on a build without OpenMP is said to give one thread, not ignored",
           [] if status == 0 and (not serial or any("Run/Threads = 2, but" in w for w in summary(threads)["warnings"]))
           else [f"exit status {status}, or no warning"], output)


def class_22_numbers_that_hold():
    """A number is given only where it carries more than round-off, and an error bar only with what it rests on:
    a body force too small for the density to hold is refused or warned of, and a ladder's unsteady levels are
    named even without a steady tolerance."""
    square = os.path.join(INPUT, "square_array", "square_array_c20.xml")
    coarse = "Discretization/Particle Spacing=0.002"
    tiny = fresh("tiny-force")
    # At this spacing c = 0.001 m/s and L = 0.1 m: |F| L / c^2 = 1e5 |F|.
    case("a body force of 1e-30 m/s^2 (density differences of 1e-25): refused, nothing written",
         [square, "--output", tiny] + sets(coarse, "Fluid/Body Force={1e-30, 0}"), 2,
         r"holds density differences of about \|F\| L / c\^2 = 1e-25 of the fluid's density.*"
         r"round-off more than flow.*a Fluid/Body Force of 1e-1[45] m/s\^2 keeps it below 5e-6", absent(tiny))
    # The same cell 1e4 times larger: c follows the flow's speed F L^2 / (8 nu), a larger force would make the
    # differences smaller, and the advice is a smaller force.
    large = fresh("large-cell")
    case("a cell of 1000 m at the scene's force (a fast flow): refused, the advice a smaller force",
         [square, "--output", large] + sets("Domain/Cell Size={1000, 1000}", "Grains/Inline={500, 500, 252.313252202016}",
                                            "Discretization/Particle Spacing=20"), 2,
         r"The speed of sound follows the flow's speed here .* so a smaller force holds larger differences: "
         r"a Fluid/Body Force of [0-9.e-]+ m/s\^2 keeps it", absent(large))
    short_kernel = fresh("short-kernel")
    case("a smoothing length of 0.8 spacings (k 1.1 % high, 167 % at 0.5): refused",
         [square, "--output", short_kernel] + sets(coarse, "Discretization/Smoothing Length Ratio=0.8"), 2,
         r"Smoothing Length Ratio", absent(short_kernel))
    ks = {}
    for force in ["1e-16", "1e-8"]:
        out = fresh(f"force-{force}")
        case(f"a body force of {force} m/s^2, marched", [square, "--output", out] +
             sets(coarse, f"Fluid/Body Force={{{force}, 0}}", "Run/Max Steps=50"), 0, r"summary in",
             lambda o=out, f=force: ks.__setitem__(f, summary(o)) or "")
    warned = [w for w in ks.get("1e-16", {}).get("warnings", []) if "holds density differences" in w]
    report("... at 1e-16 (differences of 1e-11) the round-off is warned of, at 1e-8 not",
           [] if len(ks) == 2 and warned and "round-off error of about 5e-05" in warned[0] and
           not any("holds density differences" in w for w in ks["1e-8"]["warnings"]) else [f"warnings {warned}"])
    # Run/End Time and Run/Max Steps are the march's: a steady solve is not refused or warned by them.
    for end_time, what in [("1e300", "beyond 2^62 steps"), ("1e-30", "below half a step")]:
        solved = fresh(f"solve-end-{end_time}")
        case(f"a steady solve with Run/End Time {what}: neither refused nor warned of it",
             [square, "--output", solved] + sets(coarse, "Solver/Method=steady", f"Run/End Time={end_time}"), 0,
             r"steady solve converged",
             lambda o=solved: "" if not any("Run/End Time" in w for w in summary(o)["warnings"])
             else f"warnings {summary(o)['warnings']}")
    ladder = fresh("unsteady-ladder")
    case("a ladder whose levels end unsteady, without a steady tolerance: each level named",
         [square, "--output", ladder] + sets(coarse, "Convergence/Levels=3", "Run/Max Steps=300",
                                             "Permeability/Steady Tolerance=0"), 0,
         r"k was not steady when level 3 of 3 ended .*takes each level's k as steady",
         lambda: "" if sum("takes each level's k as steady" in w for w in summary(ladder)["warnings"]) == 3
         else "not three warnings in summary.json")


CLASSES = {"1": class_1_counts, "2": class_2_xml, "3": class_3_grains, "4": class_4_restart,
           "5": class_5_output_directories, "6": class_6_results_kept,
           "7": class_7_messages, "8": class_8_setup_time,
           "9": class_9_tests_stay, "10": class_10_run_files, "11": class_11_claim,
           "12": class_12_restart_no_step_left, "13": class_13_signals, "14": class_14_continued_runs,
           "15": class_15_scene_requests, "16": class_16_messages, "17": class_17_names_and_encodings,
           "18": class_18_image_sizes, "19": class_19_paths, "20": class_20_durability,
           "21": class_21_results_as_asked, "22": class_22_numbers_that_hold}
os.makedirs(WORK, exist_ok=True)
os.chdir(WORK)  # a default output directory (poresph-NAME) lands here, never in the source tree
CLASSES[CLASS]()
print(f"class {CLASS}: {len(failures)} failed" if failures else f"class {CLASS}: all cases ok")
sys.exit(1 if failures else 0)
