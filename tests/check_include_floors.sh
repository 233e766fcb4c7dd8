#!/usr/bin/env bash
# Every include points to the same floor or lower (docs/architecture.md, "The floors").
#
# The core's folders stand on floors, lowest first:
#   0 geometry   1 sampling   2 accel, materials, media   3 scene   4 lights   5 io   6 render   7 farm
#   8 driver
# A file under common/F/ may include a header of its own folder or of a folder on a floor at or
# below F's. The chapters stand above the core, in the lecture's order: a file of chapters/NN_*/
# may include any core header and the headers of chapters numbered NN or lower, never a later
# lesson's. Every quoted include names its folder ("render/film.h", "05_bidirectional/mis.h"),
# so the lesson or floor of a header is read from its path; an include that names no folder, or
# a folder that is neither a core folder nor a lesson, is an error. The core includes no chapter
# and no tool. A folder under common/ that is not in the table below is an error too, so that a
# new room must be given a floor.
# Prints each violation as "FILE:LINE: includes HEADER (why)" and exits 1 if there is one; else
# prints how many includes it checked and exits 0.
# Usage: tests/check_include_floors.sh [REPOSITORY_ROOT]   (default: this script's parent folder)
#        tests/check_include_floors.sh --negative-control [REPOSITORY_ROOT]
# The second form checks the check: on a copy of the core and chapters in which geometry/math.h
# includes driver/app.h, render/film.h includes farm/part.h, lesson 1 includes lesson 5's header
# and lesson 4's own header by its bare name, io/image.h a lesson's header, and sampling/rng.h
# <driver/lesson.h> in angle brackets, it must report all six and fail. (Bash 4: declare -A.)
set -euo pipefail

if [ "${1:-}" = "--negative-control" ]; then
    source_root="$(cd "${2:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
    copy="$(mktemp -d)"
    trap 'rm -rf "$copy"' EXIT
    cp -r "$source_root/common" "$source_root/chapters" "$copy/"
    echo '#include "driver/app.h"' >>"$copy/common/geometry/math.h"
    echo '#include "farm/part.h"' >>"$copy/common/render/film.h"
    echo '#include "05_bidirectional/bidirectional.h"' >>"$copy/chapters/01_ray_casting/ray_casting.cpp"
    echo '#include "rendering_equation.h"' >>"$copy/chapters/04_rendering_equation/lesson.cpp"
    echo '#include "01_ray_casting/ray_casting.h"' >>"$copy/common/io/image.h"
    echo '#include <driver/lesson.h>' >>"$copy/common/sampling/rng.h"
    if out="$(bash "${BASH_SOURCE[0]}" "$copy")"; then
        echo "negative control: the check passed a core with upward includes:"
        echo "$out"
        exit 1
    fi
    echo "$out"
    missing=0
    for expected in \
        '^common/geometry/math.h:[0-9]*: includes "driver/app.h" (floor 8' \
        '^common/render/film.h:[0-9]*: includes "farm/part.h" (floor 7' \
        '^chapters/01_ray_casting/ray_casting.cpp:[0-9]*: includes "05_bidirectional/bidirectional.h" (lesson 05' \
        '^chapters/04_rendering_equation/lesson.cpp:[0-9]*: includes "rendering_equation.h" (names no folder' \
        '^common/io/image.h:[0-9]*: includes "01_ray_casting/ray_casting.h" (a lesson' \
        '^common/sampling/rng.h:[0-9]*: includes "driver/lesson.h" (floor 8'; do
        grep -q "$expected" <<<"$out" || { echo "negative control: not reported: $expected"; missing=1; }
    done
    [ "$missing" -eq 0 ] || exit 1
    echo "negative control: all six planted includes reported"
    exit 0
fi
ROOT="$(cd "${1:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
cd "$ROOT"

declare -A floor=([geometry]=0 [sampling]=1 [accel]=2 [materials]=2 [media]=2 [scene]=3 [lights]=4
                  [io]=5 [render]=6 [farm]=7 [driver]=8)

status=0
checked=0
report() {  # file:line, header, message
    echo "$1: includes \"$2\" ($3)"
    status=1
}

for dir in common/*/; do
    room="$(basename "$dir")"
    if [ -z "${floor[$room]+set}" ]; then
        echo "common/$room/: a folder with no floor: add it to the table in $0 and to docs/architecture.md"
        status=1
    fi
done

while IFS= read -r hit; do
    file="${hit%%:*}"
    rest="${hit#*:}"
    line="${rest%%:*}"
    header="$(sed -E 's/^[^"<]*["<]([^">]+)[">].*$/\1/' <<<"${rest#*:}")"
    # An angle include is the core's or a lesson's only if it names a core folder or a lesson's
    # (the core and chapters/ are on the include path, so <render/film.h> would compile too).
    if [[ "${rest#*:}" =~ \<[^\>]*\> ]]; then
        first="${header%%/*}"
        [[ "$header" == */* ]] && { [ -n "${floor[$first]+set}" ] || [[ "$first" =~ ^[0-9][0-9]_ ]]; } ||
            continue
    fi
    checked=$((checked + 1))
    if [[ "$header" != */* ]]; then
        report "$file:$line" "$header" "names no folder: write it as \"FOLDER/$header\""
        continue
    fi
    target="${header%%/*}"
    # The including file's place: a core folder's floor, or a lesson's number.
    case "$file" in
        common/*) room="$(cut -d/ -f2 <<<"$file")"; from="${floor[$room]:-}"; number="" ;;
        chapters/[0-9][0-9]_*/*) lesson="$(cut -d/ -f2 <<<"$file")"; number="${lesson:0:2}"; from="" ;;
        *) number="99"; from="" ;;  # chapters/all_lessons.h and the like: above every lesson
    esac
    if [[ "$target" =~ ^[0-9][0-9]_ ]]; then
        if [ ! -d "chapters/$target" ]; then
            report "$file:$line" "$header" "not a lesson's folder"
        elif [ -z "$number" ]; then
            report "$file:$line" "$header" "a lesson's header, above the whole core"
        elif [ "${target:0:2}" \> "$number" ]; then
            report "$file:$line" "$header" "lesson ${target:0:2}'s header, a later lesson than $number"
        fi
    elif [ -z "${floor[$target]+set}" ]; then
        report "$file:$line" "$header" "not a folder of the core or a lesson"
    elif [ -n "$from" ] && [ "${floor[$target]}" -gt "$from" ]; then
        report "$file:$line" "$header" "floor ${floor[$target]}, $target/, above floor $from, $room/"
    fi
done < <(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]' common chapters \
             --include='*.h' --include='*.cpp')

[ "$checked" -gt 0 ] || { echo "check_include_floors: no includes found under $ROOT" >&2; exit 2; }
[ "$status" -eq 0 ] && echo "check_include_floors: $checked includes, every one at its floor or lower"
exit "$status"
