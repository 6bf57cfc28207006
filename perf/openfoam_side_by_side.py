#!/usr/bin/python3
"""Permeability of a segmented image with OpenFOAM's simpleFoam on one hex
cell per voxel: the yardstick that image users run (Debian's `openfoam`,
OpenFOAM v1912; `scripts/setup.sh openfoam` installs it).

The case: blockMesh of the whole box, one cell per voxel, cyclic patches on
all three axes; the solid voxels removed (their cells left out with
subsetMesh, the faces this exposes becoming the no-slip patch `walls`);
laminar, steady SIMPLEC (U relaxed by 0.95, p not relaxed); driven by a
uniform body force F along --axis (fvOptions vectorSemiImplicitSource, per
unit mass). --method penalise keeps the solid cells instead, with a Darcy
drag nu D u in them (explicitPorositySource, DarcyForchheimer, D =
--penalty per voxel^2), for comparison. Lengths are in voxels and nu = 1
inside the case; k = nu <u> / F with <u> the superficial velocity (the
integral of u over the fluid cells over the box volume), in voxels^2 and,
with --voxel-size, in m^2. docs/openfoam.md says why these settings.

Pore clusters that do not cross the periodic cell along --axis (isolated
pockets; face connectivity through the periodic faces, perf/blobs.py's
check, which needs SciPy) are made solid first: they carry no mean flow
along the axis, and a pore cell with no fluid neighbour would make the
pressure matrix singular.

Converged when the initial residuals of p and of every component of U are
below --residual (SIMPLE residualControl) and k changed by less than
--k-tolerance (relative) over the last --k-window iterations. A run that
reaches --max-iterations first is reported with "converged": false.

    openfoam_side_by_side.py --image IMAGE [--shape NX NY NZ] [--dataset /path] [--solid-values 1]
    openfoam_side_by_side.py --spheres sc --fraction 0.125 --per-side 40
        [--axis x] [--cores 1|2] [--case DIR] [--json OUT] [--voxel-size M]

Images: raw volumes (uint8, x fastest, then y, then z; --shape), TIFF stacks
(one page per z, first row at the largest y, as perf/rasterise.py writes
them), PNG (2D), .npy arrays (index [x, y(, z)]) and HDF5 datasets
(--dataset; stored [z][y][x], x fastest, as perf/blobs.py writes them).
Solid: voxels whose value is in --solid-values (default: every non-zero
voxel). A 2D image becomes one layer of cells between `empty` patches.
Spheres: one voxel per (L / --per-side), solid when its centre lies in a
sphere of the simple cubic (sc), bcc or fcc array of solid fraction
--fraction (perf/rasterise.py's rule), with Zick & Homsy's k (sc) or the
project's reference (bcc, fcc) beside OpenFOAM's.

Writes the case into --case and a JSON summary (stdout, and --json): k,
iterations, wall and CPU seconds (mesh, solve, total), peak resident
memory of each step (per rank for the solver, /usr/bin/time -v), cells,
porosity, the final residuals and k's relative change over the window. Times are of this machine as it was
loaded at the time: repeat them and quote medians.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
OPENFOAM_DIR = "/usr/share/openfoam"


# ---------------------------------------------------------------- the image

def read_image(path, shape=None, dataset=None, dtype="uint8"):
    """The image as an array indexed [x, y(, z)] of its values."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".npy":
        return np.load(path)
    if ext in (".h5", ".hdf5"):
        import h5py
        if not dataset:
            raise SystemExit("an HDF5 image needs --dataset")
        with h5py.File(path, "r") as f:
            data = f[dataset][...]
        return data.transpose(tuple(range(data.ndim))[::-1])
    if ext in (".tif", ".tiff", ".png"):
        from PIL import Image
        img = Image.open(path)
        pages = []
        for n in range(getattr(img, "n_frames", 1)):
            img.seek(n)
            pages.append(np.array(img)[::-1, :].T)  # rows from the largest y -> [x, y]
        return pages[0] if len(pages) == 1 else np.stack(pages, axis=2)
    if not shape:
        raise SystemExit("a raw volume needs --shape NX NY [NZ]")
    data = np.fromfile(path, dtype=dtype)
    if data.size != int(np.prod(shape)):
        raise SystemExit(f"{path}: {data.size} values, the shape {shape} needs {int(np.prod(shape))}")
    return data.reshape(shape[::-1]).transpose(tuple(range(len(shape)))[::-1])


