"""Builds any suite scene in Blender, for Cycles: the other end of the lessons' comparisons.

    blender -b --factory-startup --python scripts/blender/toml_to_blender.py -- SCENE \\
        [--blend FILE.blend] [--render FILE.exr --spp N [--seed S] [--threads T] [--png FILE]] \\
        [--width W --height H] [--json FILE] [--scene-export PROGRAM]

SCENE is a TOML scene (or a glTF file) as the lessons take it. It is not parsed here: the
suite's own loader reads it (build/bin/scene_export, the code every lesson uses), and writes
the loaded scene as JSON: boxes as their quads, transforms applied, OBJ and glTF meshes
triangulated, MTL and glTF materials mapped. This script only maps that onto Blender, so a
scene means the same thing in Cycles as in the lessons. What cannot be mapped exactly is printed
as "toml_to_blender: approximated: ..." (docs/interop.md has the table).

  coordinates   ours are y-up, Blender's z-up: (x, y, z) -> (x, -z, y), a proper rotation
                (+90 degrees about x), so nothing is mirrored and no face turns around
  quads         a mesh of four-sided faces (corner, +u, +u+v, +v: the normal is cross(u, v)),
                with (u, v) as the face's UV; tagged lessons_shape = "quads"
  spheres       a point cloud (Geometry Nodes' Mesh to Points): Cycles renders each point as a
                true sphere, as the lessons do; but a ray inside such a point does not hit it,
                and Cycles light-samples emitting triangles (points perhaps not), so glass and
                emitting spheres are smooth UV-sphere meshes of 256 x 128 segments, tagged lessons_shape = "sphere"
                (and every sphere with --sphere-mesh N)
  triangles     one mesh per material, smooth faces with the shading normals as custom normals
  diffuse       Diffuse BSDF, roughness 0 (Lambert)
  glossy        Diffuse BSDF + Glossy BSDF (Beckmann, roughness sqrt(alpha)): approximated, the
                lessons' lobe is a normalised Blinn-Phong of the same width
  conductor     Principled BSDF, metallic 1, GGX, roughness sqrt(alpha): approximated, Cycles'
                metallic Fresnel is not Schlick's
  mirror        Glossy BSDF, sharp
  glass         Glass BSDF, sharp; a tinted glass tints only the refracted light, as ours:
                Fresnel-weighted mix of a Refraction BSDF (the tint) and a sharp white Glossy
  emission      Emission added to the surface's BSDF; one-sided emission is zero on back faces
  checker       Checker Texture over UV scaled by the cells (Cycles' odd cells are Color1)
  texture       Image Texture, linear interpolation, repeat or extend; an 8-bit image decoded
                to linear floats first (interpolated after decoding, as ours)
  point light   a point light of radius 0: Cycles' intensity is power / (4 pi) W/sr
  spot light    a spot of radius 0, spot_size twice the cone angle, spot_blend the cone blend,
                power 4 pi I; its shader divides the strength by the cosine to the axis, which
                Cycles 3.x multiplies a spot by and ours does not: exact
  directional   a sun of angle 0, strength the irradiance (W/m^2)
  background    the world's Background: a colour, or the map as an Environment Texture
                (closest texel: the lessons' map is piecewise constant)
  camera        perspective, vertical field of view, the image size

With --render, Cycles estimates the same integral as the lessons: CPU, no clamping, denoising,
adaptive sampling or glossy filter, no light threshold, 1024 bounces of every kind (Russian
roulette as by default), a box pixel filter one pixel wide, written as linear 32-bit float RGB
OpenEXR. The render's wall time is printed as "cycles_seconds: X".
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector

# Segments of a glass sphere's mesh (2N around, N from pole to pole): the silhouette is within
# r (1 - cos(pi / 2N)) = 7.5e-5 r of the sphere, and the normals are the sphere's at the vertices.
GLASS_SPHERE_SEGMENTS = 128
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def note(message):
    print(f"toml_to_blender: approximated: {message}", flush=True)


def to_blender(p):
    """Our y-up (x, y, z) to Blender's z-up: (x, -z, y)."""
    return (p[0], -p[2], p[1])


