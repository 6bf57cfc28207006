#!/usr/bin/env python3
"""Rasterise a grain scene into a segmented image and write the image scene.

Reads a PoreSPH scene whose solid is Grains (File or Inline), paints every
voxel whose centre lies inside a grain (periodic images included) as solid
(value 255 in PNG and TIFF, 1 in raw volumes; pore 0), and writes the image
beside a copy of the scene whose Grains sublist is replaced by an Image
sublist. The voxel size is the scene's particle spacing over
--voxels-per-spacing, so the same scene can be run from grains and from
images at 2, 4, 8 voxels per spacing and the voxel error told apart from the
particle error (docs/validation.md, section 5).

  rasterise.py SCENE.xml --voxels-per-spacing 4 --format png --output DIR

Formats: png (2D, 8-bit grey, first row at the largest y), tif (2D page or
3D stack, one page per z, first row at the largest y) and raw (x fastest,
then y, then z; uint8). Needs numpy, and Pillow for png and tif.
"""
import argparse
import os
import re
import xml.etree.ElementTree as ET

import numpy as np


def parameter(root, path):
    node = root
    for name in path[:-1]:
        node = next((c for c in node if c.tag == "ParameterList" and c.get("name") == name), None)
        if node is None:
            return None
    return next((c for c in node if c.tag == "Parameter" and c.get("name") == path[-1]), None)


def numbers(text):
    return [float(v) for v in re.findall(r"[-+0-9.eE]+", text)]


def grains_of(root, scene_dir, dim):
    values = []
    inline = parameter(root, ["Grains", "Inline"])
    if inline is not None:
        values += numbers(inline.get("value"))
    grain_file = parameter(root, ["Grains", "File"])
    if grain_file is not None and grain_file.get("value"):
        path = os.path.join(scene_dir, grain_file.get("value"))
        for line in open(path):
            line = line.split("#")[0].strip()
            if line:
                values += [float(v) for v in line.split()]
    return np.array(values).reshape(-1, dim + 1)


def rasterise(cell, grains, voxel):
    """Solid flags, index [i, j(, k)]: voxel centres inside any grain."""
    dim = len(cell)
    shape = [int(round(c / voxel)) for c in cell]
    for c, n in zip(cell, shape):
        if abs(n * voxel - c) > 1e-9 * c:
            raise SystemExit(f"cell side {c} is not a whole number of voxels of {voxel}")
    axes = [(np.arange(n) + 0.5) * voxel for n in shape]
    solid = np.zeros(shape, dtype=bool)
    for g in grains:
        centre, radius = g[:dim], g[dim]
        # The voxels of the grain's bounding box, each at its nearest periodic image.
        ranges = []
        for d in range(dim):
            lo = int(np.floor((centre[d] - radius) / voxel)) - 1
            hi = int(np.ceil((centre[d] + radius) / voxel)) + 1
            ranges.append(np.arange(lo, hi + 1))
        grids = np.meshgrid(*ranges, indexing="ij")
        dist_sq = np.zeros(grids[0].shape)
        for d in range(dim):
            dist_sq += ((grids[d] + 0.5) * voxel - centre[d]) ** 2
        inside = dist_sq < radius * radius
        index = tuple(np.mod(grids[d][inside], shape[d]) for d in range(dim))
        solid[index] = True
    return solid


def write_image(solid, fmt, path):
    dim = solid.ndim
    if fmt == "raw":
        # x fastest: the array's last axis must be x.
        solid.astype(np.uint8).transpose(tuple(range(dim))[::-1]).tofile(path)
        return
    from PIL import Image

    def page(plane):  # plane[i, j] -> rows from the largest y down
        return Image.fromarray((plane.T[::-1, :] * 255).astype(np.uint8), mode="L")

    if fmt == "png":
        if dim != 2:
            raise SystemExit("png holds a 2D image only")
        page(solid).save(path)
    elif fmt == "tif":
        pages = [page(solid)] if dim == 2 else [page(solid[:, :, k]) for k in range(solid.shape[2])]
        pages[0].save(path, save_all=True, append_images=pages[1:])
    else:
        raise SystemExit(f"unknown format {fmt}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--voxels-per-spacing", type=float, required=True)
    ap.add_argument("--spacing", type=float, help="particle spacing (default: the scene's)")
    ap.add_argument("--format", choices=["png", "tif", "raw"], default="raw")
    ap.add_argument("--output", required=True, help="directory for the image and image.xml")
    args = ap.parse_args()

    tree = ET.parse(args.scene)
    root = tree.getroot()
    cell = numbers(parameter(root, ["Domain", "Cell Size"]).get("value"))
    dim = len(cell)
    spacing_node = parameter(root, ["Discretization", "Particle Spacing"])
    spacing = args.spacing or float(spacing_node.get("value"))
    voxel = spacing / args.voxels_per_spacing
    grains = grains_of(root, os.path.dirname(os.path.abspath(args.scene)), dim)
    solid = rasterise(cell, grains, voxel)

    os.makedirs(args.output, exist_ok=True)
    name = f"image.{args.format}"
    write_image(solid, args.format, os.path.join(args.output, name))

    # The scene with Image instead of Grains.
    for node in list(root):
        if node.tag == "ParameterList" and node.get("name") == "Grains":
            root.remove(node)
    spacing_node.set("value", repr(spacing))
    image = ET.SubElement(root, "ParameterList", name="Image")
    ET.SubElement(image, "Parameter", name="File", type="string", value=name)
    ET.SubElement(image, "Parameter", name="Solid Values", type="Array(int)",
                  value="{1}" if args.format == "raw" else "{255}")
    ET.SubElement(image, "Parameter", name="Voxel Size", type="double", value=repr(voxel))
    if args.format == "raw":
        ET.SubElement(image, "Parameter", name="Shape", type="Array(int)",
                      value="{" + ", ".join(str(n) for n in solid.shape) + "}")
    tree.write(os.path.join(args.output, "image.xml"))
    print(f"{os.path.join(args.output, name)}: {' x '.join(map(str, solid.shape))} voxels of {voxel}, "
          f"solid fraction {solid.mean():.6f}")


if __name__ == "__main__":
    main()
