// A glTF scene's node hierarchy walked: each node's transform composed with its parents' (in
// double), its meshes placed, the first perspective camera taken and its lights placed.
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "io/gltf_reader.h"
#include "io/scene_file.h"

namespace lessons::gltf_reader {

namespace {

glm::dmat4 local_matrix(const Reader& r, const tinygltf::Node& n, const std::string& field) {
    glm::dmat4 m(1.0);
    if (n.matrix.size() == 16) {
        m = glm::make_mat4(n.matrix.data());  // column-major, as glTF stores it
    } else {
        glm::dvec3 t(0.0), s(1.0);
        glm::dquat q(1.0, 0.0, 0.0, 0.0);
        if (n.translation.size() == 3) t = glm::make_vec3(n.translation.data());
        if (n.scale.size() == 3) s = glm::make_vec3(n.scale.data());
        if (n.rotation.size() == 4) {
            // w, x, y, z
            q = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
            const double len = glm::length(q);
            if (!(len > 0.0) || !std::isfinite(len))
                r.fail(field + ".rotation", "is not a rotation");
            q /= len;
        }
        m = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q) * glm::scale(glm::dmat4(1.0), s);
    }
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(m[c][k])) r.fail(field, "its transform is not finite");
    return m;
}

struct Walk {
    const Reader& r;
    GltfScene& scene;
    std::set<int> visited;  // the hierarchy is a forest: no node twice
    int degenerate = 0;
    int default_material = -1;
    std::map<std::pair<int, size_t>, GltfPrimitive> read;  // (mesh, primitive): read once
    uint64_t vertices = 0;                                 // placed, over every instance
    static constexpr uint64_t kMaxVertices = uint64_t{1} << 28;

    void node(int index, const glm::dmat4& parent, int depth) {
        const tinygltf::Model& m = r.model();
        const std::string field = "nodes[" + std::to_string(index) + "]";
        if (index < 0 || index >= static_cast<int>(m.nodes.size()))
            r.fail("nodes", "names node " + std::to_string(index) + ", which does not exist");
        if (!visited.insert(index).second || depth > 256)
            r.fail(field,
                   "is reached twice (or 256 levels deep): the node hierarchy must be a "
                   "forest of trees, each node in one place");
        const tinygltf::Node& n = m.nodes[index];
        const glm::dmat4 world = parent * local_matrix(r, n, field);
        if (n.mesh >= 0) place_mesh(n, world, field);
        if (n.camera >= 0 && !scene.camera) camera(n, world, field);
        if (auto it = n.extensions.find("KHR_lights_punctual");
            it != n.extensions.end() && it->second.Has("light")) {
            const tinygltf::Value& v = it->second.Get("light");
            const double index = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
            light(index >= 0.0 && index < 1e9 ? static_cast<int>(index) : -1, world, field);
        }
        for (int child : n.children) node(child, world, depth + 1);
    }

