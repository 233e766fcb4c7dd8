#!/usr/bin/env bash
# Every include points to the same floor or lower (docs/architecture.md, "The floors").
#
# The core's folders stand on floors, lowest first:
#   0 geometry   1 sampling   2 accel, materials   3 scene   4 lights   5 io   6 render
# A file under common/F/ may include a header of its own folder or of a folder on a floor at or
# below F's. The chapters stand above the core, in the lecture's order: chapters/NN_*/ may include
# any core header and the headers of chapters numbered NN or lower (found by name in their
# folders), never a later lesson's. The core includes no chapter and no tool. A folder under
# common/ that is not in the table below is an error too, so that a new room must be given a floor.
# Prints each violation as "FILE:LINE: includes HEADER (floor X above floor Y)" and exits 1 if
# there is one; else prints how many includes it checked and exits 0.
# Usage: tests/check_include_floors.sh [REPOSITORY_ROOT]   (default: this script's parent folder)
#        tests/check_include_floors.sh --negative-control [REPOSITORY_ROOT]
# The second form checks the check: on a copy of the core and chapters in which geometry/math.h
# includes render/app.h and lesson 1 includes lesson 5's header, it must report both and fail.
set -euo pipefail

if [ "${1:-}" = "--negative-control" ]; then
    source_root="$(cd "${2:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
    copy="$(mktemp -d)"
    trap 'rm -rf "$copy"' EXIT
    cp -r "$source_root/common" "$source_root/chapters" "$copy/"
    echo '#include "render/app.h"' >>"$copy/common/geometry/math.h"
    echo '#include "bidirectional.h"' >>"$copy/chapters/01_ray_casting/ray_casting.cpp"
    if out="$(bash "${BASH_SOURCE[0]}" "$copy")"; then
        echo "negative control: the check passed a core with upward includes:"
        echo "$out"
        exit 1
    fi
    echo "$out"
    grep -q '^common/geometry/math.h:[0-9]*: includes "render/app.h" (floor 6' <<<"$out" &&
        grep -q '^chapters/01_ray_casting/ray_casting.cpp:[0-9]*: includes "bidirectional.h"' \
            <<<"$out" || { echo "negative control: a violation was not reported"; exit 1; }
    echo "negative control: both upward includes reported"
    exit 0
fi
ROOT="$(cd "${1:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
cd "$ROOT"

declare -A floor=([geometry]=0 [sampling]=1 [accel]=2 [materials]=2 [scene]=3 [lights]=4
                  [io]=5 [render]=6)
chapter_floor=7  # every chapter stands above the whole core

# Which chapter (its two-digit number) holds a header named by its bare name.
declare -A chapter_of_header=()
for h in chapters/[0-9][0-9]_*/*.h; do
    [ -e "$h" ] || continue
    number="$(basename "$(dirname "$h")")"
    chapter_of_header[$(basename "$h")]="${number:0:2}"
done

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
    header="$(sed -E 's/^[^"]*"([^"]+)".*$/\1/' <<<"${rest#*:}")"
    checked=$((checked + 1))
    case "$file" in
        common/*)
            room="$(cut -d/ -f2 <<<"$file")"
            from="${floor[$room]:-}"
            [ -n "$from" ] || continue  # reported above
            if [[ "$header" == */* ]]; then
                target="${header%%/*}"
                to="${floor[$target]:-}"
                if [ -z "$to" ]; then
                    report "$file:$line" "$header" "not a folder of the core"
                elif [ "$to" -gt "$from" ]; then
                    report "$file:$line" "$header" "floor $to, $target/, above floor $from, $room/"
                fi
            elif [ -n "${chapter_of_header[$header]+set}" ] && [ ! -e "common/$room/$header" ]; then
                report "$file:$line" "$header" "a chapter's header, above the whole core"
            fi
            ;;
        chapters/*)
            number="$(cut -d/ -f2 <<<"$file")"
            number="${number:0:2}"
            if [[ "$header" == */* ]]; then
                target="${header%%/*}"
                [ -n "${floor[$target]+set}" ] ||
                    report "$file:$line" "$header" "not a folder of the core"
            elif [ -n "${chapter_of_header[$header]+set}" ] &&
                 [ "${chapter_of_header[$header]}" \> "$number" ]; then
                report "$file:$line" "$header" \
                    "lesson ${chapter_of_header[$header]}'s header, a later lesson than $number"
            fi
            ;;
    esac
done < <(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]+"' common chapters \
             --include='*.h' --include='*.cpp')

[ "$checked" -gt 0 ] || { echo "check_include_floors: no includes found under $ROOT" >&2; exit 2; }
[ "$status" -eq 0 ] && echo "check_include_floors: $checked includes, every one at its floor or lower"
exit "$status"
