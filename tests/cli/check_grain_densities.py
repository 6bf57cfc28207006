"""check_grain_densities.py DIR GRAIN_FILE: a run of moving grains that took each grain's density from
the grain file's column wrote them back in grains_used.txt, under the header that names the column, and
ran its steps without a failure."""
import json
import os
import sys

directory, given = sys.argv[1], sys.argv[2]


def rows(path):
    lines = [line.split("#")[0].split() for line in open(path)]
    return [words for words in lines if words]


used, source = rows(os.path.join(directory, "grains_used.txt")), rows(given)
assert used[0] == ["cx", "cy", "r", "density"], used[0]
assert [float(w) for w in used[1][3:]] == [1500.0] and [float(w) for w in used[2][3:]] == [3000.0], used
assert [[float(w) for w in r] for r in used[1:]] == [[float(w) for w in r] for r in source[1:]], (used, source)
summary = json.load(open(os.path.join(directory, "summary.json")))
assert summary["steps"] > 0 and "failure" not in summary, summary.get("failure")
print("grain densities ok")
