#!/usr/bin/env bash
# example_test.sh EXAMPLE CHECK DIR — runs examples/first_triangle as a reader
# would and holds its picture to hand-worked numbers (first_triangle_check.c).
set -euo pipefail
example=${1:?usage: example_test.sh EXAMPLE CHECK DIR} check=${2:?} dir=${3:?}
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir"
out=$("$example" triangle.png)
echo "$out"
covered=$(sed -n 's/.*rasterized, \([0-9]*\) pixels covered$/\1/p' <<<"$out")
[[ -n $covered ]] || { echo "example_test: FAIL: expected '... N pixels covered' on stdout"; exit 1; }
"$check" triangle.png "$covered"