def points_to_blender(flat):
    """A flat array of (x, y, z) to Blender's axes, as an (n, 3) array."""
    a = np.asarray(flat, dtype=np.float64).reshape(-1, 3)
    return np.stack([a[:, 0], -a[:, 2], a[:, 1]], axis=1)


def load_export(args):
    """The scene as the suite loads it: scene_export's JSON."""
    if args.json and os.path.exists(args.json) and not args.scene:
        with open(args.json) as f:
            return json.load(f)
    program = args.scene_export or os.environ.get(
        "LESSONS_SCENE_EXPORT", os.path.join(ROOT, "build", "bin", "scene_export"))
    out = args.json or os.path.join(tempfile.mkdtemp(prefix="toml_to_blender_"), "scene.json")
    result = subprocess.run([program, args.scene, "--out", out], capture_output=True, text=True)
    if result.returncode != 0:
        sys.stderr.write(result.stderr)
        raise SystemExit(f"toml_to_blender: {program} could not load {args.scene}")
    with open(out) as f:
        return json.load(f)


# ---- materials ----


class Nodes:
    """A material's node tree, built left to right."""

    def __init__(self, material):
        material.use_nodes = True
        self.tree = material.node_tree
        self.tree.nodes.clear()

    def new(self, kind, **inputs):
        node = self.tree.nodes.new(kind)
        for key, value in inputs.items():
            node.inputs[key].default_value = value
        return node

    def link(self, output, socket):
        self.tree.links.new(output, socket)


def rgba(c):
    return (float(c[0]), float(c[1]), float(c[2]), 1.0)


def albedo_socket(nodes, albedo, name):
    """Sets up the albedo (a colour, a checker or an image) and returns (colour, node output or
    None). The UV map is the object's (quads: their edge coordinates; meshes: their vt)."""
    if "color" in albedo:
        return rgba(albedo["color"]), None
    uv = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    nodes.link(uv.outputs["UV"], mapping.inputs["Vector"])
    if "checker" in albedo:
        even, odd = albedo["checker"]
        cu, cv = albedo["cells"]
        mapping.inputs["Scale"].default_value = (cu, cv, 1.0)
        # Cycles' checker: Color1 where floor(x) + floor(y) is odd (with z = 0), as our odd cells.
        checker = nodes.new("ShaderNodeTexChecker", Color1=rgba(odd), Color2=rgba(even), Scale=1.0)
        nodes.link(mapping.outputs["Vector"], checker.inputs["Vector"])
        return None, checker.outputs["Color"]
    su, sv = albedo["scale"]
    mapping.inputs["Scale"].default_value = (su, sv, 1.0)
    image_node = nodes.new("ShaderNodeTexImage")
    image_node.image = linear_texture(albedo["texture"])
    image_node.interpolation = "Linear"
    image_node.extension = "REPEAT" if albedo["wrap"] == "repeat" else "EXTEND"
    nodes.link(mapping.outputs["Vector"], image_node.inputs["Vector"])
    return None, image_node.outputs["Color"]


_textures = {}


def linear_texture(path):
    """The image as linear floats, as the lessons hold it. Cycles would keep an 8-bit sRGB image
    as bytes and interpolate the encoded values, which darkens every edge between light and dark
    texels (3% on scenes/sky_map.toml's tiles); so 8-bit images are decoded here by the sRGB
    curve into a float image, packed into the .blend. The file it came from is kept in the image's
    lessons_file property (blender_to_toml names it)."""
    if path in _textures:
        return _textures[path]
    image = bpy.data.images.load(path, check_existing=True)
    if path.lower().endswith((".exr", ".hdr")):
        image.colorspace_settings.name = "Linear"
    elif not image.is_float:
        w, h = image.size
        encoded = np.empty(w * h * 4, dtype=np.float32)
        image.pixels.foreach_get(encoded)
        rgb = encoded.reshape(-1, 4)[:, :3]
        # The sRGB decoding curve (IEC 61966-2-1), as io/texture.cpp applies it.
        rgb[:] = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
        decoded = bpy.data.images.new(os.path.basename(path), w, h, alpha=False,
                                      float_buffer=True)
        decoded.colorspace_settings.name = "Linear"
        decoded.pixels.foreach_set(encoded)
        decoded.pack()
        bpy.data.images.remove(image)
        image = decoded
    image["lessons_file"] = os.path.abspath(path)
    _textures[path] = image
    return image


