// The [media.NAME] tables of a scene file: each medium's type and coefficients
// (docs/scene-format.md, "Media").
#include <toml++/toml.h>

#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/scene_tables.h"

namespace lessons::scene_file {

namespace {

// The most a coefficient may be, per unit length: light would not get a billionth of a unit far.
constexpr double kMostCoefficient = 1e9;

Color coefficient(TableReader& r, std::string_view key) {
    const Color c = r.color(key, false, Color(0.0f));
    if (max_component(c) > kMostCoefficient)
        r.fail(key, "must be at most 1e9 per unit length in every channel");
    return c;
}

}  // namespace

MediumDescription parse_medium(const toml::table& t, const std::string& file,
                               const std::string& name) {
    TableReader r(t, file, "media." + name);
    MediumDescription d;
    d.where = {file, r.line(), "media." + name};
    Medium& m = d.medium;
    m.name = name;
    const std::string type = r.string("type");
    const std::vector<std::string> types = {"homogeneous"};
    if (type != "homogeneous")
        r.fail("type", "unknown medium type '" + type + "'" + did_you_mean(type, types) +
                           known_names(types));
    if (!r.has("sigma_a") && !r.has("sigma_s"))
        r.fail("sigma_s", "missing: a medium needs sigma_a (absorption) or sigma_s (scattering), "
                          "[r, g, b] per unit length");
    m.sigma_a = coefficient(r, "sigma_a");
    m.sigma_s = coefficient(r, "sigma_s");
    m.g = static_cast<float>(r.number_in("g", -1.0, 1.0, true, true, 0.0));
    r.reject_unknown({"type", "sigma_a", "sigma_s", "g"}, "a homogeneous medium");
    return d;
}

}  // namespace lessons::scene_file
