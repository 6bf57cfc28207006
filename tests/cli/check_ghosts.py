"""check_ghosts.py SUMMARY.json RANKS: summary.json's ghost counts for tests/cli/tiny.xml (a periodic
20 x 20 lattice, no walls) on 1 or 2 processes. A process's ghosts are the particles within the
kernel's reach (3 spacings: the rows at 0.5, 1.5 and 2.5 spacings from a face) outside its box,
corners included (the halo's two stages): (20 + 6) (20 / RANKS + 6) - 20 (20 / RANKS) for boxes of
20 by 20 / RANKS."""
import json
import sys

summary = json.load(open(sys.argv[1]))
ranks = int(sys.argv[2])
assert summary["ranks"] == ranks, summary["ranks"]
per_rank = (20 + 6) * (20 // ranks + 6) - 20 * (20 // ranks)
assert summary["ghost_particles_max"] == per_rank, (summary["ghost_particles_max"], per_rank)
assert summary["ghost_particles"] == ranks * per_rank, (summary["ghost_particles"], ranks * per_rank)
print(f"ghosts as the boxes give: {summary['ghost_particles']} in all, {per_rank} a process")
