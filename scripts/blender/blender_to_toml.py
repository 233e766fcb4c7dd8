"""Exports a Blender scene to a suite scene: TOML, with its meshes as OBJ files.

    blender -b SCENE.blend --python scripts/blender/blender_to_toml.py -- --out DIR/scene.toml

A teacher builds a scene in Blender and renders it with the lessons. What is exported is what
Cycles would render, after modifiers and geometry nodes, in world coordinates:

  meshes        one OBJ file per object and material (DIR/meshes/), placed by the TOML's
                `material`: the triangles Blender renders (its loop triangles), texture
                coordinates (the active UV map), and shading normals for smooth faces
                (Blender's split normals, custom ones included)
  quads         objects tagged lessons_shape = "quads" (toml_to_blender makes them) whose faces
                are parallelograms: `type = "quad"` shapes, corner v0, edges v1 - v0, v3 - v0
  point clouds  (geometry nodes' points, which Cycles renders as spheres): spheres
  spheres       objects tagged lessons_shape = "sphere" (toml_to_blender's glass spheres):
                a sphere of radius lessons_radius x the object's scale at its origin
  materials     read from the node tree: Diffuse, Glossy (sharp: a mirror), Glass, Refraction
                mixed by Fresnel with a sharp Glossy (tinted glass), Principled (metallic >= 0.5:
                conductor; transmission >= 0.5: glass; else diffuse), Emission added to any of
                them (one-sided when its strength is multiplied by 1 - Backfacing), Checker and
                Image Texture colours through a Mapping node's scale
  point lights  intensity = colour x power / (4 pi) W/sr (Cycles' own conversion)
  spot lights   spots: the same intensity on the axis, cone_angle = spot_size / 2, cone_blend =
                spot_blend; Cycles 3.x also multiplies a spot by the cosine to its axis, which
                the lessons do not (noted; toml_to_blender's spots undo it in their shader)
  suns          directional lights: irradiance = colour x strength W/m^2; an angle > 0 becomes
                0 (noted)
  area lights   square and rectangle: emitting quads, one-sided towards the light's -Z, of
                radiance colour x power / (4 area) (Cycles 3.x); disc and ellipse are refused
  world         a Background colour x strength, or an Environment Texture (an EXR; other
                images are written as EXR next to the scene)
  camera        perspective: position, direction, up, vertical field of view, image size

Our axes are y-up, Blender's z-up: (X, Y, Z) -> (X, Z, -Y), the inverse of toml_to_blender's.
What cannot be mapped is printed as "blender_to_toml: approximated: ..." or "... ignored: ...".
"""

import argparse
import math
import os
import sys

import bpy
from mathutils import Vector

LIGHT_POWER_TO_INTENSITY = 1.0 / (4.0 * math.pi)  # Cycles: a point light's W/sr per W


def note(message):
    print(f"blender_to_toml: approximated: {message}", flush=True)


def ignored(message):
    print(f"blender_to_toml: ignored: {message}", flush=True)


def ours(p):
    """Blender's (X, Y, Z), z-up, to our y-up (X, Z, -Y)."""
    return (p[0], p[2], -p[1])


def num(x):
    """9 significant digits: a float32 reads back to the same value."""
    x = float(x)
    if x == 0.0:
        return "0"
    s = format(x, ".9g")
    return s if ("e" in s or "." in s or "inf" in s or "nan" in s) else s + ".0"


def vec(v):
    return "[" + ", ".join(num(x) for x in v) + "]"


