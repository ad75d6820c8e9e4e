#!/usr/bin/env bash
# startup_test.sh BIN — a program loads OpenCV (and Qt with
# it) and assimp only when it uses them (docs/startup.md). Reads which
# libraries the dynamic linker initialised (LD_DEBUG=libs) for:
#   --version and headless PNG renders: none of OpenCV, Qt, GDAL or assimp,
#     and at most 12 libraries in all (6 in a plain build, a sanitizer
#     build's runtimes besides; 157 when OpenCV was linked);
#   a model file: assimp, and still no OpenCV;
#   a JPEG: the OpenCV module, opened on demand, and the file is written.
set -uo pipefail
bin=${1:?usage: startup_test.sh BIN}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# The libraries a command initialised, one a line (its own output dropped).
libs() { LD_DEBUG=libs "$@" 2>&1 >/dev/null | sed -n 's/.*calling init: //p' | sort -u; }

# expect NAME PRESENT-REGEX ABSENT-REGEX MAX-COUNT COMMAND...
expect() {
  local name=$1 present=$2 absent=$3 max=$4
  shift 4
  local l n
  l=$(libs "$@")
  n=$(grep -c . <<<"$l")
  if [[ -n $present ]] && ! grep -Eq "$present" <<<"$l"; then
    echo "startup_test: FAIL $name: expected a library matching '$present' to be loaded; loaded:" $l
    fail=1
  elif [[ -n $absent ]] && grep -Eq "$absent" <<<"$l"; then
    echo "startup_test: FAIL $name: loaded what it does not use:" $(grep -E "$absent" <<<"$l")
    fail=1
  elif ((max > 0 && n > max)); then
    echo "startup_test: FAIL $name: $n libraries, expected at most $max:" $l
    fail=1
  else
    echo "startup_test: ok   $name ($n libraries)"
  fi
}

heavy='libopencv|libQt|libgdal|libassimp'
expect "hw3_shading_ref --version" "" "$heavy" 12 "$bin/hw3_shading_ref" --version
expect "hw1_transform_ref -o png" "" "$heavy" 12 "$bin/hw1_transform_ref" --size 64x64 -o "$tmp/a.png"
expect "hw2_rasterize_ref -o png" "" "$heavy" 12 "$bin/hw2_rasterize_ref" --size 32x32 -o "$tmp/b.png"
expect "hw3_shading_ref -o png" "" "$heavy" 12 "$bin/hw3_shading_ref" --size 32x32 -o "$tmp/c.png"
expect "raster101-compare png png" "" "$heavy" 12 \
  "$bin/raster101-compare" --metric exact "$tmp/b.png" "$tmp/b.png"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/tri.obj"
expect "hw3_shading_ref --model obj" "libassimp" "libopencv|libQt|libgdal" 0 \
  "$bin/hw3_shading_ref" --model "$tmp/tri.obj" --size 32x32 -o "$tmp/d.png"
expect "hw2_rasterize_ref -o jpg" "libopencv_imgcodecs" "" 0 \
  "$bin/hw2_rasterize_ref" --size 32x32 -o "$tmp/e.jpg"
for f in a.png b.png c.png d.png e.jpg; do
  [[ -s $tmp/$f ]] || { echo "startup_test: FAIL $f was not written"; fail=1; }
done
((fail)) && exit 1
echo "startup_test: all checks passed"
