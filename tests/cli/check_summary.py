"""check_summary.py SUMMARY.json STEPS: the keys scripts rely on, with sane values."""
import json
import sys

summary = json.load(open(sys.argv[1]))
steps = int(sys.argv[2])
required = ["dimension", "fluid_particles", "boundary_particles", "steps", "simulated_time", "wall_seconds",
            "particle_steps_per_second", "ranks", "threads", "backend", "max_density_variation"]
missing = [k for k in required if k not in summary]
assert not missing, f"missing keys: {missing}"
assert summary["dimension"] == 2
assert summary["fluid_particles"] == 400, summary["fluid_particles"]
assert summary["boundary_particles"] == 0
assert summary["steps"] == steps, summary["steps"]
assert summary["stopped_by"] == "max_steps"
assert abs(summary["simulated_time"] - steps * summary["time_step"]) < 1e-12 * summary["simulated_time"]
assert summary["ranks"] == 1 and summary["threads"] >= 1
assert summary["particle_steps_per_second"] > 0
assert 0 <= summary["max_density_variation"] < 0.01
print("all keys present")
