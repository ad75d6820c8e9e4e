#!/usr/bin/env bash
# compare_agree_test.sh — ctest compare_agree: one pair of
# pictures gets one verdict and the same numbers from every tool. For each
# catalogue entry, the reference program's picture is judged against its own
# reference and against another entry's reference of the same program (a
# mistaken picture: another shader, another anti-aliasing), and, where the
# student build exists, the student program's picture (a stub's, mistaken
# by design) against its reference:
#   - by the program itself: PROGRAM ARGS --compare [--reference FILE];
#   - by raster101-compare --as COMPARISON (the catalogue's table, which the
#     grader reads for the rubric's images: ctest catalogue_rubric).
# The summary lines and the exit statuses must be identical.
#   tests/e2e/compare_agree_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
ref=$src/tests/reference
cat=$ref/catalogue.json
fail=0 pairs=0 mismatched=0
mapfile -t entries < <("$bin/raster101-catalogue" --catalogue "$cat" list)
((${#entries[@]} > 0)) || { echo "FAIL: the catalogue lists no image"; exit 1; }
judge() { # LABEL PROGRAM ARGS REFERENCE_PNG COMPARISON
  local label=$1 prog=$2 args=$3 refpng=$4 comp=$5 out1 out2 s1 s2
  # shellcheck disable=SC2086 # the arguments are words
  out1=$(cd "$work" && "$prog" $args -o "$work/got.png" --compare --reference "$refpng" 2>/dev/null)
  s1=$?
  out1=$(sed -n "s|^compare $refpng: ||p" <<<"$out1")
  out2=$("$bin/raster101-compare" --as "$comp" --catalogue "$cat" "$refpng" "$work/got.png" 2>&1)
  s2=$?
  pairs=$((pairs + 1))
  if [[ -z $out1 || $out1 != "$out2" || $s1 != "$s2" ]]; then
    echo "FAIL $label: --compare said '$out1' (exit $s1), raster101-compare --as $comp said '$out2' (exit $s2)"
    fail=1
  else
    echo "ok   $label ($comp): $out1"
    [[ $s1 == 0 ]] || mismatched=$((mismatched + 1))
  fi
}
for line in "${entries[@]}"; do
  IFS=$'\t' read -r name prog _demo args <<<"$line"
  # hw1's wireframes are judged by the grader only (its program has no --compare)
  "$bin/${prog}_ref" --help 2>/dev/null | grep -q -- '--compare' || continue
  comp=$("$bin/raster101-catalogue" --catalogue "$cat" comparison "$name") || { fail=1; continue; }
  judge "$name vs its reference" "$bin/${prog}_ref" "$args" "$ref/$name.png" "$comp"
  # another reference of the same program: a picture that does not match
  for other in "${entries[@]}"; do
    IFS=$'\t' read -r oname oprog _ _ <<<"$other"
    [[ $oprog == "$prog" && $oname != "$name" ]] || continue
    judge "$name vs $oname's reference" "$bin/${prog}_ref" "$args" "$ref/$oname.png" "$comp"
    break
  done
  [[ -x $bin/$prog ]] && judge "$name, the student build" "$bin/$prog" "$args" "$ref/$name.png" "$comp"
done
echo "$pairs pairs, $mismatched of them not matching; every tool agreed: $([[ $fail == 0 ]] && echo yes || echo no)"
# the test must see both verdicts, or it proves nothing
((mismatched > 0 && mismatched < pairs)) || { echo "FAIL: expected both matching and mismatched pairs"; fail=1; }
exit $fail
