#!/usr/bin/env python3
"""Compares two scenes as the lessons load them (build/bin/scene_export's JSON): the scene
before and after a round trip TOML -> Blender -> TOML (tests/blender/round_trip.sh).

    tests/blender/compare_exports.py BEFORE.json AFTER.json

The same image size and camera; the same spheres, quads and triangles (in any order; a triangle
up to a rotation of its vertices, which keeps its front side), each with the same material
parameters, shading normals and texture coordinates; the same point and spot lights,
directional lights and background.
Positions agree to 1e-5 of the scene's size; colours and other numbers to 1e-5 (relative, above
1); shading normals to 1e-4 (Blender stores them as 16-bit angles). Exit 1 naming the first differences; 0 when the two agree.
"""

import json
import math
import os
import sys

TOLERANCE = 1e-5
# Blender keeps custom normals as two 16-bit angles in each corner's own frame: they come back
# within about 2e-5.
NORMALS = 1e-4


class Differences:
    def __init__(self):
        self.lines = []

    def add(self, message):
        if len(self.lines) < 20:
            self.lines.append(message)
        elif len(self.lines) == 20:
            self.lines.append("... (more)")


def close(a, b, scale=1.0, tol=TOLERANCE):
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(close(x, y, scale, tol) for x, y in zip(a, b))
    return abs(float(a) - float(b)) <= tol * max(scale, abs(float(a)), abs(float(b)), 1.0)


def material_key(m):
    """A material's parameters, without its name (names may change in Blender)."""
    return {k: v for k, v in m.items() if k != "name"}


def same_material(a, b):
    if a.keys() != b.keys():
        return False
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, dict):
            if x.keys() != y.keys():
                return False
            for k in x:
                if k == "texture":
                    if os.path.realpath(x[k]) != os.path.realpath(y[k]):
                        return False
                elif k == "wrap":
                    if x[k] != y[k]:
                        return False
                elif not close(x[k], y[k]):
                    return False
        elif isinstance(x, (bool, str)):
            if x != y:
                return False
        elif not close(x, y):
            return False
    return True


def extent(export):
    values = [abs(c) for c in export["mesh"]["positions"]]
    for q in export["quads"]:
        values += [abs(c) for c in q["corner"]]
    for s in export["spheres"]:
        values += [abs(c) + s["radius"] for c in s["center"]]
    return max(values + [1e-30])


def triangles(export):
    """Each triangle as (positions, normals or None, uvs or None, material)."""
    m = export["mesh"]
    pos, nor, uv = m["positions"], m["normals"], m["uvs"]
    out = []
    for t in range(len(m["materials"])):
        idx = m["triangles"][3 * t:3 * t + 3]
        p = [tuple(pos[3 * i:3 * i + 3]) for i in idx]
        n = [tuple(nor[3 * i:3 * i + 3]) for i in idx] if nor and m["smooth"][t] else None
        u = [tuple(uv[2 * i:2 * i + 2]) for i in idx] if uv else None
        out.append((p, n, u, export["materials"][m["materials"][t]]))
    return out


def rotations(tri):
    p, n, u, mat = tri
    for k in range(3):
        yield ([p[(i + k) % 3] for i in range(3)], n and [n[(i + k) % 3] for i in range(3)],
               u and [u[(i + k) % 3] for i in range(3)], mat)


def bucket(point, cell):
    return tuple(math.floor(c / cell) for c in point)


def match(name, before, after, key_point, same, cell, diff):
    """Pairs every item of `before` with an equal one of `after` (by the spatial hash of
    key_point, looking in the neighbouring cells too)."""
    if len(before) != len(after):
        diff.add(f"{name}: {len(before)} before, {len(after)} after")
        return
    grid = {}
    for i, item in enumerate(after):
        grid.setdefault(bucket(key_point(item), cell), []).append(i)
    used = set()
    for item in before:
        b = bucket(key_point(item), cell)
        found = None
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for j in grid.get((b[0] + dx, b[1] + dy, b[2] + dz), []):
                        if j not in used and same(item, after[j]):
                            found = j
                            break
                    if found is not None:
                        break
                if found is not None:
                    break
            if found is not None:
                break
        if found is None:
            diff.add(f"{name}: nothing after the round trip matches {summary(item)}")
        else:
            used.add(found)


def summary(item):
    text = json.dumps(item, default=str)
    return text if len(text) < 300 else text[:300] + "..."


