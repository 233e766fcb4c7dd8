// glTF 2.0 through tinygltf (see gltf_file.h; what maps to what: docs/interop.md).
#include "io/gltf_file.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>
#include <set>
#include <sstream>

#include "io/input_error.h"
#include "io/input_file.h"
#include "io/scene_file.h"

namespace lessons {

namespace {

// tinygltf reads the files a glTF names itself: through these, each is a regular file under
// the cap, as every other input (input_file.h).
struct ReadLimits {
    uint64_t max_bytes;
    std::string base;  // the glTF file's folder, which tinygltf joins to every URI
};
// tinygltf joins the folder to a URI even when it is an absolute path ("/dev/zero" becomes
// "folder//dev/zero", then "File not found"): an absolute path names itself.
std::string expand_path(const std::string& joined, void* user) {
    const std::string& base = static_cast<ReadLimits*>(user)->base;
    const size_t n = base.size();
    if (n > 0 && joined.size() > n + 1 && joined.compare(0, n, base) == 0 && joined[n] == '/' &&
        joined[n + 1] == '/')
        return tinygltf::ExpandFilePath(joined.substr(n + 1), nullptr);
    return tinygltf::ExpandFilePath(joined, nullptr);
}
bool read_capped(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                 void* user) {
    try {
        const std::string bytes = read_input_file(path, "file a glTF names",
                                                  static_cast<ReadLimits*>(user)->max_bytes,
                                                  "--max-file-mb");
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const InputError& e) {
        if (err) *err += e.what();
        return false;
    }
}
// Images are not decoded here: a base colour texture is read by the scene as a file (with the
// checks of io/texture.cpp); embedded ones are noted and left out.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
    return true;
}

// One accessor, checked against its buffer view and buffer.
struct Accessor {
    const unsigned char* data = nullptr;  // null: all zeros (no buffer view)
    size_t stride = 0, count = 0;
    int component_type = 0, components = 0;
    bool normalized = false;
};

int component_bytes(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

class Reader {
public:
    Reader(const tinygltf::Model& m, std::string path) : model_(m), path_(std::move(path)) {}

    [[noreturn]] void fail(const std::string& field, const std::string& message) const {
        throw InputError(path_, 0, field, message);
    }

    Accessor accessor(int index, const std::string& used_as, int components) const {
        const std::string field = "accessors[" + std::to_string(index) + "]";
        if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
            fail(used_as, "names accessor " + std::to_string(index) + ", which does not exist");
        const tinygltf::Accessor& a = model_.accessors[index];
        Accessor v;
        v.count = a.count;
        v.component_type = a.componentType;
        v.components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
        v.normalized = a.normalized;
        if (v.components != components)
            fail(field, used_as + " needs " + std::to_string(components) +
                            " components per element, the accessor has " +
                            std::to_string(v.components));
        const int size = component_bytes(a.componentType);
        if (size == 0) fail(field, "unknown componentType " + std::to_string(a.componentType));
        if (a.sparse.isSparse) fail(field, "sparse accessors are not supported");
        if (a.bufferView < 0) fail(field, "has no bufferView (accessors of zeros are not supported)");
        if (v.count == 0) return v;
        if (a.bufferView >= static_cast<int>(model_.bufferViews.size()))
            fail(field, "names bufferView " + std::to_string(a.bufferView) + ", which does not exist");
        const tinygltf::BufferView& view = model_.bufferViews[a.bufferView];
        const std::string view_field = "bufferViews[" + std::to_string(a.bufferView) + "]";
        if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size()))
            fail(view_field, "names buffer " + std::to_string(view.buffer) + ", which does not exist");
        const std::vector<unsigned char>& buffer = model_.buffers[view.buffer].data;
        const size_t element = static_cast<size_t>(size) * v.components;
        v.stride = view.byteStride > 0 ? view.byteStride : element;
        if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
            fail(view_field, "bytes " + std::to_string(view.byteOffset) + " + " +
                                 std::to_string(view.byteLength) + " reach past the end of buffer " +
                                 std::to_string(view.buffer) + " (" +
                                 std::to_string(buffer.size()) + " bytes): truncated?");
        if (v.count > 0) {
            // The last element's end, in the view, without overflow.
            const double end = static_cast<double>(a.byteOffset) +
                               static_cast<double>(v.stride) * static_cast<double>(v.count - 1) +
                               static_cast<double>(element);
            if (v.stride < element || end > static_cast<double>(view.byteLength))
                fail(field, std::to_string(v.count) + " elements from byte " +
                                std::to_string(a.byteOffset) + " reach past the end of " +
                                view_field + " (" + std::to_string(view.byteLength) + " bytes)");
        }
        v.data = buffer.data() + view.byteOffset + a.byteOffset;
        return v;
    }

