#!/usr/bin/env bash
# SIGTERM during a run: poresph writes a checkpoint and summary.json, exits
# with 128 + 15, and the checkpoint continues the run.
set -u
poresph="$1"; scene="$2"; out="$3"
rm -rf "$out"
"$poresph" "$scene" --output "$out" --set "Run/Max Steps=100000000" --set "Run/End Time=1e9" \
  --set "Output/Final Checkpoint=false" &
pid=$!
# Wait until the run is past its set-up (summary-less output directory exists), then interrupt.
for _ in $(seq 50); do [ -f "$out/parameters_used.xml" ] && break; sleep 0.1; done
sleep 1
kill -TERM "$pid"
wait "$pid"; status=$?
echo "exit status $status"
[ "$status" -eq 143 ] || { echo "expected exit status 143"; exit 1; }
[ -f "$out/checkpoint.h5" ] || { echo "no checkpoint.h5"; exit 1; }
grep -q '"stopped_by": "signal"' "$out/summary.json" || { echo "summary.json does not say signal"; exit 1; }
# The summary of an interrupted run says what ran, as at a normal end.
/usr/bin/python3 - "$out/summary.json" <<'PY' || exit 1
import json, sys
summary = json.load(open(sys.argv[1]))
zero = [key for key in ["time_step", "sound_speed", "smoothing_length", "wall_seconds", "fluid_particles",
                        "particle_steps_per_second", "ranks", "threads"] if not summary.get(key, 0) > 0]
if summary["steps"] >= 100 and "permeability" not in summary:  # k is measured every 100 steps
    zero.append("permeability")
if zero:
    sys.exit(f"summary.json of the interrupted run lacks {', '.join(zero)}")
print(f"summary of the interrupted run: {summary['steps']} steps, {summary['wall_seconds']:.2f} s")
PY
steps=$(sed -n 's/.*"steps": \([0-9]*\).*/\1/p' "$out/summary.json")
"$poresph" "$scene" --output "$out" --restart "$out/checkpoint.h5" --set "Run/Max Steps=$((steps + 20))" || exit 1
grep -q "\"restarted_from_step\": $steps" "$out/summary.json" || { echo "restart did not continue from step $steps"; exit 1; }
echo "interrupted at step $steps and continued"
