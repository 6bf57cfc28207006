"""Opens a run's particles.xmf and grid.xmf with ParaView's XDMF reader
(pvpython) and prints, for the last frame, the points and the arrays read.

usage: pvpython open_in_paraview.py OUTPUT_DIR
"""
import sys

from paraview.simple import UpdatePipeline, XDMFReader, servermanager

for name in ["particles.xmf", "grid.xmf"]:
    reader = XDMFReader(FileNames=[sys.argv[1] + "/" + name])
    reader.UpdatePipelineInformation()
    times = reader.TimestepValues
    UpdatePipeline(time=times[-1], proxy=reader)
    data = servermanager.Fetch(reader)
    arrays = data.GetPointData()
    names = [arrays.GetArrayName(i) for i in range(arrays.GetNumberOfArrays())]
    assert "velocity" in names and arrays.GetArray("velocity").GetNumberOfComponents() == 3, names
    speed = arrays.GetArray("velocity").GetRange(-1)
    assert speed[1] > 0, "the velocity read back is zero everywhere"
    print(f"{name}: {len(times)} frames, {data.GetNumberOfPoints()} points, {data.GetClassName()}, "
          f"arrays {names}, |v| up to {speed[1]:.3e}")