def set_color(nodes, shader, socket_name, albedo, name):
    value, output = albedo_socket(nodes, albedo, name)
    if output is None:
        shader.inputs[socket_name].default_value = value
    else:
        nodes.link(output, shader.inputs[socket_name])


def is_black(c):
    return max(c[:3]) <= 0.0


def surface_shader(nodes, m):
    """The reflecting part of material m as a shader output, or None when it reflects nothing."""
    kind, name = m["type"], m["name"]
    if kind == "diffuse":
        albedo = m["albedo"]
        if "color" in albedo and is_black(albedo["color"]):
            return None
        shader = nodes.new("ShaderNodeBsdfDiffuse", Roughness=0.0)
        set_color(nodes, shader, "Color", albedo, name)
        return shader.outputs[0]
    if kind == "glossy":
        r = math.sqrt(m["roughness"])
        note(f"material '{name}': glossy: the lessons' normalised Blinn-Phong lobe of alpha "
             f"{m['roughness']:g} becomes Cycles' Beckmann Glossy BSDF of roughness {r:.4g}")
        diffuse = nodes.new("ShaderNodeBsdfDiffuse", Roughness=0.0)
        set_color(nodes, diffuse, "Color", m["albedo"], name)
        glossy = nodes.new("ShaderNodeBsdfGlossy", Color=rgba(m["specular"]), Roughness=r)
        glossy.distribution = "BECKMANN"
        add = nodes.new("ShaderNodeAddShader")
        nodes.link(diffuse.outputs[0], add.inputs[0])
        nodes.link(glossy.outputs[0], add.inputs[1])
        return add.outputs[0]
    if kind == "conductor":
        r = math.sqrt(m["roughness"])
        note(f"material '{name}': conductor: Principled BSDF, metallic 1, GGX roughness {r:.4g} "
             "(alpha = roughness^2); Cycles' metallic Fresnel is close to, not equal to, Schlick's")
        shader = nodes.new("ShaderNodeBsdfPrincipled", Metallic=1.0, Roughness=r,
                           **{"Base Color": rgba(m["specular"])})
        shader.distribution = "GGX"
        return shader.outputs[0]
    if kind == "mirror":
        shader = nodes.new("ShaderNodeBsdfGlossy", Color=rgba(m["reflectance"]), Roughness=0.0)
        shader.distribution = "SHARP"
        return shader.outputs[0]
    if kind == "glass":
        ior, tint = m["ior"], m["transmittance"]
        if min(tint) >= 1.0:
            shader = nodes.new("ShaderNodeBsdfGlass", IOR=ior, Roughness=0.0,
                               Color=(1.0, 1.0, 1.0, 1.0))
            shader.distribution = "SHARP"
            return shader.outputs[0]
        # Ours tints the refracted light only: (1 - F) Refraction(tint) + F Glossy(white).
        fresnel = nodes.new("ShaderNodeFresnel", IOR=ior)
        refraction = nodes.new("ShaderNodeBsdfRefraction", IOR=ior, Roughness=0.0, Color=rgba(tint))
        refraction.distribution = "SHARP"
        reflection = nodes.new("ShaderNodeBsdfGlossy", Roughness=0.0, Color=(1.0, 1.0, 1.0, 1.0))
        reflection.distribution = "SHARP"
        mix = nodes.new("ShaderNodeMixShader")
        nodes.link(fresnel.outputs[0], mix.inputs["Fac"])
        nodes.link(refraction.outputs[0], mix.inputs[1])
        nodes.link(reflection.outputs[0], mix.inputs[2])
        return mix.outputs[0]
    raise SystemExit(f"toml_to_blender: material '{name}': unknown type {kind}")


