#!/usr/bin/python3
"""An independent reference for the drag and permeability of cubic arrays of
spheres (simple, body-centred and face-centred cubic): a spectral boundary-
integral solution of Stokes flow past one sphere in a periodic Bravais
lattice, the formulation of Hasimoto (1959) and Zick & Homsy (1982), written
here from the equations, not from their tables.

    perf/periodic_stokes_spheres.py [--lattice sc|bcc|fcc] [--fractions 0.125 ...]
                                    [--degrees 12 16 24 32] [--out build/periodic-stokes]

The method, with viscosity 1 and the cubic cell of side 1:

- The velocity is u(x) = U + sum over the spheres of the single layer
  integral of G(x - y) f(y) over the sphere's surface, G the periodic
  Stokeslet with zero mean over the cell: the flow of point forces on the
  lattice with the mean pressure gradient that balances them. Inside the
  spheres u = 0, so U is the mean over the whole cell, the superficial
  velocity. No slip, u = 0 on the surface, makes this a first-kind equation
  for the force density f, and F = the integral of f is each sphere's force.
- G is summed by Ewald's method in Hasimoto's split: real space,
  (1/8pi) [erfc(xi r)/r (I + r r / r^2) + 2 xi/sqrt(pi) exp(-xi^2 r^2) r r / r^2]
  over the lattice's images; reciprocal space,
  (1/V) sum over k != 0 of exp(-k^2/4xi^2) [I/k^2 - (1 + k^2/4xi^2) k k / k^4] cos(k.r);
  and -I / (4 xi^2 V), which makes the mean zero. A result must not depend
  on xi: `--check` compares two values of it.
- f is expanded in spherical harmonics up to degree p and the equation is
  projected on the same harmonics (Galerkin), with Gauss-Legendre by
  trapezoidal quadrature on the sphere. The free-space 1/r singularity is
  integrated in polar coordinates about each quadrature point, where the
  integrand is smooth; the rest of G is smooth on the sphere and needs no
  special care. The error then falls faster than any power of p while the
  spheres are apart; near contact the force concentrates in the throats
  and needs higher degrees.

K = -F_x / (6 pi a U) is Zick & Homsy's dimensionless drag per sphere, and
k / a^2 = 2 / (9 phi K), phi the solid fraction, as in PoreSPH's summary.
Writes periodic_stokes_<lattice>.csv into --out and prints a Markdown table:
K and k/a^2 at each degree, and the change from the degree before.
"""
import argparse
import csv
import math
import os
import sys
import time

import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy.special import erf, erfc, sph_harm

# Primitive vectors (rows) of the three lattices, in units of the cubic
# cell's side; their cells hold one sphere, the cubic cell 1, 2 or 4.
PRIMITIVE = {
    "sc": np.eye(3),
    "bcc": 0.5 * np.array([[-1.0, 1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, -1.0]]),
    "fcc": 0.5 * np.array([[0.0, 1.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 0.0]]),
}
# Ewald sums are cut where their terms fall below this, relative to the largest.
EWALD_TOLERANCE = 1e-14


