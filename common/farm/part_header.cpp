// A part's header: its fields as "lessons.*" text attributes, written from a PartHeader and read
// back one field at a time, each checked, in the order a merge needs them.
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "farm/part_format.h"
#include "io/input_error.h"
#include "io/scene_file.h"

namespace lessons {

namespace part_format {

namespace {

constexpr const char* kFormat = "lessons part 1";

std::string join(const std::vector<std::string>& lines) {
    std::string s;
    for (size_t i = 0; i < lines.size(); ++i) s += (i ? "\n" : "") + lines[i];
    return s;
}
std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> lines;
    if (s.empty()) return lines;
    size_t start = 0;
    for (size_t end; (end = s.find('\n', start)) != std::string::npos; start = end + 1)
        lines.push_back(s.substr(start, end - start));
    lines.push_back(s.substr(start));
    return lines;
}

std::string number(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

bool parse_range(const std::string& text, long long& a, long long& b) {
    return parse_pair(text, ':', a, b);
}

}  // namespace

// The header as name -> text: what is written as attributes, and what the checksum covers.
std::map<std::string, std::string> header_fields(const PartHeader& h) {
    return {
        {"lessons.format", kFormat},
        {"lessons.lesson", h.lesson},
        {"lessons.scene", h.scene},
        {"lessons.scene_hash", h.scene_hash},
        {"lessons.options", h.options},
        {"lessons.seed", std::to_string(h.seed)},
        {"lessons.image", std::to_string(h.image_width) + "x" + std::to_string(h.image_height)},
        {"lessons.pixels", h.pixels_text()},
        {"lessons.samples", h.samples_text()},
        {"lessons.planned", std::to_string(h.planned_end)},
        {"lessons.films", join(h.films)},
        {"lessons.seconds", number(h.seconds)},
        {"lessons.rays", std::to_string(h.rays)},
        {"lessons.threads", std::to_string(h.threads)},
        {"lessons.exposure", number(h.exposure)},
        {"lessons.notes", join(h.notes)},
        {"lessons.bias", join(h.bias)},
        {"lessons.build", h.build},
        {"lessons.cpu", h.cpu},
    };
}

namespace {

// A part's "lessons.*" attributes, read one field at a time; a field missing, or a count that is
// not one, is refused with the file and the field's name.
struct HeaderFields {
    const std::string& path;
    const std::map<std::string, std::string>& fields;

