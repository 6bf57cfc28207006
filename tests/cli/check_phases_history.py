"""check_phases_history.py DIR STEPS...: phases_history.csv of a two-fluid run: rows at exactly the
steps given (the check interval's, and the end; a restart keeps the rows before its checkpoint and
drops the end-of-run row it goes on past), the capillary pressure phase 1's mean pressure less phase
0's, and the last row the run's summary.json phases to the 12 digits written."""
import csv
import json
import os
import sys

directory, steps = sys.argv[1], [int(s) for s in sys.argv[2:]]
rows = list(csv.DictReader(open(os.path.join(directory, "phases_history.csv"))))
assert [int(r["step"]) for r in rows] == steps, [r["step"] for r in rows]
for r in rows:
    jump = float(r["mean_pressure_1"]) - float(r["mean_pressure_0"])
    assert abs(float(r["capillary_pressure"]) - jump) <= 1e-11 * max(1.0, abs(float(r["mean_pressure_1"]))), r
summary = json.load(open(os.path.join(directory, "summary.json")))
for phase in summary["phases"]:
    p = phase["index"]
    for key in ("superficial_velocity", "mean_pressure"):
        written, reported = float(rows[-1][f"{key}_{p}"]), phase[key]
        assert abs(written - reported) <= 1e-11 * abs(reported), (key, p, written, reported)
assert float(rows[-1]["superficial_velocity_1"]) != 0.0, "the phases did not flow"
print(f"phases history as the run: {len(rows)} rows")
