#!/usr/bin/python3
"""Linear solvers for the steady fixed-particle SPH equations, measured on the
exact Jacobian that poresph_export_jacobian writes (docs/steady_solver.md).

    study.py PREFIX METHOD [options]

PREFIX is what poresph_export_jacobian was given (PREFIX_J.txt, ...). The
system is the Newton step at the scene's start state, bordered by the uniform
density drift lambda (see `bordered`). Every method reports its iterations to
a relative residual of --tol and k against the direct solution.

Methods:
  direct           bordered and unbordered sparse LU; k, mean density change, LU fill
  direct-regions   sparse LU with a border per region of the fluid (lattice neighbours, corners
                   counted, as solver/FluidRegions.hpp): k where pockets keep their own mass
  lsc              FGMRES, block-triangular, exact A^-1, Schur by LSC with exact (DG)^-1
  simple           as lsc, Schur by D diag(A)^-1 G, exact
  scaled-identity  as lsc, Schur by s I (s: the Schur complement on a smooth mode)
  lsc-inner        as lsc, (DG)^-1 by unpreconditioned GMRES to --inner-tol; counts DG products
  lsc-capped       as lsc, (DG + s I)^-1 as the steady solver solves it: GMRES to --inner-tol, at
                   most --inner-maxit, with --inner-preconditioner; and by LU (--dg-shift)
  weak-modes       the --modes eigenvalues of DG nearest 0 (sparse): size, participation, place
  sa               DG alone: GMRES unpreconditioned, with the wide (stride-2) compact Laplacian, and
                   with smoothed aggregation on modulated near-null vectors (--block, default 4)
  lsc-sa           as lsc, (DG)^-1 by GMRES with that smoothed aggregation to --inner-tol
  newton           --newton-steps of Newton with the Jacobian at rest, the rates at each state from
                   --exporter on --scene with --set PATH=VALUE...; k and the residual after each step
  modes            the --modes weakest eigenmodes of DG against the compact Laplacian (dense):
                   their energy near each corner of the Brillouin zone and next to walls
  stabilised       pressure stabilisation beta T (T: compact Laplacian): k shift, and
                   FGMRES on the stabilised and true systems with Schur s I + beta T
  pair-stabilised  continuity stabilised by the pairs' pressure jumps less their mean gradient
                   (--alpha): k shift, and FGMRES with a compact-Laplacian Schur preconditioner
  schwarz          two-level restricted additive Schwarz: blocks of --block points,
                   --overlap, coarse space one constant per block and unknown
  two-grid         Schwarz smoothing and a coarse correction by the Jacobian of the same
                   scene at twice the spacing (--coarse PREFIX), bilinear transfer
  inner            A with Jacobi against a compact-Laplacian preconditioner; DG with none
                   against the inverse of its interior symbol by FFT

DG is singular and not symmetric: its right null vector is the constant, its
left null vector y is not (the walls). A right-hand side r of DG p = r has a
solution only if y . r = 0; every DG solve here first removes from r its part
along y (`DgRange`), since a solve of an inconsistent system stalls at that
part's size whatever its preconditioner.
Needs NumPy and SciPy (python3-numpy, python3-scipy).
"""
import argparse
import itertools
import os
import subprocess
import tempfile
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from dg_symbol import quintic_derivative


def load(prefix):
    info = {}
    for line in open(prefix + "_info.txt"):
        key, *values = line.split()
        info[key] = [float(x) for x in values] if len(values) > 1 else float(values[0])
    dim, fluid = int(info["dim"]), int(info["nf"])
    entries = np.loadtxt(prefix + "_J.txt")
    size = fluid * (dim + 1)
    J = sp.csr_matrix((entries[:, 2], (entries[:, 0].astype(int), entries[:, 1].astype(int))), shape=(size, size))
    R0 = np.loadtxt(prefix + "_R0.txt")
    lattice = np.loadtxt(prefix + "_particles.txt")[:, dim:2 * dim].astype(int)
    return info, J, R0, lattice


def permeability(info, u):
    """k = nu <v> / F along the body force, from the velocity unknowns of u."""
    dim = int(info["dim"])
    force = np.atleast_1d(info["F"])
    axis = int(np.argmax(np.abs(force)))
    mean_velocity = u[axis:len(u) - len(u) % (dim + 1):dim + 1].sum() * info["dx"] ** dim / info["volume"]
    return info["nu"] * mean_velocity / force[axis]


def fgmres(apply, b, precondition, tol, maxit, restart=None):
    """Right-preconditioned flexible GMRES; returns x, iterations, residual history."""
    restart = restart or maxit
    x = np.zeros_like(b)
    norm_b = np.linalg.norm(b)
    if norm_b == 0:
        return x, 0, [0.0]
    iterations, history = 0, [1.0]
    while iterations < maxit and history[-1] > tol:
        r = b - apply(x)
        beta = np.linalg.norm(r)
        if beta == 0:
            history.append(0.0)
            break
        V, Z = [r / beta], []
        H = np.zeros((restart + 1, restart))
        g = np.zeros(restart + 1)
        g[0] = beta
        rotations = []
        for j in range(restart):
            Z.append(precondition(V[j]))
            w = apply(Z[j])
            for i in range(j + 1):
                H[i, j] = w @ V[i]
                w = w - H[i, j] * V[i]
            H[j + 1, j] = np.linalg.norm(w)
            V.append(w / H[j + 1, j] if H[j + 1, j] > 0 else w)
            for i, (c, s) in enumerate(rotations):
                H[i, j], H[i + 1, j] = c * H[i, j] + s * H[i + 1, j], -s * H[i, j] + c * H[i + 1, j]
            d = np.hypot(H[j, j], H[j + 1, j])
            c, s = H[j, j] / d, H[j + 1, j] / d
            rotations.append((c, s))
            H[j, j], H[j + 1, j] = d, 0.0
            g[j + 1], g[j] = -s * g[j], c * g[j]
            iterations += 1
            history.append(abs(g[j + 1]) / norm_b)
            if history[-1] <= tol or iterations >= maxit:
                break
        k = len(Z)
        y = np.linalg.solve(np.triu(H[:k, :k]), g[:k])
        for i in range(k):
            x += y[i] * Z[i]
    return x, iterations, history


