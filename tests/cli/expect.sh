#!/usr/bin/env bash
# expect.sh fail|pass REGEX -- COMMAND...
# Runs COMMAND; checks its exit status (non-zero for fail, zero for pass)
# and that its output (stdout and stderr) matches REGEX.
set -u
want="$1"; regex="$2"; shift 3
output="$("$@" 2>&1)"; status=$?
echo "$output"
if [ "$want" = fail ] && [ $status -eq 0 ]; then echo "expect.sh: exit status 0, expected failure"; exit 1; fi
if [ "$want" = pass ] && [ $status -ne 0 ]; then echo "expect.sh: exit status $status, expected success"; exit 1; fi
if ! grep -Eq -- "$regex" <<<"$output"; then echo "expect.sh: output does not match /$regex/"; exit 1; fi
exit 0