    // Component c of element i, as a float (normalized integers scaled to [0, 1] or [-1, 1]).
    static float component(const Accessor& a, size_t i, int c) {
        if (!a.data) return 0.0f;
        const unsigned char* p = a.data + i * a.stride + c * component_bytes(a.component_type);
        switch (a.component_type) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                float f;
                std::memcpy(&f, p, 4);
                return f;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return a.normalized ? *p / 255.0f : *p;
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                const float f = static_cast<signed char>(*p);
                return a.normalized ? std::max(f / 127.0f, -1.0f) : f;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p, 2);
                return a.normalized ? u / 65535.0f : u;
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                int16_t s;
                std::memcpy(&s, p, 2);
                return a.normalized ? std::max(s / 32767.0f, -1.0f) : s;
            }
            default: {
                uint32_t u;
                std::memcpy(&u, p, 4);
                return static_cast<float>(u);
            }
        }
    }
    static uint32_t index_value(const Accessor& a, size_t i) {
        if (!a.data) return 0;
        const unsigned char* p = a.data + i * a.stride;
        switch (a.component_type) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p, 2);
                return u;
            }
            default: {
                uint32_t u;
                std::memcpy(&u, p, 4);
                return u;
            }
        }
    }

    const tinygltf::Model& model() const { return model_; }
    const std::string& path() const { return path_; }

private:
    const tinygltf::Model& model_;
    std::string path_;
};

// ---- Transforms ----

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
            q = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // w, x, y, z
            const double len = glm::length(q);
            if (!(len > 0.0) || !std::isfinite(len)) r.fail(field + ".rotation", "is not a rotation");
            q /= len;
        }
        m = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q) * glm::scale(glm::dmat4(1.0), s);
    }
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(m[c][k])) r.fail(field, "its transform is not finite");
    return m;
}

// ---- Materials ----

