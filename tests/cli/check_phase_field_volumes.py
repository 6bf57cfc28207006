"""check_phase_field_volumes.py DIR DIMENSION: a run with a moving interface (a drop) in DIMENSION
dimensions kept each phase's volume by the phase field (phases_history.csv, first row and last) to
1e-10 of the fluid's, summary.json reports the last, and surface tension acts: the drop's pressure
is above the other phase's at the end (capillary_pressure > 0). The other checks of moving
interfaces call volumes_kept."""
import csv
import json
import os
import sys


def volumes_kept(directory):
    """Asserts each phase's phase_field_volume is kept to 1e-10 of the fluid's from the first row of
    phases_history.csv to the last, and that summary.json reports the last; returns the rows."""
    summary = json.load(open(os.path.join(directory, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(directory, "phases_history.csv"))))
    assert len(rows) > 1, "one row of phases_history.csv: no step"
    fluid = sum(float(rows[0][f"phase_field_volume_{p}"]) for p in (0, 1))
    for p in (0, 1):
        first, last = float(rows[0][f"phase_field_volume_{p}"]), float(rows[-1][f"phase_field_volume_{p}"])
        assert first > 0, (p, first)
        assert abs(last - first) < 1e-10 * fluid, (p, first, last)
        reported = next(ph["phase_field_volume"] for ph in summary["phases"] if ph["index"] == p)
        assert abs(reported - last) < 1e-10 * fluid, (p, reported, last)
    return rows


if __name__ == "__main__":
    directory, dimension = sys.argv[1], int(sys.argv[2])
    assert json.load(open(os.path.join(directory, "summary.json")))["dimension"] == dimension
    rows = volumes_kept(directory)
    pressure = float(rows[-1]["capillary_pressure"])
    assert pressure > 0, f"the drop's pressure is not above the other phase's: {pressure}"
    print(f"phase volumes kept in {dimension}D over {rows[-1]['step']} steps, capillary pressure {pressure:.4g} Pa")
