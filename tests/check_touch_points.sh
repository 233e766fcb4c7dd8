#!/usr/bin/env bash
# The places a new material type and a new light kind touch are the ones docs/architecture.md
# lists ("How to add ...", the paragraphs "A material" and "A light").
#
# Each paragraph lists, one bullet each, the files that branch on the type or the kind: the
# paths before a bullet's first ": ". The tree's own answer is found by grep:
#   a material  C++ under common/, chapters/, tools/ naming a type (`MaterialType::`, or the
#               enum's declaration); scripts/ naming a type as the scene format writes it
#               ("diffuse", ...: the names in materials/material.h's facts_of);
#   a light     C++ naming a kind (`LightKind::`, or the enum's declaration) or lesson 5's
#               vertex flags (`.point_light`, `.delta_light()`); scripts/ naming the export's `point_lights` or a
#               Blender light's type (`light.type`, `lights.new`).
# Fails, naming the file, when a file branches but is not listed, when a listed file does not
# branch, or when a paragraph names a path (common/, chapters/, tools/, scripts/, docs/,
# tests/) that does not exist; else prints how many files each paragraph lists and exits 0.
# Usage: tests/check_touch_points.sh [REPOSITORY_ROOT]   (default: this script's parent folder)
#        tests/check_touch_points.sh --negative-control [REPOSITORY_ROOT]
# The second form checks the check: on a copy of the tree in which common/render/film.cpp
# compares a material's type with MaterialType::Glass, scripts/farm/plan.sh reads the export's
# point_lights, tools/studio/probe.cpp no longer names a LightKind, and the doc's "A light" names
# a file that does not exist, it must report all four and fail.
set -euo pipefail

if [ "${1:-}" = "--negative-control" ]; then
    source_root="$(cd "${2:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
    copy="$(mktemp -d)"
    trap 'rm -rf "$copy"' EXIT
    mkdir -p "$copy/docs"
    cp -r "$source_root/common" "$source_root/chapters" "$source_root/tools" \
        "$source_root/scripts" "$source_root/tests" "$copy/"
    cp -r "$source_root/docs/." "$copy/docs/"
    echo 'static bool is_glass(const Material& m) { return m.type == MaterialType::Glass; }' \
        >>"$copy/common/render/film.cpp"
    echo '# python3 -c "import json; print(json.load(open(\"s.json\"))[\"point_lights\"])"' \
        >>"$copy/scripts/farm/plan.sh"
    sed -i 's/LightKind::/Kind::/g' "$copy/tools/studio/probe.cpp"
    sed -i 's|^\*\*A light\.\*\*|& See `common/lights/light_list.h`.|' "$copy/docs/architecture.md"
    if out="$(bash "${BASH_SOURCE[0]}" "$copy")"; then
        echo "negative control: the check passed a tree whose doc is wrong:"
        echo "$out"
        exit 1
    fi
    echo "$out"
    missing=0
    for expected in '^common/render/film.cpp: branches on the material type' \
                    '^scripts/farm/plan.sh: branches on the light kind' \
                    '^tools/studio/probe.cpp: listed under "A light"' \
                    '^docs/architecture.md, "A light": common/lights/light_list.h does not exist'; do
        grep -q "$expected" <<<"$out" || { echo "negative control: not reported: $expected"; missing=1; }
    done
    [ "$missing" -eq 0 ] || exit 1
    echo "negative control: the unlisted branches, the listed file without one and the wrong path reported"
    exit 0
fi
ROOT="$(cd "${1:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
cd "$ROOT"
doc=docs/architecture.md

# The lines of the doc's paragraph that opens with **TITLE.**, up to the next one or heading.
paragraph() {
    awk -v title="**$1.**" 'index($0, title) == 1 { on = 1; print; next }
                            on && /^(\*\*|#)/ { exit }
                            on { print }' "$doc"
}
# The files that lead the paragraph's bullets: a bullet ("- " and its indented lines) up to its
# first ": ", and the paths quoted there.
listed() {
    paragraph "$1" |
        awk '/^- / { if (b != "") print b; b = substr($0, 3); next }
             /^  / && b != "" { b = b " " $0; next }
             { if (b != "") print b; b = "" }
             END { if (b != "") print b }' |
        sed 's/: .*//' | { grep -o '`[^`]*/[^`]*`' || true; } | tr -d '`' | sort -u
}
# Every path the paragraph quotes.
named_paths() {
    paragraph "$1" | { grep -oE '`(common|chapters|tools|scripts|docs|tests)/[^`]*`' || true; } |
        tr -d '`' | sort -u
}

cpp() { grep -rlE "$1" common chapters tools --include='*.h' --include='*.cpp' || true; }
scripts() { grep -rlE "$1" scripts --include='*.py' --include='*.sh' || true; }

names="$(sed -n 's/.*\.name = "\([a-z_]*\)".*/\1/p' common/materials/material.h | paste -sd'|')"
[ -n "$names" ] || { echo "check_touch_points: no type names in common/materials/material.h" >&2; exit 2; }
material_files="$({ cpp 'MaterialType::|enum class MaterialType'
                    scripts "\"($names)\""; } | sort -u)"
light_files="$({ cpp 'LightKind::|enum class LightKind|\.point_light\b|\.delta_light\(\)'
                 scripts 'point_lights|light\.type|lights\.new'; } | sort -u)"

status=0
compare() {  # title, what the files branch on, the files found
    local title="$1" what="$2" found="$3" listed_files
    listed_files="$(listed "$title")"
    if [ -z "$listed_files" ]; then
        echo "docs/architecture.md: no paragraph \"**$title.**\" with a list of files"
        status=1
        return
    fi
    while IFS= read -r f; do
        [ -n "$f" ] || continue
        echo "$f: branches on the $what, but docs/architecture.md's \"$title\" does not list it"
        status=1
    done < <(comm -23 <(echo "$found") <(echo "$listed_files"))
    while IFS= read -r f; do
        [ -n "$f" ] || continue
        echo "$f: listed under \"$title\" in docs/architecture.md, but it does not branch on the $what"
        status=1
    done < <(comm -13 <(echo "$found") <(echo "$listed_files"))
    while IFS= read -r p; do
        [ -e "$p" ] || { echo "docs/architecture.md, \"$title\": $p does not exist"; status=1; }
    done < <(named_paths "$title")
}
compare "A material" "material type" "$material_files"
compare "A light" "light kind" "$light_files"

[ "$status" -eq 0 ] && echo "check_touch_points: a material type touches $(wc -l <<<"$material_files")" \
    "files that branch on it, a light kind $(wc -l <<<"$light_files"), as docs/architecture.md lists"
exit "$status"
