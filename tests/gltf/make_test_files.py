#!/usr/bin/env python3
"""Writes the glTF test scene (cubes.gltf, its embedded buffer in base64) and the TOML scene that
says the same in the suite's own format (cubes.toml), for tests/gltf/run.sh; and the bad glTF
files of the bad-input corpus (tests/bad_input/gltf_*.gltf and their .toml).

    python3 tests/gltf/make_test_files.py    (from the repository's root)
"""
import base64, json, math, struct, os

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "..", "bad_input")

# A unit cube centred at 0 (8 corners, 12 triangles, outward), and a 1 x 1 quad facing -y.
cube_v = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
def c(x, y, z): return cube_v.index((x, y, z))
h = 0.5
cube_f = []
for axis in range(3):
    for sign in (-h, h):
        quad = []
        for a, b in ((-h, -h), (h, -h), (h, h), (-h, h)):
            p = [0, 0, 0]; p[axis] = sign; p[(axis + 1) % 3] = a; p[(axis + 2) % 3] = b
            quad.append(c(*p))
        if sign < 0: quad.reverse()
        cube_f += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
quad_v = [(-0.5, 0.0, -0.5), (0.5, 0.0, -0.5), (0.5, 0.0, 0.5), (-0.5, 0.0, 0.5)]
quad_uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
quad_f = [(0, 1, 2), (0, 2, 3)]  # facing -y: cross((1,0,0), (1,0,1)) = (0,-1,0)
# A textured floor facing +y, its texture repeated 3 times each way. glTF's texture coordinates
# start at the image's top left (t down); OBJ's and the suite's v goes up: v = 1 - t.
floor_v = [(-3.0, 0.0, -3.0), (-3.0, 0.0, 3.0), (3.0, 0.0, 3.0), (3.0, 0.0, -3.0)]
floor_uv = [(0.0, 0.0), (0.0, 3.0), (3.0, 3.0), (3.0, 0.0)]  # glTF (s, t)
floor_f = [(0, 1, 2), (0, 2, 3)]  # facing +y
def floats(vs): return b"".join(struct.pack("<3f", *v) for v in vs)
def shorts(fs): return b"".join(struct.pack("<3H", *f) for f in fs)
def pairs(ts): return b"".join(struct.pack("<2f", *t) for t in ts)
parts = [floats(cube_v), shorts(cube_f), floats(quad_v), pairs(quad_uv), shorts(quad_f),
         floats(floor_v), pairs(floor_uv), shorts(floor_f)]
offsets, blob = [], b""
for p in parts:
    while len(blob) % 4: blob += b"\0"
    offsets.append(len(blob)); blob += p
views = [{"buffer": 0, "byteOffset": o, "byteLength": len(p)} for o, p in zip(offsets, parts)]
def acc(view, count, ctype, typ, **kw):
    a = {"bufferView": view, "componentType": ctype, "count": count, "type": typ}; a.update(kw); return a
F, US = 5126, 5123
accessors = [acc(0, 8, F, "VEC3", min=[-0.5] * 3, max=[0.5] * 3), acc(1, 36, US, "SCALAR"),
             acc(2, 4, F, "VEC3", min=[-0.5, 0, -0.5], max=[0.5, 0, 0.5]), acc(3, 4, F, "VEC2"), acc(4, 6, US, "SCALAR"),
             acc(5, 4, F, "VEC3", min=[-3, 0, -3], max=[3, 0, 3]), acc(6, 4, F, "VEC2"), acc(7, 6, US, "SCALAR")]
