#!/usr/bin/python3
"""Periodic "blobs" media: segmented images of a given porosity and
correlation length, 2D or 3D, any size, for tests, examples and the
OpenFOAM side by side (docs/openfoam.md).

White noise (one normal value a voxel, numpy's generator seeded by --seed)
is smoothed by a Gaussian of standard deviation --sigma voxels with
wrap-around (a product in Fourier space, so the field is periodic along
every axis), and thresholded at the rank that makes exactly
round(porosity x voxels) voxels pore: the lowest values are pore, the
others solid. --blobiness b sets sigma = mean(shape) / (40 b), as PoreSpy's
`blobs` does; larger b gives smaller grains.

The pore space is checked for percolation along each axis, through the
periodic boundaries, voxels joined by their faces: an axis percolates when a
connected pore cluster reaches its own periodic image along that axis (a
path of pore voxels that leaves the box through one face and comes back
through the opposite one as often as needed). The script says which axes
percolate, and the fraction of the pore space in clusters that percolate
along none (isolated pockets); --require-percolation makes an image that
does not percolate along every axis an error (status 1). Needs SciPy
(python3-scipy) for the check; without it the check is skipped, saying so.

    blobs.py --shape 64 64 64 --porosity 0.35 --sigma 2.5 --seed 1 --output blobs.raw [--scene blobs.xml]

Output by extension (several --output are allowed): .raw (uint8, x
fastest, then y, then z; solid 1, pore 0), .tif/.tiff (one page per z,
first row at the largest y, solid 255), .png (2D, as a TIFF page), .h5
(dataset --dataset, default /image, uint8 stored [z][y][x] so that x is
fastest, solid 1), .npy (bool, index [x, y(, z)], True = solid). --scene
writes a PoreSPH scene for the first output (one particle per voxel, voxel
--voxel-size, creeping flow along x, stopping at a steady k); its image path
is relative to the scene's folder.
"""
import argparse
import json
import os
import sys
import xml.sax.saxutils as saxutils

import numpy as np


def smooth(noise, sigma):
    """The Gaussian filter of standard deviation sigma (voxels) with wrap-around: a product with the
    Gaussian's transform, so that the result is periodic along every axis."""
    shape = noise.shape
    spectrum = np.fft.rfftn(noise)
    factor = np.ones(spectrum.shape)
    for axis, n in enumerate(shape):
        freq = np.fft.rfftfreq(n) if axis == len(shape) - 1 else np.fft.fftfreq(n)
        g = np.exp(-2.0 * (np.pi * sigma * freq) ** 2)
        factor = factor * g.reshape([-1 if a == axis else 1 for a in range(len(shape))])
    return np.fft.irfftn(spectrum * factor, s=shape)


def threshold(field, porosity):
    """Solid flags: the round(porosity * size) lowest values are pore (ties broken by position)."""
    n_pore = int(round(porosity * field.size))
    order = np.argsort(field, axis=None, kind="stable")
    solid = np.ones(field.size, dtype=bool)
    solid[order[:n_pore]] = False
    return solid.reshape(field.shape)


def blobs(shape, porosity, sigma, seed):
    """Solid flags, index [x, y(, z)], with exactly round(porosity * size) pore voxels, and the field."""
    noise = np.random.default_rng(seed).standard_normal(shape)
    field = smooth(noise, sigma)
    return threshold(field, porosity), field


def periodic_percolation(pore):
    """Face-connected pore clusters of a periodic image and the axes along
    which each reaches its own periodic image.

    Returns (labels, wraps): labels[x, y(, z)] the cluster of each pore voxel
    (0 for solid), wraps[c] a boolean array over the axes for cluster c (1..n).
    Clusters are found inside the box (scipy.ndimage.label), then joined
    across every pair of opposite faces by a union-find that keeps each
    cluster's offset, in periods, from its set's root: joining two pieces
    already in one set with a different offset closes a loop around the
    torus, whose non-zero components are the axes that percolate."""
    from scipy import ndimage

    dim = pore.ndim
    labels, n = ndimage.label(pore)
    parent = list(range(n + 1))
    offset = [np.zeros(dim, dtype=np.int64) for _ in range(n + 1)]
    winding = [np.zeros(dim, dtype=bool) for _ in range(n + 1)]

    def find(a):
        path = []
        while parent[a] != a:
            path.append(a)
            a = parent[a]
        root = a
        # Offsets relative to the root, compressing the path from its top down.
        for node in reversed(path):
            if parent[node] != root:
                offset[node] = offset[node] + offset[parent[node]]
                parent[node] = root
        return root

    for axis in range(dim):
        hi = np.take(labels, -1, axis=axis).ravel()
        lo = np.take(labels, 0, axis=axis).ravel()
        shift = np.zeros(dim, dtype=np.int64)
        shift[axis] = 1
        # A pore voxel on the high face touches the pore voxel on the low face of the next period.
        for a, b in set(zip(hi[(hi > 0) & (lo > 0)].tolist(), lo[(hi > 0) & (lo > 0)].tolist())):
            ra, rb = find(a), find(b)
            # position(b) = position(a) + shift, positions in periods relative to the roots.
            if ra != rb:
                parent[rb] = ra
                offset[rb] = offset[a] + shift - offset[b]
                winding[ra] = winding[ra] | winding[rb]
            else:
                loop = offset[a] + shift - offset[b]
                winding[ra] = winding[ra] | (loop != 0)
    roots = np.array([find(c) for c in range(n + 1)])
    wraps = np.array([winding[roots[c]] for c in range(n + 1)])
    joined = roots[labels]
    joined[labels == 0] = 0
    return joined, wraps


