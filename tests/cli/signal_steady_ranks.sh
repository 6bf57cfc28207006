#!/usr/bin/env bash
# SIGTERM to mpirun during a steady solve on 2 processes: mpirun forwards it
# to the ranks and kills them about 2 s later, so the solver must answer
# within an inner iteration. The inner solves are made slow here (a tight
# tolerance and a restart of 2: an outer iteration takes longer than mpirun
# waits), so that a solver that looks only between outer iterations leaves
# nothing (it did: no checkpoint.h5, no summary.json). Expected:
# checkpoint.h5, and summary.json saying signal.
set -u
mpirun="$1"; poresph="$2"; scene="$3"; out="$4"
rm -rf "$out"
"$mpirun" -np 2 --oversubscribe "$poresph" "$scene" --output "$out" --set "Solver/Method=steady" \
  --set "Solver/Inner Tolerance=1e-12" --set "Solver/Max Inner Iterations=20000" \
  --set "Solver/Inner Krylov Restart=2" &
pid=$!
for _ in $(seq 100); do [ -f "$out/parameters_used.xml" ] && break; sleep 0.1; done
sleep 5  # past the set-up, inside the first outer iteration's inner solves
kill -TERM "$pid"
wait "$pid"; status=$?
echo "mpirun exit status $status"
[ -f "$out/checkpoint.h5" ] || { echo "no checkpoint.h5"; exit 1; }
grep -q '"stopped_by": "signal"' "$out/summary.json" || { echo "summary.json does not say signal"; exit 1; }
/usr/bin/python3 - "$out/summary.json" <<'PY' || exit 1
import json, sys
solver = json.load(open(sys.argv[1]))["solver"]
if solver["converged"] or solver["inner_iterations"] <= 0:
    sys.exit(f"the solve did not run as expected: {solver}")
print(f"stopped after {solver['linear_iterations']} linear and {solver['inner_iterations']} inner iterations")
PY
echo "a steady solve on 2 processes stopped by SIGTERM to mpirun left its checkpoint"
