"""Measures how Cycles defines its lights (docs/interop.md, "Cycles' lights, measured"): a white
Lambert floor (albedo 1) at z = 0 under one light, seen from straight above by an orthographic
camera, direct light only, so that each pixel is E / pi and the light's intensity towards it is
pi L d^2 / cos(theta) (d and theta from the light to the pixel's centre).

    blender -b --factory-startup --python tests/blender/measure_cycles_lights.py [-- DIR]

Prints, for a point light, a spot (as Blender makes it, and with toml_to_blender.py's shader
dividing by the cosine to the axis, also tilted), a sun and square and rectangular area lights
(against an emitting mesh of the same size), what Cycles gives against the closed forms.
"""

import math
import os
import sys
import tempfile

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts", "blender"))
argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = argv[0] if argv else tempfile.mkdtemp(prefix="cycles_lights_")
PIXELS, HALF = 201, 4.0  # the view spans [-4, 4] m in x and y
POWER = 100.0
CENTRES = (np.arange(PIXELS) + 0.5) * (2 * HALF / PIXELS) - HALF


def fresh_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-50, -50, 0), (50, -50, 0), (50, 50, 0), (-50, 50, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    scene.collection.objects.link(floor)
    white = bpy.data.materials.new("white")
    white.use_nodes = True
    white.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (1, 1, 1, 1)
    tree = white.node_tree
    tree.nodes.clear()
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (1, 1, 1, 1)
    diffuse.inputs["Roughness"].default_value = 0.0
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(diffuse.outputs[0], output.inputs["Surface"])
    mesh.materials.append(white)
    camera = bpy.data.cameras.new("camera")
    camera.type, camera.ortho_scale = "ORTHO", 2 * HALF
    camera_object = bpy.data.objects.new("camera", camera)
    camera_object.location = (0, 0, 10)
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return scene


def light(scene, kind, location=(0, 0, 1), tilt=0.0, **settings):
    data = bpy.data.lights.new(kind.lower(), kind)
    for key, value in settings.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(kind.lower(), data)
    obj.location, obj.rotation_euler = location, (tilt, 0.0, 0.0)
    scene.collection.objects.link(obj)
    return data


def render(scene, name, spp):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device, cycles.samples, cycles.seed = "CPU", spp, 1
    cycles.use_adaptive_sampling = cycles.use_denoising = False
    cycles.max_bounces = 0  # direct light only
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.pixel_filter_type, cycles.filter_width = "BOX", 1.0
    scene.render.resolution_x = scene.render.resolution_y = PIXELS
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth, settings.color_mode = "OPEN_EXR", "32", "RGB"
    path = os.path.join(OUT, name + ".exr")
    scene.render.filepath, scene.render.use_file_extension = path, False
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.empty(PIXELS * PIXELS * 4, np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(PIXELS, PIXELS, 4)[:, :, :3].mean(axis=2)  # [row (y), column (x)]


def intensity_along(image, axis_of_pixels, height=1.0):
    """The intensity (W/sr) towards the pixels of the row y = 0 (or the column x = 0), from a
    light at (0, 0, height), with the direction to each."""
    line = image[PIXELS // 2] if axis_of_pixels == "x" else image[:, PIXELS // 2]
    d2 = CENTRES ** 2 + height ** 2
    cos_floor = height / np.sqrt(d2)
    directions = np.zeros((PIXELS, 3))
    directions[:, 0 if axis_of_pixels == "x" else 1] = CENTRES
    directions[:, 2] = -height
    directions /= np.sqrt(d2)[:, None]
    return line * math.pi * d2 / cos_floor, directions


def smoothstep_of(cosines, cos_outer, blend):
    t = np.clip((cosines - cos_outer) / (blend * (1.0 - cos_outer)), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def main():
    import toml_to_blender  # the shader that undoes Cycles' spot cosine

    i0 = POWER / (4.0 * math.pi)
    scene = fresh_scene()
    light(scene, "POINT", energy=POWER, shadow_soft_size=0.0)
    intensity, _ = intensity_along(render(scene, "point", 16), "x")
    at = [np.argmin(abs(CENTRES - x)) for x in (0.0, 1.0, 2.0, 3.0)]
    print("point: I / (P / 4 pi) at 0, 45, 63, 72 degrees:",
          " ".join(f"{intensity[i] / i0:.4f}" for i in at))

    half_angle, blend = math.radians(60.0), 0.5
    for name, tilt, undo in (("spot", 0.0, False), ("spot, cosine undone", 0.0, True),
                             ("spot tilted 30 degrees, cosine undone", math.radians(30), True)):
        scene = fresh_scene()
        data = light(scene, "SPOT", tilt=tilt, energy=POWER, shadow_soft_size=0.0,
                     spot_size=2 * half_angle, spot_blend=blend)
        if undo:
            toml_to_blender.undo_spot_cosine(data)
        intensity, directions = intensity_along(render(scene, name.replace(" ", "_"), 16), "y")
        axis = np.array([0.0, math.sin(tilt), -math.cos(tilt)])
        cosines = directions @ axis
        fade = smoothstep_of(cosines, math.cos(half_angle), blend)
        inside = cosines > math.cos(half_angle) + 0.3 * blend * (1 - math.cos(half_angle))
        ratio_fade = intensity[inside] / i0 / fade[inside]
        ratio_cos = intensity[inside] / i0 / (fade[inside] * cosines[inside])
        print(f"{name}: inside the cone (away from its steep rim), I / (P / 4 pi) over "
              f"smoothstep: {ratio_fade.min():.4f} .. {ratio_fade.max():.4f}; over "
              f"cos x smoothstep: {ratio_cos.min():.4f} .. {ratio_cos.max():.4f}; beyond the "
              f"edge: {intensity[cosines < math.cos(half_angle) - 0.02].max():.2g}")

    scene = fresh_scene()
    light(scene, "SUN", tilt=math.radians(30), energy=3.0, angle=0.0)
    image = render(scene, "sun", 16)
    expected = 3.0 * math.cos(math.radians(30)) / math.pi
    print(f"sun of strength 3 at 30 degrees: L / (3 cos 30 / pi) = {image.mean() / expected:.6f} "
          f"(spread {image.std() / image.mean():.1e})")

    for shape, size_y in (("SQUARE", 1.0), ("RECTANGLE", 2.0)):
        scene = fresh_scene()
        light(scene, "AREA", energy=POWER, shape=shape, size=1.0, size_y=size_y)
        area_light = render(scene, f"area_{shape.lower()}", 256)
        scene = fresh_scene()
        mesh = bpy.data.meshes.new("emitter")
        mesh.from_pydata([(-0.5, -size_y / 2, 1), (-0.5, size_y / 2, 1), (0.5, size_y / 2, 1),
                          (0.5, -size_y / 2, 1)], [], [(0, 1, 2, 3)])
        emitter = bpy.data.objects.new("emitter", mesh)
        emitter.visible_camera = False
        scene.collection.objects.link(emitter)
        material = bpy.data.materials.new("emission")
        material.use_nodes = True
        tree = material.node_tree
        tree.nodes.clear()
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = POWER / (math.pi * size_y)
        output = tree.nodes.new("ShaderNodeOutputMaterial")
        tree.links.new(emission.outputs[0], output.inputs["Surface"])
        mesh.materials.append(material)
        mesh_light = render(scene, f"mesh_{shape.lower()}", 256)
        print(f"area light, {shape.lower()} 1 x {size_y:g}: its light on the floor / an emitting "
              f"mesh's of radiance P / (pi A): {area_light.mean() / mesh_light.mean():.4f} "
              f"(pi / 4 = {math.pi / 4:.4f}: the area light's radiance is P / (4 A))")


main()
