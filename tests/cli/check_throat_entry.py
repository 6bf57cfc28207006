"""check_throat_entry.py BELOW_DIR ABOVE_DIR: two runs of input/two_phase/throat_entry.xml, one at a body
force below the throat's entry force and one above it. By perf/throat_entry.py's measures: below, the
non-wetting slug's front stops before the throat's middle and the pressure it holds (Pc(rear) + rho |F| L)
is below the entry pressure 2 sigma cos(theta) / w; above, the front passes the throat's middle and that
pressure is above the entry pressure."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "perf"))
import throat_entry  # noqa: E402

below, above = (throat_entry.measure(run) for run in sys.argv[1:3])
for r in (below, above):
    print(f"{r['run']}: front at {r['front'][-1] / r['spacing']:.2f} spacings (throat from "
          f"{r['throat_mouth'] / r['spacing']:.1f}, middle {r['throat_middle'] / r['spacing']:.1f}), Pc(front) "
          f"{r['front_over_entry']:.4f} of the entry pressure: {r['verdict']}")
assert below["front_over_entry"] < 1, below["front_over_entry"]
assert below["verdict"] == "arrested", below["verdict"]
assert above["front_over_entry"] > 1, above["front_over_entry"]
assert above["verdict"] == "entered", above["verdict"]
print("the slug enters the throat above its entry pressure and not below")
