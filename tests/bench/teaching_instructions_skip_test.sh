#!/usr/bin/env bash
# teaching_instructions_skip_test.sh — on a toolchain other than the recorded
# one, teaching_instructions_test.sh must skip (exit 77, saying how to record
# budgets) before it starts the counting run under callgrind.
#
#   teaching_instructions_skip_test.sh TEACHING_TEST.sh BUDGETS.json
#
# The program handed to the test as bench_perf only leaves a mark when it is
# started, so a skip that comes after the expensive part shows as the mark.
set -euo pipefail
script=${1:?usage: teaching_instructions_skip_test.sh TEACHING_TEST.sh BUDGETS.json}
budgets=${2:?budgets file}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '#!/bin/sh\ntouch "%s/started"\n' "$tmp" >"$tmp/bench_perf"
chmod +x "$tmp/bench_perf"

status=0
"$script" "$tmp/bench_perf" "$budgets" "NoSuchCompiler 0.0" "RelWithDebInfo" >"$tmp/out" 2>&1 || status=$?
if [[ $status -ne 77 ]]; then
  echo "teaching_instructions_skip: expected exit 77 (skipped) on another toolchain, got $status:" >&2
  cat "$tmp/out" >&2
  exit 1
fi
if [[ -e "$tmp/started" ]]; then
  echo "teaching_instructions_skip: the test skipped only after starting the counting run; expected the toolchain check first" >&2
  exit 1
fi
if ! grep -q "SKIPPED .*NoSuchCompiler 0.0.*--record" "$tmp/out"; then
  echo "teaching_instructions_skip: expected the skip message to name this toolchain and the --record command; it said:" >&2
  cat "$tmp/out" >&2
  exit 1
fi
echo "teaching_instructions_skip: skipped before counting, with the record command"