class PeriodicStokeslet:
    """The zero-mean periodic Stokeslet of a Bravais lattice (viscosity 1),
    split into its real-space and reciprocal-space parts."""

    def __init__(self, primitive, xi_scale=4.0):
        self.primitive = primitive
        self.volume = abs(np.linalg.det(primitive))
        self.xi = xi_scale / self.volume ** (1 / 3)
        reach = math.sqrt(-math.log(EWALD_TOLERANCE))
        self.real_cut = reach / self.xi
        self.reciprocal_cut = 2 * self.xi * (reach + 0.5)
        reciprocal = 2 * math.pi * np.linalg.inv(primitive).T
        self.images = self._lattice(primitive, self.real_cut + 2.0 * self.volume ** (1 / 3))
        ks = self._lattice(reciprocal, self.reciprocal_cut)
        ks = ks[np.linalg.norm(ks, axis=1) > 0]
        # k and -k give the same cosine: keep one of each pair, doubled.
        first = np.array([next((c for c in k if abs(c) > 1e-12), 0.0) > 0 for k in ks])
        self.wavevectors = ks[first]
        k2 = np.sum(self.wavevectors**2, axis=1)
        s = k2 / (4 * self.xi**2)
        kk = self.wavevectors[:, :, None] * self.wavevectors[:, None, :]
        self.reciprocal_weights = (2 / self.volume) * np.exp(-s)[:, None, None] * (
            np.eye(3)[None] / k2[:, None, None] - ((1 + s) / k2**2)[:, None, None] * kk)
        self.mean_correction = -1.0 / (4 * self.xi**2 * self.volume)

    @staticmethod
    def _lattice(vectors, radius):
        span = int(math.ceil(radius / min(np.linalg.norm(vectors, axis=1)) * 2)) + 1
        ijk = np.array(np.meshgrid(*[np.arange(-span, span + 1)] * 3, indexing="ij")).reshape(3, -1).T
        points = ijk @ vectors
        return points[np.linalg.norm(points, axis=1) <= radius]

    def real_space(self, r, self_image):
        """Sum over images n of the screened Stokeslet at r + n (r: ... x 3);
        with self_image the free-space Stokeslet is taken out of the n = 0 term."""
        total = np.zeros(r.shape[:-1] + (3, 3))
        rmax = np.max(np.linalg.norm(r.reshape(-1, 3), axis=1)) if r.size else 0.0
        xi = self.xi
        for n in self.images:
            if np.linalg.norm(n) - rmax > self.real_cut:
                continue
            s = r + n
            d = np.linalg.norm(s, axis=-1)
            zero = d == 0
            dsafe = np.where(zero, 1.0, d)
            sh = s / dsafe[..., None]
            ss = sh[..., :, None] * sh[..., None, :]
            gauss = 2 * xi / math.sqrt(math.pi) * np.exp(-(xi * d) ** 2)
            if self_image and not np.any(n):
                # erfc/r - 1/r = -erf/r, finite at r = 0 with the limit -2 xi/sqrt(pi) I.
                a = -erf(xi * d) / dsafe
                term = a[..., None, None] * (np.eye(3) + ss) + gauss[..., None, None] * ss
                term[zero] = -2 * xi / math.sqrt(math.pi) * np.eye(3)
            else:
                a = erfc(xi * d) / dsafe
                term = a[..., None, None] * (np.eye(3) + ss) + gauss[..., None, None] * ss
            total += term / (8 * math.pi)
        return total

    def reciprocal(self, r):
        phase = np.cos(r @ self.wavevectors.T)
        return np.einsum("...k,kab->...ab", phase, self.reciprocal_weights)

    def regular_part(self, r):
        """G(r) minus the free-space Stokeslet: smooth for |r| below the nearest image."""
        return self.real_space(r, True) + self.reciprocal(r) + self.mean_correction * np.eye(3)

    def __call__(self, r):
        return self.real_space(r, False) + self.reciprocal(r) + self.mean_correction * np.eye(3)


def free_stokeslet(r):
    d = np.linalg.norm(r, axis=-1)
    rr = r[..., :, None] * r[..., None, :]
    return (np.eye(3) / d[..., None, None] + rr / (d**3)[..., None, None]) / (8 * math.pi)


def harmonics(degree, polar, azimuth):
    """Complex spherical harmonics Y_lm, l <= degree, at the points given; the
    last axis is l^2 + l + m."""
    columns = []
    for l in range(degree + 1):
        for m in range(-l, l + 1):
            columns.append(sph_harm(m, l, azimuth, polar))
    return np.stack(columns, axis=-1)


class SphereGrid:
    """Gauss-Legendre (in cos theta) by trapezoidal quadrature on a sphere of
    radius a, exact for products of harmonics up to degree p."""

    def __init__(self, degree, a):
        self.degree, self.a = degree, a
        t, wt = leggauss(degree + 1)
        self.polar = np.arccos(t)
        self.rings, self.per_ring = degree + 1, 2 * degree + 2
        self.azimuth = 2 * math.pi * np.arange(self.per_ring) / self.per_ring
        P, A = np.meshgrid(self.polar, self.azimuth, indexing="ij")
        self.points = a * np.stack([np.sin(P) * np.cos(A), np.sin(P) * np.sin(A), np.cos(P)], axis=-1).reshape(-1, 3)
        self.weights = (a**2 * wt[:, None] * np.full(self.per_ring, 2 * math.pi / self.per_ring)).reshape(-1)
        self.Y = harmonics(degree, P.reshape(-1), A.reshape(-1))


