"""Running poresph from the perf scripts: one scene of input/, --set
overrides, on one process or under mpiexec; returns the run's summary.json."""
import csv
import functools
import json
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORES = os.cpu_count() or 1
# Open MPI as root and beyond the cores; quiet Kokkos about OMP_PROC_BIND.
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMP_PROC_BIND="false", KOKKOS_DISABLE_WARNINGS="1")


def openmp_env(ranks, threads):
    """The environment of a run: the threads of one process without mpiexec
    are bound to cores, one each, as Kokkos recommends (and as mpiexec binds
    single-thread ranks). Under mpiexec they stay unbound: every rank would
    bind its first thread to the same first core."""
    env = dict(MPI_ENV, OMP_NUM_THREADS=str(threads))
    if ranks is None and threads > 1:
        env.update(OMP_PROC_BIND="spread", OMP_PLACES="cores")
    return env


def poresph_command(build, scene, directory, settings=(), ranks=None, threads=1):
    """The command line that runs input/SCENE with "Sublist/Name=value"
    settings into DIRECTORY. ranks=None runs one process without mpiexec.
    Ranks of one thread are bound to cores while there are cores for them
    (unbound ranks wander and lose their caches); so are the OpenMP threads
    of a single process (openmp_env)."""
    cmd = []
    if ranks is not None:
        binding = "core" if threads == 1 and ranks <= CORES else "none"
        cmd = ["mpiexec", "-n", str(ranks), "--bind-to", binding]
    # A script's run replaces the results of its earlier run in the same directory
    # (a build older than --overwrite replaced them without being asked).
    cmd += [os.path.join(build, "poresph"), os.path.join(ROOT, "input", scene), "--output", directory]
    cmd += ["--overwrite"] if knows_overwrite(build) else []
    cmd += ["--set", "Run/Progress=never"]
    for setting in settings:
        cmd += ["--set", setting]
    return cmd


@functools.lru_cache(maxsize=None)
def knows_overwrite(build):
    """Whether the poresph of `build` takes --overwrite (issue 18 and after)."""
    usage = subprocess.run([os.path.join(build, "poresph"), "--help"], capture_output=True, text=True)
    return "--overwrite" in usage.stdout


def moving_particles(build):
    """The settings that make a poresph of `build` move its particles, as the
    paper's SPH (and LAMMPS's) does: the default keeps them fixed
    (docs/method.md). Empty for a build older than that setting, whose
    particles always move."""
    listing = subprocess.run([os.path.join(build, "poresph"), "--help-parameters"], capture_output=True, text=True)
    if "Particle Motion" not in listing.stdout:
        return []
    return ["Discretization/Particle Motion=lagrangian", "Discretization/Wall Pressure=continuity"]


def read_summary(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def run_poresph(build, scene, directory, settings=(), ranks=None, threads=1, allow_failure=False):
    """Runs poresph_command(...) and returns the run's summary.json.
    allow_failure: a run the solver stopped (exit status 3) still returns its
    summary.json, which then says "stopped_by": "failure" and why."""
    cmd = poresph_command(build, scene, directory, settings, ranks, threads)
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, env=openmp_env(ranks, threads))
    if done.returncode != 0 and not (allow_failure and done.returncode == 3):
        raise subprocess.CalledProcessError(done.returncode, cmd)
    return read_summary(directory)


def run_disc_in_channel(build, directory, length, height, radius, across, end_time, settings=(),
                        particle_motion="lagrangian"):
    """input/couette.xml made LENGTH long (periodic) and HEIGHT high, ACROSS
    particles across the height, moving particles (or PARTICLE_MOTION), a
    disc of RADIUS at its centre, no profile samples, to END_TIME; SETTINGS
    add the walls' speed and how the disc moves. Returns the wall seconds."""
    start = time.monotonic()
    run_poresph(build, "couette.xml", directory, [
        f"Domain/Cell Size={{{length!r}, {height!r}}}", f"Discretization/Particle Spacing={height / across!r}",
        f"Discretization/Particle Motion={particle_motion}",
        f"Grains/Inline={{{length / 2!r}, {height / 2!r}, {radius!r}}}",
        "Diagnostics/Profile Sample Times={}", f"Run/End Time={end_time!r}", *settings])
    return time.monotonic() - start


def write_csv(path, rows):
    """Writes a list of dicts (all with the first row's keys) as CSV."""
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
