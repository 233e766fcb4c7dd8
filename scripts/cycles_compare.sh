#!/usr/bin/env bash
# Cycles renders of scenes/cornell_box_rtiow.toml (scripts/cycles_cornell_rtiow.py), for
# measuring an independent path tracer's error against time beside the lessons:
#   1. a reference in two independent halves, seeds 1 and 2, REF_SPP samples each (default 1024):
#      their mean is the reference, their difference shows how converged it is;
#   2. one render per sample count in the list, each with its own seed (1000 + spp), so that no
#      two renders share samples.
# Every render is an OpenEXR (linear float RGB) in DIR (default out/cycles/), named after its
# size, samples and seed; a file that exists is not rendered again (delete it to redo it). Each
# render's wall time, as measured inside Blender around the render alone, is appended to
# DIR/times.csv as "spp,seconds,file". No metric is computed here: tools/compare does that.
# Usage: scripts/cycles_compare.sh [--size N] [--dir DIR] SPP [SPP ...]
#   e.g. scripts/cycles_compare.sh "1 4 16 64 256"; REF_SPP=4 scripts/cycles_compare.sh --size 64 1 2
#   Environment: REF_SPP (default 1024), BLENDER (default blender).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCRIPT="$ROOT/scripts/cycles_cornell_rtiow.py"
BLENDER="${BLENDER:-blender}"
REF_SPP="${REF_SPP:-1024}"
SIZE=512
DIR="$ROOT/out/cycles"
SPP_LIST=()

usage() {
    echo "usage: scripts/cycles_compare.sh [--size N] [--dir DIR] SPP [SPP ...]" >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case "$1" in
        --size) [ $# -ge 2 ] || usage; SIZE="$2"; shift 2 ;;
        --dir) [ $# -ge 2 ] || usage; DIR="$2"; shift 2 ;;
        -h|--help) usage ;;
        -*) echo "unknown option $1" >&2; usage ;;
        *) for spp in $1; do SPP_LIST+=("$spp"); done; shift ;;  # "1 2 4" or 1 2 4
    esac
done
[ ${#SPP_LIST[@]} -gt 0 ] || usage
for n in "$SIZE" "$REF_SPP" "${SPP_LIST[@]}"; do
    [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "not a positive integer: $n" >&2; exit 2; }
done
command -v "$BLENDER" > /dev/null || { echo "blender not found (set BLENDER)" >&2; exit 2; }

mkdir -p "$DIR"
CSV="$DIR/times.csv"
[ -f "$CSV" ] || echo "spp,seconds,file" > "$CSV"

# render SPP SEED NAME: renders DIR/NAME.exr unless it exists, and records its time.
render() {
    local spp="$1" seed="$2" name="$3"
    local file="$DIR/$name.exr" log="$DIR/$name.log"
    if [ -f "$file" ]; then
        echo "cached: $file"
        return
    fi
    echo "rendering: $file ($SIZE x $SIZE, $spp spp, seed $seed)"
    # Rendered under a temporary name and renamed when complete: an interrupted render leaves
    # nothing that would later pass for a cached one.
    if ! "$BLENDER" -b --factory-startup --python "$SCRIPT" -- --spp "$spp" --seed "$seed" \
        --size "$SIZE" --out "$file.tmp.exr" > "$log" 2>&1; then
        echo "error: Blender failed; see $log" >&2
        exit 1
    fi
    local seconds
    seconds="$(sed -n 's/^cycles_seconds: //p' "$log")"
    if [ -z "$seconds" ] || [ ! -f "$file.tmp.exr" ]; then
        echo "error: no image or no time from Blender; see $log" >&2
        exit 1
    fi
    mv "$file.tmp.exr" "$file"
    echo "$spp,$seconds,$(basename "$file")" >> "$CSV"
    echo "  $seconds s"
}

render "$REF_SPP" 1 "ref_${SIZE}px_${REF_SPP}spp_seed1"
render "$REF_SPP" 2 "ref_${SIZE}px_${REF_SPP}spp_seed2"
for spp in "${SPP_LIST[@]}"; do
    render "$spp" $((1000 + spp)) "cycles_${SIZE}px_${spp}spp_seed$((1000 + spp))"
done
echo "times: $CSV"
