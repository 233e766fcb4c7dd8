// Stage 2 of scene loading: SceneDescription -> Scene.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "io/gltf_file.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/mesh_file.h"
#include "io/scene_file.h"
#include "io/texture.h"
#include "scene/environment.h"

namespace lessons {

namespace {

// Adds a file loading read to the scene's record of its inputs (each file once).
void record_input(Scene& scene, const std::string& file) {
    if (std::find(scene.input_files.begin(), scene.input_files.end(), file) ==
        scene.input_files.end())
        scene.input_files.push_back(file);
}

// Reads the image a material's albedo names (once per file), and checks what needed its texels:
// where a diffuse base and a lobe share the light the surface receives (a glossy material),
// albedo + specular at most 1.
void read_albedo_texture(Material& m, const SourceLocation& where, const InputLimits& limits,
                         TextureCache& textures, Scene& scene) {
    if (m.albedo.image_file.empty() || m.albedo.image) return;
    auto it = textures.find(m.albedo.image_file);
    if (it == textures.end()) {
        try {
            it = textures
                     .emplace(m.albedo.image_file,
                              read_texture(m.albedo.image_file, limits.file_bytes(), &scene.notes))
                     .first;
        } catch (const InputError& e) {
            throw InputError(where.file, where.line, where.field, e.what());
        }
        record_input(scene, m.albedo.image_file);
    }
    m.albedo.image = it->second;
    const MaterialTypeFacts type = facts_of(m.type);
    if (type.albedo && type.lobe && max_component(m.albedo.maximum() + m.specular) > 1.0f)
        throw InputError(where.file, where.line, where.field,
                         "albedo (its brightest texel) + specular must be at most 1 in every "
                         "channel; lower specular");
}

// [background] map: read, checked, and made the scene's environment. A map of one colour is a
// uniform sky (the same images, bit for bit, as radiance = that colour: nothing to sample).
void read_environment_map(const SceneDescription& d, const InputLimits& limits, Scene& scene) {
    const SourceLocation& w = d.background_where;
    Image image;
    try {
        check_input_file(d.background_map, "environment map", limits.file_bytes(), "--max-file-mb");
        image = read_linear_image(d.background_map);
        record_input(scene, d.background_map);
        scene.notes.insert(scene.notes.end(), image.notes.begin(), image.notes.end());
    } catch (const InputError& e) {
        throw InputError(w.file, w.line, w.field, e.what());
    } catch (const std::runtime_error& e) {
        throw InputError(w.file, w.line, w.field, e.what());
    }
    ClampedTexels clamped;
    try {
        clamped = clamp_negative_texels(image.pixels, image.width);
    } catch (const std::invalid_argument& e) {
        throw InputError(w.file, w.line, w.field, d.background_map + ": " + e.what());
    }
    if (clamped.texels > 0) {
        char minimum[32];
        std::snprintf(minimum, sizeof minimum, "%.3g", clamped.minimum);
        scene.notes.push_back(d.background_map + ": " + std::to_string(clamped.texels) +
                              " texel(s) with channels slightly below 0 (the lowest " + minimum +
                              "; flaws of compression or colour conversion, down to -0.01 "
                              "allowed) set to 0");
    }
    bool constant = true;
    for (const Color& c : image.pixels) constant &= c == image.pixels.front();
    try {
        auto map = std::make_shared<const EnvironmentMap>(
            image.width, image.height, std::move(image.pixels), d.background_rotate,
            d.background_strength);
        if (constant)
            scene.background = map->radiance(Vec3(0.0f, 1.0f, 0.0f));
        else
            scene.environment_map = map;
    } catch (const std::invalid_argument& e) {
        throw InputError(w.file, w.line, w.field, d.background_map + ": " + e.what());
    }
}

// A mesh placed by its shape's transform: positions in double, rounded once; normals by the
// inverse transpose. A mirroring transform reverses every triangle's winding (v1 <-> v2), so
// that front faces stay on the side the mirror image puts them and closed meshes stay outward.
void place_mesh(const ShapeDescription& s, std::vector<Vec3>& positions, std::vector<Vec3>& normals,
                std::vector<Triangle>& triangles) {
    const Transform& t = s.transform;
    if (t.is_identity()) return;
    for (Vec3& p : positions) {
        const glm::dvec3 q = t.point(glm::dvec3(p));
        if (!(max_component(glm::abs(q)) <= kMaxCoordinate))
            throw InputError(s.transform_where.file, s.transform_where.line,
                             s.transform_where.field,
                             "moves the mesh too far for single precision geometry (|x| must be "
                             "at most 1e9)");
        p = Vec3(q);
    }
    for (Vec3& n : normals)
        if (n != Vec3(0.0f)) n = Vec3(t.normal(glm::dvec3(n)));
    if (t.mirrors())
        for (Triangle& tri : triangles) std::swap(tri.v[1], tri.v[2]);
}

void add_polygon_mesh(Scene& scene, const ShapeDescription& s, uint32_t material) {
    std::vector<Triangle> triangles;
    int degenerate = 0;
    for (const auto& face : s.faces) {
        // Convex planar polygons are split into a fan of triangles around their first vertex.
        for (size_t k = 1; k + 1 < face.size(); ++k) {
            const Vec3 &a = s.vertices[face[0]], &b = s.vertices[face[k]],
                       &c = s.vertices[face[k + 1]];
            const Vec3 n = glm::cross(b - a, c - a);
            if (!(glm::dot(n, n) > 0.0f)) {
                ++degenerate;
                continue;
            }
            triangles.push_back({{face[0], face[k], face[k + 1]}, material, false});
        }
    }
    if (degenerate > 0)
        std::cerr << "warning: " << s.where.file << ":" << s.where.line << ": " << s.where.field
                  << ": skipped " << degenerate << " zero-area triangle(s)\n";
    if (triangles.empty())
        throw InputError(s.where.file, s.where.line, s.where.field + ".faces",
                         "every face has zero area");
    std::vector<Vec3> positions = s.vertices, normals;
    place_mesh(s, positions, normals, triangles);
    scene.add_mesh(positions, {}, {}, triangles);
}

// OBJ files read so far in this build, by path: a mesh placed several times is read once.
using MeshCache = std::map<std::string, MeshData>;

void add_obj_mesh(Scene& scene, const ShapeDescription& s,
                  const std::map<std::string, uint32_t>& material_ids, int override_material,
                  const InputLimits& limits, MeshCache& cache, TextureCache& textures) {
    auto cached = cache.find(s.file);
    if (cached == cache.end()) {
        try {
            cached = cache.emplace(s.file, load_obj(s.file, limits.file_bytes())).first;
        } catch (const InputError& e) {
            // Name both the OBJ problem and the scene line that asked for the file.
            throw InputError(s.file_where.file, s.file_where.line, s.file_where.field, e.what());
        }
        for (const std::string& f : cached->second.files) record_input(scene, f);
        if (cached->second.skipped_degenerate > 0)
            std::cerr << "warning: " << s.file << ": skipped " << cached->second.skipped_degenerate
                      << " zero-area triangle(s)\n";
    }
    const MeshData& mesh = cached->second;
    // MTL materials: a scene material of the same name wins; otherwise the MTL's own values.
    std::vector<uint32_t> mtl_to_scene(mesh.materials.size());
    for (size_t i = 0; i < mesh.materials.size(); ++i) {
        auto it = material_ids.find(mesh.materials[i].name);
        if (it != material_ids.end()) {
            mtl_to_scene[i] = it->second;
            continue;
        }
        Material m = mesh.materials[i];  // its map_Kd, if any, is read here
        read_albedo_texture(m, s.file_where, limits, textures, scene);
        mtl_to_scene[i] = scene.add_material(m);
    }
    std::vector<Triangle> triangles;
    triangles.reserve(mesh.faces.size());
    for (const MeshData::Face& f : mesh.faces) {
        uint32_t material;
        if (override_material >= 0) {
            material = static_cast<uint32_t>(override_material);
        } else if (f.material >= 0) {
            material = mtl_to_scene[f.material];
        } else {
            throw InputError(s.where.file, s.where.line, s.where.field + ".material",
                             "missing: " + s.file +
                                 " has faces without a usable material (no usemtl, or a name "
                                 "its MTL file does not define); give the mesh a material");
        }
        triangles.push_back({{f.v[0], f.v[1], f.v[2]}, material, true});
    }
    if (s.transform.is_identity()) {
        scene.add_mesh(mesh.positions, mesh.normals, mesh.uvs, triangles);
        return;
    }
    std::vector<Vec3> positions = mesh.positions, normals = mesh.normals;
    place_mesh(s, positions, normals, triangles);
    scene.add_mesh(positions, normals, mesh.uvs, triangles);
}

// glTF files read so far in this build, by path.
using GltfCache = std::map<std::string, std::shared_ptr<const GltfScene>>;

std::shared_ptr<const GltfScene> read_gltf_once(const std::string& file,
                                                const SourceLocation& where,
                                                const InputLimits& limits, GltfCache& cache,
                                                Scene& scene) {
    auto it = cache.find(file);
    if (it != cache.end()) return it->second;
    std::shared_ptr<const GltfScene> g;
    try {
        g = std::make_shared<const GltfScene>(load_gltf(file, limits.file_bytes()));
    } catch (const InputError& e) {
        throw InputError(where.file, where.line, where.field, e.what());
    }
    record_input(scene, file);
    for (const std::string& f : g->files) record_input(scene, f);
    return cache.emplace(file, g).first->second;
}

// One primitive of a glTF, placed by its node's transform and then the shape's (in double,
// rounded once), added to the scene with the given material. Returns how many of its triangles
// the placement flattened to zero area in float, which are skipped.
int add_gltf_primitive(Scene& scene, const ShapeDescription& s, const GltfPrimitive& p,
                       uint32_t material) {
    int flattened = 0;
    const glm::dmat4& w = p.to_world;
    const Transform node{glm::dmat3(w), glm::dvec3(w[3])};
    const Transform t = node.then(s.transform);
    std::vector<Vec3> positions(p.positions.size()), normals(p.normals.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 q = t.point(glm::dvec3(p.positions[i]));
        if (!(max_component(glm::abs(q)) <= kMaxCoordinate))
            throw InputError(s.where.file, s.where.line, s.where.field,
                             s.file + ": " + p.where +
                                 " is placed too far for single precision geometry (|x| "
                                 "must be at most 1e9)");
        positions[i] = Vec3(q);
    }
    for (size_t i = 0; i < normals.size(); ++i)
        normals[i] = Vec3(t.normal(glm::dvec3(p.normals[i])));
    std::vector<Triangle> triangles;
    triangles.reserve(p.triangles.size());
    for (const auto& tri : p.triangles) {
        const Vec3 n = glm::cross(positions[tri[1]] - positions[tri[0]],
                                  positions[tri[2]] - positions[tri[0]]);
        if (!(glm::dot(n, n) > 0.0f)) {  // flattened by the placement, in float
            ++flattened;
            continue;
        }
        triangles.push_back({{tri[0], t.mirrors() ? tri[2] : tri[1], t.mirrors() ? tri[1] : tri[2]},
                             material,
                             !normals.empty()});
    }
    if (!triangles.empty()) scene.add_mesh(positions, normals, p.uvs, triangles);
    return flattened;
}

// A glTF's lights placed by its shape's transform; a spot's axis and a sun's direction turned by
// it (rounded to float, then normalised, as the scene file's directions are).
void add_gltf_lights(Scene& scene, const ShapeDescription& s, const GltfScene& g) {
    auto turned = [&](const Vec3& direction) {
        return glm::normalize(Vec3(s.transform.vector(glm::dvec3(direction))));
    };
    for (const PointLight& l : g.lights) {
        const glm::dvec3 q = s.transform.point(glm::dvec3(l.position));
        if (!(max_component(glm::abs(q)) <= kMaxCoordinate))
            throw InputError(s.where.file, s.where.line, s.where.field,
                             s.file + ": a light is placed beyond 1e9");
        PointLight placed{Vec3(q), l.intensity, l.cone};
        if (placed.cone) placed.cone->axis = turned(l.cone->axis);
        scene.add_point_light(placed);
    }
    for (const DirectionalLight& l : g.directional_lights)
        scene.add_directional_light({turned(l.direction), l.irradiance});
}

// A glTF placed by its shape's transform: each primitive's node transform, then the shape's, in
// double, rounded once; its materials (or the shape's), and its lights.
void add_gltf(Scene& scene, const ShapeDescription& s, int override_material,
              const InputLimits& limits, GltfCache& cache, TextureCache& textures) {
    const std::shared_ptr<const GltfScene> g =
        s.gltf ? s.gltf : read_gltf_once(s.file, s.file_where, limits, cache, scene);
    std::vector<uint32_t> materials(g->materials.size());
    for (size_t i = 0; i < g->materials.size(); ++i) {
        if (override_material >= 0) break;
        Material m = g->materials[i];
        read_albedo_texture(m, s.file_where, limits, textures, scene);
        materials[i] = scene.add_material(m);
    }
    int flattened = 0;
    for (const GltfPrimitive& p : g->primitives) {
        const uint32_t material = override_material >= 0 ? static_cast<uint32_t>(override_material)
                                                         : materials[p.material];
        flattened += add_gltf_primitive(scene, s, p, material);
    }
    add_gltf_lights(scene, s, *g);
    if (flattened > 0)
        scene.notes.push_back(s.file + ": " + std::to_string(flattened) +
                              " triangle(s) of zero area once placed, skipped");
    for (const std::string& note : g->notes)  // (with an override, its materials are not used)
        if (override_material < 0 || note.rfind("glTF material", 0) != 0)
            scene.notes.push_back(note);
    if (override_material >= 0)
        scene.notes.push_back(s.file + ": every primitive has the shape's material");
}

}  // namespace

std::array<Quad, 6> box_faces(const ShapeDescription& b) {
    const Transform& m = b.transform;
    const glm::dvec3 size = b.box_max - b.box_min;
    const glm::dvec3 dx = m.vector({size.x, 0.0, 0.0}), dy = m.vector({0.0, size.y, 0.0}),
                     dz = m.vector({0.0, 0.0, size.z});
    const glm::dvec3 lo = m.point(b.box_min);  // the corner at box_min
    // Each face: corner, edge_u, edge_v with cross(edge_u, edge_v) pointing out of the box (a
    // mirroring transform reverses the cross product: then the edges swap).
    const bool mirrors = m.mirrors();
    auto face = [mirrors](const glm::dvec3& corner, const glm::dvec3& u, const glm::dvec3& v) {
        return mirrors ? Quad(Vec3(corner), Vec3(v), Vec3(u))
                       : Quad(Vec3(corner), Vec3(u), Vec3(v));
    };
    return {
        face(lo, dz, dy),       // x = min.x, normal -x: cross(z, y) = -x
        face(lo + dx, dy, dz),  // x = max.x, normal +x
        face(lo, dx, dz),       // y = min.y, normal -y: cross(x, z) = -y
        face(lo + dy, dz, dx),  // y = max.y, normal +y
        face(lo, dy, dx),       // z = min.z, normal -z
        face(lo + dz, dx, dy),  // z = max.z, normal +z
    };
}

namespace {

// The scene's materials, each with its texture read, by name for the shapes to find.
struct Materials {
    std::map<std::string, uint32_t> ids;
    std::vector<std::string> names;

