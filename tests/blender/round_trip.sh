#!/usr/bin/env bash
# The Blender bridge's round trip (ctest blender_round_trip, label slow): every scene in scenes/
# (and scenes/hard/, and the glTF test scene) goes TOML -> Blender (toml_to_blender.py, saved as
# a .blend) -> TOML (blender_to_toml.py, with OBJ meshes), and the scene the lessons load from
# the result must be the one they load from the original: the same triangles, quads, spheres,
# materials, lights, camera and background (build/bin/scene_export of both, compared by
# compare_exports.py; positions to 1e-5 of the scene's size).
# Usage: tests/blender/round_trip.sh BIN_DIR [SCENE ...]. Needs Debian's blender and
# python3-numpy (scripts/test.sh installs them).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BIN="$(cd "$1" && pwd)"; shift
BLENDER="${BLENDER:-blender}"
command -v "$BLENDER" > /dev/null || { echo "blender not found: scripts/test.sh installs it (apt-get install blender python3-numpy)" >&2; exit 1; }
SCENES=("$@")
[ ${#SCENES[@]} -gt 0 ] || SCENES=("$ROOT"/scenes/*.toml "$ROOT"/scenes/hard/*.toml "$ROOT/tests/gltf/cubes.gltf" "$ROOT/tests/gltf/sun_and_spot.gltf")
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
failed=0
for scene in "${SCENES[@]}"; do
    name="$(basename "$scene")"; name="${name%.*}"
    w="$WORK/$name"; mkdir -p "$w"
    if ! "$BIN/scene_export" "$scene" --out "$w/before.json" 2> "$w/export.log" ||
       ! "$BLENDER" -b --factory-startup --python-exit-code 1 --python "$ROOT/scripts/blender/toml_to_blender.py" -- \
            --json "$w/before.json" --blend "$w/scene.blend" > "$w/to_blender.log" 2>&1 ||
       ! "$BLENDER" -b "$w/scene.blend" --python-exit-code 1 --python "$ROOT/scripts/blender/blender_to_toml.py" -- \
            --out "$w/back/scene.toml" > "$w/to_toml.log" 2>&1 ||
       grep -q "Traceback" "$w/to_blender.log" "$w/to_toml.log" ||
       ! "$BIN/scene_export" "$w/back/scene.toml" --out "$w/after.json" 2>> "$w/export.log"; then
        echo "FAIL: $scene: the round trip did not run:"
        tail -n 15 "$w"/*.log
        failed=1
        continue
    fi
    python3 "$ROOT/tests/blender/compare_exports.py" "$w/before.json" "$w/after.json" || failed=1
done
[ "$failed" = 0 ] && echo "round trip: all ${#SCENES[@]} scenes came back the same"
exit "$failed"