yfov = 0.7
gltf = {
    "asset": {"version": "2.0", "generator": "tests/gltf/make_test_files.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
    "scene": 0,
    "scenes": [{"nodes": [0, 3, 4, 5, 6]}],
    "nodes": [
        {"name": "group", "translation": [0.25, 0.75, -0.5], "scale": [2, 2, 2], "children": [1, 2]},
        # a matrix (column-major): turned about z by atan2(0.8, 0.6), moved
        {"name": "red cube", "mesh": 0, "matrix": [0.6, 0.8, 0, 0, -0.8, 0.6, 0, 0, 0, 0, 1, 0, -0.5, 0.25, 0.125, 1]},
        # TRS: a box 0.5 x 0.25 x 1 turned 90 degrees about y (so 1 x 0.25 x 0.5), moved
        {"name": "metal cube", "mesh": 1, "translation": [0.625, 0.25, -0.25], "scale": [0.5, 0.25, 1.0],
         "rotation": [0, math.sqrt(0.5), 0, math.sqrt(0.5)]},
        {"name": "lamp", "mesh": 2, "translation": [0.25, 3.5, -0.75]},
        {"name": "bulb", "translation": [-1.5, 2.5, 1.5], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "camera", "camera": 0, "translation": [0.25, 1.5, 6.5]},
        {"name": "floor", "mesh": 3, "translation": [0.0, -0.25, 0.0]},
    ],
    "meshes": [
        {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
        {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]},
        {"primitives": [{"attributes": {"POSITION": 2, "TEXCOORD_0": 3}, "indices": 4, "material": 2}]},
        {"primitives": [{"attributes": {"POSITION": 5, "TEXCOORD_0": 6}, "indices": 7, "material": 3}]},
    ],
    "materials": [
        {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 1}},
        {"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.7, 0.3, 1], "metallicFactor": 1, "roughnessFactor": 0.5}},
        {"name": "lamp", "emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5}},
         "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}},
        {"name": "tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
    ],
    "textures": [{"source": 0}],
    "images": [{"uri": "../../scenes/maps/tiles.png"}],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1], "intensity": 683 * 5}]}},
    "cameras": [{"type": "perspective", "perspective": {"yfov": yfov, "aspectRatio": 4 / 3, "znear": 0.01}}],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
with open(os.path.join(HERE, "cubes.gltf"), "w") as f:
    json.dump(gltf, f, indent=1)
# The same as a binary glTF: the JSON chunk, then the buffer as the BIN chunk.
glb = json.loads(json.dumps(gltf))
glb["buffers"] = [{"byteLength": len(blob)}]
js = json.dumps(glb).encode()
js += b" " * (-len(js) % 4)
bin_ = blob + b"\0" * (-len(blob) % 4)
body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(bin_), 0x004E4942) + bin_
with open(os.path.join(HERE, "cubes.glb"), "wb") as f:
    f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
# The floor as an OBJ with its (u, v) = (s, 1 - t), for the TOML scene.
with open(os.path.join(HERE, "floor.obj"), "w") as f:
    f.write("# The floor of cubes.gltf (tests/gltf/make_test_files.py)\n")
    for v in floor_v: f.write("v %r %r %r\n" % v)
    for s_, t in floor_uv: f.write("vt %r %r\n" % (s_, 1.0 - t))
    for a, b, c_ in floor_f: f.write("f %d/%d %d/%d %d/%d\n" % (a + 1, a + 1, b + 1, b + 1, c_ + 1, c_ + 1))

# The same scene in TOML: each transform is the glTF's node chain, child first.
def mesh(name, material, vs, fs, steps):
    out = f'[[shapes]]\n# {name}\ntype = "mesh"\nmaterial = "{material}"\n'
    out += "vertices = [" + ", ".join("[%r, %r, %r]" % v for v in vs) + "]\n"
    out += "faces = [" + ", ".join("[%d, %d, %d]" % f for f in fs) + "]\n"
    out += "transform = [" + ", ".join(steps) + "]\n\n"
    return out
