#!/usr/bin/env bash
# Does a lesson reach Cycles' error in a fraction of Cycles' time? (docs/performance.md)
# For each sample count S in the list, RUNS times in turn:
#   1. Cycles renders S samples per pixel (a fresh seed each run); its time is the wall time
#      Blender measures around its render call, its error the RMSE against Cycles' own
#      converged render (two halves, their noise subtracted: tools/compare --second-half);
#   2. the lesson renders with --time set to FRACTION of that run's Cycles time (its default
#      sampler, a fresh seed), and its error is taken against the same converged Cycles render.
# The renderers alternate, so that the machine's drift falls on both. The lesson reaches
# Cycles' error within FRACTION of its time when its median error is at most Cycles' median
# error. The converged renders come from scripts/cycles_compare.sh (cached in DIR).
# Writes DIR/time_to_error.csv (target_spp,run,renderer,seconds,wall_seconds,spp,rmse) and
# prints medians and ranges.
# Usage: scripts/cycles_time_to_error.sh [--width W] [--height H] [--dir DIR] [--lesson 4|5|6]
#                                        [--runs N] [--fraction F] SCENE [SPP ...]
#   e.g. scripts/cycles_time_to_error.sh --lesson 4 scenes/cornell_box_rtiow.toml 64 256
#   Defaults: 3 runs, fraction 0.5, SPP 64. Environment: REF_SPP (default 1024), BLENDER,
#   LESSONS_BIN, as for scripts/cycles_compare.sh.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BLENDER="${BLENDER:-blender}"
BIN="${LESSONS_BIN:-$ROOT/build/bin}"
REF_SPP="${REF_SPP:-1024}"
WIDTH="" HEIGHT="" DIR="" LESSON="" RUNS=3 FRACTION=0.5 SCENE=""
SPP_LIST=()
usage() {
    echo "usage: scripts/cycles_time_to_error.sh [--width W] [--height H] [--dir DIR] [--lesson 4|5|6] [--runs N] [--fraction F] SCENE [SPP ...]" >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case "$1" in
        --width) [ $# -ge 2 ] || usage; WIDTH="$2"; shift 2 ;;
        --height) [ $# -ge 2 ] || usage; HEIGHT="$2"; shift 2 ;;
        --dir) [ $# -ge 2 ] || usage; DIR="$2"; shift 2 ;;
        --lesson) [ $# -ge 2 ] || usage; LESSON="$2"; shift 2 ;;
        --runs) [ $# -ge 2 ] || usage; RUNS="$2"; shift 2 ;;
        --fraction) [ $# -ge 2 ] || usage; FRACTION="$2"; shift 2 ;;
        -h|--help) usage ;;
        -*) echo "unknown option $1" >&2; usage ;;
        *) if [ -z "$SCENE" ]; then SCENE="$1"; else for spp in $1; do SPP_LIST+=("$spp"); done; fi
           shift ;;
    esac
done
[ -n "$SCENE" ] || usage
[ ${#SPP_LIST[@]} -gt 0 ] || SPP_LIST=(64)
for n in "$RUNS" "${SPP_LIST[@]}"; do
    [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "not a positive integer: $n" >&2; exit 2; }
done
[[ "$FRACTION" =~ ^(0?\.[0-9]+|[1-9][0-9]*(\.[0-9]+)?)$ ]] || { echo "--fraction: not a positive number: $FRACTION" >&2; exit 2; }
NAME="$(basename "$SCENE")"; NAME="${NAME%.*}"
DIR="${DIR:-$ROOT/out/cycles/$NAME}"

# The converged renders (and, cached, the lesson chosen for the scene).
mkdir -p "$DIR"
REF_SPP="$REF_SPP" BLENDER="$BLENDER" LESSONS_BIN="$BIN" "$ROOT/scripts/cycles_compare.sh" \
    ${LESSON:+--lesson "$LESSON"} ${WIDTH:+--width "$WIDTH"} ${HEIGHT:+--height "$HEIGHT"} \
    --dir "$DIR" "$SCENE" "${SPP_LIST[0]}" > "$DIR/compare.log" 2>&1 ||
    { echo "error: scripts/cycles_compare.sh failed; see $DIR/compare.log" >&2; exit 1; }
LESSON="$(sed -n 's/.*, lesson \([456]\),.*/\1/p' "$DIR/stamp")"
case "$LESSON" in 4) PROGRAM="$BIN/04_rendering_equation" ;; 5) PROGRAM="$BIN/05_bidirectional" ;;
    6) PROGRAM="$BIN/06_photon_mapping" ;;
    *) echo "error: no lesson in $DIR/stamp" >&2; exit 1 ;; esac
