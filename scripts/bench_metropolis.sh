#!/usr/bin/env bash
# Lesson 7's targets, as figures (docs/07_metropolis.md):
#   1. scenes/door_ajar.toml at 384 x 256 against its shipped reference (lesson 4, 4096 spp):
#      lessons 4, 5, 6 (its default, vcm, is lesson 5 bit for bit in a scene without mirrors or
#      glass; so ppm and vpl) and 7 with the same time, at the lessons page's budget and four
#      times it, each run R times in turns (4 5 6 6 7 4 5 ...), with another seed each round: the
#      median MSE and its range, per run and budget.
#   2. scenes/cornell_box.toml at 128 x 128, 32 spp (lesson 7: 32 mutations per pixel), against a
#      lesson 5 reference rendered once here (4096 spp, cached in out/bench_metropolis/): seconds,
#      MSE and efficiency (1 / (MSE x seconds)) of lessons 5 and 7, R rounds in turns, medians.
# Usage: scripts/bench_metropolis.sh [ROUNDS] (default 3). Environment: BUDGET (default 4 s).
set -euo pipefail
ROUNDS="${1:-3}"
BUDGET="${BUDGET:-4}"
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
build_suite
cd "$ROOT"
BIN="$BUILD/bin"
OUT="${LESSONS_OUT:-$ROOT/out}/bench_metropolis"
mkdir -p "$OUT"
field() { sed -n "s/^  \"$2\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$1"; }
# median and range of the numbers on stdin
summary() { sort -g | awk '{v[NR] = $1} END {m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.4g [%.4g .. %.4g]", m, v[1], v[NR]}'; }

echo "== machine: $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), commit $(git rev-parse --short HEAD), $(date -u +%F)"
echo "== door_ajar, 384 x 256, against references/door_ajar (lesson 4, 4096 spp); MSE, median [range] of $ROUNDS"
RUNS=("lesson4|04_rendering_equation|" "lesson5|05_bidirectional|" "lesson6_ppm|06_photon_mapping|--method ppm"
      "lesson6_vpl|06_photon_mapping|--method vpl" "lesson7|07_metropolis|")
for budget in "$BUDGET" "$(awk "BEGIN {print 4 * $BUDGET}")"; do
    for round in $(seq 1 "$ROUNDS"); do
        for run in "${RUNS[@]}"; do
            IFS='|' read -r name lesson flags <<< "$run"
            # shellcheck disable=SC2086
            "$BIN/$lesson" --scene scenes/door_ajar.toml --width 384 --height 256 --time "$budget" \
                --seed "$round" --reference references/door_ajar/reference.exr --quiet $flags \
                --out "$OUT/door_$name" --report "$OUT/door_${name}_${budget}_$round.json"
        done
    done
    for run in "${RUNS[@]}"; do
        IFS='|' read -r name _ _ <<< "$run"
        mse="$(for round in $(seq 1 "$ROUNDS"); do field "$OUT/door_${name}_${budget}_$round.json" mse; done | summary)"
        spp="$(for round in $(seq 1 "$ROUNDS"); do field "$OUT/door_${name}_${budget}_$round.json" spp; done | summary)"
        printf '%-12s %5s s: MSE %s, spp %s\n' "$name" "$budget" "$mse" "$spp"
    done
done

echo "== cornell_box, 128 x 128, 32 spp, against lesson 5 at 4096 spp; median [range] of $ROUNDS"
if [ ! -f "$OUT/cornell_reference.exr" ]; then
    "$BIN/05_bidirectional" --scene scenes/cornell_box.toml --width 128 --height 128 --spp 4096 \
        --seed 1000003 --sampler independent --out "$OUT/cornell_reference" --quiet
fi
for round in $(seq 1 "$ROUNDS"); do
    for lesson in 05_bidirectional 07_metropolis; do
        "$BIN/$lesson" --scene scenes/cornell_box.toml --width 128 --height 128 --spp 32 \
            --seed "$round" --reference "$OUT/cornell_reference.exr" --quiet \
            --out "$OUT/cornell_$lesson" --report "$OUT/cornell_${lesson}_$round.json"
    done
done
for lesson in 05_bidirectional 07_metropolis; do
    row=""
    for f in seconds mse efficiency; do
        row+="$f $(for round in $(seq 1 "$ROUNDS"); do field "$OUT/cornell_${lesson}_$round.json" "$f"; done | summary), "
    done
    printf '%-24s %s\n' "$lesson" "${row%, }"
done
