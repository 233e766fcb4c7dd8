"""scenes/cornell_box_rtiow.toml rendered by Blender's Cycles, to compare the lessons against an
independent path tracer.

    blender -b --factory-startup --python scripts/cycles_cornell_rtiow.py -- \\
        --spp N --seed S --out FILE.exr [--size 512] [--png FILE.png]

The scene is built from scratch, value for value as in the TOML file: the same quads, the same
two turned boxes, Lambertian (Diffuse BSDF, roughness 0) walls with the same linear albedos, a
lamp of radiance 15 on both sides that reflects nothing, no environment. Our y-up coordinates
become Blender's z-up ones by (x, y, z) -> (x, -z, y), a rotation of +90 degrees about x (a proper
rotation, so no face turns around and the image is not mirrored).

Cycles is set to estimate the same integral as lesson 4: no clamping, no denoising, no adaptive
sampling, no glossy filter, 1024 bounces (Russian roulette as by default), a box pixel filter one
pixel wide (our uniform jitter within the pixel), the Standard view transform, and the result
written as linear 32-bit float RGB OpenEXR. The render's wall time is printed as
"cycles_seconds: X".
"""

import argparse
import math
import os
import sys
import time

import bpy
from mathutils import Vector

# ---- the scene of scenes/cornell_box_rtiow.toml, in its own (y-up) coordinates ----

ALBEDO = {
    "red": (0.65, 0.05, 0.05),
    "white": (0.73, 0.73, 0.73),
    "green": (0.12, 0.45, 0.15),
}
LIGHT_RADIANCE = 15.0  # W/(sr m^2), white, both sides

# (material, corner Q, edge u, edge v), as in the book and the TOML file.
QUADS = [
    ("green", (555, 0, 0), (0, 555, 0), (0, 0, 555)),
    ("red", (0, 0, 0), (0, 555, 0), (0, 0, 555)),
    ("light", (343, 554, 332), (-130, 0, 0), (0, 0, -105)),
    ("white", (0, 0, 0), (555, 0, 0), (0, 0, 555)),
    ("white", (555, 555, 555), (-555, 0, 0), (0, 0, -555)),
    ("white", (0, 0, 555), (555, 0, 0), (0, 555, 0)),
]

# (material, min, max, rotate_y in degrees, translate)
BOXES = [
    ("white", (0, 0, 0), (165, 330, 165), 15.0, (265, 0, 295)),
    ("white", (0, 0, 0), (165, 165, 165), -18.0, (130, 0, 65)),
]

CAMERA_POSITION = (278, 278, -800)
CAMERA_LOOK_AT = (278, 278, 0)
CAMERA_UP = (0, 1, 0)
FOV_Y_DEGREES = 40.0


def box_faces(lo, hi, rotate_y_degrees, translate):
    """The six faces of a box as (corner, u, v) with cross(u, v) pointing out of the box, exactly
    as common/io/scene_build.cpp's box_faces: p -> R_y(t) p + translate with
    x' = cos t x + sin t z, z' = -sin t x + cos t z, in double precision."""
    t = math.radians(rotate_y_degrees)
    c, s = math.cos(t), math.sin(t)

    def rotate(p):
        return (c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2])

    def add(a, b):
        return tuple(x + y for x, y in zip(a, b))

    size = tuple(h - l for h, l in zip(hi, lo))
    dx, dy, dz = rotate((size[0], 0, 0)), rotate((0, size[1], 0)), rotate((0, 0, size[2]))
    base = add(rotate(lo), translate)
    return [
        (base, dz, dy),  # x = min.x, normal -x
        (add(base, dx), dy, dz),  # x = max.x, normal +x
        (base, dx, dz),  # y = min.y, normal -y
        (add(base, dy), dz, dx),  # y = max.y, normal +y
        (base, dy, dx),  # z = min.z, normal -z
        (add(base, dz), dx, dy),  # z = max.z, normal +z
    ]


def to_blender(p):
    """Our y-up (x, y, z) to Blender's z-up: (x, -z, y), a rotation by +90 degrees about x."""
    return (p[0], -p[2], p[1])


# ---- building it in Blender ----


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for blocks in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for block in list(blocks):
            blocks.remove(block)