SIZE_ARGS=()
size="$(sed -n 's/.*, size \([0-9a-z]*\)x\([0-9a-z]*\),.*/\1 \2/p' "$DIR/stamp")"
read -r width height <<< "$size"
[ "$width" = scene ] || SIZE_ARGS+=(--width "$width")
[ "$height" = scene ] || SIZE_ARGS+=(--height "$height")
CYCLES_REF=("$DIR/cycles_ref_${REF_SPP}spp_seed1.exr" --second-half "$DIR/cycles_ref_${REF_SPP}spp_seed2.exr")
field() { sed -n "s/.*\"$2\": \([0-9.eE+-]*\).*/\1/p" "$1" | head -1; }
now() { date +%s.%N; }

CSV="$DIR/time_to_error.csv"
echo "target_spp,run,renderer,seconds,wall_seconds,spp,rmse" > "$CSV"
for target in "${SPP_LIST[@]}"; do
    for run in $(seq 1 "$RUNS"); do
        seed=$((5000 + 10 * target + run))
        file="$DIR/tte_cycles_${target}spp_run$run"
        start="$(now)"
        "$BLENDER" -b --factory-startup --python-exit-code 1 --python "$ROOT/scripts/blender/toml_to_blender.py" -- \
            --json "$DIR/scene.json" --render "$file.exr" --spp "$target" --seed "$seed" --threads 2 \
            "${SIZE_ARGS[@]}" > "$file.log" 2>&1 || { echo "error: Blender failed; see $file.log" >&2; exit 1; }
        wall="$(awk -v a="$start" -v b="$(now)" 'BEGIN{printf "%.3f", b - a}')"
        seconds="$(sed -n 's/^cycles_seconds: //p' "$file.log")"
        [ -n "$seconds" ] && [ -f "$file.exr" ] || { echo "error: no image or time from Blender; see $file.log" >&2; exit 1; }
        rmse="$("$BIN/compare" "$file.exr" "${CYCLES_REF[@]}" | field /dev/stdin rmse_corrected)"
        echo "$target,$run,cycles,$seconds,$wall,$target,$rmse" >> "$CSV"
        budget="$(awk -v s="$seconds" -v f="$FRACTION" 'BEGIN{printf "%.3f", s * f}')"
        file="$DIR/tte_ours_${target}spp_run$run"
        start="$(now)"
        "$PROGRAM" --scene "$SCENE" --time "$budget" --seed "$seed" --threads 2 "${SIZE_ARGS[@]}" \
            --out "$file" --report "$file.json" --quiet
        wall="$(awk -v a="$start" -v b="$(now)" 'BEGIN{printf "%.3f", b - a}')"
        rmse="$("$BIN/compare" "$file.exr" "${CYCLES_REF[@]}" | field /dev/stdin rmse_corrected)"
        echo "$target,$run,lesson$LESSON,$(field "$file.json" seconds),$wall,$(field "$file.json" spp),$rmse" >> "$CSV"
        echo "target $target spp, run $run: $(tail -2 "$CSV" | tr '\n' ' ')"
    done
done

python3 - "$CSV" "$FRACTION" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
fraction = float(sys.argv[2])
def spread(values):
    return f"{statistics.median(values):.4g} ({min(values):.4g}-{max(values):.4g})"
for target in sorted({int(r["target_spp"]) for r in rows}):
    print(f"== Cycles' {target}-spp error, the lesson given {fraction:g} of Cycles' time"
          " (median (range) of the runs; errors against Cycles' converged render)")
    medians = {}
    for who in sorted({r["renderer"] for r in rows}):
        sel = [r for r in rows if int(r["target_spp"]) == target and r["renderer"] == who]
        get = lambda k: [float(r[k]) for r in sel]
        medians[who] = statistics.median(get("rmse"))
        print(f"  {who:8s} seconds {spread(get('seconds'))}, wall {spread(get('wall_seconds'))},"
              f" spp {spread(get('spp'))}, rmse {spread(get('rmse'))}")
    lesson = [w for w in medians if w != "cycles"][0]
    ratio = medians[lesson] / medians["cycles"]
    verdict = "reached" if ratio <= 1 else "not reached"
    print(f"  error, lesson / Cycles: {ratio:.3f}: Cycles' error {verdict} in {fraction:g} of its time")
EOF
echo "runs: $CSV"
