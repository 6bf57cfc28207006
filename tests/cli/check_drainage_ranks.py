"""check_drainage_ranks.py ONE TWO: a scene with phase 1 placed by drainage, run on one process
(ONE) and on two (TWO): each particle has the same phase (particles.csv, by id), drainage.csv is
the same text, summary.json's drainage is the same, and each phase's superficial velocity (the
body force on phase 1 alone) the same to round-off."""
import csv
import json
import os
import sys


def phases(directory):
    with open(os.path.join(directory, "particles.csv")) as f:
        return {int(row["id"]): int(row["phase"]) for row in csv.DictReader(f)}


one, two = sys.argv[1], sys.argv[2]
a, b = phases(one), phases(two)
assert a.keys() == b.keys(), "the runs hold other particles"
differ = [i for i in a if a[i] != b[i]]
assert not differ, f"{len(differ)} particles of other phases, e.g. id {differ[0]}"
assert sum(a.values()) > 0, "no particle of phase 1"
curve = [open(os.path.join(d, "drainage.csv")).read() for d in (one, two)]
assert curve[0] == curve[1], "drainage.csv differs"
drainage = [json.load(open(os.path.join(d, "summary.json")))["drainage"] for d in (one, two)]
assert drainage[0] == drainage[1], drainage
flows = [json.load(open(os.path.join(d, "summary.json")))["phases"] for d in (one, two)]
for p, q in zip(*flows):
    assert p["driven"] == q["driven"] and [p["driven"] for p in flows[0]] == [False, True], (p, q)
    u, w = p["superficial_velocity"], q["superficial_velocity"]
    assert u > 0 and abs(u - w) <= 1e-9 * abs(u), (p["index"], u, w)
print(f"drainage as on one process: {sum(a.values())} of {len(a)} particles of phase 1, "
      f"saturation {drainage[0]['saturation']:.4f}")