def free_single_layer(grid):
    """Galerkin matrix of the free-space single layer on one sphere:
    entry [(alpha, lm), (beta, l'm')] = integral of conj(Y_lm(x)) G_ab(x - y) Y_l'm'(y).
    The inner integral is taken in polar coordinates about each x (smooth
    there); x on one ring differ by a rotation about z, so it is done once per ring."""
    p, a = grid.degree, grid.a
    n_inner = p + 24
    u, wu = leggauss(n_inner)
    tp = math.pi * (u + 1) / 2
    wtp = math.pi / 2 * wu
    n_az = 2 * n_inner
    ap = 2 * math.pi * np.arange(n_az) / n_az
    TP, AP = np.meshgrid(tp, ap, indexing="ij")
    TP, AP = TP.reshape(-1), AP.reshape(-1)
    wq = a**2 * np.sin(TP) * np.repeat(wtp, n_az) * (2 * math.pi / n_az)
    nb = (p + 1) ** 2
    result = np.zeros((3, nb, 3, nb), dtype=complex)
    m_of = np.concatenate([np.arange(-l, l + 1) for l in range(p + 1)])
    for ring, theta in enumerate(grid.polar):
        axis = np.array([math.sin(theta), 0.0, math.cos(theta)])
        e1 = np.array([math.cos(theta), 0.0, -math.sin(theta)])
        e2 = np.array([0.0, 1.0, 0.0])
        y = a * (np.cos(TP)[:, None] * axis + np.sin(TP)[:, None] * (np.cos(AP)[:, None] * e1 + np.sin(AP)[:, None] * e2))
        x0 = a * axis
        G = free_stokeslet(x0 - y) * wq[:, None, None]
        Yq = harmonics(p, np.arccos(np.clip(y[:, 2] / a, -1, 1)), np.arctan2(y[:, 1], y[:, 0]))
        M = np.einsum("qab,ql->abl", G, Yq)
        for k, phi in enumerate(grid.azimuth):
            i = ring * grid.per_ring + k
            c, s = math.cos(phi), math.sin(phi)
            Rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
            T = np.einsum("ag,gdl,bd->abl", Rz, M, Rz) * np.exp(1j * m_of * phi)[None, None, :]
            result += grid.weights[i] * np.einsum("l,abm->albm", np.conj(grid.Y[i]), T)
    return result


def regular_single_layer(grid, stokeslet):
    """Galerkin matrix of the smooth rest of the periodic Stokeslet, same layout."""
    x, w, Y = grid.points, grid.weights, grid.Y
    N, nb = len(x), Y.shape[1]
    wY = w[:, None] * Y
    real = stokeslet.real_space(x[:, None, :] - x[None, :, :], True)  # N x N x 3 x 3
    P = real.transpose(0, 2, 3, 1).reshape(N * 9, N) @ wY
    result = (np.conj(wY).T @ P.reshape(N, 9 * nb)).reshape(nb, 3, 3, nb).transpose(1, 0, 2, 3)
    # Reciprocal part: cos(k.(x - y)) = cos kx cos ky + sin kx sin ky, a sum of products.
    phase = x @ stokeslet.wavevectors.T
    Cc = np.conj(wY).T @ np.cos(phase)  # nb x K
    Cs = np.conj(wY).T @ np.sin(phase)
    for alpha in range(3):
        for beta in range(3):
            weight = stokeslet.reciprocal_weights[:, alpha, beta]
            result[alpha, :, beta, :] += (Cc * weight) @ np.conj(Cc).T + (Cs * weight) @ np.conj(Cs).T
    mean = np.conj(wY).T @ np.ones(N)
    for alpha in range(3):
        result[alpha, :, alpha, :] += stokeslet.mean_correction * np.outer(mean, np.conj(mean))
    return result


def touching_fraction(lattice):
    """The solid fraction at which neighbouring spheres touch: pi/6 (SC),
    0.680 (BCC), 0.740 (FCC)."""
    primitive = PRIMITIVE[lattice]
    nearest = min(np.linalg.norm(n) for n in PeriodicStokeslet._lattice(primitive, 2.0) if np.any(n))
    return 4 / 3 * math.pi * (nearest / 2) ** 3 / abs(np.linalg.det(primitive))