def solid_of(values, solid_values):
    if solid_values is None:
        return values != 0
    return np.isin(values, solid_values)


def sphere_array(lattice, fraction, per_side):
    """Solid voxels of a cubic array of spheres, its sphere radius in voxels
    and the reference k / a^2 (Zick & Homsy for sc)."""
    from rasterise import rasterise
    from sphere_arrays import CENTRES, DRAG, L, radius

    a = radius(lattice, fraction)
    grains = np.array([[c[0] * L, c[1] * L, c[2] * L, a] for c in CENTRES[lattice]])
    solid = rasterise([L, L, L], grains, L / per_side)
    drag = DRAG[lattice].get(fraction)
    reference = 2 / (9 * fraction * drag) if drag else None
    return solid, a / (L / per_side), reference


# ---------------------------------------------------------------- the case

HEADER = """FoamFile
{{
    version 2.0;
    format ascii;
    class {cls};
    location "{location}";
    object {obj};
}}
"""


def write_dict(case, location, obj, body, cls="dictionary"):
    path = os.path.join(case, location, obj)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(HEADER.format(cls=cls, location=location, obj=obj) + body)


def write_case(case, shape, solid, axis, force, nu, args):
    dim = len(shape)
    nx, ny = shape[0], shape[1]
    nz = shape[2] if dim == 3 else 1
    # Vertices in blockMesh's order: (0 0 0) (X 0 0) (X Y 0) (0 Y 0), then the same at Z.
    X, Y, Z = nx, ny, nz
    vertices = f"(0 0 0) ({X} 0 0) ({X} {Y} 0) (0 {Y} 0) (0 0 {Z}) ({X} 0 {Z}) ({X} {Y} {Z}) (0 {Y} {Z})"
    z_type = "cyclic" if dim == 3 else "empty"
    zlo = f"type {z_type};" + (" neighbourPatch zhi;" if dim == 3 else "")
    zhi = f"type {z_type};" + (" neighbourPatch zlo;" if dim == 3 else "")
    write_dict(case, "system", "blockMeshDict", f"""
scale 1;
vertices ({vertices});
blocks (hex (0 1 2 3 4 5 6 7) ({nx} {ny} {nz}) simpleGrading (1 1 1));
boundary
(
    xlo {{ type cyclic; neighbourPatch xhi; faces ((0 4 7 3)); }}
    xhi {{ type cyclic; neighbourPatch xlo; faces ((1 2 6 5)); }}
    ylo {{ type cyclic; neighbourPatch yhi; faces ((0 1 5 4)); }}
    yhi {{ type cyclic; neighbourPatch ylo; faces ((3 7 6 2)); }}
    zlo {{ {zlo} faces ((0 3 2 1)); }}
    zhi {{ {zhi} faces ((4 5 6 7)); }}
    walls {{ type wall; faces (); }}
);
""")
    write_dict(case, "system", "controlDict", f"""
application simpleFoam;
startFrom latestTime;
startTime 0;
stopAt endTime;
endTime {args.max_iterations};
deltaT 1;
writeControl timeStep;
writeInterval {args.max_iterations};
purgeWrite 0;
writeFormat binary;
writePrecision 12;
writeCompression off;
timeFormat general;
timePrecision 8;
runTimeModifiable false;
functions
{{
    flow
    {{
        type volFieldValue;
        libs ("libfieldFunctionObjects.so");
        writeControl timeStep;
        writeInterval 1;
        log false;
        writeFields false;
        regionType all;
        operation volIntegrate;
        fields (U);
    }}
}}
""")
    write_dict(case, "system", "fvSchemes", """
ddtSchemes { default steadyState; }
gradSchemes { default Gauss linear; }
divSchemes
{
    default none;
    div(phi,U) bounded Gauss linear;
    div((nuEff*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
""")
    write_fv_solution(case, args, args.residual)
    f = [0.0, 0.0, 0.0]
    f["xyz".index(axis)] = force
    write_dict(case, "constant", "fvOptions", f"""
bodyForce
{{
    type vectorSemiImplicitSource;
    active yes;
    selectionMode all;
    volumeMode specific;
    injectionRateSuSp
    {{
        U (({f[0]!r} {f[1]!r} {f[2]!r}) 0);
    }}
}}
""")
    if args.method == "penalise":
        force_options = open(os.path.join(case, "constant", "fvOptions")).read()
        # Brinkman penalisation: a Darcy drag nu D u in the solid cells (zone `solid`), D in 1/voxel^2.
        d = args.penalty
        write_dict(case, "constant", "fvOptions", f"""
solidDrag
{{
    type explicitPorositySource;
    active yes;
    explicitPorositySourceCoeffs
    {{
        selectionMode cellZone;
        cellZone solid;
        type DarcyForchheimer;
        DarcyForchheimerCoeffs
        {{
            d ({d!r} {d!r} {d!r});
            f (0 0 0);
            coordinateSystem
            {{
                type cartesian;
                origin (0 0 0);
                coordinateRotation {{ type axesRotation; e1 (1 0 0); e2 (0 1 0); }}
            }}
        }}
    }}
}}
""")
        with open(os.path.join(case, "constant", "fvOptions")) as f:
            drag = f.read().split("}\n", 1)[1]  # after the FoamFile header
        with open(os.path.join(case, "constant", "fvOptions"), "w") as f:
            f.write(force_options + drag)
    write_dict(case, "constant", "transportProperties", f"transportModel Newtonian;\nnu {nu!r};\n")
    write_dict(case, "constant", "turbulenceProperties", "simulationType laminar;\n")
    empty_z = "" if dim == 3 else "    \"z.*\" { type empty; }\n"
    write_dict(case, "0", "U", f"""
dimensions [0 1 -1 0 0 0 0];
internalField uniform (0 0 0);
boundaryField
{{
    "(x|y|z).*" {{ type cyclic; }}
{empty_z}    walls {{ type noSlip; }}
}}
""", cls="volVectorField")
    write_dict(case, "0", "p", f"""
dimensions [0 2 -2 0 0 0 0];
internalField uniform 0;
boundaryField
{{
    "(x|y|z).*" {{ type cyclic; }}
{empty_z}    walls {{ type zeroGradient; }}
}}
""", cls="volScalarField")
    if args.cores > 1:
        write_dict(case, "system", "decomposeParDict",
                   f"numberOfSubdomains {args.cores};\nmethod {args.decomposition};\n"
                   f"simpleCoeffs {{ n ({args.cores} 1 1); }}\n")


