#!/usr/bin/env bash
# scripts/cycles_time_to_error.sh end to end on a small image (ctest cycles_time_to_error, label
# slow): two runs at 8 spp of lesson 4 and Cycles on the Cornell box, 48 x 48, references of
# 2 x 32 spp. It checks the protocol, not the speed: the CSV has a row per renderer and run,
# the lesson's --time budget is the given fraction of that run's Cycles time (within the one
# pass it may overrun by), every error is a positive number, and the summary gives a verdict.
# Usage: tests/blender/time_to_error.sh BIN_DIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BIN="$(cd "$1" && pwd)"
command -v "${BLENDER:-blender}" > /dev/null || { echo "blender not found: scripts/test.sh installs it (apt-get install blender python3-numpy)" >&2; exit 1; }
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
REF_SPP=32 LESSONS_BIN="$BIN" "$ROOT/scripts/cycles_time_to_error.sh" --lesson 4 --runs 2 \
    --fraction 0.5 --width 48 --height 48 --dir "$WORK/box" "$ROOT/scenes/cornell_box.toml" 8 \
    > "$WORK/out.log" 2>&1 || { cat "$WORK/out.log"; echo "FAIL: the script failed"; exit 1; }
cat "$WORK/out.log"
grep -q "Cycles' error \(reached\|not reached\) in 0.5 of its time" "$WORK/out.log" ||
    { echo "FAIL: no verdict"; exit 1; }
python3 - "$WORK/box/time_to_error.csv" "$WORK/box" <<'PY'
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 4, rows
for run in ("1", "2"):
    cycles = [r for r in rows if r["run"] == run and r["renderer"] == "cycles"]
    ours = [r for r in rows if r["run"] == run and r["renderer"] == "lesson4"]
    assert len(cycles) == 1 and len(ours) == 1, rows
    budget = json.load(open(f"{sys.argv[2]}/tte_ours_8spp_run{run}.json"))["time_budget"]
    expected = 0.5 * float(cycles[0]["seconds"])
    assert abs(budget - expected) <= 0.002, (budget, expected)
    for r in cycles + ours:
        assert float(r["rmse"]) > 0 and float(r["seconds"]) > 0 and int(r["spp"]) >= 1, r
print("PASS: time_to_error.csv has both renderers' runs, budgets of half Cycles' time")
PY