class System:
    """The Newton system at the start state, its blocks and its border.

    The SPH continuity equation is not conservative at walls, so the marched
    steady state keeps a uniform density drift lambda: the rates are zero up
    to d rho/dt = lambda. The bordered system J u + e lambda = -R0,
    e . u = 0 (e: the density unknowns, normalised) is what the march solves.
    """

    def __init__(self, prefix, reference=True):
        self.info, J, self.R0, self.lattice = load(prefix)
        self.dim = int(self.info["dim"])
        self.shape = np.array([int(v) for v in np.atleast_1d(self.info["N"])])
        U = self.dim + 1
        n = J.shape[0] // U
        self.n = n
        self.velocity = np.sort(np.concatenate([np.arange(n) * U + q for q in range(self.dim)]))
        self.density = np.arange(n) * U + self.dim
        self.J = J.tocsr()
        self.A = self.J[self.velocity][:, self.velocity].tocsc()
        self.G = self.J[self.velocity][:, self.density].tocsc()
        self.D = self.J[self.density][:, self.velocity].tocsc()
        e = np.zeros(J.shape[0])
        e[self.density] = 1.0 / np.sqrt(n)
        self.border = e
        column = sp.csr_matrix(e.reshape(-1, 1))
        self.Jb = sp.bmat([[self.J, column], [column.T, None]]).tocsr()
        self.b = np.append(-self.R0, 0.0)
        # The direct solution, for k: minutes beyond about 20,000 unknowns (--no-reference).
        self.reference = spla.spsolve(self.Jb.tocsc(), self.b) if reference else None
        self.k = permeability(self.info, self.reference[:-1]) if reference else float("nan")

    def block_preconditioner(self, schur_solve, velocity_solve):
        """Block upper-triangular [[A, G], [0, S]]^-1 with the border handled:
        lambda takes the mean of the density residual, the mean density change
        comes from the border row."""
        n = self.n

        def apply(r):
            rv, rp, border = r[self.velocity], r[self.density].copy(), r[-1]
            drift = rp.sum() / np.sqrt(n)
            rp -= drift / np.sqrt(n)
            p = schur_solve(rp)
            p += border / np.sqrt(n) - p.mean()
            z = np.empty_like(r)
            z[self.velocity] = velocity_solve(rv - self.G @ p)
            z[self.density] = p
            z[-1] = drift
            return z

        return apply

    def point_index(self):
        """Each lattice point's fluid unknown, -1 where there is none."""
        index = -np.ones(self.shape, dtype=int)
        index[tuple(self.lattice.T)] = np.arange(self.n)
        return index

    def compact_laplacian(self, neumann=True, stride=1):
        """The 2d+1-point graph Laplacian on the fluid lattice points (periodic), its
        neighbours `stride` points away: Neumann (only fluid neighbours count) or
        Dirichlet (solid neighbours count on the diagonal)."""
        index = self.point_index()
        rows, cols, vals = [], [], []
        everyone = np.arange(self.n)
        for q in range(self.dim):
            for step in (-stride, stride):
                shifted = self.lattice.copy()
                shifted[:, q] = (shifted[:, q] + step) % self.shape[q]
                neighbour = index[tuple(shifted.T)]
                fluid = neighbour >= 0
                diagonal = fluid if neumann else np.ones(self.n, dtype=bool)
                rows += [everyone[diagonal], everyone[fluid]]
                cols += [everyone[diagonal], neighbour[fluid]]
                vals += [np.ones(diagonal.sum()), -np.ones(fluid.sum())]
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(self.n, self.n))


def report(label, system, x, iterations, history, seconds, extra=""):
    k = permeability(system.info, x[:-1])
    print(f"  {label}: {iterations} iterations, residual {history[-1]:.1e}, k {k:.6e} ({k / system.k - 1:+.1e} "
          f"from direct), {seconds:.1f} s{extra}")


def smooth_mode_schur(system, A_lu):
    x = np.cos(2 * np.pi * system.lattice[:, 0] / (system.shape[0] / 2))
    x -= x.mean()
    return (x @ (-system.D @ A_lu.solve(system.G @ x))) / (x @ x)


def method_direct(system, args):
    t = time.time()
    lu = spla.splu(system.Jb.tocsc(), permc_spec="MMD_AT_PLUS_A")
    seconds = time.time() - t
    fill = lu.L.nnz + lu.U.nnz
    unbordered = spla.spsolve(system.J.tocsc(), -system.R0)
    rho0 = system.info["rho0"]
    print(f"  bordered: k {system.k:.6e}, drift lambda {system.reference[-1]:.3e}, "
          f"mean density change {system.reference[system.density].mean() / rho0:+.1e} rho0")
    print(f"  unbordered: k {permeability(system.info, unbordered):.6e}, "
          f"mean density change {unbordered[system.density].mean() / rho0:+.1e} rho0")
    print(f"  LU of the bordered system: {seconds:.1f} s, fill {fill:.3e} ({fill / system.Jb.shape[0]:.0f} a row; "
          f"the matrix has {system.Jb.nnz / system.Jb.shape[0]:.0f})")