    // The node's mesh: each primitive (read once per mesh) placed by the node's transform.
    void place_mesh(const tinygltf::Node& n, const glm::dmat4& world, const std::string& field) {
        const tinygltf::Model& m = r.model();
        if (n.mesh >= static_cast<int>(m.meshes.size()))
            r.fail(field + ".mesh",
                   "names mesh " + std::to_string(n.mesh) + ", which does not exist");
        const tinygltf::Mesh& mesh = m.meshes[n.mesh];
        const double det = glm::determinant(glm::dmat3(world));
        if (!(std::fabs(det) > 1e-300)) {
            scene.notes.push_back("glTF: " + field + " flattens its mesh (a zero scale): left out");
            return;
        }
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            auto cached = read.find({n.mesh, p});
            if (cached == read.end()) {
                GltfPrimitive fresh;
                fresh.where =
                    "meshes[" + std::to_string(n.mesh) + "].primitives[" + std::to_string(p) + "]";
                read_primitive(r, mesh.primitives[p], fresh.where, fresh, degenerate);
                cached = read.emplace(std::make_pair(n.mesh, p), std::move(fresh)).first;
            }
            GltfPrimitive prim = cached->second;
            vertices += prim.positions.size();
            if (vertices > kMaxVertices)
                r.fail(field,
                       "places more than 2^28 vertices in all (meshes placed by many "
                       "nodes count each time)");
            const int mat = mesh.primitives[p].material;
            if (mat >= static_cast<int>(m.materials.size()))
                r.fail(prim.where + ".material",
                       "names material " + std::to_string(mat) + ", which does not exist");
            prim.material = mat >= 0 ? mat : default_material_index();
            prim.to_world = world;
            for (const Vec3& v : prim.positions)
                scene.bounds.expand(Vec3(world * glm::dvec4(glm::dvec3(v), 1.0)));
            if (!prim.triangles.empty()) scene.primitives.push_back(std::move(prim));
        }
    }

    int default_material_index() {
        if (default_material < 0) {
            std::vector<std::string> notes;
            scene.materials.push_back(
                map_material(r, tinygltf::Material{}, "the default material", notes));
            scene.notes.insert(scene.notes.end(), notes.begin(), notes.end());
            default_material = static_cast<int>(scene.materials.size()) - 1;
        }
        return default_material;
    }

    void camera(const tinygltf::Node& n, const glm::dmat4& world, const std::string& field) {
        const tinygltf::Model& m = r.model();
        if (n.camera >= static_cast<int>(m.cameras.size()))
            r.fail(field + ".camera",
                   "names camera " + std::to_string(n.camera) + ", which does not exist");
        const tinygltf::Camera& c = m.cameras[n.camera];
        if (c.type != "perspective") {
            scene.notes.push_back("glTF: the " + c.type + " camera of " + field +
                                  " is ignored (perspective cameras only)");
            return;
        }
        GltfCamera cam;
        cam.name = !c.name.empty() ? c.name : !n.name.empty() ? n.name : field;
        const glm::dvec3 at = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
        const glm::dvec3 forward = glm::normalize(glm::dvec3(world * glm::dvec4(0, 0, -1, 0)));
        const glm::dvec3 up = glm::normalize(glm::dvec3(world * glm::dvec4(0, 1, 0, 0)));
        const double yfov = c.perspective.yfov * 180.0 / 3.14159265358979323846;
        if (!std::isfinite(forward.x + forward.y + forward.z + up.x + up.y + up.z) ||
            !(yfov > 0.0 && yfov < 180.0))
            r.fail("cameras[" + std::to_string(n.camera) + "]",
                   "is not a usable perspective camera");
        cam.position = Vec3(at);
        cam.look_at = Vec3(at + forward * std::max(1.0, 1e-3 * glm::length(at)));
        cam.up = Vec3(up);
        if (!(glm::length(at) <= kMaxCoordinate) || cam.look_at == cam.position ||
            !(c.perspective.aspectRatio == 0.0 ||
              (c.perspective.aspectRatio > 1e-2 && c.perspective.aspectRatio < 1e2)))
            r.fail("cameras[" + std::to_string(n.camera) + "]",
                   "is not a usable perspective camera (placed beyond 1e9, or an aspectRatio "
                   "outside [0.01, 100])");
        cam.fov_y_degrees = static_cast<float>(yfov);
        cam.aspect = static_cast<float>(c.perspective.aspectRatio);
        scene.camera = cam;
    }

    // A KHR_lights_punctual light placed by its node: a point light at the node's origin; a spot
    // too, pointing along the node's -z; a directional light shining along the node's -z.
    void light(int index, const glm::dmat4& world, const std::string& field) {
        const tinygltf::Model& m = r.model();
        const std::string lf = "KHR_lights_punctual.lights[" + std::to_string(index) + "]";
        if (index < 0 || index >= static_cast<int>(m.lights.size()))
            r.fail(field + ".KHR_lights_punctual",
                   "names light " + std::to_string(index) + ", which does not exist");
        const tinygltf::Light& l = m.lights[index];
        if (l.type != "point" && l.type != "spot" && l.type != "directional")
            r.fail(lf,
                   "is a '" + l.type + "' light: glTF's lights are point, spot and directional");
        // glTF gives a point or spot light's luminous intensity in candela (lm/sr), a directional
        // light's illuminance in lux (lm/m^2); at 683 lm/W they are cd / 683 W/sr and lux / 683
        // W/m^2 (docs/interop.md).
        const Color radiometric =
            rgb(l.color, Color(1.0f)) * static_cast<float>(l.intensity / 683.0);
        if (!is_finite(radiometric) || radiometric.x < 0.0f || radiometric.y < 0.0f ||
            radiometric.z < 0.0f)
            r.fail(lf, "its colour and intensity must be finite and not negative");
        // The node's -z in the scene's space, where a spot points and a sun shines: rounded to
        // float and not yet normalised (add_gltf normalises it once placed, as the scene file's
        // directions are).
        const Vec3 axis = Vec3(glm::dvec3(world * glm::dvec4(0, 0, -1, 0)));
        if (l.type != "point" && !(is_finite(axis) && glm::length(axis) > 0.0f))
            r.fail(field, "turns its light's -z into no direction (a zero or non-finite scale)");
        if (l.type == "directional") {
            scene.directional_lights.push_back({axis, radiometric});
            return;
        }
        const glm::dvec3 at = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
        if (!(std::fabs(at.x) <= kMaxCoordinate && std::fabs(at.y) <= kMaxCoordinate &&
              std::fabs(at.z) <= kMaxCoordinate))
            r.fail(field, "places its light beyond 1e9 (or not at a finite point)");
        PointLight light{Vec3(at), radiometric};
        if (l.type == "spot") light.cone = spot_cone(l, axis, lf);
        scene.lights.push_back(light);
        scene.bounds.expand(Vec3(at));
        if (l.range > 0.0)
            scene.notes.push_back("glTF: " + lf + ": range " + fixed(l.range) +
                                  " ignored (light falls off as 1/d^2 without end)");
    }

    // A spot's cone: glTF's outerConeAngle (default pi/4) is the edge, its innerConeAngle (default
    // 0) where the fade starts. glTF recommends a fade of t^2 in the cosine; the suite's is
    // smoothstep, t^2 (3 - 2t) (SpotCone::falloff): noted.
    SpotCone spot_cone(const tinygltf::Light& l, const Vec3& axis, const std::string& lf) {
        const double outer = l.spot.outerConeAngle, inner = l.spot.innerConeAngle;
        const double half_pi = 1.57079632679489661923;
        const double narrowest = kNarrowestSpotDegrees * half_pi / 90.0;
        if (!(outer >= narrowest && outer <= half_pi))
            r.fail(lf + ".spot.outerConeAngle",
                   "is " + fixed(outer) + ", outside [" + fixed(narrowest) + ", pi/2]");
        if (!(inner >= 0.0 && inner <= outer))
            r.fail(lf + ".spot.innerConeAngle",
                   "is " + fixed(inner) + ", outside [0, outerConeAngle " + fixed(outer) + "]");
        scene.notes.push_back("glTF: " + lf +
                              " (spot): fades between innerConeAngle and outerConeAngle as "
                              "smoothstep in the cosine, not glTF's recommended square");
        return {axis, static_cast<float>(std::cos(outer)), static_cast<float>(std::cos(inner))};
    }
};

}  // namespace

std::vector<int> root_nodes(const Reader& r) {
    const tinygltf::Model& model = r.model();
    std::vector<int> roots;
    const int which = model.defaultScene >= 0 ? model.defaultScene : model.scenes.empty() ? -1 : 0;
    if (which >= static_cast<int>(model.scenes.size()))
        r.fail("scene", "names scene " + std::to_string(which) + ", which does not exist");
    if (which >= 0) {
        roots = model.scenes[which].nodes;
    } else {  // no scenes: every node that is no node's child
        std::set<int> children;
        for (const tinygltf::Node& n : model.nodes)
            children.insert(n.children.begin(), n.children.end());
        for (int i = 0; i < static_cast<int>(model.nodes.size()); ++i)
            if (!children.count(i)) roots.push_back(i);
    }
    return roots;
}

int place_nodes(const Reader& r, const std::vector<int>& roots, GltfScene& scene) {
    Walk walk{r, scene, {}, 0, -1, {}, 0};
    for (int root : roots) walk.node(root, glm::dmat4(1.0), 0);
    return walk.degenerate;
}

}  // namespace lessons::gltf_reader