def percolation_report(solid):
    """Which axes percolate, and the pore fraction in isolated clusters; None without SciPy."""
    try:
        labels, wraps = periodic_percolation(~solid)
    except ImportError:
        return None
    pore_voxels = int((~solid).sum())
    axes = wraps[labels[labels > 0]]  # per pore voxel: the axes its cluster percolates along
    percolates = [bool(axes[:, d].any()) for d in range(solid.ndim)] if pore_voxels else [False] * solid.ndim
    isolated = float((~axes.any(axis=1)).sum() / pore_voxels) if pore_voxels else 0.0
    return {"percolates": dict(zip("xyz", percolates)), "isolated_pore_fraction": isolated,
            "clusters": int(len(np.unique(labels[labels > 0])))}


def write(solid, path, dataset="/image"):
    dim = solid.ndim
    ext = os.path.splitext(path)[1].lower()
    reverse = tuple(range(dim))[::-1]
    if ext == ".raw":
        np.ascontiguousarray(solid.astype(np.uint8).transpose(reverse)).tofile(path)
    elif ext == ".npy":
        np.save(path, solid)
    elif ext in (".h5", ".hdf5"):
        import h5py
        with h5py.File(path, "w") as f:
            f.create_dataset(dataset, data=solid.astype(np.uint8).transpose(reverse))
    elif ext in (".tif", ".tiff", ".png"):
        from PIL import Image

        def page(plane):  # plane[i, j] -> rows from the largest y down
            return Image.fromarray((plane.T[::-1, :] * 255).astype(np.uint8), mode="L")

        if ext == ".png":
            if dim != 2:
                raise SystemExit("png holds a 2D image only")
            page(solid).save(path)
        else:
            pages = [page(solid)] if dim == 2 else [page(solid[:, :, k]) for k in range(solid.shape[2])]
            pages[0].save(path, save_all=True, append_images=pages[1:])
    else:
        raise SystemExit(f"{path}: unknown format (raw, tif, png, h5, npy)")