def emission_shader(nodes, m):
    """The emitting part: Cycles' Emission of colour c and strength s has radiance c s on both
    sides; a one-sided emitter's strength is multiplied by (1 - Backfacing)."""
    e = m["emission"]
    strength = max(e)
    color = tuple(c / strength for c in e) + (1.0,)
    emission = nodes.new("ShaderNodeEmission", Color=color, Strength=strength)
    if not m["two_sided"]:
        geometry = nodes.new("ShaderNodeNewGeometry")
        front = nodes.new("ShaderNodeMath")
        front.operation = "MULTIPLY_ADD"
        # strength * (-backfacing) + strength
        nodes.link(geometry.outputs["Backfacing"], front.inputs[0])
        front.inputs[1].default_value = -strength
        front.inputs[2].default_value = strength
        nodes.link(front.outputs[0], emission.inputs["Strength"])
    return emission.outputs[0]


def make_material(m):
    material = bpy.data.materials.new(m["name"])
    nodes = Nodes(material)
    output = nodes.new("ShaderNodeOutputMaterial")
    output.target = "ALL"
    surface = surface_shader(nodes, m)
    if not is_black(m["emission"]):
        emission = emission_shader(nodes, m)
        if surface is None:
            surface = emission
        else:
            add = nodes.new("ShaderNodeAddShader")
            nodes.link(surface, add.inputs[0])
            nodes.link(emission, add.inputs[1])
            surface = add.outputs[0]
    if surface is None:  # black and not emitting: absorbs everything
        surface = nodes.new("ShaderNodeBsdfDiffuse", Color=(0.0, 0.0, 0.0, 1.0)).outputs[0]
    nodes.link(surface, output.inputs["Surface"])
    # What the lessons' material was, for people reading the .blend (blender_to_toml reads the
    # nodes, not this).
    material["lessons_type"] = m["type"]
    return material


# ---- shapes ----


def link_object(name, data, scene):
    obj = bpy.data.objects.new(name, data)
    scene.collection.objects.link(obj)
    return obj


def build_mesh(name, vertices, faces_flat, face_sizes, uvs=None, smooth=None, loop_normals=None):
    """A mesh from vertices (n, 3), loops' vertex indices, face sizes, per-loop uvs (m, 2),
    per-face smooth flags and per-loop custom normals (m, 3), with numpy arrays."""
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(vertices))
    mesh.vertices.foreach_set("co", np.asarray(vertices, dtype=np.float32).ravel())
    mesh.loops.add(len(faces_flat))
    mesh.loops.foreach_set("vertex_index", np.asarray(faces_flat, dtype=np.int32))
    mesh.polygons.add(len(face_sizes))
    starts = np.concatenate([[0], np.cumsum(face_sizes)[:-1]]).astype(np.int32)
    mesh.polygons.foreach_set("loop_start", starts)
    mesh.polygons.foreach_set("loop_total", np.asarray(face_sizes, dtype=np.int32))
    if smooth is not None:
        mesh.polygons.foreach_set("use_smooth", np.asarray(smooth, dtype=bool))
    mesh.update(calc_edges=True)
    if uvs is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", np.asarray(uvs, dtype=np.float32).ravel())
    if loop_normals is not None:
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.pi
        mesh.normals_split_custom_set([tuple(n) for n in np.asarray(loop_normals)])
    return mesh


def add_quads(scene, quads, materials):
    by_material = {}
    for q in quads:
        by_material.setdefault(q["material"], []).append(q)
    for index, group in by_material.items():
        corner = np.array([to_blender(q["corner"]) for q in group], dtype=np.float64)
        u = np.array([to_blender(q["edge_u"]) for q in group], dtype=np.float64)
        v = np.array([to_blender(q["edge_v"]) for q in group], dtype=np.float64)
        vertices = np.stack([corner, corner + u, corner + u + v, corner + v], axis=1).reshape(-1, 3)
        n = len(group)
        uvs = np.tile(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32), (n, 1))
        mesh = build_mesh(f"quads_{materials[index].name}", vertices, np.arange(4 * n),
                          np.full(n, 4), uvs=uvs)
        mesh.materials.append(materials[index])
        obj = link_object(mesh.name, mesh, scene)
        obj["lessons_shape"] = "quads"


