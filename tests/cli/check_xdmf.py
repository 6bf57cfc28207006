"""Checks that every HDF5 array an XDMF file names exists with the stated
shape and type, that the meshes hold as many points as their arrays, that
the values are finite and the grid's solid flag is 0 or 1: what ParaView's
XDMF reader relies on.

usage: check_xdmf.py FILE.xmf [FILE.xmf ...]
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np


def check(xmf):
    base = os.path.dirname(os.path.abspath(xmf))
    frames = ET.parse(xmf).getroot().findall("./Domain/Grid/Grid")
    assert frames, f"{xmf}: no frames"
    times = [float(f.find("Time").get("Value")) for f in frames]
    assert times == sorted(times) and len(set(times)) == len(times), f"{xmf}: times not increasing: {times}"
    for frame in frames:
        topology = frame.find("Topology")
        kind = topology.get("TopologyType")
        if kind == "Polyvertex":
            points = int(topology.get("NumberOfElements"))
        else:
            assert kind == "3DCoRectMesh", kind
            points = int(np.prod([int(n) for n in topology.get("Dimensions").split()]))
        for item in frame.iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            file_name, dataset = item.text.strip().split(":")
            dims = tuple(int(n) for n in item.get("Dimensions").split())
            with h5py.File(os.path.join(base, file_name), "r") as f:
                assert dataset in f, f"{file_name} has no {dataset}"
                data = f[dataset]
                assert data.shape == dims, f"{file_name}:{dataset} is {data.shape}, XDMF says {dims}"
                want = "f" if item.get("NumberType") == "Float" else "i"
                assert data.dtype.kind == want and data.dtype.itemsize == int(item.get("Precision")), \
                    f"{file_name}:{dataset} is {data.dtype}"
                tuples = dims[0] if kind == "Polyvertex" else int(np.prod(dims[:3]))
                assert tuples == points, f"{file_name}:{dataset}: {tuples} values for {points} points"
                assert np.all(np.isfinite(data[...])), f"{file_name}:{dataset} holds NaN or Inf"
                if dataset == "/grid_solid":
                    assert set(np.unique(data[...])) <= {0.0, 1.0}
    return len(frames)


if __name__ == "__main__":
    for path in sys.argv[1:]:
        print(f"{path}: {check(path)} frames, layout matches")
    print("xdmf layout ok")
