// glTF 2.0 through tinygltf (see gltf_file.h; what maps to what: docs/interop.md): the file read
// under the cap, with every file it names, and the scene made of it, step by step.
#include "io/gltf_file.h"

#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>

#include "io/gltf_reader.h"
#include "io/input_error.h"
#include "io/input_file.h"

namespace lessons {

namespace gltf_reader {

namespace {

int hex_digit(char c) {
    return c >= '0' && c <= '9'   ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : -1;
}

}  // namespace

std::string resolve_uri(const std::string& gltf_path, const std::string& uri) {
    std::string decoded;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex_digit(uri[i + 1]) >= 0 &&
            hex_digit(uri[i + 2]) >= 0) {
            decoded += static_cast<char>(16 * hex_digit(uri[i + 1]) + hex_digit(uri[i + 2]));
            i += 2;
        } else {
            decoded += uri[i];
        }
    }
    return (std::filesystem::path(gltf_path).parent_path() / decoded).lexically_normal().string();
}

}  // namespace gltf_reader

namespace {

using gltf_reader::Reader;

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
        const std::string bytes = read_input_file(
            path, "file a glTF names", static_cast<ReadLimits*>(user)->max_bytes, "--max-file-mb");
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

// tinygltf parses JSON recursively, extras and unknown extensions included: a file of deeply
// nested arrays would overflow the stack. No glTF needs more than a few levels.
void check_json_depth(const std::string& path, const std::string& bytes, size_t begin, size_t end) {
    int depth = 0;
    bool in_string = false, escaped = false;
    for (size_t i = begin; i < end && i < bytes.size(); ++i) {
        const char c = bytes[i];
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > 64) throw InputError(path, 0, "", "its JSON nests deeper than 64 levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

// The JSON's depth checked: of a .glb's JSON chunk, or of the whole text.
void check_depth_of_file(const std::string& path, const std::string& bytes) {
    if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {  // .glb: the JSON chunk
        uint32_t length = 0;
        std::memcpy(&length, bytes.data() + 12, 4);
        check_json_depth(path, bytes, 20, 20 + static_cast<size_t>(length));
    } else {
        check_json_depth(path, bytes, 0, bytes.size());
    }
}

// The model tinygltf makes of the file's bytes (.glb by its extension, else JSON text), every
// file it names read through the capped callbacks above.
tinygltf::Model parse_model(const std::string& path, const std::string& bytes, uint64_t max_bytes) {
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
    const bool ok = ext == ".glb" || ext == ".GLB"
                        ? loader.LoadBinaryFromMemory(&model, &err, &warn, data,
                                                      static_cast<unsigned int>(bytes.size()), base)
                        : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                     static_cast<unsigned int>(bytes.size()), base);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        throw InputError(path, 0, "", "cannot be read as glTF: " + (err.empty() ? warn : err));
    }
    return model;
}

// Refuses a file that requires an extension this loader does not read.
void check_required_extensions(const std::string& path, const tinygltf::Model& model) {
    for (const std::string& e : model.extensionsRequired)
        if (e != "KHR_materials_emissive_strength" && e != "KHR_materials_transmission" &&
            e != "KHR_materials_ior" && e != "KHR_lights_punctual")
            throw InputError(path, 0, "extensionsRequired",
                             "requires " + e + ", which this loader does not support");
}

// What the scene leaves out as a whole, and the files it named (buffers and images not
// embedded as data URIs).
void add_notes_and_files(const Reader& r, int degenerate, GltfScene& scene) {
    const tinygltf::Model& model = r.model();
    if (degenerate > 0)
        scene.notes.push_back("glTF: " + std::to_string(degenerate) +
                              " zero-area triangle(s) skipped");
    if (model.skins.size() > 0 || model.animations.size() > 0)
        scene.notes.push_back("glTF: skins and animations ignored (the scene as it rests)");
    for (const tinygltf::Buffer& b : model.buffers)
        if (!b.uri.empty() && b.uri.rfind("data:", 0) != 0)
            scene.files.push_back(gltf_reader::resolve_uri(r.path(), b.uri));
    for (const tinygltf::Image& i : model.images)
        if (!i.uri.empty() && i.uri.rfind("data:", 0) != 0)
            scene.files.push_back(gltf_reader::resolve_uri(r.path(), i.uri));
}

// The file read and checked, its model parsed, its materials mapped, its nodes placed.
GltfScene read_gltf(const std::string& path, uint64_t max_bytes) {
    const std::string bytes = read_input_file(path, "glTF file", max_bytes, "--max-file-mb");
    check_depth_of_file(path, bytes);
    const tinygltf::Model model = parse_model(path, bytes, max_bytes);
    check_required_extensions(path, model);
    const Reader r(model, path);
    GltfScene scene;
    for (size_t i = 0; i < model.materials.size(); ++i)
        scene.materials.push_back(gltf_reader::map_material(
            r, model.materials[i], "materials[" + std::to_string(i) + "]", scene.notes));
    const int degenerate = gltf_reader::place_nodes(r, gltf_reader::root_nodes(r), scene);
    if (scene.primitives.empty() && scene.lights.empty() && scene.directional_lights.empty())
        r.fail("meshes", "the scene has no triangles and no lights");
    add_notes_and_files(r, degenerate, scene);
    return scene;
}

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

}  // namespace lessons
