#!/usr/bin/env bash
# Measures the LAMMPS SPH yardstick quoted in issue 5 on THIS machine:
# pair sph/taitwater/morris (Lucy kernel, support h = 3 dx), 48,000
# particles of 2D Poiseuille flow (perf/lammps/poiseuille.in), one core.
# Prints particle-steps per second (atoms * steps / loop time) for each run,
# their median, min and max, and the ns per particle-step, so that PoreSPH's
# speed can be quoted as a ratio measured on the same machine.
#
#   perf/lammps_yardstick.sh [--repeats N] [--steps N]
#
# Once per machine it builds a serial LAMMPS with only the SPH package from
# Debian's source package (`apt-get source lammps`, through a private apt
# configuration so the system's sources are untouched) into
# $LAMMPS_WORK (default /var/tmp/poresph-lammps, outside the repository).
# The build (437 targets) runs under `nice -n 19` with $JOBS (default 2)
# jobs: about 4 min on an idle 2-core machine, 13 min 20 s measured while
# the machine was busy (load 3-4); ~20 s more to fetch the 80 MB source.
# An existing $LAMMPS_WORK/build/lmp is reused. Each run is 100 warm-up +
# 1000 timed steps: about 30 s here (3 runs: under 2 min).
#
# Environment: LAMMPS_WORK, JOBS.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
input="$here/lammps/poiseuille.in"
work="${LAMMPS_WORK:-/var/tmp/poresph-lammps}"
jobs="${JOBS:-2}"
repeats=3
steps=1000
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "lammps_yardstick: unknown argument $1" >&2; exit 2 ;;
  esac
done
lmp="$work/build/lmp"

if [ ! -x "$lmp" ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  start=$(date +%s)
  # Build tools: install only what is missing (no upgrades of installed packages).
  need=()
  for tool in g++:g++ cmake:cmake ninja:ninja-build ccache:ccache dpkg-source:dpkg-dev; do
    command -v "${tool%%:*}" >/dev/null || need+=("${tool#*:}")
  done
  if [ ${#need[@]} -gt 0 ]; then
    $sudo apt-get install -y -qq --no-install-recommends "${need[@]}"
  fi

  # The source package (scripts/debian-source.sh).
  source "$here/../scripts/debian-source.sh"
  fetch_debian_source lammps "$work"

  # Serial (no MPI, no OpenMP), SPH package only (every package is off by
  # default in a fresh LAMMPS CMake build), Release = CMake's "-O3 -DNDEBUG"
  # for g++, no optional image/compression libraries.
  launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  generator=(-G "Unix Makefiles")
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake -S "$source_dir/cmake" -B "$work/build" "${generator[@]}" "${launcher[@]}" \
    -DCMAKE_BUILD_TYPE=Release -DBUILD_MPI=off -DBUILD_OMP=off -DPKG_SPH=on \
    -DBUILD_SHARED_LIBS=off -DBUILD_TOOLS=off -DLAMMPS_EXCEPTIONS=off \
    -DWITH_JPEG=off -DWITH_PNG=off -DWITH_GZIP=off -DWITH_FFMPEG=off
  nice -n 19 cmake --build "$work/build" -j "$jobs"
  elapsed=$(( $(date +%s) - start ))
  echo "lammps_yardstick: built $lmp in $((elapsed / 60)) min $((elapsed % 60)) s" | tee "$work/BUILD-TIME.txt"
fi

# Logs of the last invocation are kept in $work/runs (log.1, log.2, ...).
rundir="$work/runs"
rm -rf "$rundir"
mkdir -p "$rundir"
cd "$rundir"
"$lmp" -h | sed -n 's/^\(Large-scale Atomic.*\)$/\1/p' | head -n 1 || true

rates=()
for r in $(seq 1 "$repeats"); do
  load="$(cut -d' ' -f1-3 /proc/loadavg)"
  "$lmp" -in "$input" -var nsteps "$steps" -log "log.$r" -screen none
  # The last "Loop time" line is the timed run (the first is the warm-up).
  read -r loop nsteps_done natoms < <(awk '/^Loop time of/ {t=$4; s=$9; n=$12} END {print t, s, n}' "log.$r")
  neighs="$(awk '/^Ave neighs\/atom/ {v=$4} END {print v}' "log.$r")"
  rate="$(awk -v t="$loop" -v s="$nsteps_done" -v n="$natoms" 'BEGIN {printf "%.4g", n*s/t}')"
  # LAMMPS's "% CPU use" = CPU time / wall time of the loop: below ~99% the
  # run shared its core with other processes and the rate is pessimistic.
  cpu="$(awk '/% CPU use/ {v=$1} END {print v}' "log.$r")"
  builds="$(awk '/^Neighbor list builds/ {v=$5} END {print v}' "log.$r")"
  rates+=("$rate")
  printf 'run %d: loop time %s s, %s steps, %s atoms, Ave neighs/atom %s, %s neighbour builds, %s particle-steps/s, CPU use %s (load avg before: %s)\n' \
    "$r" "$loop" "$nsteps_done" "$natoms" "$neighs" "$builds" "$rate" "$cpu" "$load"
  if [ "$r" -eq 1 ]; then
    sed -n '/^Neighbor list info/,/^Setting up/p' "log.$r" | head -n 12 | sed 's/^/  | /'
    sed -n '/^MPI task timing breakdown/,/^Total/p' "log.$r" | sed 's/^/  | /'
    grep '^CHECK' "log.$r" | sed 's/^/  | /' || true
    grep -m1 -i "WARNING" "log.$r" | sed 's/^/  | /' || true
  fi
done

printf '%s\n' "${rates[@]}" | sort -g | awk '
  { v[NR] = $1 }
  END {
    med = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    printf "LAMMPS SPH yardstick: median %.4g particle-steps/s (min %.4g, max %.4g, %d runs) = %.1f ns per particle-step\n",
      med, v[1], v[NR], NR, 1e9 / med
  }'
