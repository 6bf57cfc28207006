#!/usr/bin/env bash
# skip_without.sh PROGRAM -- COMMAND...
# Runs COMMAND if PROGRAM is on PATH now, at test time; otherwise says so and
# exits 77, which CTest reports as "skipped" (SKIP_RETURN_CODE). The test is
# registered whatever was installed when the build was configured, so it
# cannot vanish because a tool came after `cmake` (issue 18, class 9).
set -u
program="$1"; shift 2
if ! command -v "$program" >/dev/null 2>&1; then
  echo "skip_without.sh: $program is not on PATH: skipped (scripts/setup.sh tools installs it)"
  exit 77
fi
exec "$@"
