// Reading one TOML table of a scene file field by field, for the scene parser (scene_tables.h):
// typed getters with ranges, each failure an InputError naming the file, line and field, and a
// record of the fields used, so that anything left over (a typo, a field of another material
// type) is refused with a suggestion.
#pragma once

#include <toml++/toml.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "io/input_error.h"
#include "io/scene_file.h"

namespace lessons::scene_file {

// The value of a number node (integer or float) as a double.
inline double as_number(const toml::node& n) {
    if (n.is_integer()) return static_cast<double>(*n.value<int64_t>());
    return *n.value<double>();
}

// Reads the fields of one TOML table, remembering which were used, so that anything left over
// (a typo, a field of another material type) is refused with a suggestion.
class TableReader {
public:
    TableReader(const toml::table& table, const std::string& file, std::string path)
        : table_(table), file_(file), path_(std::move(path)) {}

    std::string field(std::string_view key) const {
        return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
    }
    int line_of(const toml::node& n) const { return static_cast<int>(n.source().begin.line); }
    int line() const { return line_of(table_); }
    SourceLocation where(std::string_view key) const {
        const toml::node* n = table_.get(key);
        return {file_, n ? line_of(*n) : line(), field(key)};
    }
    [[noreturn]] void fail(std::string_view key, const std::string& message) const {
        const SourceLocation w = where(key);
        throw InputError(w.file, w.line, w.field, message);
    }

    bool has(std::string_view key) const { return table_.contains(key); }

    const toml::node& require(std::string_view key) {
        const toml::node* n = table_.get(key);
        if (!n) {
            std::string message =
                "missing (required in " + (path_.empty() ? "the scene" : path_) + ")";
            // A key already read as another field (a box's min, when max is missing) is no typo.
            std::vector<std::string> present;
            for (const auto& [k, v] : table_)
                if (!used_.count(std::string(k.str()))) present.emplace_back(k.str());
            const std::string typo = closest_match(std::string(key), present);
            if (!typo.empty()) message += "; found '" + typo + "': a typo?";
            throw InputError(file_, line(), field(key), message);
        }
        used_.insert(std::string(key));
        return *n;
    }

    double number(std::string_view key) {
        const toml::node& n = require(key);
        if (!n.is_number()) fail(key, "expected a number, got " + type_name(n));
        const double v = as_number(n);
        if (!std::isfinite(v)) fail(key, "must be finite, got " + std::to_string(v));
        return v;
    }
    double number(std::string_view key, double fallback) {
        return has(key) ? number(key) : fallback;
    }
    double number_in(std::string_view key, double lo, double hi, bool lo_open, bool hi_open,
                     std::optional<double> fallback = std::nullopt) {
        if (fallback && !has(key)) return *fallback;
        const double v = number(key);
        const bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
        if (!ok) {
            std::ostringstream s;
            s << "must be in " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]")
              << ", got " << v;
            fail(key, s.str());
        }
        return v;
    }
    int integer_in(std::string_view key, int lo, int hi) {
        const toml::node& n = require(key);
        if (!n.is_integer()) fail(key, "expected an integer, got " + type_name(n));
        const int64_t v = *n.value<int64_t>();
        if (v < lo || v > hi)
            fail(key, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                          ", got " + std::to_string(v));
        return static_cast<int>(v);
    }
    std::string string(std::string_view key) {
        const toml::node& n = require(key);
        if (!n.is_string()) fail(key, "expected a string, got " + type_name(n));
        return std::string(*n.value<std::string>());
    }
    bool boolean(std::string_view key, bool fallback) {
        if (!has(key)) return fallback;
        const toml::node& n = require(key);
        if (!n.is_boolean()) fail(key, "expected true or false, got " + type_name(n));
        return *n.value<bool>();
    }

