#!/usr/bin/env bash
# The converged references of the lessons page (scripts/lessons.sh) and the studio: which
# estimator renders a scene's reference, a reference render with its provenance, and whether a
# shipped one (references/SCENE/) can stand for a render with today's settings. Source it after
# setting ROOT and BIN; scripts/lessons.sh --references runs it to re-render the shipped ones.

# A field of one of our JSON reports (flat, one field per line).
field() { sed -n "s/^  \"$2\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$1"; }
# A list field of a report, as its strings joined by "; ".
list_field() { sed -n "s/^  \"$2\": \[\(.*\)\],\{0,1\}$/\1/p" "$1" | sed 's/", "/; /g; s/^"//; s/"$//'; }
# A string or number of a provenance file (reference.toml: one `key = value` a line).
toml_field() { sed -n "s/^$2 = \"\{0,1\}\([^\"]*\)\"\{0,1\}$/\1/p" "$1"; }

# The seed of every reference: no run of the page or pane of the studio uses it.
REFERENCE_SEED=1000003

# reference_probe SCENE DIR: lesson 4 at 8x8 and 1 spp, whose report says whether it is biased
# in the scene (point-light caustics) and whether it finds lamps' caustics only by chance (its
# notes then point to lesson 5), and the hash of the scene's files. Sets REF_LESSON (the
# estimator unbiased here), REF_WHY (why, for the page) and SCENE_FILES (the hash).
reference_probe() {
    local scene="$1" dir="$2"
    "$BIN/04_rendering_equation" --scene "scenes/$scene.toml" --width 8 --height 8 --spp 1 \
        --out "$dir/probe" --report "$dir/probe.json" --quiet
    SCENE_FILES="$(field "$dir/probe.json" scene_files)"
    if [ "$(field "$dir/probe.json" biased)" = true ] || grep -q "lesson 5" "$dir/probe.json"; then
        REF_LESSON=05_bidirectional
        REF_WHY="lesson 5, bidirectional path tracing: lesson 4 $( [ "$(field "$dir/probe.json" biased)" = true ] && echo "misses light here ($(list_field "$dir/probe.json" bias))" || echo "finds this scene's caustics only by chance")"
    else
        REF_LESSON=04_rendering_equation
        REF_WHY="lesson 4, path tracing: unbiased here (no point light, mirror or glass)"
    fi
}

# shipped_reference_fits PROVENANCE LESSON WIDTH HEIGHT SPP SCENE_FILES: whether the shipped
# reference was rendered by that lesson, at that size and sample count, with the sampler and
# seed of render_reference, from scene files with that hash.
shipped_reference_fits() {
    local p="$1"
    [ -f "$p" ] && [ -f "${p%.toml}.exr" ] && [ -f "${p%.toml}_variance.exr" ] &&
        [ "$(toml_field "$p" lesson)" = "$2" ] && [ "$(toml_field "$p" width)" = "$3" ] &&
        [ "$(toml_field "$p" height)" = "$4" ] && [ "$(toml_field "$p" spp)" = "$5" ] &&
        [ "$(toml_field "$p" sampler)" = independent ] &&
        [ "$(toml_field "$p" seed)" = "$REFERENCE_SEED" ] &&
        [ "$(toml_field "$p" scene_files)" = "$6" ]
}

# render_reference SCENE LESSON WIDTH HEIGHT SPP DIR: renders DIR/reference.exr (and
# reference_variance.exr, the per-pixel variance of its mean; reference.png) with independent
# samples and REFERENCE_SEED, printing the lesson's progress line
# every 10% with the time left, then writes DIR/reference.toml, its provenance.
render_reference() {
    local scene="$1" lesson="$2" width="$3" height="$4" spp="$5" dir="$6"
    mkdir -p "$dir"
    local report
    report="$(mktemp)"
    local args=(--scene "scenes/$scene.toml" --width "$width" --height "$height" --spp "$spp"
                --seed "$REFERENCE_SEED" --sampler independent --out "$dir/reference"
                --variance "$dir/reference_variance")
    # The commit, and whether the sources differ from it, as the render starts.
    local commit dirty
    commit="$(git -C "$ROOT" rev-parse HEAD 2>/dev/null || echo unknown)"
    dirty="$(git -C "$ROOT" status --porcelain -- common chapters scenes CMakeLists.txt 2>/dev/null | head -1)"
    echo "references: $scene: rendering ($spp spp, ${width}x${height}, $lesson)"
    # Its progress every 10%, with the time left, and any error it prints.
    "$BIN/$lesson" "${args[@]}" --report "$report" 2>&1 |
        sed -u -n -e "s/^render: /references: $scene: /p" -e '/error/p'
    [ "${PIPESTATUS[0]}" = 0 ] || { echo "references: $scene: the render failed" >&2; exit 1; }
    # Paths relative to the repository, so the command runs as written from its root.
    local command="build/bin/$lesson ${args[*]}"
    command="${command//$ROOT\//}"
    cat > "$dir/reference.toml" <<EOF
# Provenance of reference.exr beside this file (and reference_variance.exr, the per-pixel
# variance of its mean): the converged reference of scenes/$scene.toml that scripts/lessons.sh
# and the studio measure error against. Written by scripts/references.sh; the tests
# ShippedReferences.* (tests/test_shipped_references.cpp) check that today's code still renders
# the same image within the noise of both.
scene = "scenes/$scene.toml"
scene_files = "$(field "$report" scene_files)"
lesson = "$lesson"
sampler = "independent"
seed = $REFERENCE_SEED
spp = $(field "$report" spp)
width = $(field "$report" width)
height = $(field "$report" height)
commit = "$commit"
uncommitted_changes = $( [ -n "$dirty" ] && echo true || echo false )
build_type = "$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$BUILD/CMakeCache.txt" 2>/dev/null)"
command = "$command"
seconds = $(field "$report" seconds)
threads = $(field "$report" threads)
cpu = "$(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -1)"
date = "$(date -u +%Y-%m-%dT%H:%M:%SZ)"
EOF
    echo "references: $scene: done in $(field "$report" seconds) s; provenance $dir/reference.toml"
    rm -f "$report"
}
