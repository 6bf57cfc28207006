"""check_contact_angle.py DIR ANGLE TOLERANCE: a drop on a wall (input/two_phase/drop_on_wall.xml)
has settled at ANGLE degrees through the drop, within TOLERANCE, by the circle that
perf/contact_angle.py fits to its interface; the interface is a circle to a tenth of a spacing;
each phase's volume by the phase field (phases_history.csv, first row and last) is conserved to
1e-10 of the cell's fluid volume, and summary.json reports the last."""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "perf"))
import contact_angle  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
import check_phase_field_volumes  # noqa: E402

directory, angle, tolerance = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
points, dx = contact_angle.interface_points(os.path.join(directory, "particles.csv"))
measured = contact_angle.measure(points, dx, 0.0, 3.0)
drop, centre, radius = measured["drop_angle"], measured["centre"], measured["radius"]
above = points[points[:, 1] > 3 * dx]
off = max(abs(math.dist(p, centre) - radius) for p in above) / dx
assert abs(drop - angle) < tolerance, f"the drop's angle is {drop:.2f} degrees, set {angle}"
assert off < 0.1, f"the interface is {off:.3f} spacings off its circle"

rows = check_phase_field_volumes.volumes_kept(directory)
print(f"drop at its contact angle: {drop:.2f} degrees (set {angle}), {len(above)} interface points within "
      f"{off:.3f} spacings of a circle, phase volumes kept over {rows[-1]['step']} steps")