def scene_xml(image_path, scene_path, shape, voxel, steady_tolerance, name, dataset="/image"):
    """A PoreSPH scene for the image: one particle per voxel, nu = 1e-6, creeping flow along x."""
    dim = len(shape)
    ext = os.path.splitext(image_path)[1].lower()
    if ext not in (".raw", ".tif", ".tiff", ".png", ".h5", ".hdf5"):
        raise SystemExit(f"PoreSPH reads .raw, .tif, .png and .h5 images, not {ext}")
    rel = os.path.relpath(os.path.abspath(image_path), os.path.dirname(os.path.abspath(scene_path)))
    cell = ", ".join(repr(n * voxel) for n in shape)
    force = ", ".join(["1.0e-9"] + ["0.0"] * (dim - 1))
    image = [("File", "string", rel)]
    if ext == ".raw":
        image += [("Shape", "Array(int)", "{" + ", ".join(map(str, shape)) + "}"), ("Type", "string", "uint8")]
    if ext in (".h5", ".hdf5"):
        image += [("Dataset", "string", dataset)]
    image += [("Solid Values", "Array(int)", "{1}" if ext in (".raw", ".h5", ".hdf5") else "{255}"),
              ("Voxel Size", "double", repr(voxel))]
    q = saxutils.quoteattr

    def params(items):
        return "\n".join(f"    <Parameter name={q(n)} type={q(t)} value={q(v)}/>" for n, t, v in items)

    return f"""<!-- A periodic blobs image made by perf/blobs.py ({name}): {' x '.join(map(str, shape))} voxels
     of {voxel!r} m, one particle per voxel, nu = 1e-6 m^2/s, F = 1e-9 m/s^2 along x
     (creeping flow); the run stops by itself at a steady k. -->
<ParameterList name="PoreSPH">
  <ParameterList name="Scene">
{params([("Name", "string", "blobs")])}
  </ParameterList>
  <ParameterList name="Domain">
{params([("Cell Size", "Array(double)", "{" + cell + "}")])}
  </ParameterList>
  <ParameterList name="Fluid">
{params([("Density", "double", "1000.0"), ("Kinematic Viscosity", "double", "1.0e-6"),
         ("Body Force", "Array(double)", "{" + force + "}")])}
  </ParameterList>
  <ParameterList name="Discretization">
{params([("Particle Spacing", "double", repr(voxel))])}
  </ParameterList>
  <ParameterList name="Image">
{params(image)}
  </ParameterList>
  <ParameterList name="Permeability">
{params([("Steady Tolerance", "double", repr(steady_tolerance))])}
  </ParameterList>
  <ParameterList name="Run">
{params([("End Time", "double", "1.0e7")])}
  </ParameterList>
</ParameterList>
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shape", type=int, nargs="+", required=True, help="NX NY [NZ] voxels")
    ap.add_argument("--porosity", type=float, required=True)
    size = ap.add_mutually_exclusive_group(required=True)
    size.add_argument("--sigma", type=float, help="Gaussian's standard deviation, voxels")
    size.add_argument("--blobiness", type=float, help="sigma = mean(shape) / (40 blobiness), as PoreSpy")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--output", action="append", default=[], help="image file(s), format by extension")
    ap.add_argument("--dataset", default="/image", help="HDF5 dataset path (default /image)")
    ap.add_argument("--scene", help="also write a PoreSPH scene for the first output")
    ap.add_argument("--voxel-size", type=float, default=1e-3, help="scene: voxel side in m (default 1e-3)")
    ap.add_argument("--steady-tolerance", type=float, default=1e-3, help="scene: Permeability/Steady Tolerance")
    ap.add_argument("--require-percolation", action="store_true",
                    help="exit 1 unless the pore space percolates along every axis")
    ap.add_argument("--json", help="write the image's facts (porosity, sigma, percolation) here")
    args = ap.parse_args()

    if len(args.shape) not in (2, 3) or min(args.shape) < 1:
        raise SystemExit("--shape takes 2 or 3 positive sizes")
    if not 0.0 < args.porosity < 1.0:
        raise SystemExit("--porosity must lie in (0, 1)")
    sigma = args.sigma if args.sigma is not None else float(np.mean(args.shape)) / (40.0 * args.blobiness)
    if sigma <= 0:
        raise SystemExit("sigma must be positive")
    solid, _ = blobs(tuple(args.shape), args.porosity, sigma, args.seed)
    for path in args.output:
        write(solid, path, args.dataset)

    porosity = 1.0 - float(solid.mean())
    facts = {"shape": args.shape, "porosity": porosity, "porosity_asked": args.porosity, "sigma": sigma,
             "seed": args.seed, "outputs": args.output}
    perc = percolation_report(solid)
    name = f"porosity {args.porosity:g}, sigma {sigma:g} voxels, seed {args.seed}"
    print(f"blobs: {' x '.join(map(str, args.shape))} voxels, {name}: porosity {porosity:.6f} "
          f"({int((~solid).sum())} pore voxels)")
    if perc is None:
        print("blobs: percolation not checked (needs SciPy: apt-get install python3-scipy)")
    else:
        facts["percolation"] = perc
        along = [a for a, p in perc["percolates"].items() if p]
        print(f"blobs: the pore space percolates along {', '.join(along) if along else 'no axis'}"
              f"{'' if len(along) == solid.ndim else ' (not along ' + ', '.join(a for a, p in perc['percolates'].items() if not p) + ')'}"
              f"; {100 * perc['isolated_pore_fraction']:.2f} % of it in isolated pockets, {perc['clusters']} clusters")
    if args.scene:
        if not args.output:
            raise SystemExit("--scene needs an --output image")
        with open(args.scene, "w") as f:
            f.write(scene_xml(args.output[0], args.scene, args.shape, args.voxel_size, args.steady_tolerance, name,
                              args.dataset))
        print(f"blobs: scene {args.scene}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(facts, f, indent=2)
    if args.require_percolation and (perc is None or not all(perc["percolates"].values())):
        print("blobs: the pore space does not percolate along every axis", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
