#!/usr/bin/env bash
# Plans a render split across jobs (docs/farm.md): writes one lesson command per part and prints
# how to run them with GNU parallel (this machine's cores, or other machines over ssh) or as a
# Slurm array job with a dependent merge job, and how to watch and merge them.
#
#   scripts/farm/plan.sh --lesson LESSON --spp N --parts K [--tiles CxR] [--dir DIR]
#                        [--threads T] [--hosts H1,H2] [--slurm] [--bin DIR] [--jobs J]
#                        -- LESSON_FLAGS...
#
# The parts are K ranges of sample indices (and, with --tiles, C x R crops of the image each:
# K x C x R parts; --tiles needs --width and --height among the lesson's flags). Each part runs
# on T threads (default 1; a Slurm task asks for T CPUs), GNU parallel runs J at once (default:
# cores / T). Each part is one line of DIR/parts.txt; DIR/part_files.txt lists the part EXRs.
# With --hosts (GNU parallel's --sshlogin list), the line that runs them over ssh is printed ready
# to run; without, it is printed as a comment with HOST1,HOST2 to fill in.
# With --slurm, also writes DIR/farm.sbatch (task i runs line i + 1) and DIR/merge.sbatch.
# Nothing is run here.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

usage() { sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }
die() { echo "plan.sh: error: $*" >&2; exit 2; }

LESSON="" SPP="" PARTS="" TILES="1x1" DIR="farm" SLURM=0 BIN="$ROOT/build/bin" JOBS="" THREADS=1
HOSTS=""
while [ $# -gt 0 ]; do
    case $1 in
        --lesson) LESSON=$2; shift 2 ;;
        --spp) SPP=$2; shift 2 ;;
        --parts) PARTS=$2; shift 2 ;;
        --tiles) TILES=$2; shift 2 ;;
        --dir) DIR=$2; shift 2 ;;
        --bin) BIN=$2; shift 2 ;;
        --jobs) JOBS=$2; shift 2 ;;
        --threads) THREADS=$2; shift 2 ;;
        --hosts) HOSTS=$2; shift 2 ;;
        --slurm) SLURM=1; shift ;;
        --help|-h) usage ;;
        --) shift; break ;;
        *) die "unknown option '$1' (the lesson's flags go after --)" ;;
    esac
done
FLAGS=("$@")
[ -n "$LESSON" ] && [ -n "$SPP" ] && [ -n "$PARTS" ] || usage
[[ $SPP =~ ^[1-9][0-9]*$ ]] || die "--spp: '$SPP' is not a positive count"
[[ $PARTS =~ ^[1-9][0-9]*$ ]] || die "--parts: '$PARTS' is not a positive count"
[ "$PARTS" -le "$SPP" ] || die "--parts: $PARTS sample ranges of $SPP samples would leave some empty"
[[ $THREADS =~ ^[1-9][0-9]*$ ]] || die "--threads: '$THREADS' is not a positive count"
[ -n "$JOBS" ] || JOBS=$(( $(nproc) / THREADS > 0 ? $(nproc) / THREADS : 1 ))
[[ $JOBS =~ ^[1-9][0-9]*$ ]] || die "--jobs: '$JOBS' is not a positive count"
[[ -z $HOSTS || $HOSTS =~ ^[^[:space:]]+$ ]] || die "--hosts: '$HOSTS' is not a comma-separated list of ssh logins"
[[ $TILES =~ ^([1-9][0-9]*)x([1-9][0-9]*)$ ]] || die "--tiles: '$TILES' is not COLUMNSxROWS"
COLS=${BASH_REMATCH[1]} ROWS=${BASH_REMATCH[2]}
[ -x "$BIN/$LESSON" ] || die "--lesson: no $BIN/$LESSON (build first: scripts/test.sh --quick, or cmake --build build)"
for f in "${FLAGS[@]}"; do
    case $f in
        --spp|--spp=*|--samples|--samples=*|--pixels|--pixels=*|--out|--out=*|--time|--time=*|--threads|--threads=*)
            die "the plan sets ${f%%=*} itself: leave it out of the lesson's flags" ;;
        --width=*|--height=*) die "write ${f%%=*} W as two words, so that the plan can read it" ;;
    esac
done

