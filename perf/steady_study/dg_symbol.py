#!/usr/bin/env python3
"""How well the wide Laplacian models DG in the interior of a lattice: the
symbols, as functions of the wavenumber k, of DG = D Q^-1 G with Q constant
(a cell with no grains) and of the wide Laplacian (points two apart), for
the quintic kernel of PoreSPH at h = ratio * dx.

    perf/steady_study/dg_symbol.py [--ratio 1.0] [--points 48]

The gradient's symbol along axis d is g_d(k) = sum_r W'(|r|) r_d / |r|
sin(k . r) over the lattice offsets r within the support; DG's is
sum_d g_d(k)^2, the wide Laplacian's sum_d sin^2(k_d) (in units of dx).
Both vanish at the 2^Dim corners of the Brillouin zone (k_d in {0, pi}),
where the lattice's sign patterns live. The script prints their ratio
rho(k), normalised to 1 at k -> 0: over the whole zone, at each corner
(just off it), and within each corner's region of the zone (the points
nearer that corner than any other), where one weight per sign pattern can
fix the level but not the spread."""
import argparse
import itertools

import numpy as np


def quintic_derivative(q):
    """dW/dq of the quintic spline (support 3), up to its constant."""
    t = lambda a: np.maximum(a, 0.0)
    return -5 * t(3 - q) ** 4 + 30 * t(2 - q) ** 4 - 75 * t(1 - q) ** 4


def ratio_of(k, dim, h):
    """rho(k) = DG(k) / wide Laplacian(k), unnormalised; k: (points, dim)."""
    reach = int(np.floor(3 * h))
    g = np.zeros((len(k), dim))
    for n in itertools.product(range(-reach, reach + 1), repeat=dim):
        r = np.linalg.norm(n)
        if r == 0 or r >= 3 * h: continue
        w = quintic_derivative(r / h) / r
        s = np.sin(k @ np.array(n, dtype=float))
        for d in range(dim): g[:, d] += w * n[d] * s
    return (g ** 2).sum(1) / (np.sin(k) ** 2).sum(1)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--ratio", type=float, default=1.0, help="h / dx")
    parser.add_argument("--points", type=int, default=48, help="wavenumbers per axis")
    args = parser.parse_args()
    for dim in (2, 3):
        n = args.points
        axis = np.linspace(-np.pi, np.pi, n, endpoint=False) + np.pi / n  # no point on a corner
        k = np.array(np.meshgrid(*([axis] * dim), indexing="ij")).reshape(dim, -1).T
        smooth = ratio_of(np.full((1, dim), 1e-3), dim, args.ratio)[0]
        rho = ratio_of(k, dim, args.ratio) / smooth
        print(f"{dim}D: rho over the zone {rho.min():.3g} to {rho.max():.3g}, "
              f"quantiles 1/10/50/90 % {', '.join(f'{q:.3g}' for q in np.quantile(rho, [0.01, 0.1, 0.5, 0.9]))}")
        corner = (np.abs(k) > np.pi / 2).astype(int)  # the nearest corner, per axis 0 or pi
        for c in itertools.product([0, 1], repeat=dim):
            at = np.array([[np.pi - 1e-3 if ci else 1e-3 for ci in c]])
            inside = np.all(corner == np.array(c), axis=1)
            spread = rho[inside].max() / rho[inside].min()
            print(f"  corner {c}: rho {ratio_of(at, dim, args.ratio)[0] / smooth:.3g}, "
                  f"in its region {rho[inside].min():.3g} to {rho[inside].max():.3g} (spread {spread:.3g})")


if __name__ == "__main__":
    main()
