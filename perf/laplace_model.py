#!/usr/bin/python3
"""A model of the 2D drop of input/two_phase/laplace_drop.xml on its own
lattice equations, to choose the surface tension's kernels
(docs/method.md, "Surface tension"). On a periodic lattice of fixed
particles the SPH pressure gradient, continuity and Morris viscous sums are
convolutions; the steady Stokes flow of a given force,
    -G p / rho + nu L v + f = 0,   G . v = 0,
is then solved exactly per Fourier mode (the convective term, of order v^2,
and the equation of state's 1/rho^2 are left out). f is the code's force
sigma kappa n / rho (physics/SurfaceTension.hpp) with the colour, h_c and
h_s given; the model reports the pressure jump (mean p at r < R - 3h less
r > R + 3h) against sigma / R and max |v| / (sigma / mu).

    perf/laplace_model.py [--radii 10 20 40]

Lengths in spacings, h = dx = 1, sigma = rho = nu = 1. numpy only.
"""
import argparse

import numpy as np

ALPHA = 7 / (478 * np.pi)  # the 2D quintic's normalisation at h = 1


def shape(s):
    t3, t2, t1 = (np.maximum(k - s, 0) for k in (3, 2, 1))
    return t3 ** 5 - 6 * t2 ** 5 + 15 * t1 ** 5


def dshape(s):
    t3, t2, t1 = (np.maximum(k - s, 0) for k in (3, 2, 1))
    return -5 * t3 ** 4 + 30 * t2 ** 4 - 75 * t1 ** 4


def offsets(h):
    m = int(np.ceil(3 * h))
    return [(i, j) for i in range(-m, m + 1) for j in range(-m, m + 1) if 0 < i * i + j * j < 9 * h * h]


def at(f, i, j):
    """f at a + (i, j), periodic."""
    return np.roll(np.roll(f, -i, 0), -j, 1)


def gradient(c, h):
    a, n = ALPHA / h ** 2, np.zeros(c.shape + (2,))
    for i, j in offsets(h):
        F = a / h * dshape(np.hypot(i, j) / h) / np.hypot(i, j)
        n[..., 0] += (at(c, i, j) - c) * F * -i
        n[..., 1] += (at(c, i, j) - c) * F * -j
    return n


def curvature(n, h):
    """Morris: -div(n/|n|) over the particles with |n| > 0.01/h, over their Shepard sum."""
    a = ALPHA / h ** 2
    length = np.hypot(n[..., 0], n[..., 1])
    counts = (length > 0.01 / h).astype(float)
    unit = np.where(length[..., None] > 0, n / np.maximum(length, 1e-300)[..., None], 0)
    divergence, shepard = np.zeros(length.shape), counts * a * shape(0.0)
    for i, j in offsets(h):
        r = np.hypot(i, j)
        both = np.minimum(counts, at(counts, i, j))
        d = at(unit, i, j) - unit
        divergence += both * a / h * dshape(r / h) / r * (d[..., 0] * -i + d[..., 1] * -j)
        shepard += both * a * shape(r / h)
    return np.where(counts > 0, -divergence / np.maximum(shepard, 1e-300), 0), length * counts


def averaged(kappa, weight, h):
    a = ALPHA / h ** 2
    total, weights = a * shape(0.0) * kappa * weight, a * shape(0.0) * weight
    for i, j in offsets(h):
        W = a * shape(np.hypot(i, j) / h)
        total += W * at(kappa * weight, i, j)
        weights += W * at(weight, i, j)
    return np.where(weights > 0, total / np.maximum(weights, 1e-300), 0)


def stokes(f, L):
    k = 2 * np.pi * np.fft.fftfreq(L)
    kx, ky = np.meshgrid(k, k, indexing="ij")
    G = [np.zeros((L, L), complex), np.zeros((L, L), complex)]
    lap = np.zeros((L, L), complex)
    for i, j in offsets(1.0):
        F, e = ALPHA * dshape(np.hypot(i, j)) / np.hypot(i, j), np.exp(1j * (kx * i + ky * j))
        G[0] += -i * F * e
        G[1] += -j * F * e
        lap += 2 * F * (1 - e)
    fh = [np.fft.fft2(f[..., d]) for d in range(2)]
    GG = G[0] * G[0] + G[1] * G[1]
    GG[0, 0], lap[0, 0] = 1, 1
    p = (G[0] * fh[0] + G[1] * fh[1]) / GG
    p[0, 0] = 0
    v = [(G[d] * p - fh[d]) / lap for d in range(2)]
    for d in range(2):
        v[d][0, 0] = 0
    return np.real(np.fft.ifft2(p)), np.stack([np.real(np.fft.ifft2(x)) for x in v], -1)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--radii", type=float, nargs="+", default=[10, 20, 40])
    args = parser.parse_args()
    print("| R / dx | colour | h_c / h | h_s / h | jump / (sigma/R) - 1 (%) | max abs(v) mu / sigma |")
    print("|---|---|---|---|---|---|")
    for R in args.radii:
        L = int(4 * R)
        x = np.arange(L) + 0.5
        X, Y = np.meshgrid(x, x, indexing="ij")
        r = np.hypot(X - L / 2, Y - L / 2)
        sub = (np.arange(16) + 0.5) / 16 - 0.5
        fraction = sum(np.hypot(X + u - L / 2, Y + w - L / 2) < R for u in sub for w in sub) / 256.0
        for name, c in (("phase", (r < R).astype(float)), ("volume fraction", fraction)):
            n = gradient(c, 1.0)
            for hc, hs in ((1, 0), (2, 0), (2, 3), (2, 4), (2, 6), (3, 0)):
                kappa, weight = curvature(gradient(c, hc), hc)
                if hs:
                    kappa = averaged(kappa, weight, hs)
                p, v = stokes(kappa[..., None] * n, L)
                jump = p[r < R - 3].mean() - p[r > R + 3].mean()
                print(f"| {R:g} | {name} | {hc} | {hs or '-'} | {100 * (jump * R - 1):+.2f} | {np.abs(v).max():.1e} |",
                      flush=True)


if __name__ == "__main__":
    main()