def add_triangles(scene, mesh_json, materials, export):
    tri = np.asarray(mesh_json["triangles"], dtype=np.int64).reshape(-1, 3)
    if len(tri) == 0:
        return
    positions = points_to_blender(mesh_json["positions"])
    normals = points_to_blender(mesh_json["normals"]) if mesh_json["normals"] else None
    uv_all = np.asarray(mesh_json["uvs"], dtype=np.float64).reshape(-1, 2) if mesh_json["uvs"] else None
    tri_material = np.asarray(mesh_json["materials"], dtype=np.int64)
    smooth = np.asarray(mesh_json["smooth"], dtype=bool)
    for index in np.unique(tri_material):
        mine = tri[tri_material == index]
        used, local = np.unique(mine.ravel(), return_inverse=True)
        n = len(mine)
        # Without texture coordinates the lessons use each triangle's barycentric (u, v), which
        # only matters to a checker; Blender's mesh then has no UV map either.
        uvs = uv_all[mine.ravel()] if uv_all is not None else None
        albedo = export["materials"][index].get("albedo", {})
        if uvs is None and "checker" in albedo:
            note(f"material '{materials[index].name}' on a mesh without texture coordinates: "
                 "the lessons' checker follows each triangle's barycentric (u, v), Cycles' is "
                 "looked up at (0, 0)")
        face_smooth = smooth[tri_material == index]
        loop_normals = None
        if normals is not None and face_smooth.any():
            loop_normals = normals[mine.ravel()].copy()
            loop_normals[np.repeat(~face_smooth, 3)] = 0.0  # flat faces: Blender's own normal
        mesh = build_mesh(f"mesh_{materials[index].name}", positions[used], local, np.full(n, 3),
                          uvs=uvs, smooth=face_smooth, loop_normals=loop_normals)
        mesh.materials.append(materials[index])
        link_object(mesh.name, mesh, scene)


