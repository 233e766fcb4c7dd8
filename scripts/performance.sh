#!/usr/bin/env bash
# The figures of docs/performance.md, measured on this machine:
#   1. build/bin/bench_bvh: ray throughput, build time and memory against Embree 3, and lesson 4's
#      render throughput on 1 and 2 threads (out/perf/bench.csv);
#   2. the whole renderer against Blender's Cycles on scenes/cornell_box_rtiow.toml: RMSE against
#      time, each renderer against a converged reference of its own, rendered as two independent
#      halves whose own noise is estimated and subtracted (tools/compare --second-half);
#   3. time to Cycles' error (scripts/cycles_time_to_error.sh): lesson 4 on that box, lesson 5 on
#      scenes/cornell_spheres.toml (glass), each given a fraction of Cycles' time, in turns.
# Installs libembree-dev and blender (Debian's) first when missing; both are optional for the
# suite itself. References are cached in out/perf/ and out/cycles/ (delete them to redo them).
# Usage: scripts/performance.sh [--quick | --bench | --renders | --scaling]
#   --quick: bench_bvh --quick only (under a minute); --bench: bench_bvh only; --renders: the
#   comparison with Cycles only; --scaling: bench_bvh --scaling only (10k to 10M triangles,
#   about 2 minutes and 3.3 GB), with a log-log plot (out/perf/scaling.svg, gnuplot). The full
#   run does all of them. Environment: REF_SPP (default 512 per half), SPP_LIST.
set -euo pipefail

MODE="${1:-full}"
case "$MODE" in
    full | --quick | --bench | --renders | --scaling) ;;
    *) echo "usage: scripts/performance.sh [--quick | --bench | --renders | --scaling]" >&2; exit 2 ;;
esac

source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
install_missing_packages libembree-dev || echo "setup: Embree not installed: bench_bvh measures ours only" >&2
if [ "$MODE" = full ] || [ "$MODE" = --renders ]; then install_missing_packages blender python3-numpy; fi
build_suite
OUT="${LESSONS_OUT:-$ROOT/out}/perf"
CYCLES="${LESSONS_OUT:-$ROOT/out}/cycles/cornell_box_rtiow"
mkdir -p "$OUT"
cd "$ROOT"
BIN="$BUILD/bin"

echo "== machine: $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date +%F)"
if [ "$MODE" = --quick ]; then
    "$BIN/bench_bvh" --quick --csv "$OUT/bench_quick.csv"
    exit 0
fi
if [ "$MODE" = full ] || [ "$MODE" = --bench ]; then "$BIN/bench_bvh" --csv "$OUT/bench.csv"; fi
[ "$MODE" = --bench ] && exit 0
if [ "$MODE" = full ] || [ "$MODE" = --scaling ]; then
    # How cost grows: build time, memory and random-ray throughput against the triangle count.
    install_missing_packages gnuplot-nox
    "$BIN/bench_bvh" --scaling --csv "$OUT/scaling.csv"
    gnuplot <<PLOT
set terminal svg size 900,320 font "sans,11"
set output '$OUT/scaling.svg'
set datafile separator ','
set logscale xy
set xlabel 'triangles'
set multiplot layout 1,3
set title 'build, 1 thread (ms)'
plot '$OUT/scaling.csv' every ::1 using 1:2 with linespoints title 'ours', '' every ::1 using 1:3 with linespoints title 'Embree'
set title 'memory with the BVH (bytes)'
plot '$OUT/scaling.csv' every ::1 using 1:4 with linespoints title 'ours', '' every ::1 using 1:5 with linespoints title 'Embree'
set title 'random rays, closest hit (Mrays/s)'
plot '$OUT/scaling.csv' every ::1 using 1:6 with linespoints title 'ours', '' every ::1 using 1:7 with linespoints title 'Embree'
unset multiplot
PLOT
    echo "plot: $OUT/scaling.svg"
fi
[ "$MODE" = --scaling ] && exit 0

# ---- the whole renderer: lesson 4 and Cycles on the Cornell box of Ray Tracing in One Weekend ----
SCENE=scenes/cornell_box_rtiow.toml
REF_SPP="${REF_SPP:-512}"
SPP_LIST="${SPP_LIST:-16 64 256}"
field() { sed -n "s/.*\"$2\": \([0-9.eE+-]*\).*/\1/p" "$1" | head -1; }