def write_fv_solution(case, args, residual):
    """Linear solvers, SIMPLE(C) with its residualControl at `residual`, relaxation."""
    write_dict(case, "system", "fvSolution", f"""
solvers
{{
    p
    {{
        solver GAMG;
        smoother GaussSeidel;
        tolerance {args.linear_tolerance};
        relTol {args.p_rel_tol};
    }}
    U
    {{
        solver smoothSolver;
        smoother symGaussSeidel;
        tolerance {args.linear_tolerance};
        relTol {args.u_rel_tol};
    }}
}}
SIMPLE
{{
    nNonOrthogonalCorrectors 0;
    consistent {"yes" if args.consistent else "no"};
    pRefCell 0;
    pRefValue 0;
    residualControl
    {{
        p {residual};
        U {residual};
    }}
}}
relaxationFactors
{{
    fields {{ p {args.relax_p}; }}
    equations {{ U {args.relax_u}; }}
}}
""")

def write_solid_zone(case, solid):
    """The cellZone `solid` (the penalised cells), in blockMesh's cell numbering."""
    nx, ny = solid.shape[0], solid.shape[1]
    nz = solid.shape[2] if solid.ndim == 3 else 1
    cells = np.flatnonzero(solid.reshape(nx, ny, nz).transpose(2, 1, 0).ravel())
    with open(os.path.join(case, "constant", "polyMesh", "cellZones"), "w") as out:
        out.write(HEADER.format(cls="regIOobject", location="constant/polyMesh", obj="cellZones"))
        out.write(f"1\n(\nsolid\n{{\n    type cellZone;\n    cellLabels List<label> {cells.size}\n(\n")
        np.savetxt(out, cells, fmt="%d")
        out.write(");\n}\n)\n")


def write_fluid_set(case, solid):
    """The cellSet of the fluid cells (after blockMesh, which clears polyMesh/): blockMesh numbers the
    cells of one block x fastest, then y, then z."""
    nx, ny = solid.shape[0], solid.shape[1]
    nz = solid.shape[2] if solid.ndim == 3 else 1
    fluid = np.flatnonzero(~solid.reshape(nx, ny, nz).transpose(2, 1, 0).ravel())
    path = os.path.join(case, "constant", "polyMesh", "sets", "fluid")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as out:
        out.write(HEADER.format(cls="cellSet", location="constant/polyMesh/sets", obj="fluid"))
        out.write(f"{fluid.size}\n(\n")
        np.savetxt(out, fluid, fmt="%d")
        out.write(")\n")