def fluid_regions(system):
    """Each fluid particle's region: the fluid joined by chains of lattice
    neighbours, one step along each axis, corners counted, across the
    periodic cell (the solver's regions, solver/FluidRegions.hpp)."""
    index = system.point_index()
    parent = np.arange(system.n)

    def root(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for offset in itertools.product((-1, 0, 1), repeat=system.dim):
        if not any(offset):
            continue
        neighbour = index[tuple(((system.lattice + np.array(offset)) % system.shape).T)]
        for i in np.flatnonzero(neighbour >= 0):
            a, b = root(i), root(neighbour[i])
            if a != b:
                parent[a] = b
    return np.unique([root(i) for i in range(system.n)], return_inverse=True)[1]


def method_direct_regions(system, args):
    regions = fluid_regions(system)
    count = regions.max() + 1
    border = sp.lil_matrix((system.J.shape[0], count))
    for r in range(count):
        members = system.density[regions == r]
        border[members, r] = 1.0 / np.sqrt(len(members))
    border = border.tocsr()
    bordered = sp.bmat([[system.J, border], [border.T, None]]).tocsc()
    x = spla.spsolve(bordered, np.concatenate([-system.R0, np.zeros(count)]))
    print(f"  {count} regions of {', '.join(str(c) for c in np.bincount(regions))} fluid particles: "
          f"k {permeability(system.info, x[:system.J.shape[0]]):.6e}")


def krylov_with_schur(system, args, schur_solve, label):
    A_lu = spla.splu(system.A)
    t = time.time()
    M = system.block_preconditioner(schur_solve, A_lu.solve)
    x, its, hist = fgmres(lambda y: system.Jb @ y, system.b, M, args.tol, args.maxit, args.restart)
    report(label, system, x, its, hist, time.time() - t)


def dg_operators(system):
    inverse_diagonal = sp.diags(1.0 / system.A.diagonal())
    DG = (system.D @ inverse_diagonal @ system.G).tocsc()
    DAG = (system.D @ inverse_diagonal @ system.A @ inverse_diagonal @ system.G).tocsr()
    return DG, DAG


class DgRange:
    """Projects right-hand sides onto the range of DG: r - (y . r / y . 1) 1, with y
    the left null vector of DG (found here by two inverse iterations on DG^T)."""

    def __init__(self, DG):
        lu = spla.splu((DG.T + 1e-10 * abs(DG.diagonal()).max() * sp.identity(DG.shape[0])).tocsc())
        y = lu.solve(np.random.default_rng(2).standard_normal(DG.shape[0]))
        y = lu.solve(y / np.linalg.norm(y))
        self.y = y / y.sum()

    def __call__(self, r):
        return r - (self.y @ r)


def exact_dg_solver(DG):
    shift = 1e-12 * abs(DG.diagonal()).max()
    return spla.splu((DG + shift * sp.identity(DG.shape[0])).tocsc()).solve


def wide_laplacian_solver(system, DG, coupling=0.0):
    """r -> L^-1 r / s by LU: L the wide Laplacian (stride 2, solid neighbours on the
    diagonal; zero at the same Brillouin-zone corners as DG, it splits into 2^d
    independent compact Laplacians on the sub-lattices of spacing 2), s its ratio to DG
    on a smooth mode. With `coupling`, the compact Laplacian (stride 1) times it is
    added: it joins the sub-lattices, so that a narrow passage's sign patterns are not
    nearly free."""
    L = system.compact_laplacian(neumann=False, stride=2)
    if coupling:
        L = L + coupling * system.compact_laplacian(neumann=True)
    smooth = np.cos(2 * np.pi * system.lattice[:, 0] / system.shape[0])
    scale = (smooth @ (DG @ smooth)) / (smooth @ (L @ smooth))
    lu = spla.splu(L.tocsc())
    return lambda r: lu.solve(r) / scale


def dg_schwarz(system, DG, block, overlap, keep=None):
    """Restricted additive Schwarz on DG: blocks of block^d lattice points, each
    extended by overlap points a side, DG on each extended block solved by LU (a
    shift of 1e-8 of its largest diagonal: the block of a closed pocket is
    singular), each block's solution kept on its own points. `keep`: a mask of the
    fluid points; only the blocks that own one of them are taken (all if None)."""
    DG = DG.tocsr()
    patches = []
    for members, owns in extended_blocks(system, block, overlap)[1]:
        if keep is not None and not keep[members[owns]].any():
            continue
        local = DG[members][:, members].tocsc()
        local = local + 1e-8 * abs(local.diagonal()).max() * sp.identity(len(members), format="csc")
        patches.append((members, owns, spla.splu(local).solve))
    print(f"  Schwarz on DG: {len(patches)} blocks of {block}, overlap {overlap}, "
          f"largest {max(len(p[0]) for p in patches)} particles")
    return restricted_additive_schwarz(patches)


def narrow_points(system, width):
    """Which fluid points lie where no ball `width` points across fits in the pore
    space (the scene check's passages narrower than `width` spacings): the pore
    space less its opening by that ball, on the periodic lattice."""
    from scipy import ndimage
    pore = np.zeros(system.shape, dtype=bool)
    pore[tuple(system.lattice.T)] = True
    tiled = np.tile(pore, (3,) * system.dim)
    middle = tuple(slice(n, 2 * n) for n in system.shape)
    distance = ndimage.distance_transform_edt(tiled)
    radius = width / 2.0
    centres = distance > radius
    reach = int(np.ceil(radius))
    offsets = np.array(list(itertools.product(range(-reach, reach + 1), repeat=system.dim)))
    ball = np.zeros((2 * reach + 1,) * system.dim, dtype=bool)
    ball[tuple((offsets + reach).T)] = np.linalg.norm(offsets, axis=1) <= radius
    covered = ndimage.binary_dilation(centres, structure=ball)[middle]
    return ~covered[tuple(system.lattice.T)]


def dg_narrow_schwarz(system, DG, block, overlap, width):
    """The wide Laplacian (wide_laplacian_solver), then a restricted additive
    Schwarz correction of DG's residual on the blocks of block^d points that hold a
    narrow point (narrow_points), each extended by overlap points a side and solved
    by LU: the local weak modes of narrow passages resolved where they live."""
    DG = DG.tocsr()
    wide = wide_laplacian_solver(system, DG)
    narrow = narrow_points(system, width)
    print(f"  narrow points (no ball {width} across): {narrow.sum()} of {system.n}")
    ras = dg_schwarz(system, DG, block, overlap, keep=narrow)

    def apply(r):
        z = wide(r)
        return z + ras(r - DG @ z)

    return apply


def method_lsc(system, args):
    DG, DAG = dg_operators(system)
    solve = exact_dg_solver(DG)
    krylov_with_schur(system, args, lambda rp: -solve(DAG @ solve(rp)), "LSC, exact (DG)^-1")


def method_simple(system, args):
    DG, _ = dg_operators(system)
    solve = exact_dg_solver(DG)
    krylov_with_schur(system, args, lambda rp: -solve(rp), "Schur -D diag(A)^-1 G, exact")


def method_scaled_identity(system, args):
    s = smooth_mode_schur(system, spla.splu(system.A))
    krylov_with_schur(system, args, lambda rp: rp / s, f"Schur s I (s = {s:.3e})")


def method_lsc_inner(system, args):
    DG, DAG = dg_operators(system)
    products = [0]

    def dg(y):
        products[0] += 1
        return DG @ y

    in_range = DgRange(DG)

    def solve(r):
        x, _, _ = fgmres(dg, in_range(r), lambda z: z, args.inner_tol, 2000)
        return x - x.mean()

    krylov_with_schur(system, args, lambda rp: -solve(DAG @ solve(rp)), f"LSC, (DG)^-1 by GMRES to {args.inner_tol:g}")
    print(f"  DG products: {products[0]}")


def method_lsc_capped(system, args):
    """LSC as the steady solver applies it: each (DG)^-1 by FGMRES (restart 30) on
    DG + s I (s = --dg-shift times DG's mean diagonal; the solver's is 1e-10 of DG's
    largest eigenvalue, as small against the weak modes) to --inner-tol, at most
    --inner-maxit iterations, preconditioned by --inner-preconditioner: the wide Laplacian
    (stride 2, solid neighbours on the diagonal) solved exactly and scaled to DG on a
    smooth mode, nothing, the smoothed aggregation of `sa` (blocks of 4), restricted
    additive Schwarz on DG (dg_schwarz: --block, default 8, and --overlap), the wide
    Laplacian followed by that Schwarz on the blocks of narrow passages only
    (dg_narrow_schwarz: --narrow-width), or the wide Laplacian joined across its
    sub-lattices by the compact one (wide_laplacian_solver: --coupling); the
    mean removed after. And, for comparison, (DG + s I)^-1 by LU."""
    DG, DAG = dg_operators(system)
    shift = args.dg_shift * DG.diagonal().mean()
    shifted = (DG + shift * sp.identity(system.n)).tocsr()
    preconditioners = {"wide": wide_laplacian_solver(system, DG), "none": lambda z: z}
    if args.inner_preconditioner == "sa":
        preconditioners["sa"] = dg_multigrid(system, DG.tocsr(), 4)[0]
    if args.inner_preconditioner == "schwarz":
        preconditioners["schwarz"] = dg_schwarz(system, DG, args.block, args.overlap)
    if args.inner_preconditioner == "coupled":
        preconditioners["coupled"] = wide_laplacian_solver(system, DG, args.coupling)
    if args.inner_preconditioner == "narrow":
        preconditioners["narrow"] = dg_narrow_schwarz(system, DG, args.block, args.overlap, args.narrow_width)
    inner = [0, 0]

    def capped(r):
        x, its, _ = fgmres(lambda y: shifted @ y, r, preconditioners[args.inner_preconditioner], args.inner_tol,
                           args.inner_maxit, 30)
        inner[0] += its
        inner[1] += 1
        return x - x.mean()

    exact = spla.splu(shifted.tocsc()).solve
    krylov_with_schur(system, args, lambda rp: -capped(DAG @ capped(rp)),
                      f"LSC, (DG + {args.dg_shift:g} diag I)^-1 by GMRES to {args.inner_tol:g}, "
                      f"at most {args.inner_maxit}, preconditioned by {args.inner_preconditioner}")
    print(f"  inner iterations {inner[0]} in {inner[1]} solves")
    krylov_with_schur(system, args, lambda rp: -(lambda p: p - p.mean())(exact(DAG @ exact(rp))),
                      f"LSC, (DG + {args.dg_shift:g} diag I)^-1 by LU")


def method_weak_modes(system, args):
    """The --modes eigenvalues of DG nearest 0 (shift-invert, sparse), over DG's mean
    diagonal, against a smooth mode's Rayleigh quotient; per mode how many particles carry
    it (participation 1 / sum v^4 of the normalised mode), its largest entry's lattice point
    and that point's fluid neighbours among its 3^d - 1."""
    DG, _ = dg_operators(system)
    size = DG.diagonal().mean()
    smooth = np.cos(2 * np.pi * system.lattice[:, 0] / system.shape[0])
    print(f"  smooth mode cos(2 pi x / L): {(smooth @ (DG @ smooth)) / (smooth @ smooth) / size:.2e}")
    index = system.point_index()
    neighbours = np.zeros(system.n, dtype=int)
    for offset in np.ndindex(*(3,) * system.dim):
        step = np.array(offset) - 1
        if step.any():
            neighbours += index[tuple(((system.lattice + step) % system.shape).T)] >= 0
    values, vectors = spla.eigs(DG.tocsc(), k=args.modes, sigma=0, which="LM")
    order = np.argsort(np.abs(values))
    for mode in order:
        v = np.real(vectors[:, mode])
        v /= np.linalg.norm(v)
        top = int(np.argmax(v ** 2))
        print(f"  {abs(values[mode]) / size:.2e}: participation {1 / (v ** 4).sum():7.1f}, largest at "
              f"{tuple(int(c) for c in system.lattice[top])} ({neighbours[top]} fluid neighbours)")


def method_stabilised(system, args):
    A_lu = spla.splu(system.A)
    s = smooth_mode_schur(system, A_lu)
    y = np.random.default_rng(0).standard_normal(system.n)
    for _ in range(30):
        y = -system.D @ A_lu.solve(system.G @ y)
        top = np.linalg.norm(y)
        y /= top
    L = system.compact_laplacian()
    print(f"  Schur on a smooth mode {s:.3e}, largest |eigenvalue| about {top:.3e}")
    for beta in args.beta:
        T = np.sign(s) * beta * top / (2 * system.dim) * L
        stabilisation = sp.lil_matrix(system.Jb.shape)
        stabilisation[np.ix_(system.density, system.density)] = T
        stabilised = (system.Jb + stabilisation.tocsr()).tocsr()
        k_stabilised = permeability(system.info, spla.spsolve(stabilised.tocsc(), system.b)[:-1])
        schur_lu = spla.splu((s * sp.identity(system.n) + T).tocsc())
        M = system.block_preconditioner(schur_lu.solve, A_lu.solve)
        print(f"  beta {beta:g}: k of the stabilised system {k_stabilised / system.k - 1:+.2e} from the true one")
        for label, matrix in [("stabilised", stabilised), ("true", system.Jb)]:
            t = time.time()
            x, its, hist = fgmres(lambda v: matrix @ v, system.b, M, args.tol, args.maxit, args.restart)
            report(f"  {label} system, Schur s I + beta T", system, x, its, hist, time.time() - t)


def quintic_over_r(r, h, dim):
    """(1/r) dW/dr of the quintic kernel (src/core/Kernel.hpp), support 3h."""
    alpha = 7 / (478 * np.pi * h * h) if dim == 2 else 1 / (120 * np.pi * h ** 3)
    return alpha / h * quintic_derivative(r / h) / r


def pair_jump_operator(system):
    """T rho = sum_b 2 V F_ab [p_a - p_b - (g_a + g_b) . r_ab / 2] over the fluid pairs (h = dx),
    p = c^2 rho and g = grad p = -rho0 G rho the code's own pressure gradient (walls included):
    the pressure jump of a pair less what the mean of its two gradients predicts. Zero for a
    quadratic p wherever g is exact; a compact Laplacian of p where the SPH gradient does not see p."""
    dim, dx, n = system.dim, system.info["dx"], system.n
    reach = 3
    index = system.point_index()
    a_rows, b_rows, weights, separations = [], [], [], []
    for offset in np.ndindex(*(2 * reach + 1,) * dim):
        o = np.array(offset) - reach
        r = np.linalg.norm(o) * dx
        if r == 0 or r >= 3 * dx:
            continue
        b = index[tuple(((system.lattice + o) % system.shape).T)]
        fluid = b >= 0
        a_rows.append(np.nonzero(fluid)[0])
        b_rows.append(b[fluid])
        weights.append(np.full(fluid.sum(), 2 * dx ** dim * quintic_over_r(r, dx, dim)))
        separations.append(np.tile(-o * dx, (fluid.sum(), 1)))
    a, b, w, r = (np.concatenate(v) for v in (a_rows, b_rows, weights, separations))
    jump = sp.csr_matrix((np.concatenate([w, -w]), (np.concatenate([a, a]), np.concatenate([a, b]))), shape=(n, n))
    rows, cols, values = [], [], []
    for q in range(dim):
        rows += [a, a]
        cols += [a * dim + q, b * dim + q]
        values += [w * r[:, q] / 2, w * r[:, q] / 2]
    mean_gradient = sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                                  shape=(n, n * dim))
    c, rho0 = system.info["c"], system.info["rho0"]
    return (c * c * jump + rho0 * (mean_gradient @ system.G)).tocsr()


