#!/usr/bin/python3
"""A finite-element reference for the permeability of a 2D periodic cell of
circular grains (problem III, or any grains file): steady Stokes or
Navier-Stokes flow driven by a body force, Taylor-Hood (P2 velocity, P1
pressure) elements with Debian's FreeFem++, no slip on the grains, periodic
on the cell, at several mesh sizes. k_ij = nu <u_i> / F_j as in PoreSPH,
<u> the superficial velocity (the integral of u over the fluid, divided by
the cell area). Stokes flow has no inertia, so k does not depend on nu or
F; Navier-Stokes flow does, through the Reynolds number.

    perf/stokes_reference.py [--grains input/problem3/grains.txt | --grain CX CY R ...] [--cell 0.1]
        [--segments 50 100 200] [--drive x|y] [--grain-refinement R]
        [--equations stokes|navier-stokes] [--nu 1e-6] [--force 1.5e-8]
        [--out build/stokes-reference]

--grain CX CY R (repeatable) gives the grains inline instead of a file.
--drive y drives the flow along y (kyy and kxy instead of kxx and kyx).
--grain-refinement R makes the grains' boundary segments R times shorter
than the mesh size, for throats narrower than a few mesh sizes (the mesh
grades from there to the cell's own size).
--equations navier-stokes adds the convective term (u.grad)u: Newton
iterations from the Stokes solution on the same mesh, Picard (Oseen)
iterations from it again if Newton does not converge, until the relative
L2 change of the velocity is below 1e-10. --nu (m^2/s) and --force (the
body force's magnitude, m/s^2) then set the Reynolds number
Re = (|<u>| / porosity) * (mean grain diameter) / nu, as in PoreSPH's
summary.json. The table then also has each mesh's Stokes k, the relative
change of k due to inertia, Re and the iterations.

FreeFem++ comes from `scripts/setup.sh tools`. Grains may cross the cell's
boundary: the mesh is made on a translate of the cell whose edges cross no
grain (the same periodic medium), found from the grains' extents.
Writes stokes_reference.csv (navier_stokes_reference.csv) into --out and
prints a Markdown table with, from the three finest meshes, the observed
order of convergence and the Richardson-extrapolated k.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

from poresph_runs import ROOT

# Iterations stop once the relative L2 change of the velocity is below this.
TOLERANCE = 1e-10
NEWTON_ITERATIONS = 20
PICARD_ITERATIONS = 400


def read_grains(path):
    grains = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            if not line:
                continue
            if len(line) != 3:
                sys.exit(f"{path}: expected 'cx cy r' (2D) per line, got {' '.join(line)}")
            grains.append(tuple(float(v) for v in line))
    return grains


def free_edge(lows_highs, cell):
    """A coordinate in [0, cell) that no interval (mod cell) covers, as far
    from every interval as possible; None if the grains close every line."""
    covered = []
    for lo, hi in lows_highs:
        lo, hi = lo % cell, lo % cell + (hi - lo)
        covered.append((lo, hi))
        covered.append((lo - cell, hi - cell))
        covered.append((lo + cell, hi + cell))
    covered.sort()
    best, best_gap = None, 0.0
    end = covered[0][1]
    for lo, hi in covered[1:]:
        if lo > end and lo - end > best_gap:
            best, best_gap = (0.5 * (lo + end)) % cell, lo - end
        end = max(end, hi)
    return best


# The steady Navier-Stokes iterations, appended to the Stokes script: [u, v, p]
# holds the Stokes solution on entry and the Navier-Stokes one on exit.
# Newton: J(w) dw = -R(w), w += dw, J the Jacobian of the residual R (with the
# same pressure penalty as the Stokes solve); if it has not converged after
# NEWTON_ITERATIONS (or blows up), Picard from the Stokes solution: the Oseen
# problem with the previous velocity convecting, given up after PICARD_ITERATIONS
# or 20 iterations without a new smallest change. "change" is the relative L2
# norm of the last update of the velocity.
NAVIER_STOKES = """\
Wh [us, vs, ps], [du, dv, dp], [uo, vo, po];
us[] = u[];
real kStokes = nu*{stokes_along}/F;
real change = 1, speed = sqrt(int2d(Th)(u*u + v*v));
int iterations = 0;
string method = "newton";
problem newton([du, dv, dp], [uu, vv, pp]) =
    int2d(Th)(nu*(dx(du)*dx(uu) + dy(du)*dy(uu) + dx(dv)*dx(vv) + dy(dv)*dy(vv))
              + (u*dx(du) + v*dy(du) + du*dx(u) + dv*dy(u))*uu
              + (u*dx(dv) + v*dy(dv) + du*dx(v) + dv*dy(v))*vv
              - dp*(dx(uu) + dy(vv)) - pp*(dx(du) + dy(dv)) - 1e-12*dp*pp)
    + int2d(Th)(nu*(dx(u)*dx(uu) + dy(u)*dy(uu) + dx(v)*dx(vv) + dy(v)*dy(vv))
                + (u*dx(u) + v*dy(u))*uu + (u*dx(v) + v*dy(v))*vv
                - p*(dx(uu) + dy(vv)) - pp*(dx(u) + dy(v)) - 1e-12*p*pp)
    - int2d(Th)(F*{test})
    + on({grains}, du=0, dv=0);