WIDTH="" HEIGHT=""
for ((i = 0; i < ${#FLAGS[@]}; ++i)); do
    case ${FLAGS[i]} in
        --width) WIDTH=${FLAGS[i + 1]:-} ;;
        --height) HEIGHT=${FLAGS[i + 1]:-} ;;
    esac
done
if [ "$COLS" -gt 1 ] || [ "$ROWS" -gt 1 ]; then
    [ -n "$WIDTH" ] && [ -n "$HEIGHT" ] || die "--tiles: give the image size as --width W --height H among the lesson's flags"
    [ "$COLS" -le "$WIDTH" ] && [ "$ROWS" -le "$HEIGHT" ] || die "--tiles: more tiles than pixels"
fi

mkdir -p "$DIR"
DIR=$(cd "$DIR" && pwd)
WORKDIR=$PWD
if [ "$SLURM" -eq 1 ] && [[ "$DIR$WORKDIR" =~ [[:space:]] ]]; then
    die "--slurm: #SBATCH lines cannot quote a path with spaces: use a --dir and a folder without"
fi
q() {  # the arguments quoted for the shell, separated by spaces
    local s
    s=$(printf '%q ' "$@")
    printf '%s' "${s% }"
}

: > "$DIR/parts.txt"
: > "$DIR/part_files.txt"
n=0
for ((k = 0; k < PARTS; ++k)); do
    a=$((k * SPP / PARTS)) b=$(((k + 1) * SPP / PARTS))
    for ((r = 0; r < ROWS; ++r)); do
        for ((c = 0; c < COLS; ++c)); do
            part=$(printf '%s/part_%04d' "$DIR" $n)
            crop=()
            if [ "$COLS" -gt 1 ] || [ "$ROWS" -gt 1 ]; then
                crop=(--pixels "$((c * WIDTH / COLS)):$(((c + 1) * WIDTH / COLS)),$((r * HEIGHT / ROWS)):$(((r + 1) * HEIGHT / ROWS))")
            fi
            echo "$(q "$BIN/$LESSON" "${FLAGS[@]}" --samples "$a:$b" "${crop[@]}" --threads "$THREADS" --quiet --out "$part")" >> "$DIR/parts.txt"
            echo "$part.exr" >> "$DIR/part_files.txt"
            n=$((n + 1))
        done
    done
done

MERGE="$(q "$BIN/merge") \$(cat $(q "$DIR/part_files.txt")) --out $(q "$DIR/merged")"
STATUS="$(q "$BIN/merge") --status \$(cat $(q "$DIR/part_files.txt"))"
echo "# $n parts of $LESSON at $SPP spp ($PARTS sample ranges x $COLS x $ROWS tiles): $DIR/parts.txt"
echo "# Run them on this machine's cores with GNU parallel:"
echo "parallel --will-cite --jobs $JOBS --halt soon,fail=1 < $(q "$DIR/parts.txt")"
echo "# or on other machines that see this folder at the same path (ssh logins):"
LOGINS=HOST1,HOST2
[ -z "$HOSTS" ] || LOGINS=$(q "$HOSTS")
SSH_LINE="parallel --will-cite --sshlogin $LOGINS --workdir $(q "$WORKDIR") --halt soon,fail=1 < $(q "$DIR/parts.txt")"
if [ -n "$HOSTS" ]; then echo "$SSH_LINE"; else echo "# $SSH_LINE"; fi
echo "# Progress, and a preview of what there is (--out):"
echo "$STATUS"
echo "# When every part is there:"
echo "$MERGE"

if [ "$SLURM" -eq 1 ]; then
    cat > "$DIR/farm.sbatch" <<SBATCH
#!/bin/bash
# Array task i renders part i (line i + 1 of parts.txt). Written by scripts/farm/plan.sh.
#SBATCH --job-name=lessons-$LESSON
#SBATCH --array=0-$((n - 1))
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=$THREADS
#SBATCH --output=$DIR/slurm_%A_%a.log
set -euo pipefail
cd $(q "$WORKDIR")
line=\$(sed -n "\$((SLURM_ARRAY_TASK_ID + 1))p" $(q "$DIR/parts.txt"))
[ -n "\$line" ] || { echo "no part \$SLURM_ARRAY_TASK_ID in $DIR/parts.txt" >&2; exit 2; }
srun bash -c "\$line"
SBATCH
    cat > "$DIR/merge.sbatch" <<SBATCH
#!/bin/bash
# Merges the parts once the array job is done. Written by scripts/farm/plan.sh.
#SBATCH --job-name=lessons-merge
#SBATCH --ntasks=1
#SBATCH --output=$DIR/slurm_merge.log
set -euo pipefail
cd $(q "$WORKDIR")
srun $MERGE
SBATCH
    echo "# On a Slurm cluster: the array job, then the merge once every task has succeeded:"
    echo "jobid=\$(sbatch --parsable --array=0-$((n - 1)) $(q "$DIR/farm.sbatch")) && echo \"Submitted array job \$jobid\" && sbatch --dependency=afterok:\$jobid $(q "$DIR/merge.sbatch")"
fi
