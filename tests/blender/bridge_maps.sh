#!/usr/bin/env bash
# The Blender bridge with the environment maps users bring (ctest bridge_maps, labels slow and
# blender): scenes/sky_map.toml with its map replaced by
#   - the same map saved by Blender as a Radiance .hdr (RGBE), and
#   - Blender's own studio-light map forest.exr (DWAB-compressed, with a few slightly negative
#     texels that the lessons set to 0 with a note), when Debian's blender-data ships it;
# each rendered by Cycles through scripts/blender/toml_to_blender.py and by lesson 4, which must
# agree as tests/blender/cycles_agreement.sh requires (image mean within 0.5%, blocks within 2%).
# Usage: tests/blender/bridge_maps.sh BIN_DIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BIN="$(cd "$1" && pwd)"
BLENDER="${BLENDER:-blender}"
command -v "$BLENDER" > /dev/null || { echo "blender not found: scripts/test.sh installs it" >&2; exit 1; }
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
cp -r "$ROOT/scenes" "$WORK/scenes"

# The map as Blender writes a Radiance file (scene-linear: the Standard view, no look).
"$BLENDER" -b --factory-startup --python-expr "
import bpy
img = bpy.data.images.load('$ROOT/scenes/maps/sky.exr')
_ = img.pixels[0]
s = bpy.context.scene
s.view_settings.view_transform = 'Standard'
s.view_settings.look = 'None'
s.render.image_settings.file_format = 'HDR'
img.save_render('$WORK/scenes/maps/sky.hdr', scene=s)
" > "$WORK/convert.log" 2>&1 || { cat "$WORK/convert.log"; exit 1; }
[ -s "$WORK/scenes/maps/sky.hdr" ] || { echo "Blender wrote no .hdr"; cat "$WORK/convert.log"; exit 1; }

cases=()
sed 's|^map = "maps/sky.exr"|map = "maps/sky.hdr"|' "$ROOT/scenes/sky_map.toml" > "$WORK/scenes/sky_map_hdr.toml"
grep -q 'map = "maps/sky.hdr"' "$WORK/scenes/sky_map_hdr.toml"
cases+=("$WORK/scenes/sky_map_hdr.toml")
forest=/usr/share/blender/datafiles/studiolights/world/forest.exr
if [ -f "$forest" ]; then
    sed "s|^map = \"maps/sky.exr\"|map = \"$forest\"|" "$ROOT/scenes/sky_map.toml" > "$WORK/scenes/sky_map_forest.toml"
    cases+=("$WORK/scenes/sky_map_forest.toml")
else
    echo "note: $forest is absent (Debian's blender-data ships it): only the .hdr case runs"
fi
failed=0
for scene in "${cases[@]}"; do
    bash "$ROOT/tests/blender/cycles_agreement.sh" "$BIN" "$scene" 160 96 256 || failed=1
done
exit "$failed"
