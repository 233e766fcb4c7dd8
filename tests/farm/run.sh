#!/usr/bin/env bash
# The farm's tests (docs/farm.md): parts of a render merge back bit for bit into the single run,
# for every lesson and every way of splitting; every refusal says what is wrong; an interrupted
# part merges to the image of the samples it holds; scripts/farm/plan.sh with GNU parallel, and
# its Slurm scripts run task by task as Slurm would run them (with real daemons: live.sh).
#
#   tests/farm/run.sh BUILD_DIR merge|refusals|interrupt|plan
set -euo pipefail
BUILD=$(cd "$1" && pwd)
MODE=$2
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BIN=$BUILD/bin
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cd "$ROOT"

fail() { echo "FAIL: $*" >&2; exit 1; }
same() {  # same FILE_A FILE_B WHAT: byte for byte
    cmp -s "$1" "$2" || fail "$3: $1 and $2 differ"
}
# expect_refusal WHAT EXPECTED_TEXT COMMAND...: exit status 2 and the message on stderr.
expect_refusal() {
    local what=$1 text=$2
    shift 2
    local status=0
    "$@" > "$WORK/out.txt" 2> "$WORK/err.txt" || status=$?
    [ "$status" -eq 2 ] || { cat "$WORK/err.txt" >&2; fail "$what: exit status $status, not 2"; }
    grep -qF -- "$text" "$WORK/err.txt" || {
        cat "$WORK/err.txt" >&2
        fail "$what: the message does not say '$text'"
    }
    echo "ok: $what: $(head -c 300 "$WORK/err.txt")"
}

SIZE=(--width 32 --height 24)
SPP=8

# check_lesson NAME DIR FLAGS...: the single run, then 4 sample ranges, 4 tiles and 2 x 2, each
# merged and compared, file by file (the image and every layer), with the single run's.
check_lesson() {
    local lesson=$1 dir=$WORK/$2
    shift 2
    local run=("$BIN/$lesson" --quiet "${SIZE[@]}" "$@")
    mkdir -p "$dir"
    "${run[@]}" --spp $SPP --out "$dir/single"
    local splits=(samples)
    # Lessons 5 and 6 render whole passes over the image (splats, photons): by samples only.
    case "$lesson" in 05_* | 06_*) ;; *) splits+=(tiles both) ;; esac
    for split in "${splits[@]}"; do
        local parts=()
        case $split in
            samples)
                for r in 0:1 1:3 3:6 6:8; do
                    "${run[@]}" --samples $r --out "$dir/$split/p$r"
                    parts+=("$dir/$split/p$r.exr")
                done ;;
            tiles)
                for p in 0:16,0:12 16:32,0:12 0:16,12:24 16:32,12:24; do
                    "${run[@]}" --spp $SPP --pixels $p --threads 1 --out "$dir/$split/p$p"
                    parts+=("$dir/$split/p$p.exr")
                done ;;
            both)
                for r in 0:5 5:8; do
                    for p in 0:32,0:7 0:32,7:24; do
                        "${run[@]}" --samples $r --pixels $p --out "$dir/$split/p$r-$p"
                        parts+=("$dir/$split/p$r-$p.exr")
                    done
                done ;;
        esac
        "$BIN/merge" --quiet "${parts[@]}" --out "$dir/$split/merged"
        for single in "$dir"/single*.exr; do
            local suffix=${single#"$dir/single"}
            same "$single" "$dir/$split/merged$suffix" "$lesson $* ($split)"
        done
        echo "ok: $lesson $* merged from ${#parts[@]} parts ($split): bit-identical ($(ls "$dir"/single*.exr | wc -l) EXRs)"
    done
}

