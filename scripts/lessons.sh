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
    render 03_reflection_equation "$scene"
done
# Lesson 3's estimators side by side, at equal sample count.
for estimator in uniform cosine brdf light mis; do
    "$BUILD/bin/03_reflection_equation" --scene scenes/veach_mis.toml --estimator "$estimator" \
        --out "$OUT/03_reflection_equation_veach_mis_$estimator" \
        --report "$OUT/03_reflection_equation_veach_mis_$estimator.json" --quiet
    echo "lessons: $OUT/03_reflection_equation_veach_mis_$estimator.png"
done
render 03_reflection_equation quad_light_plane
# Lesson 4: global illumination, with the series L = E + KE + K^2E + ... split by bounce.
render 04_rendering_equation cornell_box --bounces 4
render 04_rendering_equation cornell_spheres
render 04_rendering_equation furnace --bounces 4
render 04_rendering_equation sky
"$BUILD/bin/04_rendering_equation" --scene scenes/cornell_box.toml --plain \
    --out "$OUT/04_rendering_equation_cornell_box_plain" \
    --report "$OUT/04_rendering_equation_cornell_box_plain.json" --quiet
echo "lessons: $OUT/04_rendering_equation_cornell_box_plain.png"

echo "lessons: done; images, EXRs and reports are in $OUT"