def toml_string(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def toml_key(name):
    bare = name and all(c.isalnum() or c in "-_" for c in name) and name.isascii()
    return name if bare else toml_string(name)


# ---- materials: the node tree read back ----


def clamp01(c, what):
    out = [min(max(float(x), 0.0), 1.0) for x in c[:3]]
    if any(abs(a - float(b)) > 1e-7 for a, b in zip(out, c[:3])):
        note(f"{what} {tuple(round(float(x), 4) for x in c[:3])} clamped to [0, 1]")
    return out


def linked_node(socket):
    return socket.links[0].from_node if socket.is_linked else None


def mapping_scale(node):
    """The (u, v) scale of the Mapping node feeding a texture's Vector, if any."""
    source = linked_node(node.inputs["Vector"])
    if source is not None and source.type == "MAPPING":
        s = source.inputs["Scale"].default_value
        return float(s[0]), float(s[1])
    return 1.0, 1.0


class MaterialReader:
    def __init__(self, out_dir):
        self.out_dir = out_dir

    def color(self, socket, what):
        """An albedo: a colour, a checker or an image texture (TOML inline table text)."""
        node = linked_node(socket)
        if node is None:
            return vec(clamp01(socket.default_value, what))
        if node.type == "TEX_CHECKER":
            su, sv = mapping_scale(node)
            scale = float(node.inputs["Scale"].default_value)
            odd = clamp01(node.inputs["Color1"].default_value, what)
            even = clamp01(node.inputs["Color2"].default_value, what)
            cells = [max(1, round(su * scale)), max(1, round(sv * scale))]
            return f"{{ checker = [{vec(even)}, {vec(odd)}], cells = [{cells[0]}, {cells[1]}] }}"
        if node.type == "TEX_IMAGE" and node.image is not None:
            path = node.image.get("lessons_file") or bpy.path.abspath(
                node.image.filepath, library=node.image.library)
            if not path or not os.path.exists(path):
                note(f"{what}: image '{node.image.name}' is not a file on disk: its mean is not "
                     "known here, grey 0.5 used")
                return vec([0.5, 0.5, 0.5])
            su, sv = mapping_scale(node)
            wrap = "repeat" if node.extension == "REPEAT" else "clamp"
            return (f"{{ texture = {toml_string(os.path.abspath(path))}, wrap = \"{wrap}\", "
                    f"scale = [{num(su)}, {num(sv)}] }}")
        note(f"{what}: a {node.type} node: its input's own value is used")
        return vec(clamp01(socket.default_value, what))

    def shader(self, node, name, result):
        """Adds what `node` contributes to result: 'bsdf' (a dict of TOML fields) and
        'emission' ([r, g, b], two_sided)."""
        kind = node.type
        if kind == "ADD_SHADER":
            for socket in node.inputs:
                if socket.is_linked:
                    self.shader(socket.links[0].from_node, name, result)
            return
        if kind == "MIX_SHADER":
            fac = linked_node(node.inputs["Fac"])
            a, b = linked_node(node.inputs[1]), linked_node(node.inputs[2])
            if (fac is not None and fac.type == "FRESNEL" and a is not None and
                    a.type == "BSDF_REFRACTION" and b is not None and b.type == "BSDF_GLOSSY"):
                result["bsdf"] = {"type": '"glass"', "ior": num(fac.inputs["IOR"].default_value),
                                  "transmittance": vec(clamp01(a.inputs["Color"].default_value,
                                                               f"material '{name}' tint"))}
                return
            weight = float(node.inputs["Fac"].default_value)
            chosen = b if (fac is None and weight >= 0.5) else a
            note(f"material '{name}': a Mix Shader: only its "
                 f"{'second' if chosen is b else 'first'} shader is kept")
            if chosen is not None:
                self.shader(chosen, name, result)
            return
        if kind == "EMISSION":
            color = node.inputs["Color"].default_value
            strength_socket = node.inputs["Strength"]
            two_sided = True
            source = linked_node(strength_socket)
            if (source is not None and source.type == "MATH" and
                    source.operation == "MULTIPLY_ADD" and linked_node(source.inputs[0]) is not None
                    and linked_node(source.inputs[0]).type == "NEW_GEOMETRY"):
                strength = float(source.inputs[2].default_value)
                two_sided = False
            else:
                strength = float(strength_socket.default_value)
                if source is not None:
                    note(f"material '{name}': emission strength from a {source.type} node: its "
                         "input's own value is used")
            result["emission"] = ([max(0.0, float(c) * strength) for c in color[:3]], two_sided)
            return
        if kind == "BSDF_DIFFUSE":
            if float(node.inputs["Roughness"].default_value) > 0.0:
                note(f"material '{name}': Oren-Nayar roughness becomes Lambert")
            previous = result.get("bsdf")
            albedo = self.color(node.inputs["Color"], f"material '{name}' albedo")
            if previous and previous.get("lobe"):  # a glossy lobe came first
                previous.update({"type": '"glossy"', "albedo": albedo})
            else:
                result["bsdf"] = {"type": '"diffuse"', "albedo": albedo}
            return
        if kind == "BSDF_GLOSSY":
            color = clamp01(node.inputs["Color"].default_value, f"material '{name}' colour")
            r = float(node.inputs["Roughness"].default_value)
            if node.distribution == "SHARP" or r * r < 1e-4:
                if result.get("bsdf"):
                    note(f"material '{name}': a sharp Glossy BSDF with another shader becomes a "
                         "mirror alone (the lessons have no coated materials)")
                result["bsdf"] = {"type": '"mirror"', "reflectance": vec(color)}
                return
            alpha = min(1.0, r * r)
            previous = result.get("bsdf")
            if previous and previous["type"] == '"diffuse"':
                previous.update({"type": '"glossy"', "specular": vec(color),
                                 "roughness": num(alpha)})
            else:
                note(f"material '{name}': a Glossy BSDF alone becomes a conductor (Schlick's "
                     "Fresnel of its colour)")
                result["bsdf"] = {"type": '"conductor"', "specular": vec(color),
                                  "roughness": num(alpha), "lobe": True}
            return
        if kind in ("BSDF_GLASS", "BSDF_REFRACTION"):
            color = clamp01(node.inputs["Color"].default_value, f"material '{name}' colour")
            if float(node.inputs["Roughness"].default_value) > 0.0:
                note(f"material '{name}': rough glass becomes smooth glass")
            if kind == "BSDF_GLASS" and min(color) < 1.0:
                note(f"material '{name}': Cycles' glass colour tints reflection too; ours only "
                     "the refracted light")
            result["bsdf"] = {"type": '"glass"', "ior": num(node.inputs["IOR"].default_value),
                              "transmittance": vec(color)}
            return
        if kind == "BSDF_PRINCIPLED":
            self.principled(node, name, result)
            return
        note(f"material '{name}': a {kind} shader is not mapped: grey diffuse 0.8")
        result["bsdf"] = {"type": '"diffuse"', "albedo": vec([0.8, 0.8, 0.8])}

    def principled(self, node, name, result):
        value = lambda key: float(node.inputs[key].default_value)  # noqa: E731
        r = value("Roughness")
        alpha = r * r
        if value("Metallic") >= 0.5:
            color = clamp01(node.inputs["Base Color"].default_value, f"material '{name}' colour")
            if alpha < 1e-4:
                result["bsdf"] = {"type": '"mirror"', "reflectance": vec(color)}
            else:
                result["bsdf"] = {"type": '"conductor"', "specular": vec(color),
                                  "roughness": num(min(1.0, alpha))}
            if 0.0 < value("Metallic") < 1.0:
                note(f"material '{name}': metallic {value('Metallic'):g} taken as 1")
        elif value("Transmission") >= 0.5:
            color = clamp01(node.inputs["Base Color"].default_value, f"material '{name}' colour")
            result["bsdf"] = {"type": '"glass"', "ior": num(value("IOR")),
                              "transmittance": vec(color)}
            if alpha >= 1e-4:
                note(f"material '{name}': transmission roughness {r:g} becomes smooth glass")
        else:
            result["bsdf"] = {"type": '"diffuse"',
                              "albedo": self.color(node.inputs["Base Color"],
                                                   f"material '{name}' albedo")}
            note(f"material '{name}': Principled dielectric becomes diffuse (its specular "
                 f"{value('Specular'):g} is left out)")
        emission = node.inputs["Emission"].default_value
        strength = value("Emission Strength")
        if max(emission[:3]) * strength > 0.0:
            result["emission"] = ([float(c) * strength for c in emission[:3]], True)

    def read(self, material):
        name = material.name_full
        result = {}
        output = None
        if material.use_nodes and material.node_tree:
            outputs = [n for n in material.node_tree.nodes if n.type == "OUTPUT_MATERIAL"]
            active = [n for n in outputs if n.is_active_output] or outputs
            output = active[0] if active else None
        surface = linked_node(output.inputs["Surface"]) if output else None
        if surface is None:
            c = material.diffuse_color
            note(f"material '{name}': no shader nodes: diffuse of its viewport colour")
            result["bsdf"] = {"type": '"diffuse"', "albedo": vec(clamp01(c, name))}
        else:
            self.shader(surface, name, result)
        bsdf = result.get("bsdf") or {"type": '"diffuse"', "albedo": vec([0.0, 0.0, 0.0])}
        bsdf.pop("lobe", None)
        if bsdf["type"] == '"glossy"' and bsdf["albedo"].startswith("["):
            # The lessons' glossy material may reflect at most all it receives: albedo +
            # specular <= 1 in every channel (docs/scene-format.md).
            albedo = [float(x) for x in bsdf["albedo"].strip("[]").split(",")]
            specular = [float(x) for x in bsdf["specular"].strip("[]").split(",")]
            total = max(a + b for a, b in zip(albedo, specular))
            if total > 1.0:
                note(f"material '{name}': diffuse + glossy reflect {total:.3g} > 1: both scaled "
                     f"by {1.0 / total:.4g}")
                bsdf["albedo"] = vec([a / total for a in albedo])
                bsdf["specular"] = vec([b / total for b in specular])
        lines = [f"[materials.{toml_key(name)}]"]
        for key, text in bsdf.items():
            lines.append(f"{key} = {text}")
        if "emission" in result:
            emission, two_sided = result["emission"]
            if max(emission) > 0.0:
                lines.append(f"emission = {vec(emission)}")
                if two_sided:
                    lines.append("two_sided = true")
        return "\n".join(lines)


# ---- geometry ----


def mesh_in_world(obj, matrix):
    """Evaluated mesh of obj with loop normals, and the world matrix for points and normals."""
    mesh = obj.to_mesh()
    if hasattr(mesh, "calc_normals_split"):
        mesh.calc_normals_split()
    return mesh


def is_parallelogram(p0, p1, p2, p3):
    u, v = p1 - p0, p3 - p0
    # Blender's float rounding grows with the coordinates, not with the edges.
    size = max(u.length, v.length, p0.length, p2.length)
    return (p0 + u + v - p2).length <= 1e-6 * size and u.cross(v).length > 0.0


class Exporter:
    def __init__(self, out_path):
        self.out_path = os.path.abspath(out_path)
        self.out_dir = os.path.dirname(self.out_path)
        self.mesh_dir = os.path.join(self.out_dir, "meshes")
        self.shapes, self.lights, self.used_materials = [], [], {}
        self.area_materials = {}  # name: the TOML fields of an area light's emitting quad
        self.obj_names = set()

    def material_name(self, material):
        """The TOML name of a Blender material (None: faces without one, given a grey)."""
        if material is None:
            if None not in self.used_materials:
                taken = {m.name_full for m in bpy.data.materials}
                name, k = "default", 1
                while name in taken:
                    k += 1
                    name = f"default_{k}"
                note(f"faces without a material: grey diffuse '{name}'")
                self.used_materials[None] = name
            return self.used_materials[None]
        self.used_materials[material.name_full] = material
        return material.name_full

    def unique_file(self, base):
        safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in base) or "mesh"
        name, k = safe, 1
        while name in self.obj_names:
            k += 1
            name = f"{safe}_{k}"
        self.obj_names.add(name)
        return name + ".obj"

    def add_mesh(self, obj, matrix, tag):
        mesh = mesh_in_world(obj, matrix)
        try:
            if len(mesh.polygons) == 0:
                return
            points = [matrix @ v.co for v in mesh.vertices]
            materials = [slot.material for slot in obj.material_slots] or [None]
            if tag == "quads" and all(
                    p.loop_total == 4 and is_parallelogram(*(points[i] for i in p.vertices))
                    for p in mesh.polygons):
                for p in mesh.polygons:
                    a, b, _, d = (points[i] for i in p.vertices)
                    if matrix.determinant() < 0.0:  # a mirror: the other side faces front
                        a, b, d = a, d, b
                    m = materials[min(p.material_index, len(materials) - 1)]
                    self.shapes.append(
                        "[[shapes]]\ntype = \"quad\"\n"
                        f"material = {toml_string(self.material_name(m))}\n"
                        f"corner = {vec(ours(a))}\nedge_u = {vec(ours(b - a))}\n"
                        f"edge_v = {vec(ours(d - a))}")
                return
            self.write_obj(obj, mesh, matrix, points, materials)
        finally:
            obj.to_mesh_clear()

    def write_obj(self, obj, mesh, matrix, points, materials):
        normal_matrix = matrix.to_3x3().inverted_safe().transposed()
        mirrored = matrix.determinant() < 0.0
        uv_layer = mesh.uv_layers.active
        # Triangles as Blender triangulates the faces for rendering (a non-planar quad or an
        # n-gon would be split along other diagonals by the OBJ reader).
        mesh.calc_loop_triangles()
        by_material = {}
        for p in mesh.loop_triangles:
            by_material.setdefault(min(p.material_index, len(materials) - 1), []).append(p)
        os.makedirs(self.mesh_dir, exist_ok=True)
        for index, polygons in sorted(by_material.items()):
            material = materials[index]
            file_name = self.unique_file(f"{obj.name}_{material.name if material else 'default'}")
            lines = [f"# {obj.name}, material {material.name if material else 'none'}: "
                     "exported by scripts/blender/blender_to_toml.py (y up)"]
            vertex_index, vt_count, vn_count, faces = {}, 0, 0, []
            for p in polygons:
                loops = list(p.loops)
                if mirrored:
                    loops.reverse()
                face = []
                for li in loops:
                    vi = mesh.loops[li].vertex_index
                    if vi not in vertex_index:
                        vertex_index[vi] = len(vertex_index) + 1
                        lines.append("v " + " ".join(num(x) for x in ours(points[vi])))
                    item = str(vertex_index[vi])
                    vt = vn = ""
                    if uv_layer is not None:
                        u, v = uv_layer.data[li].uv
                        vt_count += 1
                        lines.append(f"vt {num(u)} {num(v)}")
                        vt = str(vt_count)
                    if p.use_smooth:
                        n = (normal_matrix @ Vector(mesh.loops[li].normal)).normalized()
                        vn_count += 1
                        lines.append("vn " + " ".join(num(x) for x in ours(n)))
                        vn = str(vn_count)
                    if vn:
                        item += f"/{vt}/{vn}"
                    elif vt:
                        item += f"/{vt}"
                    face.append(item)
                faces.append("f " + " ".join(face))
            lines += faces
            with open(os.path.join(self.mesh_dir, file_name), "w") as f:
                f.write("\n".join(lines) + "\n")
            self.shapes.append(
                "[[shapes]]\ntype = \"mesh\"\n"
                f"file = {toml_string('meshes/' + file_name)}\n"
                f"material = {toml_string(self.material_name(material))}")

    def add_points(self, obj, matrix):
        cloud = obj.data
        materials = list(cloud.materials) or [None]
        scale = abs(matrix.to_3x3().determinant()) ** (1.0 / 3.0)
        s = matrix.to_scale()
        if max(s) - min(s) > 1e-6 * max(s):
            note(f"'{obj.name}': a non-uniform scale: spheres scaled by its mean {scale:g}")
        name = self.material_name(materials[0])
        if len(materials) > 1:
            note(f"'{obj.name}': points take the cloud's first material '{name}'")
        for point in cloud.points:
            self.shapes.append(
                "[[shapes]]\ntype = \"sphere\"\n"
                f"material = {toml_string(name)}\n"
                f"center = {vec(ours(matrix @ Vector(point.co)))}\n"
                f"radius = {num(point.radius * scale)}")

    def add_tagged_sphere(self, obj, matrix, radius):
        """A UV sphere toml_to_blender made of a sphere: the sphere, centred at the object's
        origin, its radius scaled by the object's (uniform) scale."""
        s = matrix.to_scale()
        if max(s) - min(s) > 1e-6 * max(s):
            note(f"'{obj.name}': a sphere scaled unevenly: scaled by its mean")
        scale = abs(matrix.to_3x3().determinant()) ** (1.0 / 3.0)
        materials = [slot.material for slot in obj.material_slots] or [None]
        self.shapes.append(
            "[[shapes]]\ntype = \"sphere\"\n"
            f"material = {toml_string(self.material_name(materials[0]))}\n"
            f"center = {vec(ours(matrix.translation))}\n"
            f"radius = {num(radius * scale)}")

    def add_light(self, obj, matrix):
        light = obj.data
        kind = light.type
        # Spots and suns shine along their local -Z.
        axis = (matrix.to_3x3() @ Vector((0.0, 0.0, -1.0))).normalized()
        if kind == "SUN":
            if light.angle > 0.0:
                note(f"sun '{obj.name}': angle {math.degrees(light.angle):g} degrees becomes 0 (a "
                     "hard sun: the lessons' directional light has no angular size)")
            irradiance = [c * light.energy for c in light.color]  # Cycles: strength in W/m^2
            self.lights.append("[[lights]]\ntype = \"directional\"\n"
                               f"direction = {vec(ours(axis))}\n"
                               f"irradiance = {vec(irradiance)}")
            return
        if kind == "AREA":
            self.add_area_light(obj, matrix, axis)
            return
        if light.shadow_soft_size > 0.0:
            note(f"{kind.lower()} light '{obj.name}': radius {light.shadow_soft_size:g} becomes 0")
        intensity = [c * light.energy * LIGHT_POWER_TO_INTENSITY for c in light.color]
        text = (f"[[lights]]\ntype = \"{'spot' if kind == 'SPOT' else 'point'}\"\n"
                f"position = {vec(ours(matrix.translation))}\n"
                f"intensity = {vec(intensity)}")
        if kind == "SPOT":
            if light.get("lessons_spot") != "cosine undone":
                note(f"spot light '{obj.name}': Cycles 3.x multiplies a spot's intensity by the "
                     "cosine to its axis, the lessons do not: the lessons' spot is brighter off "
                     "its axis (by 1 / cos, 1.15 at 30 degrees)")
            s = matrix.to_scale()
            if max(s) - min(s) > 1e-6 * max(s):
                note(f"spot light '{obj.name}': its uneven scale (an elliptic cone) is left out")
            text += (f"\ndirection = {vec(ours(axis))}\n"
                     f"cone_angle = {num(math.degrees(0.5 * light.spot_size))}\n"
                     f"cone_blend = {num(light.spot_blend)}")
        self.lights.append(text)

    def add_area_light(self, obj, matrix, axis):
        """A square or rectangular area light as an emitting quad, one-sided towards the light's
        -Z: Cycles 3.x gives an area light of power P and area A the radiance P / (4 A)
        W/(sr m^2) (measured against an emitting mesh: docs/interop.md)."""
        light = obj.data
        if light.shape not in ("SQUARE", "RECTANGLE"):
            raise SystemExit(f"blender_to_toml: the {light.shape.lower()} area light '{obj.name}' "
                             "cannot be exported: the lessons have quads, not discs; make it a "
                             "square or rectangle area light (or an emitting mesh)")
        if getattr(light, "spread", math.pi) < math.pi - 1e-6:
            note(f"area light '{obj.name}': spread {math.degrees(light.spread):g} degrees becomes "
                 "180 (the emitting quad is Lambertian)")
        if getattr(light.cycles, "is_portal", False):
            ignored(f"the light portal '{obj.name}' (it emits nothing)")
            return
        sx = light.size
        sy = light.size if light.shape == "SQUARE" else light.size_y
        corner = matrix @ Vector((-0.5 * sx, -0.5 * sy, 0.0))
        edge_u = matrix @ Vector((0.5 * sx, -0.5 * sy, 0.0)) - corner
        edge_v = matrix @ Vector((-0.5 * sx, 0.5 * sy, 0.0)) - corner
        if edge_u.cross(edge_v).dot(axis) < 0.0:  # the quad's front (u x v) must face -Z
            edge_u, edge_v = edge_v, edge_u
        area = edge_u.cross(edge_v).length
        if not area > 0.0:
            ignored(f"the area light '{obj.name}' of zero area")
            return
        radiance = [c * light.energy / (4.0 * area) for c in light.color]
        note(f"area light '{obj.name}': an emitting quad of radiance {max(radiance):.6g}: unlike "
             "Cycles' light it is seen by the camera and casts shadows (it is black, both sides)")
        name, k = f"area_light_{obj.name}", 1
        taken = {m.name_full for m in bpy.data.materials} | set(self.area_materials)
        while name in taken:
            k += 1
            name = f"area_light_{obj.name}_{k}"
        self.area_materials[name] = ('type = "diffuse"\nalbedo = [0.0, 0.0, 0.0]\n'
                                     f"emission = {vec(radiance)}")
        self.shapes.append("[[shapes]]\ntype = \"quad\"\n"
                           f"material = {toml_string(name)}\n"
                           f"corner = {vec(ours(corner))}\nedge_u = {vec(ours(edge_u))}\n"
                           f"edge_v = {vec(ours(edge_v))}")

    def collect(self, depsgraph):
        for inst in depsgraph.object_instances:
            obj = inst.object
            matrix = inst.matrix_world.copy()
            original = obj.original
            tag = original.get("lessons_shape") if not inst.is_instance else None
            if obj.type == "MESH" and tag == "sphere" and "lessons_radius" in original:
                self.add_tagged_sphere(obj, matrix, float(original["lessons_radius"]))
            elif obj.type == "MESH":
                self.add_mesh(obj, matrix, tag)
            elif obj.type == "POINTCLOUD":
                self.add_points(obj, matrix)
            elif obj.type == "LIGHT":
                self.add_light(obj, matrix)
            elif obj.type in ("CURVE", "SURFACE", "META", "FONT"):
                self.add_mesh(obj, matrix, None)
            elif obj.type not in ("CAMERA", "EMPTY"):
                ignored(f"'{obj.name}', a {obj.type.lower()} object")


