#!/usr/bin/env bash
# bench_bvh's filters keep only what they name, an unknown query is refused before anything is
# measured, and --embree-robust either measures against Embree's robust mode and says so or,
# without Embree built in, is refused. Usage: tests/bench_filters_test.sh BENCH_BVH OUT_DIR
set -euo pipefail
bench="$1"
csv="$2/bench_filters.csv"
rm -f "$csv"
fail() { echo "bench_filters_test: $*"; exit 1; }

# --query any on the random set of the Cornell box: every data row is one of those.
"$bench" --rays 500 --scene cornell_box --set random --query any --csv "$csv" > /dev/null
rows=$(tail -n +2 "$csv" | wc -l)
[ "$rows" -ge 1 ] || fail "no rows written"
others=$(tail -n +2 "$csv" | grep -vc '^cornell_box,32,random,any,' || true)
[ "$others" -eq 0 ] || fail "$others rows the filters should have left out"

# An unknown query: exit status 2.
rc=0
"$bench" --rays 500 --scene cornell_box --set random --query nearest > /dev/null 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "--query nearest: exit status $rc, not 2"

# --embree-robust: measured and named, or refused with 2 when Embree is not built in.
rc=0
out=$("$bench" --rays 500 --scene cornell_box --set random --query closest --embree-robust 2>&1) ||
    rc=$?
if [ "$rc" -eq 0 ]; then
    grep -q '(robust)' <<< "$out" || fail "--embree-robust: the output does not say robust"
else
    [ "$rc" -eq 2 ] || fail "--embree-robust: exit status $rc"
    grep -q 'Embree is not built in' <<< "$out" || fail "--embree-robust: refused without a reason"
fi
echo "bench_filters_test: $rows rows, all any-hit rows of the random set"