    // [x, y, z] as written in the file (double), checked finite and at most 1e9 in magnitude.
    glm::dvec3 dvec3_of(const toml::node& n, std::string_view key) const {
        const toml::array* a = n.as_array();
        if (!a || a->size() != 3)
            fail(key, "expected an array of 3 numbers, got " +
                          (a ? "an array of " + std::to_string(a->size()) : type_name(n)));
        glm::dvec3 v;
        for (int i = 0; i < 3; ++i) {
            const toml::node& c = *a->get(static_cast<size_t>(i));
            if (!c.is_number())
                fail(key, "element " + std::to_string(i) + " is " + type_name(c) +
                              ", expected a number");
            const double x = as_number(c);
            if (!std::isfinite(x))
                fail(key,
                     "element " + std::to_string(i) + " must be finite, got " + std::to_string(x));
            if (std::fabs(x) > kMaxCoordinate)
                fail(key, "element " + std::to_string(i) +
                              " is too large for single precision "
                              "geometry (|x| must be at most 1e9)");
            v[i] = x;
        }
        return v;
    }
    Vec3 vec3_of(const toml::node& n, std::string_view key) const { return Vec3(dvec3_of(n, key)); }
    glm::dvec3 dvec3(std::string_view key) { return dvec3_of(require(key), key); }
    glm::dvec3 dvec3(std::string_view key, const glm::dvec3& fallback) {
        return has(key) ? dvec3(key) : fallback;
    }
    Vec3 vec3(std::string_view key) { return vec3_of(require(key), key); }
    Vec3 vec3(std::string_view key, const Vec3& fallback) {
        return has(key) ? vec3(key) : fallback;
    }
    Vec3 nonzero_vec3(std::string_view key) {
        const Vec3 v = vec3(key);
        if (glm::dot(v, v) == 0.0f) fail(key, "must not be the zero vector");
        return v;
    }
    // A non-negative RGB value; `at_most_one` for reflectances (energy conservation).
    Color color_of(const toml::node& n, std::string_view key, bool at_most_one) const {
        const Color c = vec3_of(n, key);
        if (min_component(c) < 0.0f) fail(key, "must not be negative");
        if (at_most_one && max_component(c) > 1.0f)
            fail(key,
                 "must be at most 1 in every channel: a surface cannot reflect more light "
                 "than it receives");
        return c;
    }
    Color color(std::string_view key, bool at_most_one) {
        return color_of(require(key), key, at_most_one);
    }
    Color color(std::string_view key, bool at_most_one, const Color& fallback) {
        return has(key) ? color(key, at_most_one) : fallback;
    }

    const toml::table& table(std::string_view key) {
        const toml::node& n = require(key);
        if (!n.is_table()) fail(key, "expected a table, got " + type_name(n));
        return *n.as_table();
    }
    const toml::array& array(std::string_view key) {
        const toml::node& n = require(key);
        if (!n.is_array()) fail(key, "expected an array, got " + type_name(n));
        return *n.as_array();
    }

    // Refuses every field that was not read. `elsewhere` names fields that are valid in another
    // context (e.g. "ior" belongs to glass materials), to explain instead of just refusing.
    void reject_unknown(const std::vector<std::string>& allowed, const std::string& context,
                        const std::vector<std::pair<std::string, std::string>>& elsewhere = {}) {
        for (const auto& [key, node] : table_) {
            const std::string k(key.str());
            if (used_.count(k)) continue;
            const int l = line_of(node);
            for (const auto& [name, owner] : elsewhere)
                if (name == k)
                    throw InputError(
                        file_, l, field(k),
                        "not a field of " + context + " (it belongs to " + owner + ")");
            const std::string message =
                "unknown field in " + context + did_you_mean(k, allowed) + known_names(allowed);
            throw InputError(file_, l, field(k), message);
        }
    }

    static std::string type_name(const toml::node& n) {
        switch (n.type()) {
            case toml::node_type::string: return "a string";
            case toml::node_type::integer: return "an integer";
            case toml::node_type::floating_point: return "a number";
            case toml::node_type::boolean: return "a boolean";
            case toml::node_type::array: return "an array";
            case toml::node_type::table: return "a table";
            default: return "a date or time";
        }
    }

private:
    const toml::table& table_;
    std::string file_;
    std::string path_;
    std::set<std::string> used_;
};

}  // namespace lessons::scene_file