def camera_text(scene):
    camera = scene.camera
    if camera is None or camera.type != "CAMERA":
        raise SystemExit("blender_to_toml: the scene has no camera")
    data = camera.data
    if data.type != "PERSP":
        raise SystemExit(f"blender_to_toml: camera '{camera.name}' is {data.type.lower()}: the "
                         "lessons have a perspective (pinhole) camera only")
    if data.shift_x or data.shift_y:
        note("the camera's lens shift is left out")
    matrix = camera.matrix_world
    position = matrix.translation
    forward = -(matrix.to_3x3() @ Vector((0.0, 0.0, 1.0))).normalized()
    up = (matrix.to_3x3() @ Vector((0.0, 1.0, 0.0))).normalized()
    frame = data.view_frame(scene=scene)  # the image's corners in the camera's space
    half_height = max(abs(c.y) for c in frame)
    distance = abs(frame[0].z)
    fov = math.degrees(2.0 * math.atan2(half_height, distance))
    render = scene.render
    width = max(1, round(render.resolution_x * render.resolution_percentage / 100))
    height = max(1, round(render.resolution_y * render.resolution_percentage / 100))
    if render.pixel_aspect_x != render.pixel_aspect_y:
        note("non-square pixels are left out")
    return (f"[image]\nwidth = {width}\nheight = {height}\n\n[camera]\n"
            f"position = {vec(ours(position))}\n"
            f"look_at = {vec(ours(position + forward * (1.0 + position.length)))}\n"
            f"up = {vec(ours(up))}\nfov = {num(fov)}")


