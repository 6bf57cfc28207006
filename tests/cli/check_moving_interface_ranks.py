"""check_moving_interface_ranks.py ONE TWO: a moving interface (a drop on a wall) run on one process
(ONE) and on two (TWO, the drop across the processes' boundary): every particle has the same phase
and the same phi to 1e-9 (particles.csv, by id), and each phase's phase_field_volume and saturation
in summary.json agree to 1e-12 of the fluid's. The phase field is whole on each process, advanced
from the velocities of all processes' particles; what differs is the SPH sums' order (round-off)."""
import csv
import json
import os
import sys


def particles(directory):
    with open(os.path.join(directory, "particles.csv")) as f:
        return {int(r["id"]): (int(r["phase"]), float(r["phi"])) for r in csv.DictReader(f) if r["kind"] == "0"}


one, two = sys.argv[1], sys.argv[2]
summaries = [json.load(open(os.path.join(d, "summary.json"))) for d in (one, two)]
assert [s["ranks"] for s in summaries] == [1, 2], [s["ranks"] for s in summaries]
a, b = particles(one), particles(two)
assert a.keys() == b.keys(), "the runs hold other fluid particles"
differ = [i for i in a if a[i][0] != b[i][0]]
assert not differ, f"{len(differ)} particles of other phases, e.g. id {differ[0]}"
ones = sum(p for p, _ in a.values())
assert 0 < ones < len(a), "no interface: the scene holds one phase"
worst = max(abs(a[i][1] - b[i][1]) for i in a)
assert worst <= 1e-9, f"phi differs by {worst}"
volume = sum(p["phase_field_volume"] for p in summaries[0]["phases"])
for p, q in zip(summaries[0]["phases"], summaries[1]["phases"]):
    assert abs(p["phase_field_volume"] - q["phase_field_volume"]) <= 1e-12 * volume, (p, q)
    assert abs(p["saturation"] - q["saturation"]) <= 1e-12, (p, q)
print(f"moving interface as on one process: {ones} of {len(a)} fluid particles of phase 1, phi to {worst:.1e}")