def sphere_points_group(material):
    """Geometry nodes turning a mesh's vertices into points of the radius stored per vertex
    (attribute 'radius'), with the material: Cycles renders them as spheres."""
    group = bpy.data.node_groups.new(f"spheres_{material.name}", "GeometryNodeTree")
    group.inputs.new("NodeSocketGeometry", "Geometry")
    group.outputs.new("NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    given, out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    to_points = nodes.new("GeometryNodeMeshToPoints")
    radius = nodes.new("GeometryNodeInputNamedAttribute")
    radius.data_type = "FLOAT"
    radius.inputs["Name"].default_value = "radius"
    set_material = nodes.new("GeometryNodeSetMaterial")
    set_material.inputs["Material"].default_value = material
    links.new(given.outputs[0], to_points.inputs["Mesh"])
    links.new(radius.outputs["Attribute"], to_points.inputs["Radius"])
    links.new(to_points.outputs[0], set_material.inputs["Geometry"])
    links.new(set_material.outputs[0], out.inputs[0])
    return group


def add_sphere_meshes(scene, spheres, materials, segments):
    """Spheres as smooth UV-sphere meshes (--sphere-mesh), to check Cycles' points against."""
    import bmesh
    for i, s in enumerate(spheres):
        mesh = bpy.data.meshes.new(f"sphere{i}")
        b = bmesh.new()
        bmesh.ops.create_uvsphere(b, u_segments=2 * segments, v_segments=segments,
                                  radius=float(s["radius"]))
        b.to_mesh(mesh)
        b.free()
        mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
        mesh.materials.append(materials[s["material"]])
        obj = link_object(mesh.name, mesh, scene)
        obj.location = to_blender(s["center"])
        obj["lessons_shape"] = "sphere"  # blender_to_toml writes it back as a sphere
        obj["lessons_radius"] = float(s["radius"])


def add_spheres(scene, spheres, materials, export):
    """Spheres as points of a point cloud, one cloud per material."""
    by_material = {}
    for s in spheres:
        by_material.setdefault(s["material"], []).append(s)
    for index, group in by_material.items():
        material = materials[index]
        m = export["materials"][index]
        if "albedo" in m and "color" not in m["albedo"]:
            note(f"material '{m['name']}' on spheres: Cycles' points have no (u, v): the pattern "
                 "is looked up at (0, 0)")
        mesh = bpy.data.meshes.new(f"spheres_{material.name}")
        mesh.from_pydata([to_blender(s["center"]) for s in group], [], [])
        attribute = mesh.attributes.new("radius", "FLOAT", "POINT")
        attribute.data.foreach_set("value", [float(s["radius"]) for s in group])
        mesh.materials.append(material)
        obj = link_object(mesh.name, mesh, scene)
        modifier = obj.modifiers.new("spheres", "NODES")
        modifier.node_group = sphere_points_group(material)
        obj["lessons_shape"] = "spheres"


def point_along(obj, direction):
    """Turns a Blender light so that its local -Z (where spots and suns shine) is `direction`
    (ours, y-up)."""
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = Vector(to_blender(direction)).normalized().to_track_quat("-Z", "Y")


def undo_spot_cosine(data):
    """Cycles 3.x gives a spot light of power P the intensity P / (4 pi) cos(a) smoothstep(...)
    at the angle a from its axis (measured: docs/interop.md), where ours has no cos(a). The
    light's own shader divides its strength by cos(a): the Texture Coordinate node's Normal is,
    in a light's shader, the direction of emission in the light's own frame, whose axis is -Z."""
    data.use_nodes = True
    tree = data.node_tree
    emission = tree.nodes["Emission"]
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    cosine = tree.nodes.new("ShaderNodeVectorMath")
    cosine.operation = "DOT_PRODUCT"
    cosine.inputs[1].default_value = (0.0, 0.0, -1.0)
    tree.links.new(coordinates.outputs["Normal"], cosine.inputs[0])
    floor = tree.nodes.new("ShaderNodeMath")
    floor.operation = "MAXIMUM"  # outside the cone Cycles gives 0 anyway; no division by 0
    floor.inputs[1].default_value = 1e-6
    tree.links.new(cosine.outputs["Value"], floor.inputs[0])
    strength = tree.nodes.new("ShaderNodeMath")
    strength.operation = "DIVIDE"
    strength.inputs[0].default_value = 1.0  # the light's power stays in data.energy
    tree.links.new(floor.outputs[0], strength.inputs[1])
    tree.links.new(strength.outputs[0], emission.inputs["Strength"])
    data["lessons_spot"] = "cosine undone"  # blender_to_toml reads the spot back as exact


def add_point_lights(scene, lights):
    """Point lights, and spots (a point light with a cone): Blender's power P gives the
    intensity P / (4 pi) W/sr (on the axis, for a spot); spot_size is the cone's full angle,
    spot_blend its blend: Cycles' smoothstep runs over spot_blend (1 - cos(spot_size / 2)) in
    cos, as ours over cone_blend (1 - cos(cone_angle))."""
    for i, light in enumerate(lights):
        intensity = light["intensity"]
        peak = max(intensity)
        if peak <= 0.0:
            print(f"toml_to_blender: point light {i} is black: left out")
            continue
        spot = light.get("spot")
        name = f"spot{i}" if spot else f"point{i}"
        data = bpy.data.lights.new(name, "SPOT" if spot else "POINT")
        data.color = tuple(c / peak for c in intensity)
        data.energy = 4.0 * math.pi * peak  # Cycles: intensity = power / (4 pi) W/sr
        data.shadow_soft_size = 0.0
        obj = link_object(name, data, scene)
        obj.location = to_blender(light["position"])
        if spot:
            data.spot_size = 2.0 * math.radians(spot["cone_angle"])
            data.spot_blend = spot["cone_blend"]
            data.show_cone = True
            point_along(obj, spot["direction"])
            undo_spot_cosine(data)


def add_directional_lights(scene, lights):
    """Directional lights as Blender's suns of angle 0: a sun's strength is the irradiance, in
    W/m^2, on a surface facing it (measured: docs/interop.md)."""
    for i, light in enumerate(lights):
        irradiance = light["irradiance"]
        peak = max(irradiance)
        if peak <= 0.0:
            print(f"toml_to_blender: directional light {i} is black: left out")
            continue
        data = bpy.data.lights.new(f"sun{i}", "SUN")
        data.color = tuple(c / peak for c in irradiance)
        data.energy = peak
        data.angle = 0.0  # a hard sun, as ours
        obj = link_object(f"sun{i}", data, scene)
        point_along(obj, light["direction"])


def set_world(scene, background):
    world = bpy.data.worlds.new("background")
    world.use_nodes = True
    tree = world.node_tree
    node = tree.nodes["Background"]
    if "map" in background:
        environment = tree.nodes.new("ShaderNodeTexEnvironment")
        environment.image = bpy.data.images.load(background["map"], check_existing=True)
        environment.image.colorspace_settings.name = "Linear"
        environment.interpolation = "Closest"
        environment.projection = "EQUIRECTANGULAR"
        # Our column u = (phi + rotate) / 2 pi, phi from +x towards +z (Blender's -y); Cycles'
        # u = 0.5 - atan2(Y, X) / 2 pi, so u = 0 looks along -X: ours is Cycles' turned by half
        # a turn, and our rotate turns the lookup direction about Blender's z by -rotate.
        coordinates = tree.nodes.new("ShaderNodeTexCoord")
        mapping = tree.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        mapping.inputs["Rotation"].default_value = (
            0.0, 0.0, math.pi - math.radians(background["rotate"]))
        tree.links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
        tree.links.new(mapping.outputs["Vector"], environment.inputs["Vector"])
        tree.links.new(environment.outputs["Color"], node.inputs["Color"])
        node.inputs["Strength"].default_value = background["strength"]
    else:
        radiance = background["radiance"]
        node.inputs["Color"].default_value = rgba(radiance)
        node.inputs["Strength"].default_value = 1.0 if not is_black(radiance) else 0.0
    scene.world = world


def set_camera(scene, camera, width, height, extent):
    data = bpy.data.cameras.new("camera")
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(camera["fov"])
    data.clip_start = max(1e-6, 1e-5 * extent)
    data.clip_end = 1e3 * extent
    obj = link_object("camera", data, scene)
    position = Vector(to_blender(camera["position"]))
    forward = (Vector(to_blender(camera["look_at"])) - position).normalized()
    right = forward.cross(Vector(to_blender(camera["up"]))).normalized()
    up = right.cross(forward)
    # Blender's camera looks along its local -z, with +y up and +x right.
    obj.matrix_world = Matrix.Translation(position) @ Matrix(
        (right, up, -forward)).transposed().to_4x4()
    scene.camera = obj
    render = scene.render
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.use_border = False
    render.film_transparent = False


def scene_extent(export):
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)

    def grow(points):
        nonlocal lo, hi
        if len(points):
            lo, hi = np.minimum(lo, points.min(axis=0)), np.maximum(hi, points.max(axis=0))

    grow(points_to_blender(export["mesh"]["positions"]))
    for q in export["quads"]:
        grow(np.array([to_blender(q["corner"])]))
    for s in export["spheres"]:
        c, r = np.array(to_blender(s["center"])), s["radius"]
        grow(np.array([c - r, c + r]))
    for light in export["point_lights"]:
        grow(np.array([to_blender(light["position"])]))
    grow(np.array([to_blender(export["camera"]["position"])]))
    return float(np.max(hi - lo)) if np.all(np.isfinite(lo)) else 1.0