def method_pair_stabilised(system, args):
    """Continuity stabilised by the pairs' pressure jumps: d rho/dt += alpha dx^2 / nu T rho
    (pair_jump_operator; Rhie and Chow's idea in SPH pairs: dx^2 / nu stands for the inverse of the
    velocity block's diagonal). For each --alpha: k of the stabilised system (direct, unless
    --no-reference), and FGMRES on it with A^-1 exact and the Schur complement C - D diag(A)^-1 G
    solved by GMRES to --inner-tol, at most --inner-maxit, preconditioned by the compact
    (2d+1-point, Neumann) Laplacian scaled to it on a smooth mode: a preconditioner a multigrid
    can apply. --true: the same preconditioner on the unstabilised system."""
    T = pair_jump_operator(system)
    A_lu = spla.splu(system.A)
    DG, _ = dg_operators(system)
    compact = system.compact_laplacian(neumann=True)
    compact_lu = spla.splu((compact + 1e-10 * sp.identity(system.n)).tocsc())
    smooth = np.cos(2 * np.pi * system.lattice[:, 0] / system.shape[0])
    for alpha in args.alpha:
        C = alpha * system.info["dx"] ** 2 / system.info["nu"] * T
        extra = sp.lil_matrix(system.Jb.shape)
        extra[np.ix_(system.density, system.density)] = C
        stabilised = (system.Jb + extra.tocsr()).tocsr()
        if system.reference is not None:
            k = permeability(system.info, spla.spsolve(stabilised.tocsc(), system.b)[:-1])
            print(f"  alpha {alpha:g}: k of the stabilised system {k:.6e}, {k / system.k - 1:+.2e} from the true one")
        schur = (C - DG).tocsr()
        scale = (smooth @ (schur @ smooth)) / (smooth @ (compact @ smooth))
        inner = [0]

        def product(v):
            inner[0] += 1
            return schur @ v

        def schur_solve(rp):
            return fgmres(product, rp - rp.mean(), lambda z: compact_lu.solve(z) / scale, args.inner_tol,
                          args.inner_maxit)[0]

        target = system.Jb if args.true else stabilised
        t = time.time()
        x, its, hist = fgmres(lambda v: target @ v, system.b, system.block_preconditioner(schur_solve, A_lu.solve),
                              args.tol, args.maxit, args.restart)
        k = permeability(system.info, x[:-1])
        print(f"  alpha {alpha:g}, {'unstabilised' if args.true else 'stabilised'} system: {its} iterations, "
              f"{inner[0]} inner, residual {hist[-1]:.1e}, k {k:.6e}, {time.time() - t:.1f} s")


