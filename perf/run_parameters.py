"""What a run's parameters_used.xml says, for the scripts that measure runs: a parameter by its path, a
list of numbers, and the scene's image (found beside the run, here, or among the shipped scenes)."""
import os
import sys

import numpy as np

SHIPPED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "input", "two_phase")


def parameter(root, path, default=None):
    """The value of the parameter at path ("Group/Sublist/Name") under root, or default if given and absent."""
    node = root
    try:
        for name in path.split("/")[:-1]:
            node = next(n for n in node.findall("ParameterList") if n.get("name") == name)
        leaf = next(n for n in node.findall("Parameter") if n.get("name") == path.split("/")[-1])
    except StopIteration:
        if default is None:
            raise
        return default
    return leaf.get("value")


def numbers(text):
    return [float(v) for v in text.strip("{} ").split(",")]


def scene_image(run, root):
    """The run's 2D uint8 image as an array (ny, nx), its solid values and its voxel size. A relative path
    is relative to the scene's folder, which the run does not record: it is tried beside the run, here, and
    in the shipped scenes' folder."""
    shape = [int(v) for v in numbers(parameter(root, "Image/Shape"))]
    path = parameter(root, "Image/File")
    folders = [""] if os.path.isabs(path) else [os.path.join(run, ".."), run, "", SHIPPED]
    found = [os.path.join(f, path) for f in folders if os.path.exists(os.path.join(f, path))]
    if not found:
        sys.exit(f"{run}: cannot find the image {path}")
    values = np.fromfile(found[0], dtype=np.uint8).reshape(shape[1], shape[0])
    solid = set(int(v) for v in numbers(parameter(root, "Image/Solid Values")))
    return values, solid, float(parameter(root, "Image/Voxel Size"))