group = ['{ scale = [2.0, 2.0, 2.0] }', '{ translate = [0.25, 0.75, -0.5] }']
fov = "%.9g" % (yfov * 180 / math.pi)
toml = f'''# The scene of cubes.gltf, written in the suite's format (tests/gltf/make_test_files.py): the
# tests render both and compare them bit for bit.
description = "glTF test scene, as TOML"

[image]
width = 64
height = 48

[camera]
position = [0.25, 1.5, 6.5]
look_at = [0.25, 1.5, 5.5]
up = [0.0, 1.0, 0.0]
fov = {fov}

[materials.red]
type = "diffuse"
albedo = [0.8, 0.1, 0.1]

[materials.metal]
type = "conductor"
specular = [0.9, 0.7, 0.3]
roughness = 0.25

[materials.lamp]
type = "diffuse"
albedo = [0.0, 0.0, 0.0]
emission = [5.0, 5.0, 5.0]

[materials.tiles]
type = "diffuse"
albedo = {{ texture = "../../scenes/maps/tiles.png" }}

[[lights]]
type = "point"
position = [-1.5, 2.5, 1.5]
intensity = [5.0, 5.0, 5.0]

'''
def scene_shapes(extra):
    # The red cube: the group's scale 2 and move times the node's matrix, as one matrix (2 x 0.6
    # is 1.2 exactly in double, as the loader's product makes it).
    red = mesh("red cube", "red", cube_v, cube_f, [])
    red = red.replace("transform = []", "matrix = [[1.2, -1.6, 0.0, -0.75], [1.6, 1.2, 0.0, 1.25], [0.0, 0.0, 2.0, -0.25], [0.0, 0.0, 0.0, 1.0]]")
    if extra:
        red = red.replace("matrix = [[1.2, -1.6, 0.0, -0.75], [1.6, 1.2, 0.0, 1.25]", "matrix = [[-1.2, 1.6, 0.0, 0.75], [1.6, 1.2, 0.0, 1.25]")
    out = red
    out += mesh("metal cube", "metal", cube_v, cube_f, ['{ scale = [0.5, 0.25, 1.0] }', '{ rotate = { axis = [0.0, 1.0, 0.0], angle = 90.0 } }', '{ translate = [0.625, 0.25, -0.25] }'] + group + extra)
    out += mesh("lamp", "lamp", quad_v, quad_f, ['{ translate = [0.25, 3.5, -0.75] }'] + extra)
    out += '[[shapes]]\n# floor\ntype = "mesh"\nfile = "floor.obj"\nmaterial = "tiles"\ntransform = [' + ", ".join(['{ translate = [0.0, -0.25, 0.0] }'] + extra) + ']\n'
    return out
header = toml
toml = header + scene_shapes([])
# Mirrored (x -> -x): the glTF placed by a mirroring transform, against every shape mirrored.
mirror = '{ scale = [-1.0, 1.0, 1.0] }'
mirrored = header.replace("position = [0.25, 1.5, 6.5]", "position = [-0.25, 1.5, 6.5]").replace(
    "look_at = [0.25, 1.5, 5.5]", "look_at = [-0.25, 1.5, 5.5]").replace(
    "position = [-1.5, 2.5, 1.5]", "position = [1.5, 2.5, 1.5]") + scene_shapes([mirror])
with open(os.path.join(HERE, "cubes_mirrored.toml"), "w") as f:
    f.write(mirrored.replace("written in the suite's format", "mirrored (x -> -x), written in the suite's format"))

with open(os.path.join(HERE, "cubes.toml"), "w") as f:
    f.write(toml)
with open(os.path.join(HERE, "cubes_placed_mirrored.toml"), "w") as f:
    f.write('''# cubes.gltf as one shape of a TOML scene, mirrored by its transform: the same image as
# cubes_mirrored.toml.
description = "glTF test scene, placed in TOML, mirrored"

[image]
width = 64
height = 48

[camera]
position = [-0.25, 1.5, 6.5]
look_at = [-0.25, 1.5, 5.5]
up = [0.0, 1.0, 0.0]
fov = %s

[[shapes]]
type = "gltf"
file = "cubes.gltf"
transform = [{ scale = [-1.0, 1.0, 1.0] }]
''' % fov)
with open(os.path.join(HERE, "cubes_placed.toml"), "w") as f:
    f.write('''# cubes.gltf as one shape of a TOML scene: the same image as cubes.toml.
description = "glTF test scene, placed in TOML"

[image]
width = 64
height = 48

[camera]
position = [0.25, 1.5, 6.5]
look_at = [0.25, 1.5, 5.5]
up = [0.0, 1.0, 0.0]
fov = %s

[[shapes]]
type = "gltf"
file = "cubes.gltf"
''' % fov)

