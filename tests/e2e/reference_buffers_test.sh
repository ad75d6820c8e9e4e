#!/usr/bin/env bash
# reference_buffers_test.sh — ctest reference_buffers: the buffers shipped in
# tests/reference/buffers/ (scripts/reference-images) are what the reference
# programs dump today. Each catalogue entry is rendered again with --dump and
# compared with `raster101-compare --buffers` (each buffer with its kind's
# tolerance; buffers kept as pictures only are skipped); a drift means
# `make reference-images` was not run after a change to solution/. The
# picture itself must be the same pixels as tests/reference/NAME.png, not only
# within a tolerance: make demo promises pictures bit-identical to them
# (README), and the exact clipper's 7 and 1 pixels by 1/255 in hw3_bump and
# hw3_displacement passed every tolerant check unseen.
#   tests/e2e/reference_buffers_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
ref=$src/tests/reference
fail=0 n=0
while IFS=$'\t' read -r name prog _demo args; do
  n=$((n + 1))
  if [[ ! -d $ref/buffers/$name ]]; then
    echo "FAIL $name: no tests/reference/buffers/$name (run make reference-images)"
    fail=1
    continue
  fi
  # shellcheck disable=SC2086 # the arguments are words
  "$bin/${prog}_ref" $args -o "$work/$name.png" --dump "$work/$name" >/dev/null 2>&1 ||
    { echo "FAIL $name: ${prog}_ref $args --dump did not run"; fail=1; continue; }
  if ! out=$("$bin/raster101-compare" --metric exact --tolerance 0 "$ref/$name.png" \
    "$work/$name.png" 2>&1); then
    echo "FAIL $name: ${prog}_ref $args draws other pixels than tests/reference/$name.png" \
      "(expected the same pixels; make reference-images if the change is intended):"
    sed 's/^/       /' <<<"$out"
    fail=1
  elif out=$("$bin/raster101-compare" --buffers "$ref/buffers/$name" "$work/$name" 2>&1); then
    echo "ok   $name"
  else
    echo "FAIL $name: the shipped buffers differ from what ${prog}_ref dumps now (make reference-images):"
    sed 's/^/       /' <<<"$out"
    fail=1
  fi
done < <("$bin/raster101-catalogue" --catalogue "$ref/catalogue.json" list)
((n > 0)) || { echo "FAIL: the catalogue lists no image"; exit 1; }
exit $fail