def build(export, width=None, height=None, sphere_mesh=0):
    """A new Blender scene holding the exported scene."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for blocks in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras,
                   bpy.data.worlds, bpy.data.node_groups, bpy.data.images):
        for block in list(blocks):
            blocks.remove(block)
    scene = bpy.context.scene
    materials = [make_material(m) for m in export["materials"]]
    add_quads(scene, export["quads"], materials)
    add_triangles(scene, export["mesh"], materials, export)
    # Cycles' points are exact spheres seen from outside, but a ray inside one does not hit it,
    # and Cycles light-samples emitting triangles (points perhaps not): glass and emitting
    # spheres (and all, with --sphere-mesh) are smooth meshes instead.
    spheres = export["spheres"]

    def needs_mesh(s):
        m = export["materials"][s["material"]]
        return sphere_mesh or m["type"] == "glass" or not is_black(m["emission"])

    as_mesh = [s for s in spheres if needs_mesh(s)]
    if as_mesh:
        segments = sphere_mesh or GLASS_SPHERE_SEGMENTS
        note(f"{len(as_mesh)} sphere(s) as smooth UV-sphere meshes of {2 * segments} x "
             f"{segments} segments (Cycles' points are not entered by rays nor sampled as "
             "lights)")
        add_sphere_meshes(scene, as_mesh, materials, segments)
    add_spheres(scene, [s for s in spheres if not any(s is t for t in as_mesh)], materials, export)
    add_point_lights(scene, export["point_lights"])
    add_directional_lights(scene, export.get("directional_lights", []))
    set_world(scene, export["background"])
    set_camera(scene, export["camera"], width or export["width"], height or export["height"],
               scene_extent(export))
    scene["lessons_source"] = export["source"]
    return scene


def configure_cycles(scene, spp, seed, threads):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = spp
    cycles.seed = seed
    cycles.use_animated_seed = False
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.time_limit = 0.0
    cycles.sample_clamp_direct = 0.0  # 0: no clamping
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0  # no light is skipped as too dim
    cycles.blur_glossy = 0.0  # "filter glossy" off
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                    "transparent_max_bounces", "volume_bounces"):
        setattr(cycles, bounces, 1024)
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0  # pixels: uniform within the pixel, as our jitter
    cycles.film_exposure = 1.0
    for layer in scene.view_layers:
        layer.cycles.use_denoising = False
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    view = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0


def render(scene, out, png=None):
    out = os.path.abspath(out)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGB"
    settings.color_depth = "32"  # full float
    settings.exr_codec = "ZIP"  # lossless
    scene.render.use_file_extension = False
    scene.render.filepath = out
    start = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - start
    print(f"cycles_seconds: {seconds:.3f}", flush=True)
    print(f"toml_to_blender: wrote {out} ({scene.render.resolution_x}x{scene.render.resolution_y}, "
          f"{scene.cycles.samples} spp, seed {scene.cycles.seed})")
    if png:
        settings.file_format = "PNG"
        settings.color_mode = "RGB"
        settings.color_depth = "8"
        bpy.data.images["Render Result"].save_render(os.path.abspath(png), scene=scene)
        print(f"toml_to_blender: wrote {png}")


def main():
    if bpy.app.version >= (4, 0, 0):
        raise SystemExit("toml_to_blender: written for Blender 3.x (Debian 12's 3.4); Blender "
                         f"{bpy.app.version_string} changed the node and mesh interfaces it uses")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="toml_to_blender.py",
                                     description="Build a suite scene in Blender for Cycles.")
    parser.add_argument("scene", nargs="?", help="a TOML scene (or glTF) of the suite")
    parser.add_argument("--json", help="scene_export's JSON: written here, or read when no "
                        "SCENE is given")
    parser.add_argument("--scene-export", help="the scene_export program "
                        "(default build/bin/scene_export)")
    parser.add_argument("--blend", help="save the Blender scene here")
    parser.add_argument("--render", help="render it with Cycles to this OpenEXR file")
    parser.add_argument("--spp", type=int, default=16, help="Cycles samples per pixel")
    parser.add_argument("--seed", type=int, default=0, help="Cycles seed")
    parser.add_argument("--threads", type=int, default=2, help="Cycles threads")
    parser.add_argument("--width", type=int, help="image width (default the scene's)")
    parser.add_argument("--height", type=int, help="image height (default the scene's)")
    parser.add_argument("--png", help="with --render, also an 8-bit sRGB PNG")
    parser.add_argument("--sphere-mesh", type=int, default=0, metavar="N",
                        help="spheres as smooth meshes of 2N x N segments instead of Cycles' "
                        "points (to check one against the other)")
    args = parser.parse_args(argv)
    if not args.scene and not args.json:
        parser.error("give a SCENE (or --json FILE)")
    for value in (args.spp, args.threads, args.width or 1, args.height or 1):
        if value < 1:
            parser.error("--spp, --threads, --width and --height must be at least 1")
    export = load_export(args)
    scene = build(export, args.width, args.height, args.sphere_mesh)
    configure_cycles(scene, args.spp, args.seed, args.threads)
    if args.blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.blend))
        print(f"toml_to_blender: wrote {args.blend}")
    if args.render:
        render(scene, args.render, args.png)


if __name__ == "__main__":
    main()