    // The field's text ("" for an optional field that is missing).
    std::string text(const char* name, bool required = true) const {
        auto it = fields.find(name);
        if (it != fields.end()) return it->second;
        if (required)
            throw InputError(path, 0, name,
                             fields.empty() ? "missing: this EXR is not a part written by a "
                                              "lesson's --samples or --pixels"
                                            : "missing from the part's header");
        return "";
    }
    // The field as a count: decimal digits only, no sign.
    unsigned long long count(const char* name) const {
        const std::string t = text(name);
        char* end = nullptr;
        errno = 0;
        const unsigned long long v = std::strtoull(t.c_str(), &end, 10);
        if (t.empty() || t[0] == '-' || *end != '\0' || errno != 0)
            throw InputError(path, 0, name, "'" + t + "' is not a count");
        return v;
    }
};

// lessons.image: the whole image's size, WIDTHxHEIGHT.
void read_image_size(const HeaderFields& f, PartHeader& h) {
    long long iw = 0, ih = 0;
    if (!parse_pair(f.text("lessons.image"), 'x', iw, ih) || iw <= 0 || ih <= 0 ||
        iw > kMaxImageSide || ih > kMaxImageSide)
        throw InputError(f.path, 0, "lessons.image",
                         "'" + f.text("lessons.image") + "' is not WIDTHxHEIGHT");
    h.image_width = static_cast<int>(iw);
    h.image_height = static_cast<int>(ih);
}

// lessons.pixels: the part's crop of the image, X0:X1,Y0:Y1.
void read_crop(const HeaderFields& f, PartHeader& h) {
    long long x0, x1, y0, y1;
    const std::string text = f.text("lessons.pixels");
    const size_t comma = text.find(',');
    if (comma == std::string::npos || !parse_range(text.substr(0, comma), x0, x1) ||
        !parse_range(text.substr(comma + 1), y0, y1) || x0 < 0 || y0 < 0 || x1 <= x0 || y1 <= y0 ||
        x1 > h.image_width || y1 > h.image_height)
        throw InputError(f.path, 0, "lessons.pixels",
                         "'" + text + "' is not a crop X0:X1,Y0:Y1 of the " +
                             f.text("lessons.image") + " image");
    h.x0 = static_cast<int>(x0);
    h.x1 = static_cast<int>(x1);
    h.y0 = static_cast<int>(y0);
    h.y1 = static_cast<int>(y1);
}

// lessons.samples: the samples A:B every pixel holds; lessons.planned: the end the run was asked
// for, at or after B (beyond it: the part was interrupted).
void read_samples(const HeaderFields& f, PartHeader& h) {
    long long a, b;
    const std::string text = f.text("lessons.samples");
    if (!parse_range(text, a, b) || a < 0 || b < a || b > (1 << 24))
        throw InputError(f.path, 0, "lessons.samples", "'" + text + "' is not a range A:B");
    h.sample_begin = static_cast<int>(a);
    h.sample_end = static_cast<int>(b);
    const unsigned long long planned = f.count("lessons.planned");
    if (planned < static_cast<unsigned long long>(h.sample_end) || planned > (1 << 24))
        throw InputError(f.path, 0, "lessons.planned",
                         "'" + f.text("lessons.planned") +
                             "' is not an end at or after the samples the part holds");
    h.planned_end = static_cast<int>(planned);
}

// lessons.films: "image" first, then the layers, each named as a file name may be.
void read_films(const HeaderFields& f, PartHeader& h) {
    h.films = split(f.text("lessons.films"));
    if (h.films.empty() || h.films[0] != "image")
        throw InputError(f.path, 0, "lessons.films", "must list 'image' first");
    for (const std::string& name : h.films)  // (they name the merge's output files)
        if (name.empty() || name.size() > 64 ||
            name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                   "0123456789_+-") != std::string::npos)
            throw InputError(f.path, 0, "lessons.films",
                             "'" + name + "' is not a film's name (letters, digits, _ + -)");
}

// The run's figures: its seconds (0 unless finite and positive), rays, threads and exposure
// (0 unless finite).
void read_run_figures(const HeaderFields& f, PartHeader& h) {
    h.seconds = std::strtod(f.text("lessons.seconds").c_str(), nullptr);
    if (!std::isfinite(h.seconds) || h.seconds < 0.0) h.seconds = 0.0;
    h.rays = f.count("lessons.rays");
    h.threads = static_cast<int>(std::min<unsigned long long>(f.count("lessons.threads"), 1 << 20));
    h.exposure = std::strtof(f.text("lessons.exposure").c_str(), nullptr);
    if (!std::isfinite(h.exposure)) h.exposure = 0.0f;
}

}  // namespace

// The header from the "lessons.*" attributes, each checked, in this order.
PartHeader header_from_fields(const std::string& path,
                              const std::map<std::string, std::string>& fields) {
    const HeaderFields f{path, fields};
    if (f.text("lessons.format") != kFormat)
        throw InputError(
            path, 0, "lessons.format",
            "is '" + f.text("lessons.format") + "', this merge reads '" + kFormat + "'");
    f.text("lessons.checksum");
    PartHeader h;
    h.lesson = f.text("lessons.lesson");
    h.scene = f.text("lessons.scene");
    h.scene_hash = f.text("lessons.scene_hash");
    h.options = f.text("lessons.options", false);
    h.seed = f.count("lessons.seed");
    read_image_size(f, h);
    read_crop(f, h);
    read_samples(f, h);
    read_films(f, h);
    h.build = f.text("lessons.build", false);
    h.cpu = f.text("lessons.cpu", false);
    read_run_figures(f, h);
    h.notes = split(f.text("lessons.notes", false));
    h.bias = split(f.text("lessons.bias", false));
    return h;
}

}  // namespace part_format

std::string PartHeader::pixels_text() const {
    return std::to_string(x0) + ":" + std::to_string(x1) + "," + std::to_string(y0) + ":" +
           std::to_string(y1);
}
std::string PartHeader::samples_text() const {
    return std::to_string(sample_begin) + ":" + std::to_string(sample_end);
}

bool parse_pair(std::string_view text, char separator, long long& a, long long& b) {
    const size_t sep = text.find(separator);
    if (sep == std::string_view::npos) return false;
    const auto number = [](std::string_view t, long long& v) {
        if (t.empty() || t.size() > 18 ||
            t.find_first_not_of("0123456789") != std::string_view::npos)
            return false;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        return r.ec == std::errc() && r.ptr == t.data() + t.size();
    };
    return number(text.substr(0, sep), a) && number(text.substr(sep + 1), b);
}

bool same_header(const PartHeader& a, const PartHeader& b) {
    return part_format::header_fields(a) == part_format::header_fields(b);
}

}  // namespace lessons