    // The index of shape s's material; -1 for none (a glTF or OBJ file brings its own); throws
    // InputError for a name the scene does not define, with the nearest one it does.
    int resolve(const ShapeDescription& s) const {
        if (s.material.empty()) return -1;
        const auto it = ids.find(s.material);
        if (it != ids.end()) return static_cast<int>(it->second);
        std::string message =
            "undefined material '" + s.material + "'" + did_you_mean(s.material, names);
        if (names.empty()) message += " (the scene defines no [materials.*])";
        throw InputError(s.material_where.file, s.material_where.line, s.material_where.field,
                         message);
    }
};

Materials add_materials(const SceneDescription& d, const InputLimits& limits,
                        TextureCache& textures, Scene& scene) {
    Materials materials;
    for (const MaterialDescription& m : d.materials) {
        Material material = m.material;
        read_albedo_texture(material, m.albedo_where, limits, textures, scene);
        materials.ids[m.material.name] = scene.add_material(material);
        materials.names.push_back(m.material.name);
    }
    return materials;
}

// The scene's media, by name for the shapes to find; the one that fills space, if named.
std::map<std::string, uint32_t> add_media(const SceneDescription& d, Scene& scene) {
    std::map<std::string, uint32_t> ids;
    for (const MediumDescription& m : d.media) ids[m.medium.name] = scene.add_medium(m.medium);
    if (!d.medium.empty()) scene.set_outside_medium(ids.at(d.medium));  // checked by stage 1
    return ids;
}

// Whether the triangles [first, end) close a surface: every edge, between vertices at the same
// place (a mesh may repeat a position for its normals or texture coordinates), is shared by
// exactly two of them. Returns a description of the first open edge found, if any.
std::optional<std::string> open_edge(const Scene& scene, uint32_t first, uint32_t end) {
    std::map<std::array<float, 3>, uint32_t> place_ids;
    std::vector<Vec3> places;
    auto place = [&](uint32_t v) {
        const Vec3& p = scene.positions()[v];
        const auto [at, added] =
            place_ids.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(places.size()));
        if (added) places.push_back(p);
        return at->second;
    };
    auto text = [](const Vec3& p) {
        std::ostringstream s;
        s << "[" << p.x << ", " << p.y << ", " << p.z << "]";
        return s.str();
    };
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (uint32_t i = first; i < end; ++i) {
        const Triangle& t = scene.triangles()[i];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = place(t.v[k]), b = place(t.v[(k + 1) % 3]);
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    }
    for (const auto& [edge, count] : edges)
        if (count != 2)
            return "the edge from " + text(places[edge.first]) + " to " +
                   text(places[edge.second]) +
                   " is shared by " + std::to_string(count) +
                   " triangle(s), where a closed surface has two at every edge";
    return std::nullopt;
}

// A shape's interior: the primitives it added since `before` enclose its medium.
void set_interior(const ShapeDescription& s, const Scene::PrimitiveCounts& before,
                  const std::map<std::string, uint32_t>& media, Scene& scene) {
    if (s.interior.empty()) return;
    if (s.type == ShapeDescription::Type::Mesh) {
        const uint32_t end = scene.primitive_counts().triangles;
        if (std::optional<std::string> open = open_edge(scene, before.triangles, end))
            throw InputError(s.interior_where.file, s.interior_where.line,
                             s.interior_where.field,
                             "the mesh is not closed (" + *open +
                                 "): only a closed surface has an inside to fill with a medium");
    }
    scene.set_interior(before, media.at(s.interior));  // the name checked by stage 1
}

void add_shapes(const SceneDescription& d, const Materials& materials,
                const std::map<std::string, uint32_t>& media, const InputLimits& limits,
                TextureCache& textures, Scene& scene) {
    MeshCache meshes;
    GltfCache gltfs;
    for (const ShapeDescription& s : d.shapes) {
        const int material = materials.resolve(s);
        const Scene::PrimitiveCounts before = scene.primitive_counts();
        switch (s.type) {
            case ShapeDescription::Type::Sphere:
                scene.add_sphere({s.center, s.radius}, static_cast<uint32_t>(material));
                break;
            case ShapeDescription::Type::Quad:
                scene.add_quad(Quad(s.corner, s.edge_u, s.edge_v), static_cast<uint32_t>(material));
                break;
            case ShapeDescription::Type::Box:
                for (const Quad& q : box_faces(s))
                    scene.add_quad(q, static_cast<uint32_t>(material));
                break;
            case ShapeDescription::Type::Mesh:
                if (s.file.empty())
                    add_polygon_mesh(scene, s, static_cast<uint32_t>(material));
                else
                    add_obj_mesh(scene, s, materials.ids, material, limits, meshes, textures);
                break;
            case ShapeDescription::Type::Gltf:
                add_gltf(scene, s, material, limits, gltfs, textures);
                break;
        }
        set_interior(s, before, media, scene);
    }
}

// A camera inside a closed shape sees only its inside. That can be meant (the furnace), so it is
// a warning, not an error.
void warn_of_a_camera_inside(const SceneDescription& d) {
    for (const ShapeDescription& s : d.shapes)
        if (s.type == ShapeDescription::Type::Sphere &&
            glm::length(d.camera_position - s.center) < s.radius)
            std::cerr << "warning: " << s.where.file << ":" << s.where.line << ": " << s.where.field
                      << ": the camera is inside this sphere; the image shows its inside\n";
}

}  // namespace

Scene build_scene(const SceneDescription& d, const BuildOptions& options) {
    Scene scene;
    scene.source = d.file;
    scene.notes = d.notes;
    scene.input_files = d.files_read;
    scene.width = options.width > 0 ? options.width : d.width;
    scene.height = options.height > 0 ? options.height : d.height;
    scene.background = d.background;
    if (!d.background_map.empty()) read_environment_map(d, options.limits, scene);
    scene.camera = Camera(d.camera_position, d.camera_look_at, d.camera_up, d.camera_fov,
                          static_cast<float>(scene.width) / static_cast<float>(scene.height));
    TextureCache textures;
    const Materials materials = add_materials(d, options.limits, textures, scene);
    const std::map<std::string, uint32_t> media = add_media(d, scene);
    add_shapes(d, materials, media, options.limits, textures, scene);
    for (const PointLightDescription& l : d.point_lights) scene.add_point_light(l.light);
    for (const DirectionalLightDescription& l : d.directional_lights)
        scene.add_directional_light(l.light);
    warn_of_a_camera_inside(d);
    scene.commit(options.threads);
    return scene;
}

}  // namespace lessons
