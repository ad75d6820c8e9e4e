#!/usr/bin/env bash
# stale_program_test.sh — ctest stale_program (item 8): the
# student's programs are current, or say they are not.
#   1. a student program older than one of its sources says, first, that it
#      runs older code (a copy dated 2000-01-01 of each program); a fresh one
#      (dated now) and the reference program say nothing of it;
#   1b. so does a student test program (build/tests/test_hwN_student, which
#      ctest and the handout's README run) older than a student file;
#   2. make grade (main and student-edition Makefiles) builds the student
#      programs in build/bin (grade --programs, in the grader's one make of
#      the trusted side; HW=N: that assignment's program) (make -n).
#   tests/e2e/stale_program_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail=0
# says_stale NAME WHAT OLD NEW: what the copy dated 2000 said (OLD) holds
# "note: WHAT was built before your last edit of SRC/...", what the copy
# dated now said (NEW) no such note.
says_stale() {
  local name=$1 what=$2 old=$3 new=$4
  if ! grep -q "$what was built before your last edit of $src/" <<<"$old"; then
    echo "FAIL $name dated 2000: expected the note '$what was built before your last edit of ...', got:"
    sed 's/^/       /' <<<"$old" | head -5
    fail=1
  elif grep -q "built before your last edit" <<<"$new"; then
    echo "FAIL $name dated now: expected no note, got: $new"
    fail=1
  else
    echo "ok   $name: $(grep -o "note: $what was built before your last edit of [^,]*" <<<"$old")"
  fi
}
for prog in hw1_transform hw2_rasterize hw3_shading; do
  [[ -x $bin/$prog ]] || { echo "FAIL $prog: not built in $bin"; fail=1; continue; }
  cp "$bin/$prog" "$work/$prog"
  [[ -e $bin/libraster101_cv.so ]] && cp "$bin/libraster101_cv.so" "$work/" 2>/dev/null
  touch -d 2000-01-01 "$work/$prog"
  old=$("$work/$prog" -o "$work/old.png" 2>&1 >/dev/null)
  touch "$work/$prog"
  new=$("$work/$prog" -o "$work/new.png" 2>&1 >/dev/null)
  says_stale "$prog" "this program" "$old" "$new"
  if [[ -x $bin/${prog}_ref ]]; then
    cp "$bin/${prog}_ref" "$work/${prog}_ref" && touch -d 2000-01-01 "$work/${prog}_ref"
    if "$work/${prog}_ref" -o "$work/ref.png" 2>&1 >/dev/null | grep -q "built before your last edit"; then
      echo "FAIL ${prog}_ref: the reference has no student sources to be older than"
      fail=1
    fi
  fi
done
for hw in hw1 hw2 hw3; do
  t=$bin/../tests/test_${hw}_student
  [[ -x $t ]] || continue # not built by this build's targets: nothing to check
  cp "$t" "$work/test_${hw}_student"
  touch -d 2000-01-01 "$work/test_${hw}_student"
  # (a filter that matches nothing: the note comes first, then exit 3, no test runs)
  old=$(RAS_TEST_FILTER=no_such_test "$work/test_${hw}_student" 2>&1)
  touch "$work/test_${hw}_student"
  new=$(RAS_TEST_FILTER=no_such_test "$work/test_${hw}_student" 2>&1)
  says_stale "test_${hw}_student" "this test program" "$old" "$new"
done
# The --programs list of a make -n plan, one name a line.
programs_of() { grep -o -- '--programs "[^"]*"' <<<"$1" | head -1 | sed 's/--programs "//; s/"$//' | tr ' ' '\n'; }
has_all() { # PLAN NAME...: the plan's --programs holds every NAME
  local plan=$1 list n
  shift
  list=$(programs_of "$plan")
  for n in "$@"; do grep -qx -- "$n" <<<"$list" || return 1; done
}
for mk in "$src/Makefile" "$src/tests/grading/handout/Makefile"; do
  [[ -f $mk ]] || continue # the student edition has its Makefile at the top only
  # (not the calling make's jobserver or flags: ctest may run under make test)
  plan=$(env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -n -f "$mk" -C "$src" grade BUILD="$work/b" 2>&1)
  # (the grader builds them, --programs, in its one make of the trusted side;
  # with HW=N the graded assignment's program alone)
  plan2=$(env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -n -f "$mk" -C "$src" grade HW=2 BUILD="$work/b" 2>&1)
  # the student edition's also builds the test programs and raster101-compare
  # its README names (build/tests/test_hwN_student, build/bin/raster101-compare)
  extra=() extra2=()
  if [[ $mk == */handout/Makefile ]]; then
    extra=(test_hw1_student test_hw2_student test_hw3_student raster101-compare)
    extra2=(test_hw2_student raster101-compare)
  fi
  if ! has_all "$plan2" hw2_rasterize "${extra2[@]}" || programs_of "$plan2" | grep -qx hw1_transform; then
    echo "FAIL ${mk#"$src"/}: make grade HW=2 should build hw2_rasterize ${extra2[*]} and not hw1_transform (grade --programs); make -n said:"
    sed 's/^/       /' <<<"$plan2" | head -8
    fail=1
  fi
  if has_all "$plan" hw1_transform hw2_rasterize hw3_shading "${extra[@]}"; then
    echo "ok   ${mk#"$src"/}: make grade builds the student programs (grade --programs)"
  else
    echo "FAIL ${mk#"$src"/}: make grade does not build hw1_transform hw2_rasterize hw3_shading ${extra[*]}; make -n said:"
    sed 's/^/       /' <<<"$plan" | head -8
    fail=1
  fi
done
exit $fail