# ---------------------------------------------------------------- running

def openfoam_env():
    env = dict(os.environ, WM_PROJECT_DIR=OPENFOAM_DIR, OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    # FOAM_SIGFPE traps floating-point exceptions by default; keep it.
    return env


CPU_SECONDS = {}  # user + system seconds of each tool, summed over its ranks and passes


def step(case, name, cmd, ranks=None):
    """Runs one OpenFOAM tool under /usr/bin/time -v; returns (wall seconds, peak RSS in MB per process)
    and adds its CPU seconds (all ranks) to CPU_SECONDS."""
    log = os.path.join(case, f"log.{name}")
    if ranks:
        inner = f"exec /usr/bin/time -v -o {case}/time.{name}.$OMPI_COMM_WORLD_RANK {' '.join(cmd)} -parallel"
        full = ["mpirun", "-np", str(ranks), "--bind-to", "core", "sh", "-c", inner]
    else:
        full = ["/usr/bin/time", "-v", "-o", f"{case}/time.{name}.0"] + cmd
    start = time.monotonic()
    with open(log, "w") as out:
        done = subprocess.run(full, cwd=case, stdout=out, stderr=subprocess.STDOUT, env=openfoam_env())
    seconds = time.monotonic() - start
    if done.returncode != 0:
        raise SystemExit(f"{name} failed (status {done.returncode}); see {log}")
    peaks, cpu = [], 0.0
    for r in range(ranks or 1):
        text = open(f"{case}/time.{name}.{r}").read()
        peaks.append(int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) / 1024)
        cpu += sum(float(v) for v in re.findall(r"(?:User|System) time \(seconds\): ([0-9.]+)", text))
    CPU_SECONDS[name.split(".")[0]] = CPU_SECONDS.get(name.split(".")[0], 0.0) + cpu
    return seconds, peaks


def residual_history(log):
    """Initial residuals per iteration: {field: [values]} (the first solve of each field in an iteration)."""
    hist = {}
    it = None
    seen = set()
    for line in open(log):
        if line.startswith("Time = "):
            it = line.split()[2]
            seen = set()
            continue
        m = re.search(r"Solving for (\w+), Initial residual = ([-+0-9.eE]+)", line)
        if m and it is not None and m.group(1) not in seen:
            seen.add(m.group(1))
            hist.setdefault(m.group(1), []).append(float(m.group(2)))
    return hist


def flow_history(case):
    """Iteration and the integral of each component of U over the fluid, every iteration of every pass
    (a pass restarted from time t writes into postProcessing/flow/t/)."""
    rows = {}
    base = os.path.join(case, "postProcessing", "flow")
    for start in sorted(os.listdir(base), key=float):
        for line in open(os.path.join(base, start, "volFieldValue.dat")):
            if line.startswith("#") or not line.strip():
                continue
            nums = [float(v) for v in re.findall(r"[-+]?[0-9.]+(?:[eE][-+]?\d+)?", line)]
            rows[int(round(nums[0]))] = nums
    return np.array([rows[i] for i in sorted(rows)])


def fill_closed_pores(solid, axis):
    """The image with every pore cluster that does not cross the periodic cell along `axis` made solid
    (face connectivity, through the periodic faces; perf/blobs.py's check), and how many voxels that
    filled. Such a cluster carries no mean flow along the axis, so k is unchanged; left in, each is a
    piece of mesh with no pressure reference, and a cell with no fluid neighbour makes the pressure
    matrix singular (simpleFoam stops on a floating-point exception)."""
    from blobs import periodic_percolation

    labels, wraps = periodic_percolation(~solid)
    crossing = wraps[:, "xyz".index(axis)]
    closed = (labels > 0) & ~crossing[labels]
    if not crossing[1:].any():
        raise SystemExit(f"no pore path crosses the cell along {axis}: k is zero")
    return solid | closed, int(closed.sum())