Color rgb(const std::vector<double>& v, Color fallback) {
    if (v.size() < 3) return fallback;
    return Color(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
}

double number_in(const tinygltf::ExtensionMap& ext, const char* extension, const char* key,
                 double fallback) {
    auto it = ext.find(extension);
    if (it == ext.end() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& v = it->second.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
}

std::string fixed(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

int hex_digit(char c) {
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}
// A relative URI as a path beside the glTF file, %XX escapes decoded (a bad one kept as it is).
std::string resolve_uri(const std::string& gltf_path, const std::string& uri) {
    std::string decoded;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex_digit(uri[i + 1]) >= 0 && hex_digit(uri[i + 2]) >= 0) {
            decoded += static_cast<char>(16 * hex_digit(uri[i + 1]) + hex_digit(uri[i + 2]));
            i += 2;
        } else {
            decoded += uri[i];
        }
    }
    return (std::filesystem::path(gltf_path).parent_path() / decoded).lexically_normal().string();
}

// The file a base colour texture names, or "" (embedded, or none), with a note why not.
std::string texture_file(const Reader& r, int texture, std::vector<std::string>& ignored,
                         bool& clamp) {
    const tinygltf::Model& m = r.model();
    if (texture < 0 || texture >= static_cast<int>(m.textures.size())) return "";
    const tinygltf::Texture& t = m.textures[texture];
    if (t.sampler >= 0 && t.sampler < static_cast<int>(m.samplers.size()))
        clamp = m.samplers[t.sampler].wrapS == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    if (t.source < 0 || t.source >= static_cast<int>(m.images.size())) return "";
    const tinygltf::Image& image = m.images[t.source];
    if (image.uri.empty() || image.uri.rfind("data:", 0) == 0) {
        ignored.push_back("its embedded baseColorTexture (the suite reads textures from files)");
        return "";
    }
    return resolve_uri(r.path(), image.uri);
}

Material map_material(const Reader& r, const tinygltf::Material& g, const std::string& field,
                      std::vector<std::string>& notes) {
    Material m;
    m.name = g.name.empty() ? field : g.name;
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    const Color base = glm::clamp(rgb(pbr.baseColorFactor, Color(1.0f)), Color(0.0f), Color(1.0f));
    const double metallic = std::clamp(pbr.metallicFactor, 0.0, 1.0);
    const double roughness = std::clamp(pbr.roughnessFactor, 0.0, 1.0);
    const double transmission =
        number_in(g.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0);
    std::vector<std::string> mapped, ignored;
    if (transmission > 0.0) {
        m.type = MaterialType::Glass;
        m.ior = static_cast<float>(number_in(g.extensions, "KHR_materials_ior", "ior", 1.5));
        if (!(m.ior >= 1.0f && m.ior <= 4.0f)) r.fail(field + ".KHR_materials_ior", "ior must be in [1, 4]");
        m.transmittance = base;
        mapped.push_back("glass of ior " + fixed(m.ior) + " (KHR_materials_transmission)");
        if (transmission < 1.0) ignored.push_back("transmission " + fixed(transmission) + " < 1 (taken as 1)");
        if (roughness > 0.0) ignored.push_back("roughness " + fixed(roughness) + " (the glass is smooth)");
    } else if (metallic >= 0.5) {
        const float alpha = static_cast<float>(roughness * roughness);  // glTF: alpha = r^2
        if (alpha < 1e-4f) {
            m.type = MaterialType::Mirror;
            m.reflectance = base;
            mapped.push_back("a mirror (metallic, roughness " + fixed(roughness) + ")");
        } else {
            m.type = MaterialType::Conductor;
            m.specular = base;
            m.roughness = alpha;
            mapped.push_back("a conductor (GGX alpha = roughness^2 = " + fixed(alpha) + ")");
        }
        if (pbr.baseColorTexture.index >= 0) ignored.push_back("baseColorTexture (a metal's colour is its factor)");
    } else {
        m.type = MaterialType::Diffuse;
        m.albedo.value = base;
        bool clamp = false;
        m.albedo.image_file = texture_file(r, pbr.baseColorTexture.index, ignored, clamp);
        m.albedo.repeat = !clamp;
        if (!m.albedo.image_file.empty()) {
            mapped.push_back("diffuse, albedo from its baseColorTexture");
            if (base != Color(1.0f)) ignored.push_back("baseColorFactor times the texture (the texture alone)");
            if (pbr.baseColorTexture.texCoord != 0) ignored.push_back("TEXCOORD_" + std::to_string(pbr.baseColorTexture.texCoord) + " (TEXCOORD_0 is used)");
        } else {
            mapped.push_back("diffuse");
        }
        ignored.push_back("the specular reflection of a dielectric (F0 = 0.04)");
    }
    if (metallic > 0.0 && metallic < 1.0) ignored.push_back("metallic " + fixed(metallic) + " between 0 and 1 (taken as " + (metallic >= 0.5 ? "1" : "0") + ")");
    const double strength = number_in(g.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
    m.emission = rgb(g.emissiveFactor, Color(0.0f)) * static_cast<float>(strength);
    if (!is_finite(m.emission) || m.emission.x < 0.0f || m.emission.y < 0.0f || m.emission.z < 0.0f)
        r.fail(field + ".emissiveFactor", "emission must be finite and not negative");
    m.two_sided = g.doubleSided;
    if (m.is_emissive()) mapped.push_back(std::string("emitting ") + (g.doubleSided ? "from both sides" : "from its front"));
    if (g.normalTexture.index >= 0) ignored.push_back("normalTexture");
    if (g.occlusionTexture.index >= 0) ignored.push_back("occlusionTexture");
    if (g.emissiveTexture.index >= 0) ignored.push_back("emissiveTexture");
    if (pbr.metallicRoughnessTexture.index >= 0) ignored.push_back("metallicRoughnessTexture");
    if (g.alphaMode != "OPAQUE") ignored.push_back("alphaMode " + g.alphaMode);
    for (const auto& [name, value] : g.extensions)
        if (name != "KHR_materials_transmission" && name != "KHR_materials_ior" &&
            name != "KHR_materials_emissive_strength")
            ignored.push_back(name);
    notes.push_back("glTF material '" + m.name + "' (" + field + "): " + join(mapped) +
                    (ignored.empty() ? "" : "; ignored: " + join(ignored)));
    return m;
}

// ---- Meshes ----

void read_primitive(const Reader& r, const tinygltf::Primitive& p, const std::string& field,
                    GltfPrimitive& out, int& degenerate) {
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        static const char* const names[] = {"points", "lines", "a line loop", "a line strip"};
        r.fail(field + ".mode", std::string("is ") + (mode >= 0 && mode < 4 ? names[mode] : "unknown") +
                                    " (" + std::to_string(mode) +
                                    "): only triangles, strips and fans are surfaces");
    }
    auto attribute = [&](const char* name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    const int position = attribute("POSITION");
    if (position < 0) r.fail(field + ".attributes", "has no POSITION");
    const Accessor pos = r.accessor(position, field + ".POSITION", 3);
    if (pos.count > (1u << 28)) r.fail(field + ".POSITION", "too many vertices");
    out.positions.resize(pos.count);
    for (size_t i = 0; i < pos.count; ++i) {
        const Vec3 v(Reader::component(pos, i, 0), Reader::component(pos, i, 1),
                     Reader::component(pos, i, 2));
        if (!is_finite(v) || max_component(glm::abs(v)) > kMaxCoordinate)
            r.fail(field + ".POSITION", "vertex " + std::to_string(i) + " is not finite (or beyond 1e9)");
        out.positions[i] = v;
    }
    if (const int normal = attribute("NORMAL"); normal >= 0) {
        const Accessor n = r.accessor(normal, field + ".NORMAL", 3);
        if (n.count != pos.count) r.fail(field + ".NORMAL", "has another count than POSITION");
        out.normals.resize(n.count);
        for (size_t i = 0; i < n.count; ++i) {
            const Vec3 v(Reader::component(n, i, 0), Reader::component(n, i, 1),
                         Reader::component(n, i, 2));
            const float len = glm::length(v);
            if (!(len > 0.0f) || !std::isfinite(len)) {
                out.normals.clear();  // a broken normal: the geometric normals for all
                break;
            }
            out.normals[i] = v / len;
        }
    }
    if (const int uv = attribute("TEXCOORD_0"); uv >= 0) {
        const Accessor t = r.accessor(uv, field + ".TEXCOORD_0", 2);
        if (t.count != pos.count) r.fail(field + ".TEXCOORD_0", "has another count than POSITION");
        out.uvs.resize(t.count);
        for (size_t i = 0; i < t.count; ++i) {
            const Vec2 v(Reader::component(t, i, 0), 1.0f - Reader::component(t, i, 1));
            if (!std::isfinite(v.x) || !std::isfinite(v.y))
                r.fail(field + ".TEXCOORD_0", "coordinate " + std::to_string(i) + " is not finite");
            out.uvs[i] = v;
        }
    }
    std::vector<uint32_t> indices;
    if (p.indices >= 0) {
        const Accessor ix = r.accessor(p.indices, field + ".indices", 1);
        if (ix.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            ix.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            ix.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            r.fail(field + ".indices", "indices must be unsigned bytes, shorts or ints");
        indices.resize(ix.count);
        for (size_t i = 0; i < ix.count; ++i) {
            indices[i] = Reader::index_value(ix, i);
            if (indices[i] >= pos.count)
                r.fail(field + ".indices", "index " + std::to_string(i) + " is " +
                                               std::to_string(indices[i]) + ", past the " +
                                               std::to_string(pos.count) + " vertices");
        }
    } else {
        indices.resize(pos.count);
        for (size_t i = 0; i < pos.count; ++i) indices[i] = static_cast<uint32_t>(i);
    }
    auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
        const Vec3 n = glm::cross(out.positions[b] - out.positions[a], out.positions[c] - out.positions[a]);
        if (!(glm::dot(n, n) > 0.0f)) {
            ++degenerate;
            return;
        }
        out.triangles.push_back({a, b, c});
    };
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < indices.size(); i += 3) add(indices[i], indices[i + 1], indices[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < indices.size(); ++i)
            i % 2 == 0 ? add(indices[i], indices[i + 1], indices[i + 2])
                       : add(indices[i + 1], indices[i], indices[i + 2]);
    } else {
        for (size_t i = 1; i + 1 < indices.size(); ++i) add(indices[0], indices[i], indices[i + 1]);
    }
}

// ---- The node hierarchy ----

struct Walk {
    const Reader& r;
    GltfScene& scene;
    std::set<int> visited;  // the hierarchy is a forest: no node twice
    int degenerate = 0;
    int default_material = -1;
    std::map<std::pair<int, size_t>, GltfPrimitive> read;  // (mesh, primitive): read once
    uint64_t vertices = 0;  // placed, over every instance
    static constexpr uint64_t kMaxVertices = uint64_t{1} << 28;

    void node(int index, const glm::dmat4& parent, int depth) {
        const tinygltf::Model& m = r.model();
        const std::string field = "nodes[" + std::to_string(index) + "]";
        if (index < 0 || index >= static_cast<int>(m.nodes.size()))
            r.fail("nodes", "names node " + std::to_string(index) + ", which does not exist");
        if (!visited.insert(index).second || depth > 256)
            r.fail(field, "is reached twice (or 256 levels deep): the node hierarchy must be a "
                          "forest of trees, each node in one place");
        const tinygltf::Node& n = m.nodes[index];
        const glm::dmat4 world = parent * local_matrix(r, n, field);
        bool mesh_skipped = false;
        if (n.mesh >= 0) {
            if (n.mesh >= static_cast<int>(m.meshes.size()))
                r.fail(field + ".mesh", "names mesh " + std::to_string(n.mesh) + ", which does not exist");
            const tinygltf::Mesh& mesh = m.meshes[n.mesh];
            const double det = glm::determinant(glm::dmat3(world));
            if (!(std::fabs(det) > 1e-300)) {
                scene.notes.push_back("glTF: " + field + " flattens its mesh (a zero scale): left out");
                mesh_skipped = true;
            }
            for (size_t p = 0; p < mesh.primitives.size() && !mesh_skipped; ++p) {
                auto cached = read.find({n.mesh, p});
                if (cached == read.end()) {
                    GltfPrimitive fresh;
                    fresh.where = "meshes[" + std::to_string(n.mesh) + "].primitives[" + std::to_string(p) + "]";
                    read_primitive(r, mesh.primitives[p], fresh.where, fresh, degenerate);
                    cached = read.emplace(std::make_pair(n.mesh, p), std::move(fresh)).first;
                }
                GltfPrimitive prim = cached->second;
                vertices += prim.positions.size();
                if (vertices > kMaxVertices)
                    r.fail(field, "places more than 2^28 vertices in all (meshes placed by many nodes count each time)");
                const int mat = mesh.primitives[p].material;
                if (mat >= static_cast<int>(m.materials.size()))
                    r.fail(prim.where + ".material", "names material " + std::to_string(mat) + ", which does not exist");
                prim.material = mat >= 0 ? mat : default_material_index();
                prim.to_world = world;
                for (const Vec3& v : prim.positions) scene.bounds.expand(Vec3(world * glm::dvec4(glm::dvec3(v), 1.0)));
                if (!prim.triangles.empty()) scene.primitives.push_back(std::move(prim));
            }
        }
        if (n.camera >= 0 && !scene.camera) camera(n, world, field);
        if (auto it = n.extensions.find("KHR_lights_punctual"); it != n.extensions.end() && it->second.Has("light"))
        {
            const tinygltf::Value& v = it->second.Get("light");
            const double index = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
            light(index >= 0.0 && index < 1e9 ? static_cast<int>(index) : -1, world, field);
        }
        for (int child : n.children) node(child, world, depth + 1);
    }

    int default_material_index() {
        if (default_material < 0) {
            std::vector<std::string> notes;
            scene.materials.push_back(map_material(r, tinygltf::Material{}, "the default material", notes));
            scene.notes.insert(scene.notes.end(), notes.begin(), notes.end());
            default_material = static_cast<int>(scene.materials.size()) - 1;
        }
        return default_material;
    }

    void camera(const tinygltf::Node& n, const glm::dmat4& world, const std::string& field) {
        const tinygltf::Model& m = r.model();
        if (n.camera >= static_cast<int>(m.cameras.size()))
            r.fail(field + ".camera", "names camera " + std::to_string(n.camera) + ", which does not exist");
        const tinygltf::Camera& c = m.cameras[n.camera];
        if (c.type != "perspective") {
            scene.notes.push_back("glTF: the " + c.type + " camera of " + field + " is ignored (perspective cameras only)");
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
            r.fail("cameras[" + std::to_string(n.camera) + "]", "is not a usable perspective camera");
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

    void light(int index, const glm::dmat4& world, const std::string& field) {
        const tinygltf::Model& m = r.model();
        const std::string lf = "KHR_lights_punctual.lights[" + std::to_string(index) + "]";
        if (index < 0 || index >= static_cast<int>(m.lights.size()))
            r.fail(field + ".KHR_lights_punctual", "names light " + std::to_string(index) + ", which does not exist");
        const tinygltf::Light& l = m.lights[index];
        if (l.type != "point")
            r.fail(lf, "is a " + l.type + " light: only point lights are supported (the lessons have no " + l.type + " lights; make it a point light or an emissive surface)");
        // glTF gives a point light's luminous intensity in candela (lm/sr); at 683 lm/W, the
        // radiant intensity is cd / 683 W/sr (docs/interop.md).
        const Color intensity = rgb(l.color, Color(1.0f)) * static_cast<float>(l.intensity / 683.0);
        if (!is_finite(intensity) || intensity.x < 0.0f || intensity.y < 0.0f || intensity.z < 0.0f)
            r.fail(lf, "its colour and intensity must be finite and not negative");
        const glm::dvec3 at = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
        if (!(std::fabs(at.x) <= kMaxCoordinate && std::fabs(at.y) <= kMaxCoordinate &&
              std::fabs(at.z) <= kMaxCoordinate))
            r.fail(field, "places its light beyond 1e9 (or not at a finite point)");
        scene.lights.push_back({Vec3(at), intensity});
        scene.bounds.expand(Vec3(at));
        if (l.range > 0.0) scene.notes.push_back("glTF: " + lf + ": range " + fixed(l.range) + " ignored (light falls off as 1/d^2 without end)");
    }
};

}  // namespace

namespace {

// tinygltf parses JSON recursively, extras and unknown extensions included: a file of deeply
// nested arrays would overflow the stack. No glTF needs more than a few levels.
void check_json_depth(const std::string& path, const std::string& bytes, size_t begin, size_t end) {
    int depth = 0;
    bool in_string = false, escaped = false;
    for (size_t i = begin; i < end && i < bytes.size(); ++i) {
        const char c = bytes[i];
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > 64) throw InputError(path, 0, "", "its JSON nests deeper than 64 levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

GltfScene read_gltf(const std::string& path, uint64_t max_bytes);

}  // namespace

GltfScene load_gltf(const std::string& path, uint64_t max_bytes) {
    try {
        return read_gltf(path, max_bytes);
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {  // (tinygltf's, the standard library's)
        throw InputError(path, 0, "", std::string("cannot be read as glTF: ") + e.what());
    }
}

namespace {

GltfScene read_gltf(const std::string& path, uint64_t max_bytes) {
    const std::string bytes = read_input_file(path, "glTF file", max_bytes, "--max-file-mb");
    if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {  // .glb: the JSON chunk
        uint32_t length = 0;
        std::memcpy(&length, bytes.data() + 12, 4);
        check_json_depth(path, bytes, 20, 20 + static_cast<size_t>(length));
    } else {
        check_json_depth(path, bytes, 0, bytes.size());
    }
    tinygltf::TinyGLTF loader;
    const std::string ext = std::filesystem::path(path).extension().string();
    const std::string base = std::filesystem::path(path).parent_path().string();
    ReadLimits limits{max_bytes, base};
    tinygltf::FsCallbacks fs{&tinygltf::FileExists, &expand_path, &read_capped,
                             &tinygltf::WriteWholeFile, &limits};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&skip_image, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const bool ok =
        ext == ".glb" || ext == ".GLB"
            ? loader.LoadBinaryFromMemory(&model, &err, &warn, data,
                                          static_cast<unsigned int>(bytes.size()), base)
            : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                         static_cast<unsigned int>(bytes.size()), base);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        throw InputError(path, 0, "", "cannot be read as glTF: " + (err.empty() ? warn : err));
    }
    for (const std::string& e : model.extensionsRequired)
        if (e != "KHR_materials_emissive_strength" && e != "KHR_materials_transmission" &&
            e != "KHR_materials_ior" && e != "KHR_lights_punctual")
            throw InputError(path, 0, "extensionsRequired",
                             "requires " + e + ", which this loader does not support");
    const Reader r(model, path);
    GltfScene scene;
    for (size_t i = 0; i < model.materials.size(); ++i)
        scene.materials.push_back(
            map_material(r, model.materials[i], "materials[" + std::to_string(i) + "]", scene.notes));
    Walk walk{r, scene, {}, 0, -1, {}, 0};
    std::vector<int> roots;
    const int which = model.defaultScene >= 0 ? model.defaultScene : model.scenes.empty() ? -1 : 0;
    if (which >= static_cast<int>(model.scenes.size()))
        r.fail("scene", "names scene " + std::to_string(which) + ", which does not exist");
    if (which >= 0) {
        roots = model.scenes[which].nodes;
    } else {  // no scenes: every node that is no node's child
        std::set<int> children;
        for (const tinygltf::Node& n : model.nodes) children.insert(n.children.begin(), n.children.end());
        for (int i = 0; i < static_cast<int>(model.nodes.size()); ++i)
            if (!children.count(i)) roots.push_back(i);
    }
    for (int root : roots) walk.node(root, glm::dmat4(1.0), 0);
    if (scene.primitives.empty() && scene.lights.empty())
        r.fail("meshes", "the scene has no triangles and no lights");
    if (walk.degenerate > 0)
        scene.notes.push_back("glTF: " + std::to_string(walk.degenerate) + " zero-area triangle(s) skipped");
    if (model.skins.size() > 0 || model.animations.size() > 0)
        scene.notes.push_back("glTF: skins and animations ignored (the scene as it rests)");
    for (const tinygltf::Buffer& b : model.buffers)
        if (!b.uri.empty() && b.uri.rfind("data:", 0) != 0) scene.files.push_back(resolve_uri(path, b.uri));
    for (const tinygltf::Image& i : model.images)
        if (!i.uri.empty() && i.uri.rfind("data:", 0) != 0) scene.files.push_back(resolve_uri(path, i.uri));
    return scene;
}

}  // namespace

}  // namespace lessons