# Bad files: each a variation of cubes.gltf, and a TOML scene placing it.
def bad(name, expect, change):
    g = json.loads(json.dumps(gltf))
    change(g)
    with open(os.path.join(BAD, name + ".gltf"), "w") as f:
        json.dump(g, f)
    with open(os.path.join(BAD, name + ".toml"), "w") as f:
        f.write(f'# expect: {expect}\n[image]\nwidth = 8\nheight = 6\n\n[camera]\nposition = [0.0, 1.0, 6.0]\nlook_at = [0.0, 1.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov = 40.0\n\n'
                f'[[shapes]]\ntype = "gltf"\nfile = "{name}.gltf"\n')
def truncate(g):
    raw = base64.b64decode(g["buffers"][0]["uri"].split(",")[1])[:100]
    g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(raw).decode()
    g["buffers"][0]["byteLength"] = 100
bad("gltf_truncated_buffer", "bufferViews[1]: bytes 96 + 72 reach past the end of buffer 0", truncate)
bad("gltf_accessor_out_of_range", "accessors[0]: 80 elements from byte 0 reach past the end of bufferViews[0]",
    lambda g: g["accessors"][0].update(count=80))
def nan_position(g):
    raw = bytearray(base64.b64decode(g["buffers"][0]["uri"].split(",")[1]))
    raw[4:8] = struct.pack("<f", float("nan"))
    g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(raw)).decode()
bad("gltf_nan_position", "meshes[0].primitives[0].POSITION: vertex 0 is not finite", nan_position)
bad("gltf_lines", "meshes[2].primitives[0].mode: is lines (1): only triangles", lambda g: g["meshes"][2]["primitives"][0].update(mode=1))
bad("gltf_spot_too_wide", "KHR_lights_punctual.lights[0].spot.outerConeAngle: is 2, outside [0.00872665, pi/2]",
    lambda g: g["extensions"]["KHR_lights_punctual"]["lights"][0].update(type="spot", spot={"outerConeAngle": 2.0}))
bad("gltf_spot_inner_above_outer", "KHR_lights_punctual.lights[0].spot.innerConeAngle: is 0.7, outside [0, outerConeAngle 0.6]",
    lambda g: g["extensions"]["KHR_lights_punctual"]["lights"][0].update(
        type="spot", spot={"innerConeAngle": 0.7, "outerConeAngle": 0.6}))
bad("gltf_light_unknown_type", "KHR_lights_punctual.lights[0]: is a 'area' light: glTF's lights are point, spot and directional",
    lambda g: g["extensions"]["KHR_lights_punctual"]["lights"][0].update(type="area"))
bad("gltf_index_out_of_range", "meshes[0].primitives[0].indices: index 6 is 4, past the 4 vertices",
    lambda g: g["meshes"][0]["primitives"][0]["attributes"].update(POSITION=2))