def run(args, solid, reference=None, a_voxels=None):
    porosity = 1.0 - float(solid.mean())
    solid, filled = fill_closed_pores(solid, args.axis)
    shape = list(solid.shape)
    case = os.path.abspath(args.case)
    if os.path.exists(case):
        shutil.rmtree(case)
    os.makedirs(case)
    nu = 1.0
    axis = args.axis
    write_case(case, shape, solid, axis, args.force, nu, args)
    box = float(np.prod(shape))
    c = 1 + "xyz".index(axis)

    times, memory = {}, {}
    t0 = time.monotonic()
    times["blockMesh"], memory["blockMesh"] = step(case, "blockMesh", ["blockMesh"])
    if args.method == "remove":
        write_fluid_set(case, solid)
        times["subsetMesh"], memory["subsetMesh"] = step(case, "subsetMesh",
                                                         ["subsetMesh", "fluid", "-patch", "walls", "-overwrite"])
    else:
        write_solid_zone(case, solid)
    if args.cores > 1:
        times["decomposePar"], memory["decomposePar"] = step(case, "decomposePar", ["decomposePar"])
    mesh_seconds = time.monotonic() - t0
    # Passes of simpleFoam, each from the last one's fields, the residual target ten times lower each
    # time, until k has also settled over the window (or the iterations run out).
    ranks = args.cores if args.cores > 1 else None
    residual = args.residual
    times["simpleFoam"], memory["simpleFoam"] = 0.0, [0.0] * (ranks or 1)
    res = {}
    passes = 0
    while True:
        write_fv_solution(case, args, residual)
        seconds, peaks = step(case, f"simpleFoam.{passes}", ["simpleFoam"], ranks=ranks)
        times["simpleFoam"] += seconds
        memory["simpleFoam"] = [max(a, b) for a, b in zip(memory["simpleFoam"], peaks)]
        for field, values in residual_history(os.path.join(case, f"log.simpleFoam.{passes}")).items():
            res.setdefault(field, []).extend(values)
        passes += 1
        flow = flow_history(case)
        k_hist = nu * flow[:, c] / box / args.force
        iterations = int(flow[-1, 0])
        window = min(args.k_window, len(k_hist) - 1)
        k = float(k_hist[-1])
        change = float(np.max(np.abs(k_hist[-1 - window:] - k)) / abs(k)) if window >= args.k_window else float("inf")
        final_res = {f: v[-1] for f, v in res.items()}
        residuals_met = all(v < args.residual for v in final_res.values())
        converged = residuals_met and change < args.k_tolerance
        if converged or iterations >= args.max_iterations or not residuals_met:
            break
        residual /= 10
    total = time.monotonic() - t0

    cells = int((~solid).sum()) if args.method == "remove" else int(solid.size)
    cross = [float(flow[-1, 1 + d] / flow[-1, c]) for d in range(3) if d != c - 1]
    summary = {
        "tool": f"OpenFOAM v1912 simpleFoam ({'SIMPLEC' if args.consistent else 'SIMPLE'})",
        "case": case,
        "shape": shape,
        "voxels": int(box),
        "cells": cells,
        "porosity": porosity,
        "closed_pore_voxels_filled": filled,
        "axis": axis,
        "cores": args.cores,
        "method": args.method,
        "force": args.force,
        "k_voxels2": k,
        "converged": bool(converged),
        "iterations": iterations,
        "passes": passes,
        "final_residual_target": residual,
        "final_initial_residuals": final_res,
        "k_relative_change_over_window": change,
        "k_window": window,
        "cross_flow_over_main": cross,
        "reynolds_box": float(flow[-1, c] / box * shape[0] / nu),
        "mesh_seconds": mesh_seconds,
        "solve_seconds": times["simpleFoam"],
        "total_seconds": total,
        "seconds": times,
        "cpu_seconds": dict(CPU_SECONDS),
        "peak_rss_mb": memory,
        "solver_peak_rss_mb_max": max(memory["simpleFoam"]),
        "solver_peak_rss_mb_sum": sum(memory["simpleFoam"]),
        "bytes_per_cell_solver": sum(memory["simpleFoam"]) * 1024 * 1024 / cells,
        "settings": {"residual": args.residual, "k_tolerance": args.k_tolerance, "k_window": args.k_window,
                     "relax_u": args.relax_u, "relax_p": args.relax_p, "consistent": args.consistent,
                     "p_rel_tol": args.p_rel_tol, "u_rel_tol": args.u_rel_tol,
                     "linear_tolerance": args.linear_tolerance, "max_iterations": args.max_iterations},
    }
    if args.voxel_size:
        summary["voxel_size"] = args.voxel_size
        summary["k_m2"] = k * args.voxel_size ** 2
    if reference is not None:
        summary["k_over_a2"] = k / a_voxels ** 2
        summary["reference_k_over_a2"] = reference
        summary["relative_error"] = k / a_voxels ** 2 / reference - 1
        summary["a_voxels"] = a_voxels
    return summary


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--image", help="raw, .tif/.tiff, .png, .npy or .h5 image")
    src.add_argument("--spheres", choices=["sc", "bcc", "fcc"], help="a cubic array of spheres")
    ap.add_argument("--shape", type=int, nargs="+", help="raw volume: NX NY [NZ]")
    ap.add_argument("--dtype", default="uint8", help="raw volume: numpy dtype (default uint8)")
    ap.add_argument("--dataset", help="HDF5: the dataset's path")
    ap.add_argument("--solid-values", type=int, nargs="+", help="solid labels (default: every non-zero voxel)")
    ap.add_argument("--fraction", type=float, help="spheres: solid fraction")
    ap.add_argument("--per-side", type=int, help="spheres: voxels per side of the cubic cell")
    ap.add_argument("--method", choices=["remove", "penalise"], default="remove",
                    help="solid voxels: cells removed (subsetMesh; default) or kept with a Darcy drag")
    ap.add_argument("--penalty", type=float, default=1e6,
                    help="penalise: Darcy coefficient D of the solid cells, 1/voxel^2 (default 1e6)")
    ap.add_argument("--axis", choices=["x", "y", "z"], default="x", help="direction of the body force")
    ap.add_argument("--force", type=float, default=1e-7,
                    help="body force per unit mass, voxel units with nu = 1 (default 1e-7: creeping flow)")
    ap.add_argument("--voxel-size", type=float, help="voxel side in m: k is also given in m^2")
    ap.add_argument("--cores", type=int, default=1, help="1, or N for decomposePar + mpirun -np N")
    ap.add_argument("--decomposition", default="simple",
                    help="decomposePar method (default simple: slabs along x of equal cell counts; Debian's "
                         "scotchDecomp is a stub)")
    ap.add_argument("--case", default="openfoam-case", help="case directory (replaced)")
    ap.add_argument("--json", help="also write the summary here")
    ap.add_argument("--residual", type=float, default=1e-6, help="initial residuals of p and U below this")
    ap.add_argument("--k-tolerance", type=float, default=1e-5, help="k's relative change over the window")
    ap.add_argument("--k-window", type=int, default=50, help="iterations of that window")
    ap.add_argument("--max-iterations", type=int, default=20000)
    ap.add_argument("--relax-u", type=float, default=0.95, help="U relaxation (default 0.95)")
    ap.add_argument("--relax-p", type=float, default=1.0, help="p relaxation (default 1: SIMPLEC)")
    ap.add_argument("--simple", dest="consistent", action="store_false",
                    help="plain SIMPLE instead of SIMPLEC (then e.g. --relax-u 0.7 --relax-p 0.3)")
    ap.add_argument("--p-rel-tol", type=float, default=0.05)
    ap.add_argument("--u-rel-tol", type=float, default=0.1)
    ap.add_argument("--linear-tolerance", type=float, default=1e-12)
    args = ap.parse_args()

    reference = a_voxels = None
    if args.spheres:
        if args.fraction is None or args.per_side is None:
            raise SystemExit("--spheres needs --fraction and --per-side")
        solid, a_voxels, reference = sphere_array(args.spheres, args.fraction, args.per_side)
    else:
        solid = solid_of(read_image(args.image, args.shape, args.dataset, args.dtype), args.solid_values)
    if solid.ndim not in (2, 3):
        raise SystemExit(f"the image has {solid.ndim} dimensions; 2 or 3 are run")
    if solid.ndim == 2 and args.axis == "z":
        raise SystemExit("a 2D image has no z axis to drive along")
    summary = run(args, solid, reference, a_voxels)
    text = json.dumps(summary, indent=2)
    print(text)
    if args.json:
        with open(args.json, "w") as f:
            f.write(text + "\n")
    if not summary["converged"]:
        print(f"openfoam_side_by_side.py: not converged after {summary['iterations']} iterations", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
