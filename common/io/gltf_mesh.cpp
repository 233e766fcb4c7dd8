// A glTF mesh primitive: its accessors, checked against their buffer views and buffers and read
// element by element, and its triangles (of a list, a strip or a fan).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "io/gltf_reader.h"
#include "io/scene_file.h"

namespace lessons::gltf_reader {

namespace {

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

// Accessor `index`, which `used_as` names in messages, of `components` per element; its
// elements must lie in its buffer view, and the view in its buffer.
Accessor accessor(const Reader& r, int index, const std::string& used_as, int components) {
    const tinygltf::Model& model = r.model();
    const std::string field = "accessors[" + std::to_string(index) + "]";
    if (index < 0 || index >= static_cast<int>(model.accessors.size()))
        r.fail(used_as, "names accessor " + std::to_string(index) + ", which does not exist");
    const tinygltf::Accessor& a = model.accessors[index];
    Accessor v;
    v.count = a.count;
    v.component_type = a.componentType;
    v.components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    v.normalized = a.normalized;
    if (v.components != components)
        r.fail(field, used_as + " needs " + std::to_string(components) +
                          " components per element, the accessor has " +
                          std::to_string(v.components));
    const int size = component_bytes(a.componentType);
    if (size == 0) r.fail(field, "unknown componentType " + std::to_string(a.componentType));
    if (a.sparse.isSparse) r.fail(field, "sparse accessors are not supported");
    if (a.bufferView < 0) r.fail(field, "has no bufferView (accessors of zeros are not supported)");
    if (v.count == 0) return v;
    if (a.bufferView >= static_cast<int>(model.bufferViews.size()))
        r.fail(field,
               "names bufferView " + std::to_string(a.bufferView) + ", which does not exist");
    const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
    const std::string view_field = "bufferViews[" + std::to_string(a.bufferView) + "]";
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
        r.fail(view_field,
               "names buffer " + std::to_string(view.buffer) + ", which does not exist");
    const std::vector<unsigned char>& buffer = model.buffers[view.buffer].data;
    const size_t element = static_cast<size_t>(size) * v.components;
    v.stride = view.byteStride > 0 ? view.byteStride : element;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        r.fail(view_field, "bytes " + std::to_string(view.byteOffset) + " + " +
                               std::to_string(view.byteLength) + " reach past the end of buffer " +
                               std::to_string(view.buffer) + " (" + std::to_string(buffer.size()) +
                               " bytes): truncated?");
    if (v.count > 0) {
        // The last element's end, in the view, without overflow.
        const double end = static_cast<double>(a.byteOffset) +
                           static_cast<double>(v.stride) * static_cast<double>(v.count - 1) +
                           static_cast<double>(element);
        if (v.stride < element || end > static_cast<double>(view.byteLength))
            r.fail(field, std::to_string(v.count) + " elements from byte " +
                              std::to_string(a.byteOffset) + " reach past the end of " +
                              view_field + " (" + std::to_string(view.byteLength) + " bytes)");
    }
    v.data = buffer.data() + view.byteOffset + a.byteOffset;
    return v;
}

// Component c of element i, as a float (normalized integers scaled to [0, 1] or [-1, 1]).
float component(const Accessor& a, size_t i, int c) {
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
uint32_t index_value(const Accessor& a, size_t i) {
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

// The primitive's mode: triangles (the default), a strip or a fan; points and lines refused.
int surface_mode(const Reader& r, const tinygltf::Primitive& p, const std::string& field) {
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        static const char* const names[] = {"points", "lines", "a line loop", "a line strip"};
        r.fail(field + ".mode",
               std::string("is ") + (mode >= 0 && mode < 4 ? names[mode] : "unknown") + " (" +
                   std::to_string(mode) + "): only triangles, strips and fans are surfaces");
    }
    return mode;
}

// The accessor an attribute names, or -1.
int attribute(const tinygltf::Primitive& p, const char* name) {
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
}

// POSITION: every vertex finite and within 1e9. Returns how many there are.
size_t read_positions(const Reader& r, const tinygltf::Primitive& p, const std::string& field,
                      GltfPrimitive& out) {
    const int position = attribute(p, "POSITION");
    if (position < 0) r.fail(field + ".attributes", "has no POSITION");
    const Accessor pos = accessor(r, position, field + ".POSITION", 3);
    if (pos.count > (1u << 28)) r.fail(field + ".POSITION", "too many vertices");
    out.positions.resize(pos.count);
    for (size_t i = 0; i < pos.count; ++i) {
        const Vec3 v(component(pos, i, 0), component(pos, i, 1), component(pos, i, 2));
        if (!is_finite(v) || max_component(glm::abs(v)) > kMaxCoordinate)
            r.fail(field + ".POSITION",
                   "vertex " + std::to_string(i) + " is not finite (or beyond 1e9)");
        out.positions[i] = v;
    }
    return pos.count;
}

// The accessor of an attribute given per vertex (`components` each), or none if the primitive
// has no such attribute.
std::optional<Accessor> per_vertex(const Reader& r, const tinygltf::Primitive& p,
                                   const std::string& field, const char* name, int components,
                                   size_t vertices) {
    const int index = attribute(p, name);
    if (index < 0) return std::nullopt;
    const std::string used_as = field + "." + name;
    const Accessor a = accessor(r, index, used_as, components);
    if (a.count != vertices) r.fail(used_as, "has another count than POSITION");
    return a;
}

// NORMAL, if given: one per vertex, each made unit length.
void read_normals(const Reader& r, const tinygltf::Primitive& p, const std::string& field,
                  size_t vertices, GltfPrimitive& out) {
    const std::optional<Accessor> n = per_vertex(r, p, field, "NORMAL", 3, vertices);
    if (!n) return;
    out.normals.resize(n->count);
    for (size_t i = 0; i < n->count; ++i) {
        const Vec3 v(component(*n, i, 0), component(*n, i, 1), component(*n, i, 2));
        const float len = glm::length(v);
        if (!(len > 0.0f) || !std::isfinite(len)) {
            out.normals.clear();  // a broken normal: the geometric normals for all
            break;
        }
        out.normals[i] = v / len;
    }
}

// TEXCOORD_0, if given: one (u, v) per vertex, v = 1 - t (glTF's t runs down the image).
void read_uvs(const Reader& r, const tinygltf::Primitive& p, const std::string& field,
              size_t vertices, GltfPrimitive& out) {
    const std::optional<Accessor> t = per_vertex(r, p, field, "TEXCOORD_0", 2, vertices);
    if (!t) return;
    out.uvs.resize(t->count);
    for (size_t i = 0; i < t->count; ++i) {
        const Vec2 v(component(*t, i, 0), 1.0f - component(*t, i, 1));
        if (!std::isfinite(v.x) || !std::isfinite(v.y))
            r.fail(field + ".TEXCOORD_0", "coordinate " + std::to_string(i) + " is not finite");
        out.uvs[i] = v;
    }
}

// The vertex indices: the primitive's (unsigned, each below `vertices`), or 0, 1, 2, ...
std::vector<uint32_t> read_indices(const Reader& r, const tinygltf::Primitive& p,
                                   const std::string& field, size_t vertices) {
    std::vector<uint32_t> indices;
    if (p.indices >= 0) {
        const Accessor ix = accessor(r, p.indices, field + ".indices", 1);
        if (ix.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            ix.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            ix.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            r.fail(field + ".indices", "indices must be unsigned bytes, shorts or ints");
        indices.resize(ix.count);
        for (size_t i = 0; i < ix.count; ++i) {
            indices[i] = index_value(ix, i);
            if (indices[i] >= vertices)
                r.fail(field + ".indices", "index " + std::to_string(i) + " is " +
                                               std::to_string(indices[i]) + ", past the " +
                                               std::to_string(vertices) + " vertices");
        }
    } else {
        indices.resize(vertices);
        for (size_t i = 0; i < vertices; ++i) indices[i] = static_cast<uint32_t>(i);
    }
    return indices;
}

// The triangles of a list, a strip (every other one turned, to keep the winding) or a fan;
// those of zero area left out and counted.
void add_triangles(int mode, const std::vector<uint32_t>& indices, GltfPrimitive& out,
                   int& degenerate) {
    auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
        const Vec3 n =
            glm::cross(out.positions[b] - out.positions[a], out.positions[c] - out.positions[a]);
        if (!(glm::dot(n, n) > 0.0f)) {
            ++degenerate;
            return;
        }
        out.triangles.push_back({a, b, c});
    };
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < indices.size(); i += 3)
            add(indices[i], indices[i + 1], indices[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < indices.size(); ++i)
            i % 2 == 0 ? add(indices[i], indices[i + 1], indices[i + 2])
                       : add(indices[i + 1], indices[i], indices[i + 2]);
    } else {
        for (size_t i = 1; i + 1 < indices.size(); ++i) add(indices[0], indices[i], indices[i + 1]);
    }
}

}  // namespace

void read_primitive(const Reader& r, const tinygltf::Primitive& p, const std::string& field,
                    GltfPrimitive& out, int& degenerate) {
    const int mode = surface_mode(r, p, field);
    const size_t vertices = read_positions(r, p, field, out);
    read_normals(r, p, field, vertices, out);
    read_uvs(r, p, field, vertices, out);
    add_triangles(mode, read_indices(r, p, field, vertices), out, degenerate);
}

}  // namespace lessons::gltf_reader
