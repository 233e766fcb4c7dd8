#!/usr/bin/env bash
# Any suite scene rendered by Blender's Cycles and by the lesson best suited to it, each measured
# against its own converged render and against the other's (docs/interop.md):
#   1. references: two independent halves per renderer (seeds 1 and 2, REF_SPP samples each);
#      their mean is the converged render, their difference says how converged it is;
#   2. one render per renderer and sample count in the list (seed 1000 + spp);
#   3. a report: each render's RMSE against its own reference and against the other's (the
#      references' own noise subtracted: tools/compare --second-half), and the ratio of the two
#      references' means, whole and in 32 x 32 blocks, with the standard errors the halves give,
#      so that a systematic difference stands out from noise.
# Cycles is built by scripts/blender/toml_to_blender.py (CPU, no denoising, no adaptive
# sampling, no clamping, a one-pixel box filter). The lesson is 05_bidirectional when the scene
# has point, spot or directional lights and mirrors or glass (caustics lesson 4 cannot find), else
# 04_rendering_equation; --lesson 4, 5 or 6 chooses (6: its default method, vertex connection
# and merging). Images are EXR in DIR (default
# out/cycles/SCENE_NAME/); an image that exists is not rendered again (delete it to redo it).
# Times: DIR/times.csv (renderer,spp,seconds,file): the lesson's rendering time from its report,
# Cycles' wall time around its render call. The report: DIR/report.csv and DIR/references.json.
# Usage: scripts/cycles_compare.sh [--width W] [--height H] [--dir DIR] [--lesson 4|5|6]
#                                  [--threads T] SCENE [SPP ...]
#   e.g. scripts/cycles_compare.sh scenes/sky.toml 16 64; REF_SPP=64 scripts/cycles_compare.sh
#   --width 64 --height 64 scenes/cornell_box.toml 4. Default SPP: 64.
#   Environment: REF_SPP (default 1024), BLENDER (default blender), LESSONS_BIN (build/bin).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BLENDER="${BLENDER:-blender}"
BIN="${LESSONS_BIN:-$ROOT/build/bin}"
REF_SPP="${REF_SPP:-1024}"
WIDTH="" HEIGHT="" DIR="" LESSON="" THREADS=2 SCENE=""
SPP_LIST=()

usage() {
    echo "usage: scripts/cycles_compare.sh [--width W] [--height H] [--dir DIR] [--lesson 4|5|6] [--threads T] SCENE [SPP ...]" >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case "$1" in
        --width) [ $# -ge 2 ] || usage; WIDTH="$2"; shift 2 ;;
        --height) [ $# -ge 2 ] || usage; HEIGHT="$2"; shift 2 ;;
        --dir) [ $# -ge 2 ] || usage; DIR="$2"; shift 2 ;;
        --lesson) [ $# -ge 2 ] || usage; LESSON="$2"; shift 2 ;;
        --threads) [ $# -ge 2 ] || usage; THREADS="$2"; shift 2 ;;
        -h|--help) usage ;;
        -*) echo "unknown option $1" >&2; usage ;;
        *) if [ -z "$SCENE" ]; then SCENE="$1"; else for spp in $1; do SPP_LIST+=("$spp"); done; fi
           shift ;;
    esac
done
[ -n "$SCENE" ] || usage
[ -f "$SCENE" ] || { echo "no such scene: $SCENE" >&2; exit 2; }
[ ${#SPP_LIST[@]} -gt 0 ] || SPP_LIST=(64)
for n in "$REF_SPP" "$THREADS" ${WIDTH:+"$WIDTH"} ${HEIGHT:+"$HEIGHT"} "${SPP_LIST[@]}"; do
    [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "not a positive integer: $n" >&2; exit 2; }
done
case "$LESSON" in ""|4|5|6) ;; *) echo "--lesson must be 4, 5 or 6" >&2; exit 2 ;; esac
command -v "$BLENDER" > /dev/null || { echo "blender not found (set BLENDER)" >&2; exit 2; }
[ -x "$BIN/scene_export" ] || { echo "$BIN/scene_export not built (cmake --build build)" >&2; exit 2; }

NAME="$(basename "$SCENE")"; NAME="${NAME%.*}"
DIR="${DIR:-$ROOT/out/cycles/$NAME}"
mkdir -p "$DIR"
JSON="$DIR/scene.json"
"$BIN/scene_export" "$SCENE" --out "$JSON"
if [ -z "$LESSON" ]; then
    LESSON="$(python3 -c '
import json, sys
s = json.load(open(sys.argv[1]))
used = {t["material"] for t in s["spheres"] + s["quads"]} | set(s["mesh"]["materials"])
delta = any(s["materials"][i]["type"] in ("mirror", "glass") for i in used)
print(5 if (s["point_lights"] or s.get("directional_lights")) and delta else 4)' "$JSON")"
fi
case "$LESSON" in 4) PROGRAM="$BIN/04_rendering_equation" ;; 5) PROGRAM="$BIN/05_bidirectional" ;;
    6) PROGRAM="$BIN/06_photon_mapping" ;; esac
SIZE_ARGS=()
[ -z "$WIDTH" ] || SIZE_ARGS+=(--width "$WIDTH")
[ -z "$HEIGHT" ] || SIZE_ARGS+=(--height "$HEIGHT")
# The cached renders are of one scene (as loaded), size and lesson: DIR/stamp says which.
STAMP="scene $(sha256sum < "$JSON" | cut -c1-16), size ${WIDTH:-scene}x${HEIGHT:-scene}, lesson $LESSON, its default sampler (kronecker), references by independent samples"
if [ -f "$DIR/stamp" ] && [ "$(cat "$DIR/stamp")" != "$STAMP" ]; then
    echo "error: $DIR holds renders of another scene, size, lesson or sampler ($(cat "$DIR/stamp")); use another --dir or delete it" >&2
    exit 2