def node_material(name, shader_type, inputs):
    """A Cycles material whose surface is one shader node, with the given input values."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    shader = nodes.new(shader_type)
    for key, value in inputs.items():
        shader.inputs[key].default_value = value
    out = nodes.new("ShaderNodeOutputMaterial")
    out.target = "CYCLES"
    links.new(shader.outputs[0], out.inputs["Surface"])
    return m


def diffuse_material(name, albedo):
    # Linear RGB, as in the TOML file; roughness 0: Lambertian, not Oren-Nayar.
    return node_material(
        name, "ShaderNodeBsdfDiffuse", {"Color": (*albedo, 1.0), "Roughness": 0.0})


def emission_material(name, strength):
    # A Cycles mesh emitter's radiance is color * strength, on both sides of the surface.
    return node_material(
        name, "ShaderNodeEmission", {"Color": (1.0, 1.0, 1.0, 1.0), "Strength": strength})


def add_quads(name, quads, material):
    """One mesh object of separate quads, each (corner, u, v) in our coordinates, its vertices in
    the order corner, +u, +u+v, +v, so that Blender's normal is cross(u, v) mapped."""
    vertices, faces = [], []
    for q, u, v in quads:
        k = len(vertices)
        for a, b in ((0, 0), (1, 0), (1, 1), (0, 1)):
            vertices.append(to_blender(tuple(q[i] + a * u[i] + b * v[i] for i in range(3))))
        faces.append((k, k + 1, k + 2, k + 3))
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.validate()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build_scene(scene, size):
    clear_scene()
    materials = {name: diffuse_material(name, albedo) for name, albedo in ALBEDO.items()}
    materials["light"] = emission_material("light", LIGHT_RADIANCE)
    for i, (material, q, u, v) in enumerate(QUADS):
        add_quads(f"quad{i}_{material}", [(q, u, v)], materials[material])
    for i, (material, lo, hi, angle, move) in enumerate(BOXES):
        add_quads(f"box{i}", box_faces(lo, hi, angle, move), materials[material])

    # No environment: black, strength 0.
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world

    # The pinhole camera: Blender's looks along its local -z with local +y up.
    camera_data = bpy.data.cameras.new("camera")
    camera_data.type = "PERSP"
    camera_data.sensor_fit = "VERTICAL"
    camera_data.angle_y = math.radians(FOV_Y_DEGREES)
    camera_data.clip_start = 1.0
    camera_data.clip_end = 1e5
    camera = bpy.data.objects.new("camera", camera_data)
    scene.collection.objects.link(camera)
    position = Vector(to_blender(CAMERA_POSITION))
    forward = Vector(to_blender(CAMERA_LOOK_AT)) - position
    up = Vector(to_blender(CAMERA_UP))
    camera.location = position
    # to_track_quat keeps the camera's y axis towards world z; our up maps to exactly that.
    assert up == Vector((0.0, 0.0, 1.0))
    camera.rotation_mode = "QUATERNION"
    camera.rotation_quaternion = forward.to_track_quat("-Z", "Y")
    scene.camera = camera

    render = scene.render
    render.resolution_x = size
    render.resolution_y = size
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.use_border = False
    render.film_transparent = False
    render.use_compositing = False
    render.use_sequencer = False
    render.threads_mode = "FIXED"
    render.threads = 2


def configure_cycles(scene, spp, seed):
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
    cycles.blur_glossy = 0.0  # "filter glossy" off
    cycles.max_bounces = 1024
    cycles.diffuse_bounces = 1024
    # min_light_bounces (Russian roulette) and the caustics switches keep their defaults.
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0  # pixels: uniform within the pixel, as our jitter
    cycles.film_exposure = 1.0
    for layer in scene.view_layers:
        layer.cycles.use_denoising = False

    view = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(
        prog="cycles_cornell_rtiow.py",
        description="Render scenes/cornell_box_rtiow.toml with Cycles to a linear float EXR.",
    )
    parser.add_argument("--spp", type=int, required=True, help="samples per pixel")
    parser.add_argument("--seed", type=int, default=0, help="Cycles seed")
    parser.add_argument("--out", required=True, help="output OpenEXR file")
    parser.add_argument("--size", type=int, default=512, help="image width and height")
    parser.add_argument("--png", help="also write an 8-bit sRGB PNG here, for looking at")
    args = parser.parse_args(argv)
    if args.spp < 1 or args.size < 1:
        parser.error("--spp and --size must be at least 1")

    scene = bpy.context.scene
    build_scene(scene, args.size)
    configure_cycles(scene, args.spp, args.seed)

    out = os.path.abspath(args.out)
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
    print(f"cycles: wrote {out} ({args.size}x{args.size}, {args.spp} spp, seed {args.seed})")

    if args.png:
        png = os.path.abspath(args.png)
        settings.file_format = "PNG"
        settings.color_mode = "RGB"
        settings.color_depth = "8"
        # The Standard view transform: linear -> sRGB, values above 1 clipped.
        bpy.data.images["Render Result"].save_render(png, scene=scene)
        print(f"cycles: wrote {png}")


if __name__ == "__main__":
    main()