# What the loader cannot model, which it must say: a normal map, clearcoat, a metallic of 0.3,
# and a glass of KHR_materials_transmission.
g = json.loads(json.dumps(gltf))
g["materials"][0]["normalTexture"] = {"index": 0}
g["materials"][0]["extensions"] = {"KHR_materials_clearcoat": {"clearcoatFactor": 1}}
g["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = 0.3
g["materials"][1] = {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
                     "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.45}}}
g["extensionsUsed"] += ["KHR_materials_clearcoat", "KHR_materials_transmission", "KHR_materials_ior"]
with open(os.path.join(HERE, "cubes_ignored.gltf"), "w") as f:
    json.dump(g, f, indent=1)

def shared_node(g):
    g["nodes"][0]["children"] = [1, 2, 1]
bad("gltf_shared_node", "nodes[1]: is reached twice (or 256 levels deep): the node hierarchy must be a forest", shared_node)
def deep(g):
    v = 1
    for _ in range(100): v = [v]
    g["extras"] = v
bad("gltf_deep_json", "its JSON nests deeper than 64 levels", deep)

# A spot and a sun (KHR_lights_punctual) in place of the point light: sun_and_spot.gltf, and the
# same in TOML (sun_and_spot.toml), mirrored too. The spot hangs in the scaled group (its -z
# turned to -y, scaled by 2: the reader normalises it), pointing down at the cubes; the sun's node
# turns -z to (0.6, -0.8, 0). glTF gives the spot in candela and the sun in lux (lm/m^2): / 683.
INNER, OUTER = 0.3, 0.6  # radians
g = json.loads(json.dumps(gltf))
g["extensions"]["KHR_lights_punctual"]["lights"] = [
    {"name": "spot", "type": "spot", "color": [1.0, 0.9, 0.8], "intensity": 683 * 8,
     "spot": {"innerConeAngle": INNER, "outerConeAngle": OUTER}},
    {"name": "sun", "type": "directional", "color": [0.9, 0.95, 1.0], "intensity": 683 * 2}]
# column-major: x -> x, y -> -z, z -> y (turned -90 degrees about x): -z goes to -y
g["nodes"].append({"name": "spot", "matrix": [1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0.5, 1.25, 0.75, 1],
                   "extensions": {"KHR_lights_punctual": {"light": 0}}})
g["nodes"][0]["children"].append(len(g["nodes"]) - 1)
# the bulb's node becomes the sun: x -> z, y -> (0.8, 0.6, 0), z -> (-0.6, 0.8, 0)
g["nodes"][4] = {"name": "sun", "matrix": [0, 0, 1, 0, 0.8, 0.6, 0, 0, -0.6, 0.8, 0, 0, 0, 5, 0, 1],
                 "extensions": {"KHR_lights_punctual": {"light": 1}}}
with open(os.path.join(HERE, "sun_and_spot.gltf"), "w") as f:
    json.dump(g, f, indent=1)
blend = (math.cos(INNER) - math.cos(OUTER)) / (1.0 - math.cos(OUTER))
lights = f'''[[lights]]
type = "spot"
position = [1.25, 3.25, 1.0]
direction = [0.0, -1.0, 0.0]
intensity = [8.0, 7.2, 6.4]
cone_angle = {math.degrees(OUTER)!r}
cone_blend = {blend!r}

[[lights]]
type = "directional"
direction = [0.6, -0.8, 0.0]
irradiance = [1.8, 1.9, 2.0]
'''
point = '''[[lights]]
type = "point"
position = [-1.5, 2.5, 1.5]
intensity = [5.0, 5.0, 5.0]
'''
assert point in header
with open(os.path.join(HERE, "sun_and_spot.toml"), "w") as f:
    f.write(header.replace(point, lights).replace("The scene of cubes.gltf", "The scene of sun_and_spot.gltf").replace(
        '"glTF test scene, as TOML"', '"glTF test scene with a spot and a sun, as TOML"') + scene_shapes([]))
mirrored_lights = lights.replace("position = [1.25, 3.25, 1.0]", "position = [-1.25, 3.25, 1.0]").replace(
    "direction = [0.6, -0.8, 0.0]", "direction = [-0.6, -0.8, 0.0]")
with open(os.path.join(HERE, "sun_and_spot_mirrored.toml"), "w") as f:
    f.write(mirrored.replace(point.replace("[-1.5, 2.5, 1.5]", "[1.5, 2.5, 1.5]"), mirrored_lights).replace(
        "The scene of cubes.gltf", "The scene of sun_and_spot.gltf").replace(
        "glTF test scene, as TOML", "glTF test scene with a spot and a sun, mirrored, as TOML"))
with open(os.path.join(HERE, "sun_and_spot_placed_mirrored.toml"), "w") as f:
    f.write(open(os.path.join(HERE, "cubes_placed_mirrored.toml")).read().replace("cubes", "sun_and_spot").replace(
        "cubes_mirrored.toml", "sun_and_spot_mirrored.toml"))