fi
echo "$STAMP" > "$DIR/stamp"
CSV="$DIR/times.csv"
[ -f "$CSV" ] || echo "renderer,spp,seconds,file" > "$CSV"
field() { sed -n "s/.*\"$2\": \([0-9.eE+-]*\).*/\1/p" "$1" | head -1; }

# cycles SPP SEED NAME: DIR/NAME.exr by Cycles, unless it exists.
cycles() {
    local spp="$1" seed="$2" file="$DIR/$3.exr" log="$DIR/$3.log"
    [ -f "$file" ] && { echo "cached: $file"; return; }
    echo "cycles: $file ($spp spp, seed $seed)"
    # Under a temporary name, renamed when complete: an interrupted render leaves nothing that
    # would pass for a cached one.
    if ! "$BLENDER" -b --factory-startup --python-exit-code 1 --python "$ROOT/scripts/blender/toml_to_blender.py" -- \
        --json "$JSON" --render "$file.tmp.exr" --spp "$spp" --seed "$seed" \
        --threads "$THREADS" "${SIZE_ARGS[@]}" > "$log" 2>&1; then
        echo "error: Blender failed; see $log" >&2
        exit 1
    fi
    local seconds
    seconds="$(sed -n 's/^cycles_seconds: //p' "$log")"
    [ -n "$seconds" ] && [ -f "$file.tmp.exr" ] || { echo "error: no image or time; see $log" >&2; exit 1; }
    mv "$file.tmp.exr" "$file"
    echo "cycles,$spp,$seconds,$(basename "$file")" >> "$CSV"
}

# ours SPP SEED NAME [FLAG ...]: DIR/NAME.exr by the lesson, unless it exists.
ours() {
    local spp="$1" seed="$2" file="$DIR/$3.exr" name="$3"
    shift 3
    [ -f "$file" ] && { echo "cached: $file"; return; }
    echo "lesson $LESSON: $file ($spp spp, seed $seed)"
    "$PROGRAM" --scene "$SCENE" --spp "$spp" --seed "$seed" --threads "$THREADS" \
        "${SIZE_ARGS[@]}" "$@" --out "$DIR/$name.tmp" --report "$DIR/$name.json" --quiet
    mv "$DIR/$name.tmp.exr" "$file"
    rm -f "$DIR/$name.tmp.png"
    echo "ours,$spp,$(field "$DIR/$name.json" seconds),$(basename "$file")" >> "$CSV"
}

for seed in 1 2; do
    cycles "$REF_SPP" "$seed" "cycles_ref_${REF_SPP}spp_seed$seed"
    # Our reference by independent numbers: not the estimator of the runs it judges.
    ours "$REF_SPP" "$seed" "ours_ref_${REF_SPP}spp_seed$seed" --sampler independent
done
for spp in "${SPP_LIST[@]}"; do
    cycles "$spp" $((1000 + spp)) "cycles_${spp}spp"
    ours "$spp" $((1000 + spp)) "ours_${spp}spp"
done

OURS_REF=("$DIR/ours_ref_${REF_SPP}spp_seed1.exr" --second-half "$DIR/ours_ref_${REF_SPP}spp_seed2.exr")
CYCLES_REF=("$DIR/cycles_ref_${REF_SPP}spp_seed1.exr" --second-half "$DIR/cycles_ref_${REF_SPP}spp_seed2.exr")
REPORT="$DIR/report.csv"
echo "renderer,spp,seconds,rmse_against_own_reference,rmse_against_other_reference" > "$REPORT"
for spp in "${SPP_LIST[@]}"; do
    for who in ours cycles; do
        if [ "$who" = ours ]; then own_ref=("${OURS_REF[@]}") other_ref=("${CYCLES_REF[@]}")
        else own_ref=("${CYCLES_REF[@]}") other_ref=("${OURS_REF[@]}"); fi
        own="$("$BIN/compare" "$DIR/${who}_${spp}spp.exr" "${own_ref[@]}")"
        theirs="$("$BIN/compare" "$DIR/${who}_${spp}spp.exr" "${other_ref[@]}")"
        seconds="$(grep ",${who}_${spp}spp.exr\$" "$CSV" | tail -1 | cut -d, -f3 || true)"
        echo "$who,$spp,$seconds,$(echo "$own" | field /dev/stdin rmse_corrected),$(echo "$theirs" | field /dev/stdin rmse_corrected)" >> "$REPORT"
    done
done
# The references: ours over Cycles', whole and per 32 x 32 block.
"$BIN/compare" "$DIR/ours_ref_${REF_SPP}spp_seed1.exr" --image-second-half "$DIR/ours_ref_${REF_SPP}spp_seed2.exr" \
    "${CYCLES_REF[@]}" --blocks 32 > "$DIR/references.json"
echo "== $SCENE, lesson $LESSON against Cycles ($(basename "$BLENDER")), references of 2 x $REF_SPP spp"
column -s, -t "$REPORT"
python3 - "$DIR/references.json" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"image mean, ours / Cycles: {r['mean_ratio']:.5f} +- {r['mean_ratio_noise']:.5f} (standard error)")
print(f"32x32 block means, ours / Cycles: {r['block_ratio_min']:.4f} .. {r['block_ratio_max']:.4f}"
      f" over {r['blocks_compared']} blocks (one block's standard error {r['block_ratio_noise']:.4f});"
      f" farthest from 1: {r['worst_block_ratio']:.4f} at pixel {tuple(r['worst_block'])}")
EOF
echo "report: $REPORT, $DIR/references.json; times: $CSV"
