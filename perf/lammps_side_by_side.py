#!/usr/bin/python3
"""PoreSPH against LAMMPS's SPH package on the same scenes (issue 15), in
one run, interleaved, one core each:

- 2D: plane Poiseuille flow from rest, 40 particles across a 1 mm channel
  and 1000 along it (periodic in x, 3 rows of wall particles on each side:
  46,000 particles), F = 2e-4 m/s^2, nu = 1e-6 m^2/s, 3000 steps;
- 3D: a periodic box of fluid at rest, 50^3 = 125,000 particles, 200 steps.

The same geometry, particle count, kernel support (3 dx: LAMMPS's Lucy
kernel of support h = 3 dx, PoreSPH's quintic of support 3h, h = dx), time
step, sound speed, steps and start state in both: this script takes the
time step and sound speed PoreSPH derives for each scene (its
summary.json) and writes the matching LAMMPS deck with them. LAMMPS needs
the serial build with the SPH package that perf/lammps_yardstick.sh makes
(default /var/tmp/poresph-lammps/build/lmp).

    perf/lammps_side_by_side.py [--build build] [--lmp LMP] [--repeats 5] [--out build/side-by-side]

PoreSPH runs each scene twice: with its default (fixed particles: what a
scene with no moving boundary needs) and with moving particles
(`Discretization/Particle Motion=lagrangian`, as LAMMPS moves them).
Rates are particle-steps per second of the timed loop (LAMMPS: atoms x
steps / "Loop time" of the run; PoreSPH: summary.json's
particle_steps_per_second, fluid and boundary particles over the time
loop); ratios are medians of the per-repeat ratios. Prints the Markdown
table for docs/performance.md and writes side_by_side.csv into --out.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

from poresph_runs import ROOT, run_poresph, write_csv

SCENES = {
    "2D channel": dict(scene="poiseuille.xml", settings=["Domain/Cell Size={0.025, 1.0e-3}", "Run/Max Steps=3000"]),
    "3D box": dict(scene="problem1/problem1.xml",
                   settings=["Domain/Cell Size={0.05, 0.05, 0.05}", "Run/Max Steps=200"]),
}
MOVING = ["Discretization/Particle Motion=lagrangian"]


def preamble(title, dimension, boundary, dx):
    """The opening lines both decks share: SI units, SPH atoms, Newton's
    third law on (half neighbour lists, as PoreSPH's), and the spacing dx."""
    return f"""# {title} (perf/lammps_side_by_side.py)
units si
dimension {dimension}
atom_style sph
boundary {boundary}
newton on
variable dx equal {dx!r}"""


def sph_model(c):
    """The fluid both decks share, as in PoreSPH's scenes: water (rho0 = 1000
    kg/m^3, mu = 1e-3 Pa s) with the Tait equation of state at sound speed c,
    Morris's viscosity, support 3 dx; LAMMPS's list with a skin of 0.2 dx,
    checked every step."""
    return f"""set group all sph/rho 1000.0
set group all sph/e 0.0
pair_style sph/taitwater/morris
pair_coeff * * 1000.0 {c!r} 1.0e-3 $(3.0*v_dx)
neighbor $(0.2*v_dx) bin
neigh_modify every 1 delay 0 check yes
"""


def timed_run(dt, steps):
    """One run of `steps` steps of dt, timed by LAMMPS's "Loop time"."""
    return f"""timestep {dt!r}
thermo {steps}
run {steps}
"""


def channel_deck(dx, c, dt, steps):
    """LAMMPS: the channel of input/poiseuille.xml, 1000 x 40 fluid particles
    on a square lattice with 3 rows of frozen wall particles on each side,
    starting from rest under the body force."""
    return f"""{preamble("2D Poiseuille flow from rest", 2, "p f p", dx)}
lattice sq ${{dx}} origin 0.5 0.5 0.0
region box block 0 1000 -3 43 -0.5 0.5 units lattice
create_box 2 box
region fluid block INF INF 0 40 INF INF units lattice
region walls block INF INF 0 40 INF INF side out units lattice
create_atoms 1 region fluid
create_atoms 2 region walls
group fluid type 1
group walls type 2
mass * $(1000.0*v_dx*v_dx)
{sph_model(c)}fix drive fluid gravity 2.0e-4 vector 1 0 0
fix integ fluid sph
fix frozen walls sph/stationary
fix twod all enforce2d
{timed_run(dt, steps)}"""


def box_deck(dx, c, dt, steps):
    """LAMMPS: a periodic cube of 50^3 fluid particles at rest."""
    return f"""{preamble("3D periodic box of fluid at rest", 3, "p p p", dx)}
lattice sc ${{dx}} origin 0.5 0.5 0.5
region box block 0 50 0 50 0 50 units lattice
create_box 1 box
create_atoms 1 region box
mass * $(1000.0*v_dx*v_dx*v_dx)
{sph_model(c)}fix integ all sph
{timed_run(dt, steps)}"""


def run_lammps(lmp, deck_path, directory):
    """Particle-steps per second of the deck's timed run."""
    log = os.path.join(directory, "log.lammps")
    subprocess.run([lmp, "-in", deck_path, "-log", log, "-screen", "none"], check=True, cwd=directory)
    text = open(log).read()
    loop = re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", text)[-1]
    seconds, steps, atoms = float(loop[0]), int(loop[1]), int(loop[2])
    return atoms * steps / seconds, atoms


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--lmp", default="/var/tmp/poresph-lammps/build/lmp")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "side-by-side"))
    args = parser.parse_args()
    if not os.access(args.lmp, os.X_OK):
        sys.exit(f"lammps_side_by_side: no LAMMPS at {args.lmp}: build it with perf/lammps_yardstick.sh")
    os.makedirs(args.out, exist_ok=True)

    # The decks, from PoreSPH's own time step and sound speed for each scene.
    decks = {}
    for name, spec in SCENES.items():
        probe = run_poresph(args.build, spec["scene"], os.path.join(args.out, f"{name}-probe".replace(" ", "_")),
                            spec["settings"])
        dx, c, dt, steps = probe["particle_spacing"], probe["sound_speed"], probe["time_step"], probe["steps"]
        text = (channel_deck if name == "2D channel" else box_deck)(dx, c, dt, steps)
        path = os.path.join(args.out, f"{name}.in".replace(" ", "_"))
        with open(path, "w") as f:
            f.write(text)
        decks[name] = (path, probe["fluid_particles"] + probe["boundary_particles"])

    rows, rates = [], {}
    for repeat in range(args.repeats):
        for name, spec in SCENES.items():
            path, particles = decks[name]
            directory = os.path.join(args.out, f"{name}-lammps".replace(" ", "_"))
            os.makedirs(directory, exist_ok=True)
            lammps_rate, atoms = run_lammps(args.lmp, path, directory)
            if atoms != particles:
                sys.exit(f"lammps_side_by_side: {name}: LAMMPS has {atoms} atoms, PoreSPH {particles} particles")
            rates.setdefault((name, "LAMMPS SPH"), []).append(lammps_rate)
            for variant, extra in (("PoreSPH, fixed particles (default)", []), ("PoreSPH, moving particles", MOVING)):
                summary = run_poresph(args.build, spec["scene"],
                                      os.path.join(args.out, f"{name}-{variant}".replace(" ", "_").replace(",", "")),
                                      spec["settings"] + extra)
                rate = summary["particle_steps_per_second"]
                rates.setdefault((name, variant), []).append(rate)
                rows.append(dict(repeat=repeat, scene=name, variant=variant, particles=particles,
                                 rate=rate, lammps_rate=lammps_rate, ratio=rate / lammps_rate))
            rows.append(dict(repeat=repeat, scene=name, variant="LAMMPS SPH", particles=particles,
                             rate=lammps_rate, lammps_rate=lammps_rate, ratio=1.0))
            print(f"repeat {repeat + 1}/{args.repeats} {name}: LAMMPS {lammps_rate:.3g}, PoreSPH "
                  f"{rates[(name, 'PoreSPH, fixed particles (default)')][-1]:.3g} fixed, "
                  f"{rates[(name, 'PoreSPH, moving particles')][-1]:.3g} moving", file=sys.stderr, flush=True)
            write_csv(os.path.join(args.out, "side_by_side.csv"), rows)

    print("| scene | particles | program | particle-steps/s, median (min-max) | vs LAMMPS (median of per-repeat ratios) |")
    print("|---|---|---|---|---|")
    for name in SCENES:
        for variant in ("LAMMPS SPH", "PoreSPH, fixed particles (default)", "PoreSPH, moving particles"):
            values = rates[(name, variant)]
            ratios = [r["ratio"] for r in rows if r["scene"] == name and r["variant"] == variant]
            print(f"| {name} | {decks[name][1]} | {variant} | {statistics.median(values):.3g} "
                  f"({min(values):.3g}-{max(values):.3g}) | {statistics.median(ratios):.2f} |")


if __name__ == "__main__":
    main()
