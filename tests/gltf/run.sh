#!/usr/bin/env bash
# glTF input (docs/interop.md): tests/gltf/cubes.gltf (a node hierarchy, two cubes, an emissive
# quad, a textured floor, a point light, a camera), the same as a .glb, and placed in a TOML
# scene, render bit for bit like cubes.toml, the same scene written in the suite's format, in
# every lesson; so does sun_and_spot.gltf (the same with a spot and a sun) like its TOML;
# what the loader ignores is in the report's notes.
#
#   tests/gltf/run.sh BUILD_DIR
set -euo pipefail
BUILD=$(cd "$1" && pwd)
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cd "$ROOT"
fail() { echo "FAIL: $*" >&2; exit 1; }

mapfile -t LESSONS < <(grep -E '^[0-9]{2}_' chapters/lessons.txt | cut -d'|' -f1 | tr -d ' ')
for lesson in "${LESSONS[@]}"; do
    run=("$BUILD/bin/$lesson" --quiet --spp 2)
    "${run[@]}" --scene tests/gltf/cubes.toml --out "$WORK/${lesson}_toml"
    "${run[@]}" --scene tests/gltf/cubes_placed.toml --out "$WORK/${lesson}_placed"
    "${run[@]}" --scene tests/gltf/cubes.gltf --width 64 --height 48 --out "$WORK/${lesson}_gltf"
    "${run[@]}" --scene tests/gltf/cubes.glb --width 64 --height 48 --out "$WORK/${lesson}_glb"
    "${run[@]}" --scene tests/gltf/cubes_mirrored.toml --out "$WORK/${lesson}_mirrored"
    "${run[@]}" --scene tests/gltf/cubes_placed_mirrored.toml --out "$WORK/${lesson}_placed_mirrored"
    for v in placed gltf glb; do
        cmp -s "$WORK/${lesson}_toml.exr" "$WORK/${lesson}_$v.exr" ||
            fail "$lesson: the glTF ($v) and cubes.toml render differently"
    done
    cmp -s "$WORK/${lesson}_mirrored.exr" "$WORK/${lesson}_placed_mirrored.exr" ||
        fail "$lesson: the glTF placed by a mirroring transform and cubes_mirrored.toml differ"
    echo "ok: $lesson: cubes.gltf, cubes.glb, the glTF placed in TOML (and mirrored) render bit for bit as their TOML"
    # A spot and a sun (KHR_lights_punctual), alone and placed by a mirroring transform.
    "${run[@]}" --scene tests/gltf/sun_and_spot.toml --out "$WORK/${lesson}_lights_toml"
    "${run[@]}" --scene tests/gltf/sun_and_spot.gltf --width 64 --height 48 --out "$WORK/${lesson}_lights_gltf"
    "${run[@]}" --scene tests/gltf/sun_and_spot_mirrored.toml --out "$WORK/${lesson}_lights_mirrored"
    "${run[@]}" --scene tests/gltf/sun_and_spot_placed_mirrored.toml --out "$WORK/${lesson}_lights_placed_mirrored"
    cmp -s "$WORK/${lesson}_lights_toml.exr" "$WORK/${lesson}_lights_gltf.exr" ||
        fail "$lesson: sun_and_spot.gltf and sun_and_spot.toml render differently"
    cmp -s "$WORK/${lesson}_lights_mirrored.exr" "$WORK/${lesson}_lights_placed_mirrored.exr" ||
        fail "$lesson: sun_and_spot.gltf placed by a mirroring transform and sun_and_spot_mirrored.toml differ"
    echo "ok: $lesson: sun_and_spot.gltf (a spot and a sun), alone and mirrored, renders bit for bit as its TOML"
done

# A glTF scene split across jobs merges like any other (the part's hash covers the file).
L4=("$BUILD/bin/04_rendering_equation" --quiet --scene tests/gltf/cubes.gltf --width 64 --height 48)
"${L4[@]}" --samples 0:1 --out "$WORK/part0"
"${L4[@]}" --samples 1:2 --out "$WORK/part1"
"$BUILD/bin/merge" --quiet "$WORK/part0.exr" "$WORK/part1.exr" --out "$WORK/merged"
cmp -s "$WORK/merged.exr" "$WORK/04_rendering_equation_gltf.exr" || fail "the merged glTF parts differ from the single run"
echo "ok: parts of a glTF scene merge into the single run, bit for bit"

# The notes: what was mapped, what was ignored, per material; the camera.
"$BUILD/bin/04_rendering_equation" --quiet --scene tests/gltf/cubes_ignored.gltf --width 32 \
    --height 24 --spp 1 --out "$WORK/ignored" --report "$WORK/ignored.json"
for expected in \
    "glTF material 'red' (materials[0]): diffuse; ignored: the specular reflection of a dielectric (F0 = 0.04), metallic 0.3 between 0 and 1 (taken as 0), normalTexture, KHR_materials_clearcoat" \
    "glTF material 'glass' (materials[1]): glass of ior 1.45 (KHR_materials_transmission)" \
    "glTF material 'metal'" \
    "glTF: the camera is the file's 'camera' (yfov 40.1070" ; do
    if [ "$expected" = "glTF material 'metal'" ]; then
        ! grep -qF "$expected" "$WORK/ignored.json" || fail "a material that is not in the file is noted"
        continue
    fi
    grep -qF "$expected" "$WORK/ignored.json" || { cat "$WORK/ignored.json"; fail "the notes do not say: $expected"; }
done
echo "ok: the report's notes say what each glTF material became and what was ignored"

# A glTF spot's fade is the suite's smoothstep, not glTF's recommended curve: the notes say so.
"$BUILD/bin/04_rendering_equation" --quiet --scene tests/gltf/sun_and_spot.gltf --width 16 \
    --height 12 --spp 1 --out "$WORK/lights" --report "$WORK/lights.json"
grep -qF "KHR_lights_punctual.lights[0] (spot): fades between innerConeAngle and outerConeAngle as smoothstep in the cosine, not glTF's recommended square" "$WORK/lights.json" ||
    { cat "$WORK/lights.json"; fail "the notes do not say how a glTF spot fades"; }
echo "ok: the notes say that a glTF spot fades as smoothstep"
