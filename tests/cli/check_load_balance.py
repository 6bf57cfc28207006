"""Checks the balance_history.csv of two runs of one scene on the same
processes, one held to its first division of the cell and one divided anew
whenever the slowest process's computing time passes the mean
(Parallel/Rebalance Threshold = 1) and the time it lost since the last
division pays for one: both record the balance every interval, only the
second divides anew, the second's division changed the particles a process
owns, the first division's cost was measured, and every measurement past
the threshold divided exactly when the time lost had reached the last
division's cost. (That the physics is the same is checked on the
checkpoints by check_restart_other_ranks.py.)

usage: check_load_balance.py HELD_DIR BALANCED_DIR INTERVAL
"""
import csv
import os
import sys

held_dir, balanced_dir, interval = sys.argv[1], sys.argv[2], int(sys.argv[3])


def rows(directory):
    with open(os.path.join(directory, "balance_history.csv")) as f:
        return list(csv.DictReader(f))


problems = []
held, balanced = rows(held_dir), rows(balanced_dir)
for name, table in (("held", held), ("balanced", balanced)):
    steps = [int(r["step"]) for r in table]
    if not steps or any(s != interval * (k + 1) for k, s in enumerate(steps)):
        problems.append(f"{name}: the balance is not recorded every {interval} steps: {steps}")
    if any(not float(r["imbalance"]) >= 1.0 for r in table):
        problems.append(f"{name}: an imbalance under 1 (the slowest under the mean): {table}")
if any(r["rebalanced"] != "0" for r in held):
    problems.append("the run without a threshold divided the cell anew")
divided = sum(r["rebalanced"] == "1" for r in balanced)
if divided == 0:
    problems.append("the run with threshold 1 never divided the cell anew")
for r in balanced:
    lost, cost, imbalance = float(r["lost_seconds"]), float(r["division_seconds"]), float(r["imbalance"])
    if lost < 0 or cost < 0:
        problems.append(f"a negative time lost or division cost: {r}")
    pays = imbalance > 1.0 and lost >= cost
    if (r["rebalanced"] == "1") != pays:
        problems.append(f"divided anew ({r['rebalanced']}) where the rule says {int(pays)}: {r}")
after_first = [r for k, r in enumerate(balanced) if any(q["rebalanced"] == "1" for q in balanced[:k])]
if divided and not all(float(r["division_seconds"]) > 0 for r in after_first):
    problems.append("a division was made and its cost not measured")
if any(float(r["lost_seconds"]) != 0 or float(r["division_seconds"]) != 0 for r in held):
    problems.append("the run without a threshold counted time lost or a division")
counts_held = {(r["particles_min"], r["particles_max"]) for r in held}
counts_balanced = {(r["particles_min"], r["particles_max"]) for r in balanced}
if counts_balanced <= counts_held:
    problems.append("dividing the cell anew changed no process's particles")
print(f"held: {len(held)} records; balanced: {len(balanced)} records, divided anew {divided} times")
for p in problems:
    print("FAILED", p)
sys.exit(1 if problems else 0)
