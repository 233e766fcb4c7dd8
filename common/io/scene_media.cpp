// The [media.NAME] tables of a scene file: each medium's type and coefficients
// (docs/scene-format.md, "Media").
#include <toml++/toml.h>

#include <cmath>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/scene_tables.h"

namespace lessons::scene_file {

namespace {

// The most a coefficient may be, per unit length: light would not get a billionth of a unit far.
constexpr double kMostCoefficient = 1e9;
// Below this a coefficient is 0: a free flight of 1 / 1e-30 units is a vacuum's, and smaller
// ones would overflow the distance sampled.
constexpr double kLeastCoefficient = 1e-30;
// The most asymmetric phase function read: beyond, the lobe is narrower than single precision
// resolves near its peak.
constexpr double kMostAsymmetry = 0.999;

// [r, g, b], each a rate per unit length in [0, 1e9] (default 0).
Color coefficient(TableReader& r, std::string_view key) {
    if (!r.has(key)) return Color(0.0f);
    const toml::array& a = r.array(key);
    const std::string shape = "expected [r, g, b], an array of 3 numbers (per unit length)";
    if (a.size() != 3) r.fail(key, shape);
    Color c(0.0f);
    for (size_t i = 0; i < 3; ++i) {
        const toml::node& n = *a.get(i);
        if (!n.is_number()) r.fail(key, shape);
        const double v = as_number(n);
        if (!std::isfinite(v)) r.fail(key, "must be finite in every channel");
        if (v < 0.0) r.fail(key, "must not be negative");
        if (v > kMostCoefficient)
            r.fail(key, "must be at most 1e9 per unit length in every channel");
        c[static_cast<int>(i)] = v < kLeastCoefficient ? 0.0f : static_cast<float>(v);
    }
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
        r.fail("sigma_s",
               "missing: a medium needs sigma_a (absorption) or sigma_s (scattering), "
               "[r, g, b] per unit length");
    m.sigma_a = coefficient(r, "sigma_a");
    m.sigma_s = coefficient(r, "sigma_s");
    m.g = static_cast<float>(r.number_in("g", -kMostAsymmetry, kMostAsymmetry, false, false, 0.0));
    r.reject_unknown({"type", "sigma_a", "sigma_s", "g"}, "a homogeneous medium");
    return d;
}

}  // namespace lessons::scene_file