def extended_blocks(system, block, overlap):
    """Each lattice point's block of block^d points, and per block its points extended
    by overlap points a side (periodic) with which of them the block owns."""
    blocks = system.lattice // block
    block_id = np.ravel_multi_index(tuple(blocks.T), tuple((system.shape + block - 1) // block))
    extended = []
    for b in np.unique(block_id):
        owned = np.where(block_id == b)[0]
        lo = blocks[owned[0]] * block - overlap
        members = np.where(np.all((system.lattice - lo) % system.shape < block + 2 * overlap, axis=1))[0]
        extended.append((members, np.isin(members, owned)))
    return block_id, extended


def schwarz_patches(system, block, overlap):
    """Non-overlapping blocks of block^d lattice points, each extended by overlap;
    the inverse of the Jacobian on each extended block, and which rows it owns."""
    U = system.dim + 1
    block_id, extended = extended_blocks(system, block, overlap)
    patches = []
    for members, owned in extended:
        unknowns = (members[:, None] * U + np.arange(U)).ravel()
        patches.append((unknowns, np.repeat(owned, U), np.linalg.inv(system.Jb[unknowns][:, unknowns].toarray()).dot))
    return block_id, patches


def restricted_additive_schwarz(patches):
    """r -> the sum over patches (unknowns, owns, solve) of solve(r on the unknowns),
    kept on the unknowns the patch owns."""
    def apply(r):
        z = np.zeros_like(r)
        for unknowns, owns, solve in patches:
            z[unknowns[owns]] += solve(r[unknowns])[owns]
        return z

    return apply


def method_schwarz(system, args):
    U = system.dim + 1
    t = time.time()
    block_id, patches = schwarz_patches(system, args.block, args.overlap)
    ras = restricted_additive_schwarz(patches)
    _, coarse_of = np.unique(block_id, return_inverse=True)
    coarse = coarse_of.max() + 1
    rows = np.append(np.arange(system.n * U), system.n * U)
    cols = np.append((coarse_of[:, None] * U + np.arange(U)).ravel(), coarse * U)
    Phi = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(system.n * U + 1, coarse * U + 1))
    coarse_inverse = np.linalg.inv((Phi.T @ system.Jb @ Phi).toarray())

    def two_level(r):
        z = Phi @ (coarse_inverse @ (Phi.T @ r))
        return z + ras(r - system.Jb @ z)

    setup = time.time() - t
    for label, M in [("one-level RAS", ras), ("two-level RAS", two_level)]:
        t = time.time()
        x, its, hist = fgmres(lambda y: system.Jb @ y, system.b, M, args.tol, args.maxit, args.restart)
        report(label, system, x, its, hist, time.time() - t,
               f" ({len(patches)} patches, coarse {coarse * U + 1}, setup {setup:.1f} s)")


def method_two_grid(system, args):
    coarse = System(args.coarse)
    U = system.dim + 1
    coarse_index = -np.ones(coarse.shape, dtype=int)
    coarse_index[tuple(coarse.lattice.T)] = np.arange(coarse.n)
    rows, cols, vals = [], [], []
    for p in range(system.n):  # bilinear from the coarse fluid points, renormalised over them
        position = (system.lattice[p] - 0.5) / 2.0
        base = np.floor(position).astype(int)
        frac = position - base
        weights, points = [], []
        for corner in range(2 ** system.dim):
            offset = np.array([(corner >> q) & 1 for q in range(system.dim)])
            w = np.prod(np.where(offset == 1, frac, 1 - frac))
            c = coarse_index[tuple((base + offset) % coarse.shape)]
            if c >= 0 and w > 0:
                weights.append(w)
                points.append(c)
        if not points:
            distance = np.abs((coarse.lattice - position + coarse.shape / 2) % coarse.shape - coarse.shape / 2).sum(1)
            weights, points = [1.0], [int(np.argmin(distance))]
        weights = np.array(weights) / sum(weights)
        for w, c in zip(weights, points):
            rows += [p * U + q for q in range(U)]
            cols += [c * U + q for q in range(U)]
            vals += [w] * U
    rows.append(system.n * U)
    cols.append(coarse.n * U)
    vals.append(1.0)
    prolong = sp.csr_matrix((vals, (rows, cols)), shape=(system.n * U + 1, coarse.n * U + 1))
    restrict = (sp.diags(1.0 / np.maximum(np.asarray(prolong.sum(0)).ravel(), 1e-300)) @ prolong.T).tocsr()
    coarse_lu = spla.splu(coarse.Jb.tocsc())
    _, patches = schwarz_patches(system, args.block, args.overlap)
    ras = restricted_additive_schwarz(patches)

    def cycle(r):
        z = ras(r)
        z = z + prolong @ coarse_lu.solve(restrict @ (r - system.Jb @ z))
        return z + ras(r - system.Jb @ z)

    t = time.time()
    x, its, hist = fgmres(lambda y: system.Jb @ y, system.b, cycle, args.tol, args.maxit, args.restart)
    report("two-grid, RAS smoothing, rediscretised coarse Jacobian", system, x, its, hist, time.time() - t)


def method_inner(system, args):
    rng = np.random.default_rng(1)
    A = system.A.tocsr()
    diagonal = A.diagonal()
    laplacian = system.compact_laplacian(neumann=False).tocsc()
    scale = -diagonal.mean() / laplacian.diagonal().mean()
    laplacian_lu = spla.splu(laplacian)

    def compact(r):
        z = np.empty_like(r)
        for q in range(system.dim):
            z[q::system.dim] = laplacian_lu.solve(r[q::system.dim]) / scale
        return z

    b = rng.standard_normal(A.shape[0])
    for label, M in [("A, Jacobi", lambda r: r / diagonal), ("A, compact Dirichlet Laplacian", compact)]:
        t = time.time()
        _, its, hist = fgmres(lambda y: A @ y, b, M, args.tol, args.maxit)
        print(f"  {label}: {its} iterations, residual {hist[-1]:.1e}, {time.time() - t:.1f} s")
    DG, _ = dg_operators(system)
    DG = DG.tocsr()
    widths = np.diff(DG.indptr)
    interior = np.where(widths == widths.max())[0]
    row = interior[len(interior) // 2]
    stencil = np.zeros(system.shape)
    for j, value in zip(DG.indices[DG.indptr[row]:DG.indptr[row + 1]], DG.data[DG.indptr[row]:DG.indptr[row + 1]]):
        stencil[tuple((system.lattice[j] - system.lattice[row]) % system.shape)] += value
    symbol = np.real(np.fft.fftn(stencil))
    inverse_symbol = np.where(np.abs(symbol) > 1e-12 * np.abs(symbol).max(), 1.0 / np.where(symbol == 0, 1, symbol), 0)

    def fft(r):
        g = np.zeros(system.shape)
        g[tuple(system.lattice.T)] = r
        z = np.real(np.fft.ifftn(np.fft.fftn(g) * inverse_symbol))[tuple(system.lattice.T)]
        return z - z.mean()

    b = DG @ rng.standard_normal(system.n)  # in the range of DG
    for label, M in [("DG, none", lambda r: r), ("DG, FFT of the interior symbol", fft)]:
        t = time.time()
        _, its, hist = fgmres(lambda y: DG @ y, b, M, args.tol, args.maxit)
        print(f"  {label}: {its} iterations, residual {hist[-1]:.1e}, {time.time() - t:.1f} s")


def modulated_vectors(system, edges=False):
    """The constant and the lattice's sign patterns (-1)^(m . i), m in {0,1}^d without 0.
    The SPH gradient vanishes at the corners of the Brillouin zone, so DG's weakest modes
    are these patterns times smooth functions (2^d near-null vectors, not one). With edges
    (3D), also the patterns of two axes times cos and sin(pi i_q / 2) along the third: the
    middle of the zone's edges, where 3D has weak modes too."""
    patterns = [np.array(m) for m in np.ndindex(*(2,) * system.dim) if any(m)]
    vectors = [np.ones(system.n)] + [1.0 - 2.0 * ((system.lattice @ m) % 2) for m in patterns]
    if edges:
        for q in range(system.dim):
            sign = 1.0 - 2.0 * (np.delete(system.lattice, q, axis=1).sum(1) % 2)
            vectors += [sign * np.cos(np.pi * system.lattice[:, q] / 2), sign * np.sin(np.pi * system.lattice[:, q] / 2)]
    return np.column_stack(vectors)


def jacobi_spectral_radius(A, inverse_diagonal, iterations=30):
    x = np.random.default_rng(1).standard_normal(A.shape[0])
    for _ in range(iterations):
        y = inverse_diagonal * (A @ x)
        radius = np.linalg.norm(y) / np.linalg.norm(x)
        x = y / np.linalg.norm(y)
    return radius


class SmoothedAggregation:
    """Smoothed-aggregation multigrid for DG with the modulated near-null vectors.

    Level by level: aggregates are the unknowns whose lattice (or aggregate) coordinates
    fall in one block of block^d; the tentative prolongator is the QR of the near-null
    vectors on each aggregate (their R rows are the next level's near-null vectors), smoothed
    once by damped Jacobi; the coarse operator is P^T A P. V(2,2) cycles with damped Jacobi
    (weight 4/3 over the spectral radius of D^-1 A), or V(1,1) with a forward Gauss-Seidel
    sweep before and a backward one after; LU below `coarsest` unknowns."""

    def __init__(self, A, coordinates, vectors, block=4, coarsest=300, gauss_seidel=False):
        self.levels = []
        self.gauss_seidel = gauss_seidel
        while True:
            level = {"A": A.tocsr()}
            level["inverse_diagonal"] = 1.0 / level["A"].diagonal()
            level["weight"] = 4.0 / 3.0 / jacobi_spectral_radius(level["A"], level["inverse_diagonal"])
            if gauss_seidel:
                level["lower"], level["upper"] = sp.tril(A, format="csr"), sp.triu(A, format="csr")
            self.levels.append(level)
            if A.shape[0] <= coarsest:
                shift = 1e-12 * abs(A.diagonal()).max()
                level["lu"] = spla.splu((A + shift * sp.identity(A.shape[0])).tocsc())
                return
            keys, aggregate = np.unique(coordinates // block, axis=0, return_inverse=True)
            aggregate = aggregate.ravel()
            rows, cols, vals, coarse_vectors, coarse_coordinates = [], [], [], [], []
            for a in range(len(keys)):
                members = np.where(aggregate == a)[0]
                Q, R = np.linalg.qr(vectors[members])
                kept = np.abs(np.diag(R)) > 1e-10 * np.abs(np.diag(R)).max()
                Q, R = Q[:, kept], R[kept]
                first = sum(len(v) for v in coarse_vectors)
                rows.append(np.repeat(members, Q.shape[1]))
                cols.append(np.tile(np.arange(first, first + Q.shape[1]), len(members)))
                vals.append(Q.ravel())
                coarse_vectors.append(R)
                coarse_coordinates.append(np.repeat(keys[a][None, :], Q.shape[1], axis=0))
            coarse = sum(len(v) for v in coarse_vectors)
            tentative = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                      shape=(A.shape[0], coarse))
            P = (tentative - level["weight"] * sp.diags(level["inverse_diagonal"]) @ (level["A"] @ tentative)).tocsr()
            level["P"], level["R"] = P, P.T.tocsr()
            A = (level["R"] @ level["A"] @ P).tocsr()
            vectors, coordinates = np.vstack(coarse_vectors), np.vstack(coarse_coordinates)

    def sizes(self):
        return [level["A"].shape[0] for level in self.levels]

    def cycle(self, b, depth=0, sweeps=2):
        level = self.levels[depth]
        if "lu" in level:
            return level["lu"].solve(b)
        A, smooth = level["A"], level["weight"] * level["inverse_diagonal"]
        if self.gauss_seidel:
            x = spla.spsolve_triangular(level["lower"], b, lower=True)
            x += level["P"] @ self.cycle(level["R"] @ (b - A @ x), depth + 1)
            return x + spla.spsolve_triangular(level["upper"], b - A @ x, lower=False)
        x = smooth * b
        for _ in range(sweeps - 1):
            x += smooth * (b - A @ x)
        x += level["P"] @ self.cycle(level["R"] @ (b - A @ x), depth + 1, sweeps)
        for _ in range(sweeps):
            x += smooth * (b - A @ x)
        return x


def dg_multigrid(system, DG, block, edges=False, gauss_seidel=False):
    """SA for DG, with the sign that makes its diagonal positive; returns the
    preconditioner r -> DG^-1 r (approximately, mean-free) and the hierarchy."""
    sign = 1.0 if DG.diagonal().mean() > 0 else -1.0
    t = time.time()
    hierarchy = SmoothedAggregation(sign * DG, system.lattice, modulated_vectors(system, edges), block,
                                    gauss_seidel=gauss_seidel)
    setup = time.time() - t

    def apply(r):  # the mean of r out first: 36 rather than 45 iterations at 0.02 L
        x = sign * hierarchy.cycle(r - r.mean())
        return x - x.mean()

    return apply, hierarchy, setup


def method_sa(system, args):
    DG, _ = dg_operators(system)
    DG = DG.tocsr()
    b = DG @ np.random.default_rng(1).standard_normal(system.n)  # in the range of DG
    multigrid, hierarchy, setup = dg_multigrid(system, DG, args.block, args.edges, args.gauss_seidel)
    wide = wide_laplacian_solver(system, DG)
    print(f"  smoothed aggregation: levels {hierarchy.sizes()}, set-up {setup:.1f} s")
    for label, M in [("DG, none", lambda r: r),
                     ("DG, wide Laplacian (exact)", wide),
                     ("DG, smoothed aggregation " + ("V(1,1) Gauss-Seidel" if args.gauss_seidel else "V(2,2)"),
                      multigrid)]:
        t = time.time()
        _, its, hist = fgmres(lambda y: DG @ y, b, M, args.tol, args.maxit)
        print(f"  {label}: {its} iterations, residual {hist[-1]:.1e}, {time.time() - t:.1f} s")


def method_lsc_sa(system, args):
    DG, DAG = dg_operators(system)
    DG = DG.tocsr()
    multigrid, hierarchy, setup = dg_multigrid(system, DG, args.block, args.edges, args.gauss_seidel)
    in_range = DgRange(DG)
    count = {"DG": 0, "cycles": 0}

    def dg(y):
        count["DG"] += 1
        return DG @ y

    def cycle(r):
        count["cycles"] += 1
        return multigrid(r)

    def solve(r):
        x, _, _ = fgmres(dg, in_range(r), cycle, args.inner_tol, 200)
        return x - x.mean()

    krylov_with_schur(system, args, lambda rp: -solve(DAG @ solve(rp)),
                      f"LSC, (DG)^-1 by GMRES and smoothed aggregation to {args.inner_tol:g}")
    print(f"  levels {hierarchy.sizes()}, set-up {setup:.1f} s, DG products {count['DG']}, "
          f"V-cycles {count['cycles']}")


def method_modes(system, args):
    """The weakest generalised eigenmodes of DG against the compact Laplacian (dense: small
    scenes only): where in the Brillouin zone their energy lies, and how much of it sits on
    the fluid points next to a wall."""
    import scipy.linalg
    from scipy.ndimage import distance_transform_edt
    DG, _ = dg_operators(system)
    L = system.compact_laplacian().toarray()
    basis, _ = np.linalg.qr(np.eye(system.n)[:, 1:] - 1.0 / system.n)  # mean-free
    values, vectors = scipy.linalg.eig(basis.T @ DG.toarray() @ basis, basis.T @ L @ basis)
    order = np.argsort(np.abs(values))
    values, vectors = np.abs(values[order]), (basis @ vectors[:, order]).real
    fluid = np.zeros(system.shape, dtype=bool)
    fluid[tuple(system.lattice.T)] = True
    distance = distance_transform_edt(np.tile(fluid, (3,) * system.dim))  # periodic
    distance = distance[tuple(slice(m, 2 * m) for m in system.shape)][tuple(system.lattice.T)]
    wavenumbers = np.meshgrid(*[np.fft.fftfreq(m) * 2 * np.pi for m in system.shape], indexing="ij")
    corners = [np.array(c) * np.pi for c in np.ndindex(*(2,) * system.dim)]
    near = [np.sqrt(sum(np.angle(np.exp(1j * (k - c))) ** 2 for k, c in zip(wavenumbers, corner))) < np.pi / 2
            for corner in corners]
    print(f"  corners (k/pi): {[tuple(int(v) for v in c / np.pi) for c in corners]}; eigenvalue over the median")
    for mode in range(args.modes):
        grid = np.zeros(system.shape)
        grid[tuple(system.lattice.T)] = vectors[:, mode]
        energy = np.abs(np.fft.fftn(grid)) ** 2
        energy /= energy.sum()
        weight = vectors[:, mode] ** 2 / (vectors[:, mode] @ vectors[:, mode])
        print(f"  mode {mode}: {values[mode] / np.median(values):.1e}, energy near each corner "
              + " ".join(f"{energy[m].sum():.2f}" for m in near)
              + f", on points next to a wall {weight[distance <= 1].sum():.2f}")


def method_newton(system, args):
    """Newton with the Jacobian at the start state (frozen), each step's bordered system solved
    directly; the rates at each new state come from the exporter (STATE=FILE) run on --scene
    with --set. Reports k after each step and the residual up to a uniform density drift."""
    lu = spla.splu(system.Jb.tocsc())
    u = np.zeros(system.Jb.shape[0] - 1)
    residual = system.R0
    with tempfile.TemporaryDirectory() as scratch:
        state, out = os.path.join(scratch, "state.txt"), os.path.join(scratch, "out")
        for step in range(args.newton_steps + 1):
            steady = residual.copy()
            steady[system.density] -= residual[system.density].mean()  # the drift the border allows
            print(f"  Newton step {step}: k {permeability(system.info, u):.7e}, "
                  f"|R up to a uniform drift| / |R0| {np.linalg.norm(steady) / np.linalg.norm(system.R0):.1e}")
            if step == args.newton_steps:
                return
            u = u + lu.solve(np.append(-residual, 0.0))[:-1]
            np.savetxt(state, u)
            subprocess.run([args.exporter, args.scene, out] + args.set, check=True, capture_output=True,
                           env=dict(os.environ, STATE=state))
            residual = np.loadtxt(out + "_Rstate.txt")


METHODS = {
    "direct": method_direct,
    "direct-regions": method_direct_regions,
    "lsc": method_lsc,
    "simple": method_simple,
    "scaled-identity": method_scaled_identity,
    "lsc-inner": method_lsc_inner,
    "lsc-capped": method_lsc_capped,
    "weak-modes": method_weak_modes,
    "stabilised": method_stabilised,
    "pair-stabilised": method_pair_stabilised,
    "schwarz": method_schwarz,
    "two-grid": method_two_grid,
    "inner": method_inner,
    "sa": method_sa,
    "lsc-sa": method_lsc_sa,
    "modes": method_modes,
    "newton": method_newton,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("prefix")
    parser.add_argument("method", choices=sorted(METHODS))
    parser.add_argument("--tol", type=float, default=1e-6)
    parser.add_argument("--maxit", type=int, default=400)
    parser.add_argument("--restart", type=int, default=None, help="GMRES restart (default: none)")
    parser.add_argument("--inner-tol", type=float, default=1e-2)
    parser.add_argument("--inner-maxit", type=int, default=100, help="lsc-capped: inner iterations at most")
    parser.add_argument("--inner-preconditioner", choices=["wide", "none", "sa", "schwarz", "narrow", "coupled"],
                        default="wide",
                        help="lsc-capped: what preconditions the DG solves")
    parser.add_argument("--dg-shift", type=float, default=1e-10,
                        help="lsc-capped: the shift of DG, over its mean diagonal")
    parser.add_argument("--beta", type=float, nargs="+", default=[1e-3, 1e-2, 1e-1])
    parser.add_argument("--alpha", type=float, nargs="+", default=[1e-2, 1e-1, 1.0], help="pair-stabilised")
    parser.add_argument("--true", action="store_true", help="pair-stabilised: precondition the true system")
    parser.add_argument("--block", type=int, default=None,
                        help="Schwarz blocks (default 8) or aggregates (default 4), in lattice points a side")
    parser.add_argument("--overlap", type=int, default=4)
    parser.add_argument("--coupling", type=float, default=0.1,
                        help="lsc-capped, coupled: the compact Laplacian's weight beside the wide one")
    parser.add_argument("--narrow-width", type=float, default=3.0,
                        help="lsc-capped, narrow: passages narrower than this many spacings get local solves")
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--newton-steps", type=int, default=4)
    parser.add_argument("--scene", help="newton: the scene the Jacobian was exported from")
    parser.add_argument("--set", nargs="*", default=[], help="newton: the exporter's overrides, PATH=VALUE")
    parser.add_argument("--exporter", default="build/perf/steady_study/poresph_export_jacobian")
    parser.add_argument("--edges", action="store_true", help="sa, lsc-sa: the edge patterns too (3D)")
    parser.add_argument("--gauss-seidel", action="store_true", help="sa, lsc-sa: V(1,1) Gauss-Seidel cycles")
    parser.add_argument("--no-reference", action="store_true",
                        help="skip the direct solution (k is then not compared; for sa and inner)")
    parser.add_argument("--coarse", help="PREFIX of the same scene at twice the spacing (two-grid)")
    args = parser.parse_args()
    if args.block is None:
        args.block = 4 if args.method in ("sa", "lsc-sa") else 8
    system = System(args.prefix, reference=not args.no_reference)
    print(f"{args.prefix}: {system.n} fluid particles, {system.Jb.shape[0]} unknowns, k {system.k:.6e}")
    METHODS[args.method](system, args)


if __name__ == "__main__":
    main()