# Both renderers' references (two halves each) and Cycles' renders: scripts/cycles_compare.sh,
# which also prints how the two references agree.
REF_SPP="$REF_SPP" LESSONS_BIN="$BIN" scripts/cycles_compare.sh --lesson 4 --dir "$CYCLES" "$SCENE" $SPP_LIST

CSV="$OUT/rtiow.csv"
echo "renderer,spp,seconds,rmse_corrected,reference_noise_rmse" > "$CSV"
for spp in $SPP_LIST; do
    # Ours: the render time as the lesson reports it (rendering only, 2 threads), with each
    # sampler (--sampler: independent random numbers, or a stratified Kronecker sequence), and
    # lesson 5 (bidirectional path tracing, which replaced lesson 4's --light-paths) on the
    # Kronecker sequence.
    for variant in independent kronecker kronecker+bidirectional; do
        sampler="${variant%%+*}"
        lesson=04_rendering_equation
        [ "$variant" = "${variant%+bidirectional}" ] || lesson=05_bidirectional
        name="ours_${variant}_${spp}spp"
        "$BIN/$lesson" --scene "$SCENE" --spp "$spp" --seed $((1000 + spp)) \
            --sampler "$sampler" --out "$OUT/$name" --report "$OUT/$name.json" --quiet
        seconds="$(field "$OUT/$name.json" seconds)"
        "$BIN/compare" "$OUT/$name.exr" "$CYCLES/ours_ref_${REF_SPP}spp_seed1.exr" \
            --second-half "$CYCLES/ours_ref_${REF_SPP}spp_seed2.exr" > "$OUT/${name}_error.json"
        echo "ours ($variant),$spp,$seconds,$(field "$OUT/${name}_error.json" rmse_corrected),$(
            awk -v m="$(field "$OUT/${name}_error.json" reference_noise_mse)" 'BEGIN{print sqrt(m)}')" >> "$CSV"
    done
    # Cycles: the wall time Blender measured around its render call (scene sync, BVH build,
    # rendering and writing the EXR; ours above counts rendering only).
    c="$CYCLES/cycles_${spp}spp.exr"
    seconds="$(grep ",$(basename "$c")\$" "$CYCLES/times.csv" | tail -1 | cut -d, -f3 || true)"
    [ -n "$seconds" ] || { echo "error: no time for $c in $CYCLES/times.csv: delete the image to render it again" >&2; exit 1; }
    "$BIN/compare" "$c" "$CYCLES/cycles_ref_${REF_SPP}spp_seed1.exr" \
        --second-half "$CYCLES/cycles_ref_${REF_SPP}spp_seed2.exr" > "$OUT/cycles_${spp}spp_error.json"
    echo "cycles,$spp,$seconds,$(field "$OUT/cycles_${spp}spp_error.json" rmse_corrected),$(
        awk -v m="$(field "$OUT/cycles_${spp}spp_error.json" reference_noise_mse)" 'BEGIN{print sqrt(m)}')" >> "$CSV"
done
echo "== RMSE against time (each renderer against its own reference): $CSV"
column -s, -t "$CSV"

# ---- time to Cycles' error: the lesson given a fraction of each Cycles run's time, in turns ----
# Lesson 4 with half of Cycles' time at its 64- and 256-spp errors on the same box; lesson 5 with
# a quarter of it at its 256-spp error on the box with a glass sphere lit by the small lamp, whose
# caustic Cycles' paths find only by hitting the lamp (256 x 256, so that both references fit).
REF_SPP="$REF_SPP" LESSONS_BIN="$BIN" scripts/cycles_time_to_error.sh --lesson 4 --dir "$CYCLES" \
    "$SCENE" 64 256
REF_SPP="$REF_SPP" LESSONS_BIN="$BIN" scripts/cycles_time_to_error.sh --lesson 5 --fraction 0.25 \
    --width 256 --height 256 --dir "${LESSONS_OUT:-$ROOT/out}/cycles/cornell_spheres_256" \
    scenes/cornell_spheres.toml 256
