// The [materials.NAME] tables of a scene file: each material's type and the fields it owns, its
// albedo a colour, a checker or an image texture (docs/scene-format.md).
#include <toml++/toml.h>

#include <filesystem>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/scene_tables.h"

namespace lessons::scene_file {

namespace {

// albedo = { texture = "FILE", wrap = "repeat" | "clamp", scale = s | [su, sv] }: the file
// resolved against the scene file's folder, read when the scene is built.
ColorTexture parse_texture(TableReader& t, const std::string& scene_file) {
    ColorTexture tex;
    const std::filesystem::path rel = t.string("texture");
    if (rel.empty()) t.fail("texture", "must name an image file (PNG, JPEG or EXR)");
    tex.image_file =
        (rel.is_absolute() ? rel : std::filesystem::path(scene_file).parent_path() / rel)
            .lexically_normal()
            .string();
    if (t.has("wrap")) {
        const std::string wrap = t.string("wrap");
        if (wrap != "repeat" && wrap != "clamp")
            t.fail("wrap",
                   "must be \"repeat\" (tile the image) or \"clamp\" (extend its edges), "
                   "got '" +
                       wrap + "'");
        tex.repeat = wrap == "repeat";
    }
    if (t.has("scale")) {
        if (t.require("scale").is_number()) {
            tex.scale = Vec2(static_cast<float>(t.number_in("scale", 0.0, 1e6, true, false)));
        } else {
            const toml::array& a = t.array("scale");
            if (a.size() != 2 || !a.get(0)->is_number() || !a.get(1)->is_number())
                t.fail("scale", "expected a number or [su, sv]");
            for (int i = 0; i < 2; ++i) {
                const double v = as_number(*a.get(static_cast<size_t>(i)));
                if (!(v > 0.0 && v <= 1e6)) t.fail("scale", "must be in (0, 1e6]");
                tex.scale[i] = static_cast<float>(v);
            }
        }
    }
    t.reject_unknown({"texture", "wrap", "scale"}, "an image texture");
    return tex;
}

ColorTexture parse_albedo(TableReader& r, std::string_view key) {
    const toml::node& n = r.require(key);
    ColorTexture tex;
    if (!n.is_table()) {
        tex.value = r.color_of(n, key, true);
        return tex;
    }
    TableReader checker(*n.as_table(), r.where(key).file, r.field(key));
    if (checker.has("texture")) return parse_texture(checker, r.where(key).file);
    const toml::array& colors = checker.array("checker");
    if (colors.size() != 2)
        checker.fail("checker",
                     "expected two colours [[even], [odd]], got " + std::to_string(colors.size()));
    tex.checker = true;
    tex.value = checker.color_of(*colors.get(0), "checker", true);
    tex.odd = checker.color_of(*colors.get(1), "checker", true);
    const toml::array& cells = checker.array("cells");
    if (cells.size() != 2 || !cells.get(0)->is_integer() || !cells.get(1)->is_integer())
        checker.fail("cells", "expected two integers [cells along u, cells along v]");
    for (int i = 0; i < 2; ++i) {
        const int64_t c = *cells.get(static_cast<size_t>(i))->value<int64_t>();
        if (c < 1 || c > 100000) checker.fail("cells", "must be between 1 and 100000");
        tex.cells[i] = static_cast<float>(c);
    }
    checker.reject_unknown({"checker", "cells"}, "a checker albedo (or give texture = FILE)");
    return tex;
}

const std::vector<std::pair<std::string, std::string>> kMaterialFieldOwners = {
    {"albedo", "diffuse and glossy materials"},
    {"specular", "glossy and conductor materials"},
    {"roughness", "glossy and conductor materials"},
    {"reflectance", "mirror materials"},
    {"ior", "glass materials"},
    {"transmittance", "glass materials"}};

}  // namespace

MaterialDescription parse_material(const toml::table& t, const std::string& file,
                                   const std::string& name) {
    TableReader r(t, file, "materials." + name);
    MaterialDescription d;
    d.where = {file, r.line(), "materials." + name};
    Material& m = d.material;
    m.name = name;
    const std::string type = r.string("type");
    m.emission = r.color("emission", false, Color(0.0f));
    m.two_sided = r.boolean("two_sided", false);
    std::vector<std::string> allowed = {"type", "emission", "two_sided"};
    if (type == "diffuse") {
        m.type = MaterialType::Diffuse;
        // An emitter may leave its albedo out (it reflects nothing); any other surface must say.
        if (r.has("albedo") || !m.is_emissive()) m.albedo = parse_albedo(r, "albedo");
        d.albedo_where = r.where("albedo");
        allowed.push_back("albedo");
    } else if (type == "glossy") {
        m.type = MaterialType::Glossy;
        if (r.has("albedo")) m.albedo = parse_albedo(r, "albedo");
        d.albedo_where = r.where("albedo");
        m.specular = r.color("specular", true, Color(1.0f));
        m.roughness = static_cast<float>(r.number_in("roughness", 0.0, 1.0, true, false));
        // Energy conservation: the diffuse base and the lobe share what the surface receives.
        const Color base = glm::max(m.albedo.value, m.albedo.checker ? m.albedo.odd : Color(0.0f));
        if (max_component(base + m.specular) > 1.0f)
            r.fail(r.has("specular") ? "specular" : "albedo",
                   "albedo + specular must be at most 1 in every channel (a surface cannot "
                   "reflect more light than it receives); lower specular (default 1)");
        allowed.insert(allowed.end(), {"albedo", "specular", "roughness"});
    } else if (type == "conductor") {
        m.type = MaterialType::Conductor;
        m.specular = r.color("specular", true);
        m.roughness = static_cast<float>(r.number_in("roughness", 0.0, 1.0, true, false));
        allowed.insert(allowed.end(), {"specular", "roughness"});
    } else if (type == "mirror") {
        m.type = MaterialType::Mirror;
        m.reflectance = r.color("reflectance", true, Color(1.0f));
        allowed.push_back("reflectance");
    } else if (type == "glass") {
        m.type = MaterialType::Glass;
        m.ior = static_cast<float>(r.number_in("ior", 0.0, 10.0, true, false, 1.5));
        m.transmittance = r.color("transmittance", true, Color(1.0f));
        allowed.insert(allowed.end(), {"ior", "transmittance"});
    } else {
        const std::vector<std::string> types = {"diffuse", "glossy", "conductor", "mirror",
                                                "glass"};
        r.fail("type", "unknown material type '" + type + "'" + did_you_mean(type, types) +
                           known_names(types));
    }
    r.reject_unknown(allowed, "a " + type + " material", kMaterialFieldOwners);
    return d;
}

}  // namespace lessons::scene_file
