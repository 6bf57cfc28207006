"""check_mixed_wetting.py DIR FLOOR ANGLE... TOLERANCE: drops side by side on a floor at y = FLOOR (m) whose
solids wet at their own angles (Phases/Contact Angles; input/two_phase/mixed_wet_floor.xml): by the circles
perf/contact_angle.py fits, drop i from the left rests at ANGLE i degrees through itself, within TOLERANCE, and
each phase's volume by the phase field is kept to 1e-10 of the fluid's (phases_history.csv, first row and last)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "perf"))
import contact_angle  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
import check_phase_field_volumes  # noqa: E402

directory, floor = sys.argv[1], float(sys.argv[2])
angles, tolerance = [float(a) for a in sys.argv[3:-1]], float(sys.argv[-1])
points, dx = contact_angle.interface_points(os.path.join(directory, "particles.csv"))
for angle, drop in zip(angles, contact_angle.drops(points, len(angles))):
    measured = contact_angle.measure(drop, dx, floor, 3.0)
    print(f"drop at x = {measured['centre'][0]:.4g} m: {measured['drop_angle']:.2f} degrees through it, set {angle}")
    assert abs(measured["drop_angle"] - angle) < tolerance, (measured["drop_angle"], angle)
check_phase_field_volumes.volumes_kept(directory)
print("each drop at its solid's angle")
