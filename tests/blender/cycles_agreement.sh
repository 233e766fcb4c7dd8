#!/usr/bin/env bash
# Cycles agreement (ctest cycles_agreement, label slow): converged renders of six scenes by
# Cycles (scripts/blender/toml_to_blender.py) and by lesson 4 agree in the whole-image mean
# within 0.5% and in every 32 x 32 block mean within 2% (docs/interop.md, "Cycles"):
#   scenes/cornell_box.toml  the Cornell box (its lamp one-sided, just under the ceiling: none of
#                            the gap paths that put Cycles low on cornell_box_rtiow.toml)
#   scenes/sky.toml          a uniform sky, a clay, a rough metal and a glass sphere
#   scenes/metals.toml       gold, copper and silver spheres of GGX roughness 0.05, 0.2, 0.5
#   scenes/whitted_1979.toml a checker floor, a mirror and a glass sphere, one point light
#   scenes/sky_map.toml      an environment map with a sun, an image texture, an OBJ placed twice
#   scenes/sun_and_spot.toml a directional light and a spot light (its cone and blend) on diffuse
#                            objects under a dim sky (1024 spp: lesson 4 picks the spot by its
#                            power, about one time in six, so it converges slowly there)
# Between them they check every mapping of scripts/blender/toml_to_blender.py that the round
# trip cannot (it runs the two scripts against each other): the map's turn, the checker's
# parity, the point light's power, the spot's cone and the sun's irradiance, one-sided
# emission, textures, glass and conductors.
# Both renderers' references are two independent halves (scripts/cycles_compare.sh), and the
# halves' differences give the standard errors: the test refuses to judge (fails) when a block
# ratio's standard error, pooled over the blocks, is above 0.5% (2% would then be under 4
# sigma), the mean's above 0.125%, or the farthest block's own (a rough, one-degree-of-freedom
# figure) above 1%. Usage: tests/blender/cycles_agreement.sh BIN_DIR [SCENE WIDTH HEIGHT REF_SPP]
# (SCENE absolute, or relative to the repository's root).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BIN="$(cd "$1" && pwd)"; shift
command -v "${BLENDER:-blender}" > /dev/null || { echo "blender not found: scripts/test.sh installs it (apt-get install blender python3-numpy)" >&2; exit 1; }
if [ $# -ge 4 ]; then CASES=("$1 $2 $3 $4"); else
    CASES=("scenes/cornell_box.toml 128 128 384"
           "scenes/sky.toml 192 128 256"
           "scenes/metals.toml 192 128 384"
           "scenes/whitted_1979.toml 192 128 256"
           "scenes/sky_map.toml 160 96 256"
           "scenes/sun_and_spot.toml 160 96 1024")
fi
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
failed=0
for c in "${CASES[@]}"; do
    read -r scene width height ref_spp <<< "$c"
    name="$(basename "$scene" .toml)"
    case $scene in /*) path="$scene" ;; *) path="$ROOT/$scene" ;; esac  # relative to the root
    if ! REF_SPP="$ref_spp" LESSONS_BIN="$BIN" "$ROOT/scripts/cycles_compare.sh" --lesson 4 \
        --width "$width" --height "$height" --dir "$WORK/$name" "$path" 4 > "$WORK/$name.log" 2>&1; then
        echo "FAIL: $scene: scripts/cycles_compare.sh failed:"; tail -n 20 "$WORK/$name.log"; failed=1; continue
    fi
    python3 - "$scene" "$WORK/$name/references.json" <<'PY' || failed=1
import json, sys
scene, r = sys.argv[1], json.load(open(sys.argv[2]))
mean, mean_se = r["mean_ratio"], r["mean_ratio_noise"]
lo, hi, block_se = r["block_ratio_min"], r["block_ratio_max"], r["block_ratio_noise"]
worst, at = r["worst_block_ratio"], tuple(r["worst_block"])
line = (f"{scene}: lesson 4 / Cycles: image mean {mean:.5f} (se {mean_se:.5f}); "
        f"{r['blocks_compared']} blocks {lo:.4f} .. {hi:.4f} (se {block_se:.4f}), "
        f"farthest {worst:.4f} (se {r['worst_block_ratio_noise']:.4f}) at pixel {at}")
problems = []
if mean_se > 0.00125 or block_se > 0.005 or r["worst_block_ratio_noise"] > 0.01:
    problems.append("the references are too noisy to judge 0.5% / 2%: raise REF_SPP")
if abs(mean - 1.0) > 0.005:
    problems.append(f"the image means differ by {100 * (mean - 1):+.2f}% (limit 0.5%)")
if abs(worst - 1.0) > 0.02:
    problems.append(f"the block at pixel {at} differs by {100 * (worst - 1):+.2f}% (limit 2%)")
print(("FAIL: " if problems else "ok: ") + line)
for p in problems:
    print(f"  {scene}: {p}")
sys.exit(1 if problems else 0)
PY
done
exit "$failed"
