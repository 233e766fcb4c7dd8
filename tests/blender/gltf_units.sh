#!/usr/bin/env bash
# glTF light units (ctest gltf_units, labels slow and blender; docs/interop.md, "Light units"): a
# scene built in Blender, a 200 W point light, a 300 W spot (60 degrees wide, blend 0.25), a sun
# of strength 4 and a quad whose Principled BSDF emits with strength 12, exported by Blender's
# own glTF add-on in its default lighting mode, loads in the lessons with the point light's
# radiant intensity 200 / (4 pi) W/sr, the spot's 300 / (4 pi) on its axis (its cone of 30
# degrees, fading from the add-on's innerConeAngle 30 (1 - 0.25) = 22.5 degrees, pointing down),
# the sun's irradiance 4 W/m^2 along its direction, and the quad's radiance 12 W/(sr m^2): the values Cycles renders the Blender scene with (a point light of P watts has
# the intensity P / (4 pi) in Cycles, the mapping that the test cycles_agreement holds lesson 4
# and Cycles to on scenes/whitted_1979.toml; emission strength is radiance). The add-on writes
# 683 P / (4 pi) candela, a sun's 683 S lux and the emission unconverted; the reader divides
# candela and lux by 683.
# Usage: tests/blender/gltf_units.sh BIN_DIR
set -euo pipefail
BIN="$(cd "$1" && pwd)"
BLENDER="${BLENDER:-blender}"
command -v "$BLENDER" > /dev/null || { echo "blender not found: scripts/test.sh installs it (apt-get install blender python3-numpy)" >&2; exit 1; }
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

cat > "$WORK/build.py" <<'PY'
import math
import sys
import bpy
out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0.0, 0.0, 0.0))
quad = bpy.context.active_object
material = bpy.data.materials.new("lamp")
material.use_nodes = True
bsdf = material.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
bsdf.inputs["Emission"].default_value = (1.0, 1.0, 1.0, 1.0)
bsdf.inputs["Emission Strength"].default_value = 12.0
quad.data.materials.append(material)
light = bpy.data.lights.new("bulb", type="POINT")
light.energy = 200.0
light.color = (1.0, 1.0, 1.0)
bulb = bpy.data.objects.new("bulb", light)
bulb.location = (0.0, 0.0, 3.0)
scene.collection.objects.link(bulb)
spot = bpy.data.lights.new("spot", type="SPOT")
spot.energy, spot.spot_size, spot.spot_blend = 300.0, math.radians(60.0), 0.25
spot_object = bpy.data.objects.new("spot", spot)
spot_object.location = (1.0, 0.0, 4.0)  # pointing down: a light shines along its local -z
scene.collection.objects.link(spot_object)
sun = bpy.data.lights.new("sun", type="SUN")
sun.energy = 4.0
sun_object = bpy.data.objects.new("sun", sun)
sun_object.rotation_euler = (0.5, 0.0, 0.0)
scene.collection.objects.link(sun_object)
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
camera.location = (0.0, -6.0, 3.0)
camera.rotation_euler = (1.1, 0.0, 0.0)
scene.collection.objects.link(camera)
scene.camera = camera
bpy.ops.export_scene.gltf(filepath=out, export_format="GLTF_SEPARATE", export_lights=True,
                          export_cameras=True)
PY
"$BLENDER" --background --factory-startup --python "$WORK/build.py" -- "$WORK/scene.gltf" \
    > "$WORK/blender.log" 2>&1 || { tail -n 30 "$WORK/blender.log"; exit 1; }
"$BIN/scene_export" "$WORK/scene.gltf" --out "$WORK/scene.json"
python3 - "$WORK/scene.gltf" "$WORK/scene.json" <<'PY'
import json, math, sys
gltf, scene = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
lights = gltf["extensions"]["KHR_lights_punctual"]["lights"]
candela = next(l["intensity"] for l in lights if l["type"] == "point")
print(f"Blender wrote the 200 W point light as {candela:.6g} cd (683 x 200 / (4 pi) = "
      f"{683 * 200 / (4 * math.pi):.6g})")
problems = []
def near(got, want, tol=1e-4):
    return all(abs(g - w) <= tol * max(1.0, abs(w)) for g, w in zip(got, want))

spots = [p for p in scene["point_lights"] if "spot" in p]
points = [p for p in scene["point_lights"] if "spot" not in p]
if len(spots) != 1:
    problems.append(f"{len(spots)} spot lights loaded, expected 1")
else:
    got, want = spots[0]["intensity"], 300.0 / (4.0 * math.pi)
    cone = spots[0]["spot"]
    inner, outer = math.radians(22.5), math.radians(30.0)
    blend = (math.cos(inner) - math.cos(outer)) / (1.0 - math.cos(outer))
    print(f"the lessons load the spot as {got} W/sr on its axis {cone['direction']}, cone "
          f"{cone['cone_angle']:.6g} degrees, blend {cone['cone_blend']:.6g} (Cycles: "
          f"{want:.6g}, [0, -1, 0], 30, from 22.5 degrees: {blend:.6g})")
    if not near(got, [want] * 3) or not near(cone["direction"], [0.0, -1.0, 0.0]) or \
            not near([cone["cone_angle"], cone["cone_blend"]], [30.0, blend]):
        problems.append(f"spot light {spots[0]}, expected {want:.6g} W/sr, axis -y, 30 degrees, "
                        f"blend {blend:.6g}")
suns = scene.get("directional_lights", [])
if len(suns) != 1:
    problems.append(f"{len(suns)} directional lights loaded, expected 1")
else:
    # Blender's -z turned 0.5 rad about x: (0, sin 0.5, -cos 0.5), in y-up axes (x, z, -y).
    want = [0.0, -math.cos(0.5), -math.sin(0.5)]
    got = suns[0]
    print(f"the lessons load the sun as {got['irradiance']} W/m^2 along {got['direction']} "
          f"(Cycles: 4 along {[round(w, 6) for w in want]})")
    if not near(got["irradiance"], [4.0] * 3) or not near(got["direction"], want):
        problems.append(f"directional light {got}, expected 4 W/m^2 along {want}")
if len(points) != 1:
    problems.append(f"{len(points)} point lights loaded, expected 1")
else:
    got, want = points[0]["intensity"], 200.0 / (4.0 * math.pi)
    print(f"the lessons load it as {got} W/sr (Cycles: 200 / (4 pi) = {want:.6g})")
    if any(abs(c - want) > 1e-4 * want for c in got):
        problems.append(f"point light intensity {got}, expected {want:.6g} W/sr in every channel")
emitters = [m for m in scene["materials"] if any(c > 0 for c in m.get("emission", [0, 0, 0]))]
if len(emitters) != 1:
    problems.append(f"{len(emitters)} emissive materials loaded, expected 1")
else:
    got = emitters[0]["emission"]
    print(f"the lessons load the quad's emission as {got} W/(sr m^2) (Cycles: 12)")
    if any(abs(c - 12.0) > 1e-4 * 12.0 for c in got):
        problems.append(f"emission {got}, expected 12 in every channel")
for p in problems:
    print("FAIL: " + p)
sys.exit(1 if problems else 0)
PY
