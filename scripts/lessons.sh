#!/usr/bin/env bash
# Renders the lessons on the suite's scenes into out/ (on a fresh Debian 12 machine it first
# installs what it needs and builds). Each render writes out/<lesson>_<scene>.exr (linear
# radiance), .png (sRGB) and .json (report).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

build_suite
OUT="$ROOT/out"
mkdir -p "$OUT"
cd "$ROOT"

render() {  # render LESSON SCENE [extra flags...]
    local lesson="$1" scene="$2"
    shift 2
    local name="${lesson}_${scene}"
    "$BUILD/bin/$lesson" --scene "scenes/$scene.toml" --out "$OUT/$name" \
        --report "$OUT/$name.json" --quiet "$@"
    echo "lessons: $OUT/$name.png"
}

for scene in cornell_box cornell_spheres whitted_1979; do
    render 01_ray_casting "$scene"
    render 02_whitted "$scene"
done

echo "lessons: done; images, EXRs and reports are in $OUT"