problem oseen([u, v, p], [uu, vv, pp]) =
    int2d(Th)(nu*(dx(u)*dx(uu) + dy(u)*dy(uu) + dx(v)*dx(vv) + dy(v)*dy(vv))
              + (uo*dx(u) + vo*dy(u))*uu + (uo*dx(v) + vo*dy(v))*vv
              - p*(dx(uu) + dy(vv)) - pp*(dx(u) + dy(v)) - 1e-12*p*pp)
    - int2d(Th)(F*{test})
    + on({grains}, u=0, v=0);
for (int i = 1; i <= {newton}; i++) {{
    iterations = i;
    newton;
    u[] += du[];
    speed = sqrt(int2d(Th)(u*u + v*v));
    change = sqrt(int2d(Th)(du*du + dv*dv))/speed;
    cout << "NEWTON " << i << " " << change << endl;
    if (!(change < 1e3) || !(speed > 0)) break;  // diverging, NaN or zero
    if (change < {tolerance}) break;
}}
if (!(change < {tolerance}) || !(speed > 0)) {{
    method = "picard";
    u[] = us[];
    real smallest = 1e30;  // the smallest change so far, and when: 20 iterations without a new one is stagnation
    int smallestAt = 0;
    for (int i = 1; i <= {picard}; i++) {{
        iterations = i;
        uo[] = u[];
        oseen;
        speed = sqrt(int2d(Th)(u*u + v*v));
        change = sqrt(int2d(Th)((u - uo)*(u - uo) + (v - vo)*(v - vo)))/speed;
        cout << "PICARD " << i << " " << change << endl;
        if (change < smallest) {{ smallest = change; smallestAt = i; }}
        if (!(change < 1e3) || !(speed > 0) || i - smallestAt >= 20) break;
        if (change < {tolerance}) break;
    }}
}}
"""


# Grain i's boundary is label GRAIN_LABEL + i (the cell's sides are 1-4).
GRAIN_LABEL = 5


def grain_force_lines(grains, cell, x0, y0):
    """FreeFem++ lines printing "GRAIN i fx fy torque" for each grain: the
    fluid's force on it per unit density and depth, and its torque about its
    centre, from the kinematic stress -p I + nu (grad u + grad u^T) on its
    boundary. N is the fluid's outward normal, into the grain: the grain's
    outward normal is -N."""
    lines = ["macro tx() (-p*N.x + nu*(2*dx(u)*N.x + (dy(u) + dx(v))*N.y)) //",
             "macro ty() (-p*N.y + nu*((dy(u) + dx(v))*N.x + 2*dy(v)*N.y)) //"]
    for i, (cx, cy, _) in enumerate(grains):
        cx = x0 + (cx - x0) % cell
        cy = y0 + (cy - y0) % cell
        label = GRAIN_LABEL + i
        lines.append(f"cout << \"GRAIN {i} \" << -int1d(Th, {label})(tx) << \" \" << -int1d(Th, {label})(ty) << \" \""
                     f" << -int1d(Th, {label})((x - {cx!r})*ty - (y - {cy!r})*tx) << endl;")
    return lines


def edp(grains, cell, x0, y0, segments, nu, force, drive, grain_refinement, equations="stokes"):
    h = cell / segments
    title = "Stokes" if equations == "stokes" else "Navier-Stokes"
    lines = [
        f"// Generated by perf/stokes_reference.py: {title} flow in a periodic cell of grains.",
        f"real L = {cell!r}, x0 = {x0!r}, y0 = {y0!r}, nu = {nu!r}, F = {force!r};",
        f"int n = {segments};",
        "border bottom(t=0, 1) {x = x0 + L*t; y = y0; label = 1;}",
        "border right(t=0, 1) {x = x0 + L; y = y0 + L*t; label = 2;}",
        "border top(t=1, 0) {x = x0 + L*t; y = y0 + L; label = 3;}",
        "border left(t=1, 0) {x = x0; y = y0 + L*t; label = 4;}",
    ]
    parts = ["bottom(n)", "right(n)", "top(n)", "left(n)"]
    for i, (cx, cy, r) in enumerate(grains):
        # The grain's image inside the translated cell.
        cx = x0 + (cx - x0) % cell
        cy = y0 + (cy - y0) % cell
        lines.append(f"border grain{i}(t=0, 2*pi) {{x = {cx!r} + {r!r}*cos(t); y = {cy!r} + {r!r}*sin(t); "
                     f"label = {GRAIN_LABEL + i};}}")
        parts.append(f"grain{i}(-{max(8, math.ceil(2 * math.pi * r * grain_refinement / h))})")
    along, across = ("ux", "uy") if drive == "x" else ("uy", "ux")
    grain_labels = ", ".join(str(GRAIN_LABEL + i) for i in range(len(grains)))
    lines += [
        f"mesh Th = buildmesh({' + '.join(parts)});",
        "fespace Wh(Th, [P2, P2, P1], periodic=[[1, x], [3, x], [2, y], [4, y]]);",
        "Wh [u, v, p], [uu, vv, pp];",
        "// p is the kinematic pressure; the small penalty fixes its constant.",
        "solve stokes([u, v, p], [uu, vv, pp]) =",
        "    int2d(Th)(nu*(dx(u)*dx(uu) + dy(u)*dy(uu) + dx(v)*dx(vv) + dy(v)*dy(vv))",
        "              - p*(dx(uu) + dy(vv)) - pp*(dx(u) + dy(v)) - 1e-12*p*pp)",
        f"    - int2d(Th)(F*{'uu' if drive == 'x' else 'vv'}) + on({grain_labels}, u=0, v=0);",
    ]
    if equations == "stokes":
        lines += [
            "real ux = int2d(Th)(u)/(L*L), uy = int2d(Th)(v)/(L*L), porosity = int2d(Th)(1.)/(L*L);",
            "cout.precision(12);",
            f'cout << "RESULT " << Th.nt << " " << Wh.ndof << " " << nu*{along}/F << " "'
            f' << nu*{across}/F << " " << porosity << endl;',
        ]
        lines += grain_force_lines(grains, cell, x0, y0)
    else:
        stokes_along = f"int2d(Th)({'u' if drive == 'x' else 'v'})/(L*L)"
        lines += [
            "cout.precision(12);",
            NAVIER_STOKES.format(stokes_along=stokes_along, test="uu" if drive == "x" else "vv", grains=grain_labels,
                                 newton=NEWTON_ITERATIONS, picard=PICARD_ITERATIONS, tolerance=TOLERANCE),
            "real ux = int2d(Th)(u)/(L*L), uy = int2d(Th)(v)/(L*L), porosity = int2d(Th)(1.)/(L*L);",
            f'cout << "RESULT " << Th.nt << " " << Wh.ndof << " " << nu*{along}/F << " "'
            f' << nu*{across}/F << " " << porosity << " " << kStokes << " " << sqrt(ux*ux + uy*uy)'
            ' << " " << method << " " << iterations << " " << change << endl;',
        ]
    return "\n".join(lines) + "\n"


def richardson(rows, key):
    """From the three finest meshes (halving): the observed order and the
    extrapolated value, or None if they do not converge monotonically."""
    if len(rows) < 3:
        return None
    (h1, k1), (h2, k2), (h3, k3) = [(r["mesh_size"], r[key]) for r in rows[-3:]]
    if (k1 - k2) * (k2 - k3) > 0 and abs(h1 / h2 - h2 / h3) < 1e-9:
        ratio = h2 / h3
        order = math.log(abs((k1 - k2) / (k2 - k3))) / math.log(ratio)
        return order, k3 + (k3 - k2) / (ratio**order - 1)
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--grains", help="grains file, 'cx cy r' per line (default input/problem3/grains.txt)")
    parser.add_argument("--grain", nargs=3, type=float, action="append", metavar=("CX", "CY", "R"),
                        help="a grain given inline (repeatable), instead of --grains")
    parser.add_argument("--cell", type=float, default=0.1, help="side of the square cell (m)")
    parser.add_argument("--segments", type=int, nargs="+", default=[50, 100, 200],
                        help="boundary segments per cell side (mesh size = cell / segments)")
    parser.add_argument("--drive", choices=["x", "y"], default="x", help="direction of the body force")
    parser.add_argument("--grain-refinement", type=float, default=1.0,
                        help="grain boundary segments this many times shorter than the mesh size")
    parser.add_argument("--equations", choices=["stokes", "navier-stokes"], default="stokes",
                        help="steady Stokes (k independent of nu and F) or steady Navier-Stokes")
    parser.add_argument("--nu", type=float, default=1e-6, help="kinematic viscosity (m^2/s)")
    parser.add_argument("--force", type=float, default=1.5e-8, help="body force magnitude (m/s^2)")
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "stokes-reference"))
    args = parser.parse_args()
    if args.grain_refinement < 1:
        sys.exit("--grain-refinement must be at least 1")
    if not (args.nu > 0 and args.force > 0):
        sys.exit("--nu and --force must be positive")
    if args.grains and args.grain:
        sys.exit("give the grains either by --grains FILE or by --grain CX CY R, not both")
    # k_ij = nu <u_i> / F_j: along the drive, and across it.
    along, across = ("kxx", "kyx") if args.drive == "x" else ("kyy", "kxy")
    if args.grain:
        grains = [tuple(g) for g in args.grain]
        if any(r <= 0 for _, _, r in grains):
            sys.exit("--grain: the radius must be positive")
    else:
        grains = read_grains(args.grains or os.path.join(ROOT, "input", "problem3", "grains.txt"))
    x0 = free_edge([(cx - r, cx + r) for cx, _, r in grains], args.cell)
    y0 = free_edge([(cy - r, cy + r) for _, cy, r in grains], args.cell)
    if x0 is None or y0 is None:
        sys.exit("the grains cross every line x = const (or y = const) of the cell: no translate to mesh")
    navier_stokes = args.equations == "navier-stokes"
    diameter = sum(2 * r for _, _, r in grains) / len(grains)
    stem = "navier_stokes" if navier_stokes else "stokes"
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for n in args.segments:
        script = os.path.join(args.out, f"{stem}_n{n}.edp")
        with open(script, "w") as f:
            f.write(edp(grains, args.cell, x0, y0, n, args.nu, args.force, args.drive, args.grain_refinement,
                        args.equations))
        start = time.monotonic()
        done = subprocess.run(["FreeFem++-nw", "-v", "0", script], capture_output=True, text=True)
        seconds = time.monotonic() - start
        result = [line for line in done.stdout.splitlines() if line.startswith("RESULT")]
        if done.returncode != 0 or not result:
            sys.exit(f"FreeFem++ failed on {script}:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
        fields = result[-1].split()
        _, triangles, dofs, k_along, k_across, porosity = fields[:6]
        if not float(k_along) > 0:  # FreeFem++ reports some failed solves (memory) only by a zero solution
            sys.exit(f"FreeFem++ gave {along} = {k_along} on {script}: the solve failed\n{done.stdout[-2000:]}")
        row = dict(segments=n, mesh_size=args.cell / n, triangles=int(triangles), dofs=int(dofs),
                   **{along: float(k_along), across: float(k_across)}, porosity=float(porosity))
        if not navier_stokes:
            rows.append(row)
            print(f"n = {n}: {along} = {float(k_along):.6e}, {across} = {float(k_across):.6e}", file=sys.stderr)
            continue
        k_stokes, speed, method, iterations, change = fields[6:11]
        if not float(change) < TOLERANCE:
            newton = [line for line in done.stdout.splitlines() if line.startswith("NEWTON")]
            picard = [line for line in done.stdout.splitlines() if line.startswith("PICARD")]
            sys.exit(f"the Navier-Stokes iterations did not converge on {script} (n = {n}): relative change "
                     f"{change} after {iterations} {method} iterations, tolerance {TOLERANCE:g}\n"
                     "iteration, relative change of the velocity:\n" + "\n".join(newton[-3:] + picard[-5:]))
        if not float(k_stokes) > 0:
            sys.exit(f"FreeFem++ gave a Stokes {along} = {k_stokes} on {script}: the solve failed")
        row.update({f"stokes_{along}": float(k_stokes), "inertial_change": float(k_along) / float(k_stokes) - 1,
                    "reynolds": float(speed) / float(porosity) * diameter / args.nu, "method": method,
                    "iterations": int(iterations), "final_change": float(change), "seconds": round(seconds, 1)})
        rows.append(row)
        print(f"n = {n}: {along} = {float(k_along):.6e}, {across} = {float(k_across):.6e}, Stokes {along} = "
              f"{float(k_stokes):.6e} ({row['inertial_change'] * 100:+.4g} %), Re = {row['reynolds']:.4g}, "
              f"{method} converged in {iterations} iterations (change {float(change):.1e}), {seconds:.1f} s",
              file=sys.stderr)
    with open(os.path.join(args.out, f"{stem}_reference.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"cell translated by ({x0:.4f}, {y0:.4f}) m so that no grain crosses its edges\n")
    if navier_stokes:
        print(f"steady Navier-Stokes, nu = {args.nu:g} m^2/s, body force {args.force:g} m/s^2 along "
              f"{args.drive}, mean grain diameter {diameter:.6g} m\n")
        print(f"| mesh size (m) | triangles | unknowns | {along} (m^2) | {across} (m^2) | porosity | {along} change "
              f"| Stokes {along} (m^2) | inertia | Re | iterations |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
    else:
        print(f"| mesh size (m) | triangles | unknowns | {along} (m^2) | {across} (m^2) | porosity | {along} change |")
        print("|---|---|---|---|---|---|---|")
    for i, r in enumerate(rows):
        change = f"{(r[along] / rows[i - 1][along] - 1) * 100:+.3f} %" if i else ""
        line = (f"| {r['mesh_size']:.5g} | {r['triangles']} | {r['dofs']} | {r[along]:.5e} | {r[across]:.5e} "
                f"| {r['porosity']:.4f} | {change} |")
        if navier_stokes:
            line += (f" {r[f'stokes_{along}']:.5e} | {r['inertial_change'] * 100:+.4g} % | {r['reynolds']:.4g} "
                     f"| {r['iterations']} {r['method']} |")
        print(line)
    extrapolated = richardson(rows, along)
    if extrapolated:
        order, k = extrapolated
        print(f"\nobserved order {order:.2f}; Richardson-extrapolated {along} = {k:.5e} m^2 "
              f"({(k / rows[-1][along] - 1) * 100:+.3f} % from the finest mesh)")
    if navier_stokes:
        stokes = richardson(rows, f"stokes_{along}")
        if stokes:
            print(f"Stokes: observed order {stokes[0]:.2f}; Richardson-extrapolated {along} = {stokes[1]:.5e} m^2")
        if extrapolated and stokes:
            print(f"inertia changes the extrapolated {along} by {(extrapolated[1] / stokes[1] - 1) * 100:+.4g} %")
        if extrapolated:
            print(f"extrapolated {along} / cell^2 = {extrapolated[1] / args.cell**2:.6f}"
                  + (f" (Stokes {stokes[1] / args.cell**2:.6f})" if stokes else ""))


if __name__ == "__main__":
    main()
