"""check_force_steps.py DIR FORCE FACTOR...: a run of input/two_phase/throat_entry.xml with Phases/Force Steps =
FACTOR... of Fluid/Body Force = FORCE (along x), the first below the throat's entry force and the last above it.
phases_history.csv's body_force is FACTOR i x FORCE in the i-th of the equal spans of the run's time (a row at a
span's end still the span's); by perf/throat_entry.py's measures the slug's front stands still before the throat's
middle at the end of the first span and is past the middle at the end of the run."""
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "perf"))
import throat_entry  # noqa: E402

directory, force = sys.argv[1], float(sys.argv[2])
factors = [float(f) for f in sys.argv[3:]]
rows = list(csv.DictReader(open(os.path.join(directory, "phases_history.csv"))))
end = float(rows[-1]["time"])
span = end / len(factors)
for r in rows:
    t = float(r["time"])
    i = min(len(factors) - 1, max(0, int(t / span - 1e-9)))  # the step that ends at t began in span i
    expected = factors[i] * force
    assert abs(float(r["body_force"]) - expected) < 1e-9 * force, (r["step"], t, r["body_force"], expected)
m = throat_entry.measure(directory)
dx = m["spacing"]
first = [x for x, t in zip(m["front"], m["times"]) if t <= span * (1 + 1e-9)]
print(f"front at the first span's end {first[-1] / dx:.2f} spacings (before it {first[-2] / dx:.2f}), at the run's "
      f"end {m['front'][-1] / dx:.2f}; the throat's middle at {m['throat_middle'] / dx:.1f}")
assert first[-1] < m["throat_middle"], first[-1]
assert abs(first[-1] - first[-2]) < 0.5 * dx, (first[-2], first[-1])
assert m["front"][-1] > m["throat_middle"], m["front"][-1]
print("the force steps: held below the entry force, through above it")