def world_text(scene, out_dir):
    world = scene.world
    if world is None:
        return ""
    if not world.use_nodes or world.node_tree is None:
        c = world.color
        return f"[background]\nradiance = {vec(c[:3])}" if max(c[:3]) > 0 else ""
    outputs = [n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"]
    surface = linked_node(outputs[0].inputs["Surface"]) if outputs else None
    if surface is None or surface.type != "BACKGROUND":
        if surface is not None:
            ignored(f"the world's {surface.type} shader (a Background node is read)")
        return ""
    strength = float(surface.inputs["Strength"].default_value)
    texture = linked_node(surface.inputs["Color"])
    if texture is not None and texture.type == "TEX_ENVIRONMENT" and texture.image is not None:
        image = texture.image
        path = bpy.path.abspath(image.filepath, library=image.library)
        if not path.lower().endswith(".exr") or not os.path.exists(path):
            path = os.path.join(out_dir, "environment.exr")
            image.filepath_raw = path
            image.file_format = "OPEN_EXR"
            image.save()
            note(f"the environment image '{image.name}' is written as {path}")
        if texture.projection != "EQUIRECTANGULAR":
            note("the environment's mirror-ball projection is read as equirectangular")
        # Cycles' u = 0 looks along -X, ours along +x (toml_to_blender.py): half a turn apart.
        turn = 0.0
        mapping = linked_node(texture.inputs["Vector"])
        if mapping is not None and mapping.type == "MAPPING":
            r = mapping.inputs["Rotation"].default_value
            if abs(r[0]) > 1e-7 or abs(r[1]) > 1e-7:
                note("the environment's tilt (rotation about x or y) is left out")
            if mapping.vector_type not in ("POINT", "VECTOR"):
                note(f"the environment's {mapping.vector_type.lower()} mapping is read as a point "
                     "mapping")
            turn = float(r[2])
        rotate = 180.0 - math.degrees(turn)
        rotate = (rotate + 180.0) % 360.0 - 180.0
        if strength <= 0.0:
            return ""
        return (f"[background]\nmap = {toml_string(os.path.abspath(path))}\n"
                f"rotate = {num(rotate)}\nstrength = {num(strength)}")
    if texture is not None:
        note(f"the world colour comes from a {texture.type} node: its input's value is used")
    c = [float(x) * strength for x in surface.inputs["Color"].default_value[:3]]
    return f"[background]\nradiance = {vec(c)}" if max(c) > 0 else ""


def main():
    if bpy.app.version >= (4, 0, 0):
        raise SystemExit("blender_to_toml: written for Blender 3.x (Debian 12's 3.4); Blender "
                         f"{bpy.app.version_string} renamed the shader inputs it reads")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="blender_to_toml.py",
                                     description="Export the open Blender scene to a suite TOML.")
    parser.add_argument("--out", required=True, help="the TOML file to write (meshes go to "
                        "meshes/ beside it)")
    args = parser.parse_args(argv)
    scene = bpy.context.scene
    exporter = Exporter(args.out)
    os.makedirs(exporter.out_dir, exist_ok=True)
    exporter.collect(bpy.context.evaluated_depsgraph_get())
    if not exporter.shapes and not exporter.lights:
        raise SystemExit("blender_to_toml: nothing to export: no meshes, points or lights")
    reader = MaterialReader(exporter.out_dir)
    materials = []
    for key, material in exporter.used_materials.items():
        if key is None:
            materials.append(f'[materials.{toml_key(material)}]\ntype = "diffuse"\n'
                             'albedo = [0.8, 0.8, 0.8]')
        else:
            materials.append(reader.read(material))
    for name, fields in exporter.area_materials.items():
        materials.append(f"[materials.{toml_key(name)}]\n{fields}")
    source = bpy.data.filepath or "an unsaved Blender scene"
    parts = [f"# Exported from {source} by scripts/blender/blender_to_toml.py.",
             f"description = {toml_string('Exported from Blender: ' + scene.name)}",
             camera_text(scene), world_text(scene, exporter.out_dir)]
    parts += materials + exporter.shapes + exporter.lights
    with open(exporter.out_path, "w") as f:
        f.write("\n\n".join(p for p in parts if p) + "\n")
    print(f"blender_to_toml: wrote {exporter.out_path} ({len(exporter.shapes)} shapes, "
          f"{len(exporter.lights)} lights, {len(materials)} materials)")


if __name__ == "__main__":
    main()
