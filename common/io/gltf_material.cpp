// A glTF material mapped onto the suite's (the table in docs/interop.md): glass, a conductor or
// mirror, or diffuse (with its base colour texture's file), its emission, and a note of what was
// approximated or left out.
#include <algorithm>
#include <string>
#include <vector>

#include "io/gltf_reader.h"

namespace lessons::gltf_reader {

namespace {

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

// One material being mapped: the glTF material and its factors (clamped to [0, 1]), the
// suite's material made of them, and what was taken (`mapped`) and left out (`ignored`), for
// the note.
struct Mapping {
    const Reader& r;
    const tinygltf::Material& g;
    const std::string& field;
    const tinygltf::PbrMetallicRoughness& pbr;
    Color base;
    double metallic, roughness, transmission;
    Material m;
    std::vector<std::string> mapped, ignored;

    // KHR_materials_transmission: smooth glass of KHR_materials_ior's index.
    void glass() {
        m.type = MaterialType::Glass;
        m.ior = static_cast<float>(number_in(g.extensions, "KHR_materials_ior", "ior", 1.5));
        if (!(m.ior >= 1.0f && m.ior <= 4.0f))
            r.fail(field + ".KHR_materials_ior", "ior must be in [1, 4]");
        m.transmittance = base;
        mapped.push_back("glass of ior " + fixed(m.ior) + " (KHR_materials_transmission)");
        if (transmission < 1.0)
            ignored.push_back("transmission " + fixed(transmission) + " < 1 (taken as 1)");
        if (roughness > 0.0)
            ignored.push_back("roughness " + fixed(roughness) + " (the glass is smooth)");
    }

    // A metal: GGX of alpha = roughness^2 (glTF's own mapping), a mirror below alpha 1e-4.
    void metal() {
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
        if (pbr.baseColorTexture.index >= 0)
            ignored.push_back("baseColorTexture (a metal's colour is its factor)");
    }

    // A dielectric as diffuse: the base colour, or its texture's file; no specular lobe.
    void diffuse() {
        m.type = MaterialType::Diffuse;
        m.albedo.value = base;
        bool clamp = false;
        m.albedo.image_file = texture_file(r, pbr.baseColorTexture.index, ignored, clamp);
        m.albedo.repeat = !clamp;
        if (!m.albedo.image_file.empty()) {
            mapped.push_back("diffuse, albedo from its baseColorTexture");
            if (base != Color(1.0f))
                ignored.push_back("baseColorFactor times the texture (the texture alone)");
            if (pbr.baseColorTexture.texCoord != 0)
                ignored.push_back("TEXCOORD_" + std::to_string(pbr.baseColorTexture.texCoord) +
                                  " (TEXCOORD_0 is used)");
        } else {
            mapped.push_back("diffuse");
        }
        ignored.push_back("the specular reflection of a dielectric (F0 = 0.04)");
    }

    // Emission as radiance: emissiveFactor x KHR_materials_emissive_strength.
    void emission() {
        const double strength =
            number_in(g.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
        m.emission = rgb(g.emissiveFactor, Color(0.0f)) * static_cast<float>(strength);
        if (!is_finite(m.emission) || m.emission.x < 0.0f || m.emission.y < 0.0f ||
            m.emission.z < 0.0f)
            r.fail(field + ".emissiveFactor", "emission must be finite and not negative");
        m.two_sided = g.doubleSided;
        if (m.is_emissive())
            mapped.push_back(std::string("emitting ") +
                             (g.doubleSided ? "from both sides" : "from its front"));
    }

    // The textures, alpha mode and extensions the suite does not read.
    void note_unread_fields() {
        if (g.normalTexture.index >= 0) ignored.push_back("normalTexture");
        if (g.occlusionTexture.index >= 0) ignored.push_back("occlusionTexture");
        if (g.emissiveTexture.index >= 0) ignored.push_back("emissiveTexture");
        if (pbr.metallicRoughnessTexture.index >= 0) ignored.push_back("metallicRoughnessTexture");
        if (g.alphaMode != "OPAQUE") ignored.push_back("alphaMode " + g.alphaMode);
        for (const auto& [name, value] : g.extensions)
            if (name != "KHR_materials_transmission" && name != "KHR_materials_ior" &&
                name != "KHR_materials_emissive_strength")
                ignored.push_back(name);
    }
};

}  // namespace

Material map_material(const Reader& r, const tinygltf::Material& g, const std::string& field,
                      std::vector<std::string>& notes) {
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    Mapping map{r,
                g,
                field,
                pbr,
                glm::clamp(rgb(pbr.baseColorFactor, Color(1.0f)), Color(0.0f), Color(1.0f)),
                std::clamp(pbr.metallicFactor, 0.0, 1.0),
                std::clamp(pbr.roughnessFactor, 0.0, 1.0),
                number_in(g.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0),
                {},
                {},
                {}};
    map.m.name = g.name.empty() ? field : g.name;
    if (map.transmission > 0.0)
        map.glass();
    else if (map.metallic >= 0.5)
        map.metal();
    else
        map.diffuse();
    if (map.metallic > 0.0 && map.metallic < 1.0)
        map.ignored.push_back("metallic " + fixed(map.metallic) + " between 0 and 1 (taken as " +
                              (map.metallic >= 0.5 ? "1" : "0") + ")");
    map.emission();
    map.note_unread_fields();
    notes.push_back("glTF material '" + map.m.name + "' (" + field + "): " + join(map.mapped) +
                    (map.ignored.empty() ? "" : "; ignored: " + join(map.ignored)));
    return map.m;
}

}  // namespace lessons::gltf_reader