def check_fraction(lattice, phi):
    """Raises ValueError unless the spheres at solid fraction phi are apart."""
    touching = touching_fraction(lattice)
    if not 0 < phi < touching:
        raise ValueError(f"{lattice}: the solid fraction must lie in (0, {touching:.4f}), where the spheres "
                         f"touch; {phi} was given")


def drag(lattice, phi, degree, xi_scale=4.0):
    """Zick & Homsy's K for the lattice at solid fraction phi, harmonics up
    to `degree`; also the sphere's radius and its force (U = 1 along x)."""
    primitive = PRIMITIVE[lattice]
    stokeslet = PeriodicStokeslet(primitive, xi_scale)
    check_fraction(lattice, phi)
    a = (3 * phi * stokeslet.volume / (4 * math.pi)) ** (1 / 3)
    grid = SphereGrid(degree, a)
    A = free_single_layer(grid) + regular_single_layer(grid, stokeslet)
    nb = grid.Y.shape[1]
    A = A.reshape(3 * nb, 3 * nb)
    U = np.array([1.0, 0.0, 0.0])
    mean = np.conj(grid.weights[:, None] * grid.Y).T @ np.ones(len(grid.points))
    rhs = -(U[:, None] * mean[None, :]).reshape(-1)
    coefficients = np.linalg.solve(A, rhs).reshape(3, nb)
    force = (coefficients @ (grid.weights[:, None] * grid.Y).T.sum(axis=1)).real
    K = -force[0] / (6 * math.pi * a * U[0])
    return K, a, force


def check_ewald(lattice):
    """The periodic Stokeslet must not depend on the split parameter, and its
    regular part must equal it minus the free-space Stokeslet."""
    rng = np.random.default_rng(1)
    r = rng.uniform(-0.3, 0.3, size=(20, 3))
    g1 = PeriodicStokeslet(PRIMITIVE[lattice], 3.0)(r)
    g2 = PeriodicStokeslet(PRIMITIVE[lattice], 5.0)(r)
    reg = PeriodicStokeslet(PRIMITIVE[lattice], 4.0).regular_part(r) + free_stokeslet(r)
    return np.max(np.abs(g1 - g2)) / np.max(np.abs(g1)), np.max(np.abs(reg - g1)) / np.max(np.abs(g1))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lattice", choices=sorted(PRIMITIVE), default="sc")
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.027, 0.064, 0.125, 0.216, 0.343, 0.45])
    parser.add_argument("--degrees", type=int, nargs="+", default=[12, 16, 24, 32])
    parser.add_argument("--xi", type=float, default=4.0, help="Ewald split, times V^(-1/3)")
    parser.add_argument("--check", action="store_true", help="only check the Ewald sum and exit")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                                   "build", "periodic-stokes"))
    args = parser.parse_args()
    if args.check:
        split, regular = check_ewald(args.lattice)
        print(f"{args.lattice}: relative change with the Ewald split {split:.2e}, regular part {regular:.2e}")
        return 0 if split < 1e-10 and regular < 1e-10 else 1
    for phi in args.fractions:
        try:
            check_fraction(args.lattice, phi)
        except ValueError as error:
            parser.error(f"--fractions: {error}")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for phi in args.fractions:
        previous = None
        for degree in args.degrees:
            start = time.time()
            K, a, force = drag(args.lattice, phi, degree, args.xi)
            change = (K / previous - 1) if previous else float("nan")
            previous = K
            rows.append(dict(lattice=args.lattice, solid_fraction=phi, degree=degree, radius=a, drag_K=K,
                             k_over_a2=2 / (9 * phi * K), change=change, force_y=force[1], force_z=force[2],
                             seconds=time.time() - start))
            print(f"{args.lattice} phi = {phi:g} p = {degree}: K = {K:.8g} ({change:+.2e}), "
                  f"{time.time() - start:.0f} s", file=sys.stderr, flush=True)
            with open(os.path.join(args.out, f"periodic_stokes_{args.lattice}.csv"), "w", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=list(rows[0]))
                writer.writeheader()
                writer.writerows(rows)
    print("| phi | degree | K | k/a^2 | change from the degree before |")
    print("|---|---|---|---|---|")
    for r in rows:
        change = "" if math.isnan(r["change"]) else f"{r['change']:+.1e}"
        print(f"| {r['solid_fraction']:g} | {r['degree']} | {r['drag_K']:.6g} | {r['k_over_a2']:.6g} | {change} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