def compare(a, b):
    diff = Differences()
    for key in ("width", "height"):
        if a[key] != b[key]:
            diff.add(f"{key}: {a[key]} before, {b[key]} after")
    size = extent(a)
    ca, cb = a["camera"], b["camera"]

    def unit(v):
        length = math.sqrt(sum(x * x for x in v))
        return [x / length for x in v]

    def forward(c):
        return unit([t - p for t, p in zip(c["look_at"], c["position"])])

    def true_up(c):  # the part of up perpendicular to the view direction
        f, u = forward(c), c["up"]
        d = sum(x * y for x, y in zip(f, u))
        return unit([x - d * y for x, y in zip(u, f)])

    if not close(ca["position"], cb["position"], size):
        diff.add(f"camera position: {ca['position']} before, {cb['position']} after")
    if not close(forward(ca), forward(cb)) or not close(true_up(ca), true_up(cb)):
        diff.add("camera direction or up differs")
    if not close(ca["fov"], cb["fov"]):
        diff.add(f"camera fov: {ca['fov']} before, {cb['fov']} after")
    ba, bb = a["background"], b["background"]
    if ("map" in ba) != ("map" in bb):
        diff.add(f"background: {ba} before, {bb} after")
    elif "map" in ba:
        if (os.path.realpath(ba["map"]) != os.path.realpath(bb["map"]) or
                not close(ba["rotate"], bb["rotate"]) or not close(ba["strength"], bb["strength"])):
            diff.add(f"background: {ba} before, {bb} after")
    elif not close(ba["radiance"], bb["radiance"]):
        diff.add(f"background: {ba} before, {bb} after")

    cell = 1e-3 * size
    mats_a, mats_b = a["materials"], b["materials"]
    match("spheres", a["spheres"], b["spheres"], lambda s: s["center"],
          lambda s, t: (close(s["center"], t["center"], size) and
                        close(s["radius"], t["radius"], size) and
                        same_material(material_key(mats_a[s["material"]]),
                                      material_key(mats_b[t["material"]]))), cell, diff)
    match("quads", a["quads"], b["quads"],
          lambda q: [c + 0.5 * (u + v) for c, u, v in zip(q["corner"], q["edge_u"], q["edge_v"])],
          lambda q, r: (all(close(q[k], r[k], size) for k in ("corner", "edge_u", "edge_v")) and
                        same_material(material_key(mats_a[q["material"]]),
                                      material_key(mats_b[r["material"]]))), cell, diff)

    def same_triangle(s, t):
        for r in rotations(t):
            if not close(s[0], r[0], size):
                continue
            if (s[1] is None) != (r[1] is None) or (s[1] and not close(s[1], r[1], tol=NORMALS)):
                return False
            if (s[2] is None) != (r[2] is None) or (s[2] and not close(s[2], r[2])):
                return False
            return same_material(material_key(s[3]), material_key(r[3]))
        return False

    centroid = lambda t: [sum(p[i] for p in t[0]) / 3.0 for i in range(3)]  # noqa: E731
    match("triangles", triangles(a), triangles(b), centroid, same_triangle, cell, diff)
    def same_spot(p, q):
        """Both without a cone, or the same cone: axis, angle (degrees) and blend."""
        s, t = p.get("spot"), q.get("spot")
        if s is None or t is None:
            return s is None and t is None
        return (close(s["direction"], t["direction"]) and close(s["cone_angle"], t["cone_angle"])
                and close(s["cone_blend"], t["cone_blend"]))

    match("point lights", a["point_lights"], b["point_lights"], lambda p: p["position"],
          lambda p, q: close(p["position"], q["position"], size) and
          close(p["intensity"], q["intensity"]) and same_spot(p, q), cell, diff)
    # Directional lights have no position: matched by their direction.
    match("directional lights", a.get("directional_lights", []), b.get("directional_lights", []),
          lambda d: d["direction"], lambda d, e: close(d["direction"], e["direction"]) and
          close(d["irradiance"], e["irradiance"]), 1e-3, diff)
    return diff.lines


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        a = json.load(f)
    with open(sys.argv[2]) as f:
        b = json.load(f)
    lines = compare(a, b)
    for line in lines:
        print(f"{a['source']}: {line}")
    if lines:
        sys.exit(1)
    m = a["mesh"]
    print(f"{a['source']}: the same after the round trip ({len(a['spheres'])} spheres, "
          f"{len(a['quads'])} quads, {len(m['materials'])} triangles, "
          f"{len(a['point_lights'])} point lights, "
          f"{len(a.get('directional_lights', []))} directional lights)")


if __name__ == "__main__":
    main()