case $MODE in
merge)
    check_lesson 01_ray_casting l1 --scene scenes/cornell_box.toml
    check_lesson 02_whitted l2 --scene scenes/cornell_spheres.toml
    check_lesson 03_reflection_equation l3 --scene scenes/cornell_box.toml
    check_lesson 03_reflection_equation l3u --scene scenes/cornell_box.toml --estimator uniform
    check_lesson 04_rendering_equation l4 --scene scenes/cornell_spheres.toml --bounces 2
    check_lesson 04_rendering_equation l4i --scene scenes/cornell_box.toml --sampler independent \
        --clamp 4
    check_lesson 05_bidirectional l5 --scene scenes/cornell_spheres.toml --strategies 2
    check_lesson 06_photon_mapping l6 --scene scenes/cornell_spheres.toml --techniques
    check_lesson 06_photon_mapping l6p --scene scenes/cornell_spheres.toml --method ppm
    # Lesson 7's passes are rounds of chains over the whole image (the render loop sees no
    # splats), so a crop runs its passes' chains whole and keeps its pixels: both splits.
    check_lesson 07_metropolis l7 --scene scenes/cornell_spheres.toml
    ;;

refusals)
    L4=("$BIN/04_rendering_equation" --quiet --scene scenes/cornell_box.toml "${SIZE[@]}")
    "${L4[@]}" --samples 0:4 --out "$WORK/a"
    "${L4[@]}" --samples 4:8 --out "$WORK/b"
    "${L4[@]}" --samples 4:8 --seed 7 --out "$WORK/seed"
    "${L4[@]}" --samples 4:8 --clamp 2 --out "$WORK/clamp"
    "${L4[@]}" --samples 2:6 --out "$WORK/overlap"
    "${L4[@]}" --samples 8:12 --out "$WORK/gap"
    "${L4[@]}" --samples 4:8 --pixels 0:16,0:24 --out "$WORK/half"
    "${L4[@]}" --samples 4:8 --pixels 8:32,0:24 --out "$WORK/tile_overlap"
    "$BIN/03_reflection_equation" --quiet --scene scenes/cornell_box.toml "${SIZE[@]}" \
        --samples 4:8 --out "$WORK/lesson3"
    "$BIN/04_rendering_equation" --quiet --scene scenes/cornell_spheres.toml "${SIZE[@]}" \
        --samples 4:8 --out "$WORK/scene"
    "$BIN/04_rendering_equation" --quiet --scene scenes/cornell_box.toml --width 32 \
        --height 20 --samples 4:8 --out "$WORK/size"
    "${L4[@]}" --spp 4 --out "$WORK/plain"
    "$BIN/merge" --quiet "$WORK/a.exr" "$WORK/b.exr" --out "$WORK/ok"  # (these two do merge)

    M=("$BIN/merge" --quiet)
    LESSONS_RAYS_NAME=lessons.rays
    expect_refusal "another seed" "lessons.seed: is '7'" "${M[@]}" "$WORK/a.exr" "$WORK/seed.exr" --out "$WORK/x"
    expect_refusal "other options" "lessons.options: is '--clamp=2'" "${M[@]}" "$WORK/a.exr" "$WORK/clamp.exr" --out "$WORK/x"
    expect_refusal "another lesson" "lessons.lesson: is '03_reflection_equation'" "${M[@]}" "$WORK/a.exr" "$WORK/lesson3.exr" --out "$WORK/x"
    expect_refusal "another scene" "lessons.scene_hash: the scene scenes/cornell_spheres.toml" "${M[@]}" "$WORK/a.exr" "$WORK/scene.exr" --out "$WORK/x"
    expect_refusal "another size" "lessons.image: is '32x20'" "${M[@]}" "$WORK/a.exr" "$WORK/size.exr" --out "$WORK/x"
    expect_refusal "overlapping samples" "holds samples 2:4 of pixels 0:32,0:24, which $WORK/a.exr holds too" "${M[@]}" "$WORK/a.exr" "$WORK/overlap.exr" --out "$WORK/x"
    expect_refusal "overlapping crops" "holds samples 4:8 of pixels 8:16,0:24, which $WORK/half.exr holds too" "${M[@]}" "$WORK/a.exr" "$WORK/half.exr" "$WORK/tile_overlap.exr" --out "$WORK/x"
    expect_refusal "a missing sample range" "missing samples 8:12 of pixels 0:32,0:24" "${M[@]}" "$WORK/a.exr" "$WORK/b.exr" --spp 12 --out "$WORK/x"
    expect_refusal "--spp below what the parts hold" "--spp: $WORK/b.exr holds samples 4:8, past the 6 asked for" "${M[@]}" "$WORK/a.exr" "$WORK/b.exr" --spp 6 --out "$WORK/x"
    expect_refusal "a gap in the samples" "missing samples 4:8 of pixels 0:32,0:24" "${M[@]}" "$WORK/a.exr" "$WORK/gap.exr" --out "$WORK/x"
    expect_refusal "a missing crop" "missing samples 4:8 of pixels 16:32,0:24" "${M[@]}" "$WORK/a.exr" "$WORK/half.exr" --out "$WORK/x"
    expect_refusal "a plain EXR" "lessons.format: missing: this EXR is not a part" "${M[@]}" "$WORK/a.exr" "$WORK/plain.exr" --out "$WORK/x"
    expect_refusal "no such part" "part EXR not found" "${M[@]}" "$WORK/a.exr" "$WORK/none.exr" --out "$WORK/x"
    size=$(stat -c %s "$WORK/b.exr")
    head -c $((size - 100)) "$WORK/b.exr" > "$WORK/truncated.exr"
    expect_refusal "a truncated part" "$WORK/truncated.exr: " "${M[@]}" "$WORK/a.exr" "$WORK/truncated.exr" --out "$WORK/x"
    grep -qE "truncated|damaged" "$WORK/err.txt" || fail "a truncated part: not said to be truncated or damaged"
    # One byte changed in the middle of the pixels: the checksum, if not the decompression, sees it.
    cp "$WORK/b.exr" "$WORK/flipped.exr"
    python3 -c 'import sys; p, at = sys.argv[1], int(sys.argv[2]); b = bytearray(open(p, "rb").read()); b[at] ^= 0xff; open(p, "wb").write(b)' "$WORK/flipped.exr" $((size - 2000))
    expect_refusal "a damaged part" "$WORK/flipped.exr" "${M[@]}" "$WORK/a.exr" "$WORK/flipped.exr" --out "$WORK/x"
    # A header changed: the rays' count (a digit for another) passes OpenEXR, not the checksum.
    cp "$WORK/b.exr" "$WORK/edited.exr"
    offset=$(grep -abo 'lessons.rays' "$WORK/edited.exr" | head -1 | cut -d: -f1)
    value_at=$((offset + ${#LESSONS_RAYS_NAME} + 1 + 7 + 4))  # name, NUL, "string", NUL, size
    old_digit=$(dd if="$WORK/edited.exr" bs=1 skip=$value_at count=1 status=none)
    new_digit=$(( (old_digit + 1) % 10 ))
    printf '%s' "$new_digit" | dd of="$WORK/edited.exr" bs=1 seek=$value_at conv=notrunc status=none
    expect_refusal "an edited header" "lessons.checksum: does not match the part's header and pixels" "${M[@]}" "$WORK/a.exr" "$WORK/edited.exr" --out "$WORK/x"
    [ ! -e "$WORK/x.exr" ] || fail "a refused merge wrote an image"

    expect_refusal "--spp and --samples" "--samples: give --spp or --samples, not both" "${L4[@]}" --spp 4 --samples 0:4 --out "$WORK/x"
    expect_refusal "an empty range" "--samples: '5:3' is not a range of sample indices A:B" "${L4[@]}" --samples 5:3 --out "$WORK/x"
    expect_refusal "a range that is not one" "--samples: 'a:b' is not" "${L4[@]}" --samples a:b --out "$WORK/x"
    expect_refusal "a crop outside the image" "--pixels: '0:40,0:24' reaches outside the 32x24 image" "${L4[@]}" --pixels 0:40,0:24 --out "$WORK/x"
    expect_refusal "a crop without rows" "--pixels: '0:16' is not a crop X0:X1,Y0:Y1" "${L4[@]}" --pixels 0:16 --out "$WORK/x"
    expect_refusal "a part with --time" "--time: a part renders a given range of samples" "${L4[@]}" --samples 0:4 --time 1 --out "$WORK/x"
    expect_refusal "a crop of lesson 5" "--pixels: 05_bidirectional splats light onto pixels anywhere in the image" "$BIN/05_bidirectional" --quiet --scene scenes/cornell_box.toml "${SIZE[@]}" --pixels 0:16,0:24 --out "$WORK/x"
    ;;

interrupt)
    # A part far too long to finish, stopped by SIGINT once it has rendered a while.
    L4=("$BIN/04_rendering_equation" --scene scenes/cornell_box.toml --width 32 --height 24 --threads 2)
    "${L4[@]}" --samples 0:100000 --out "$WORK/part" --report "$WORK/part.json" 2> "$WORK/err.txt" &
    pid=$!
    # Once it prints its header (the Ctrl-C handler is installed right after), let it render.
    for _ in $(seq 300); do
        grep -q ' threads$' "$WORK/err.txt" 2> /dev/null && break
        sleep 0.1
    done
    sleep 1
    kill -INT $pid
    status=0
    wait $pid || status=$?
    [ "$status" -eq 130 ] || { cat "$WORK/err.txt"; fail "the interrupted part exited with $status, not 130"; }
    taken=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["samples"].split(":")[1])' "$WORK/part.json")
    [ "$taken" -gt 0 ] && [ "$taken" -lt 100000 ] || fail "the interrupted part holds $taken samples"
    "$BIN/merge" --status "$WORK/part.exr" > "$WORK/status.txt"
    grep -qF "samples 0:$taken (interrupted; asked for 0:100000)" "$WORK/status.txt" ||
        { cat "$WORK/status.txt"; fail "the status does not show the part as interrupted at $taken"; }
    # Its plan was 100000 samples: the merge says what is missing, and merges what it has
    # when told that that is what is wanted.
    expect_refusal "an interrupted part alone" "missing samples $taken:100000 of pixels 0:32,0:24" \
        "$BIN/merge" --quiet "$WORK/part.exr" --out "$WORK/merged"
    "$BIN/merge" --quiet "$WORK/part.exr" --spp "$taken" --out "$WORK/merged"
    "${L4[@]}" --quiet --spp "$taken" --out "$WORK/single"
    same "$WORK/single.exr" "$WORK/merged.exr" "the interrupted part ($taken samples)"
    echo "ok: a part interrupted after $taken samples merges to the single run with --spp $taken, bit for bit"
    ;;

plan)
    command -v parallel > /dev/null || fail "GNU parallel is not installed (scripts/setup.sh installs it)"
    L=04_rendering_equation
    FLAGS=(--scene scenes/cornell_spheres.toml "${SIZE[@]}")
    "$BIN/$L" --quiet "${FLAGS[@]}" --spp 24 --out "$WORK/single"
    # 8 parts: 4 sample ranges x 2 tiles, run by GNU parallel on this machine.
    scripts/farm/plan.sh --lesson $L --spp 24 --parts 4 --tiles 1x2 --dir "$WORK/farm" \
        --bin "$BIN" -- "${FLAGS[@]}" > "$WORK/plan.txt"
    cat "$WORK/plan.txt"
    [ "$(wc -l < "$WORK/farm/parts.txt")" -eq 8 ] || fail "the plan does not have 8 parts"
    cmd=$(grep '^parallel ' "$WORK/plan.txt" | head -1)
    [ -n "$cmd" ] || fail "the plan prints no GNU parallel command"
    bash -c "$cmd"
    "$BIN/merge" --status $(cat "$WORK/farm/part_files.txt") | tail -1 | grep -qx "complete: merge them" ||
        fail "merge --status does not see the farm complete"
    bash -c "$(grep '^build/bin/merge\|/merge ' "$WORK/plan.txt" | grep -v -- --status | head -1)"
    same "$WORK/single.exr" "$WORK/farm/merged.exr" "plan.sh + GNU parallel, 8 parts"
    echo "ok: scripts/farm/plan.sh + GNU parallel: 8 parts merged bit-identical to the single run"

    # The Slurm scripts: syntax, then each array task as Slurm runs it (SLURM_ARRAY_TASK_ID set,
    # srun a stub that runs its command here), then the merge job.
    scripts/farm/plan.sh --lesson $L --spp 24 --parts 8 --dir "$WORK/slurm" --slurm \
        --bin "$BIN" -- "${FLAGS[@]}" > "$WORK/slurm_plan.txt"
    grep -q "sbatch --parsable --array=0-7" "$WORK/slurm_plan.txt" || fail "no array job in the Slurm plan"
    grep -q "dependency=afterok" "$WORK/slurm_plan.txt" || fail "no dependent merge job in the Slurm plan"
    bash -n "$WORK/slurm/farm.sbatch" && bash -n "$WORK/slurm/merge.sbatch"
    grep -q "^#SBATCH --array=0-7" "$WORK/slurm/farm.sbatch" || fail "farm.sbatch has no --array"
    grep -q "^#SBATCH --cpus-per-task=1" "$WORK/slurm/farm.sbatch" || fail "farm.sbatch asks for no CPUs"
    grep -q '^# parallel --will-cite --sshlogin HOST1,HOST2 ' "$WORK/slurm_plan.txt" ||
        fail "without --hosts, the ssh line is not a comment with HOST1,HOST2 to fill in"
    expect_refusal "plan.sh: --spp among the lesson's flags" "the plan sets --spp itself" \
        scripts/farm/plan.sh --lesson $L --spp 24 --parts 8 --dir "$WORK/bad" --bin "$BIN" -- --spp=4
    expect_refusal "plan.sh: tiles without a size" "--tiles: give the image size" \
        scripts/farm/plan.sh --lesson $L --spp 24 --parts 2 --tiles 2x2 --dir "$WORK/bad" --bin "$BIN" -- --scene scenes/cornell_box.toml
    expect_refusal "plan.sh: more parts than samples" "--parts: 30 sample ranges of 24 samples" \
        scripts/farm/plan.sh --lesson $L --spp 24 --parts 30 --dir "$WORK/bad" --bin "$BIN"
    mkdir -p "$WORK/stub"
    printf '#!/bin/sh\nexec "$@"\n' > "$WORK/stub/srun"
    chmod +x "$WORK/stub/srun"
    for task in $(seq 0 7); do
        PATH="$WORK/stub:$PATH" SLURM_ARRAY_TASK_ID=$task bash "$WORK/slurm/farm.sbatch"
    done
    PATH="$WORK/stub:$PATH" bash "$WORK/slurm/merge.sbatch"
    same "$WORK/single.exr" "$WORK/slurm/merged.exr" "the Slurm scripts, 8 tasks"
    echo "ok: the Slurm array job's 8 tasks and its merge job (srun stubbed) give the single run, bit for bit"
    # The last sample range not there: the parts there hold every sample they were asked for
    # (0:21), and the farm is still incomplete.
    rm "$WORK/slurm/part_0007.exr"
    "$BIN/merge" --status $(cat "$WORK/slurm/part_files.txt") > "$WORK/status.txt"
    grep -qF "$WORK/slurm/part_0007.exr: not there yet" "$WORK/status.txt" &&
        tail -1 "$WORK/status.txt" | grep -qx "incomplete: 1 of the 8 parts named is not there or unreadable" ||
        { cat "$WORK/status.txt"; fail "merge --status does not see the last part missing"; }
    echo "ok: merge --status: the last sample range not there leaves the farm incomplete"
    ;;
*)
    fail "unknown mode $MODE" ;;
esac
