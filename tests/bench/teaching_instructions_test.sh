#!/usr/bin/env bash
# teaching_instructions_test.sh — the teaching pipeline's instruction count per
# frame must not grow (issue 18: at or below the course framework's count).
#
#   teaching_instructions_test.sh BENCH_PERF BUDGETS.json COMPILER BUILD_TYPE [--record]
#
# Counts one frame of each shader at 1x on the built-in model with callgrind
# (bench_perf --count-frames teaching --aa none: a warm-up frame, then the
# counted one between CALLGRIND_ZERO_STATS and CALLGRIND_DUMP_STATS_AT) and
# compares each with its budget in BUDGETS.json, plus the margin there.
# Instruction counts are exact and repeatable, but only for one compiler and C
# library: the budgets name the toolchain they were recorded with, and on
# another one the test skips (exit 77) and says how to record them again.
# --record writes BUDGETS.json from this build's counts instead.
# docs/performance.md ("The teaching pipeline against the course's framework")
# has the spot cow's counts beside the framework's.
set -euo pipefail
bench=${1:?usage: teaching_instructions_test.sh BENCH_PERF BUDGETS.json COMPILER BUILD_TYPE [--record]}
budgets=${2:?budgets file}
compiler=${3:?compiler id and version}
build_type=${4:?build type}
record=${5:-}
libc=$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}' || true) # not ldd | head: SIGPIPE under pipefail
toolchain="$compiler, $build_type, glibc $libc"

# Another toolchain: skip before anything is counted (the counting run takes
# 15-20 s under callgrind and its counts could not be compared anyway).
if [[ "$record" != "--record" ]]; then
  if ! recorded=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["toolchain"])' "$budgets"); then
    echo "teaching_instructions: expected a JSON file with a \"toolchain\" entry in $budgets; record one with --record" >&2
    exit 1
  fi
  if [[ "$recorded" != "$toolchain" ]]; then
    echo "teaching_instructions: SKIPPED — the budgets were recorded with $recorded, this build is $toolchain; instruction counts differ between toolchains. To check this one, record them: tests/bench/teaching_instructions_test.sh BUILD/bin/bench_perf $budgets '$compiler' $build_type --record"
    exit 77
  fi
fi

if ! command -v valgrind >/dev/null; then
  echo "teaching_instructions: valgrind is not installed; expected it from scripts/install-deps (run it, then ctest again)" >&2
  exit 1
fi
if [[ ! -x "$bench" ]]; then
  echo "teaching_instructions: expected the program $bench; build it first (cmake --build BUILD --target bench_perf)" >&2
  exit 1
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if ! valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$bench" --count-frames teaching --aa none \
  >"$tmp/log" 2>&1; then
  echo "teaching_instructions: the counting run failed:" >&2
  tail -20 "$tmp/log" >&2
  exit 1
fi

python3 - "$tmp" "$budgets" "$toolchain" "$record" <<'EOF'
import glob, json, os, sys
tmp, budgets_path, toolchain, record = sys.argv[1:5]
shaders = ["normal", "phong", "texture", "bump", "displacement"]
counts = {}
for path in glob.glob(os.path.join(tmp, "cg.*")):
    name, total = None, None
    with open(path) as f:
        for line in f:
            if line.startswith("desc: Trigger: Client Request: "):
                name = line.split()[-1]
            elif line.startswith("totals: "):
                total = int(line.split()[1])
    if name and name.endswith("_none") and total:
        counts[name[:-5]] = total
missing = [s for s in shaders if s not in counts]
if missing:
    sys.exit("teaching_instructions: expected one counted 1x frame per shader; none for %s "
             "(does bench_perf still dump SHADER_none under callgrind?)" % ", ".join(missing))

if record == "--record":
    doc = {
        "about": "Instructions of one teaching-pipeline frame at 1x on bench_perf's built-in "
                 "model (callgrind), per shader: the budgets of ctest teaching_instructions "
                 "(tests/bench/teaching_instructions_test.sh). Recorded with --record.",
        "toolchain": toolchain,
        "margin": 0.02,
        "budgets": {s: counts[s] for s in shaders},
    }
    with open(budgets_path, "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
    print("teaching_instructions: recorded %s (%s)" % (budgets_path, toolchain))
    sys.exit(0)

with open(budgets_path) as f:
    doc = json.load(f)
if doc["toolchain"] != toolchain:  # checked before counting; the file changed meanwhile
    sys.exit("teaching_instructions: %s now names the toolchain %s, not %s" % (budgets_path, doc["toolchain"], toolchain))
margin = float(doc["margin"])
failed = False
print("shader        counted      budget   ratio")
for s in shaders:
    budget = int(doc["budgets"][s])
    got = counts[s]
    ratio = got / budget
    verdict = "ok" if got <= budget * (1 + margin) else "OVER"
    print("%-12s %10d  %10d   %.3f  %s" % (s, got, budget, ratio, verdict))
    if verdict == "OVER":
        failed = True
        print("teaching_instructions: the %s frame takes %d instructions, %.1f %% over its budget "
              "%d (margin %.0f %%). Something made the teaching pipeline's per-sample or "
              "per-fragment path slower: profile it with valgrind --tool=callgrind BUILD/bin/"
              "bench_perf --count-frames teaching --aa none and callgrind_annotate the %s_none "
              "dump; if the cost is wanted, record new budgets (--record) and say why in the "
              "commit." % (s, got, 100 * (ratio - 1), budget, 100 * margin, s), file=sys.stderr)
    elif ratio < 0.9:
        print("  (%.0f %% under budget: record the new counts with --record so they stay guarded)"
              % (100 * (1 - ratio)))
sys.exit(1 if failed else 0)
EOF
