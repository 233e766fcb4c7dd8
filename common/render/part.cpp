// Parts of a render as EXR files (see part.h).
#include "render/part.h"

#include <tinyexr.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>

#include "io/input_error.h"
#include "io/input_file.h"
#include "io/scene_file.h"

namespace lessons {

namespace {

constexpr const char* kFormat = "lessons part 1";

// The channels of one film's FilmPixel, each a 32-bit word per pixel.
const char* const kFields[] = {"sumR0", "sumR1", "sumR2", "sumR3", "sumG0", "sumG1",
                               "sumG2", "sumG3", "sumB0", "sumB1", "sumB2", "sumB3",
                               "sqR0",  "sqR1",  "sqG0",  "sqG1",  "sqB0",  "sqB1",
                               "valid", "nan",   "inf",   "clamped", "maxlum"};
constexpr int kFieldCount = sizeof kFields / sizeof kFields[0];

void to_words(const FilmPixel& p, uint32_t* w) {
    for (int c = 0; c < 3; ++c) {
        const unsigned __int128 s = static_cast<unsigned __int128>(p.sum[c]);
        for (int k = 0; k < 4; ++k) w[4 * c + k] = static_cast<uint32_t>(s >> (32 * k));
    }
    for (int c = 0; c < 3; ++c) {
        uint64_t bits;
        std::memcpy(&bits, &p.sum_squares[c], sizeof bits);
        w[12 + 2 * c] = static_cast<uint32_t>(bits);
        w[13 + 2 * c] = static_cast<uint32_t>(bits >> 32);
    }
    w[18] = p.valid;
    w[19] = p.nan;
    w[20] = p.inf;
    w[21] = p.clamped;
    std::memcpy(&w[22], &p.max_luminance, sizeof(float));
}

FilmPixel from_words(const uint32_t* w) {
    FilmPixel p;
    for (int c = 0; c < 3; ++c) {
        unsigned __int128 s = 0;
        for (int k = 0; k < 4; ++k) s |= static_cast<unsigned __int128>(w[4 * c + k]) << (32 * k);
        p.sum[c] = static_cast<__int128>(s);
    }
    for (int c = 0; c < 3; ++c) {
        const uint64_t bits = w[12 + 2 * c] | (static_cast<uint64_t>(w[13 + 2 * c]) << 32);
        std::memcpy(&p.sum_squares[c], &bits, sizeof bits);
    }
    p.valid = w[18];
    p.nan = w[19];
    p.inf = w[20];
    p.clamped = w[21];
    std::memcpy(&p.max_luminance, &w[22], sizeof(float));
    return p;
}

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
    };
}

uint64_t fnv(uint64_t h, const void* data, size_t size) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

// Over the header's fields and the merge channels (in the order of their sorted names).
std::string checksum(const std::map<std::string, std::string>& fields,
                     const std::map<std::string, const std::vector<uint32_t>*>& channels) {
    uint64_t h = 1469598103934665603ull;
    for (const auto& [name, text] : fields) {
        h = fnv(h, name.data(), name.size() + 1);
        h = fnv(h, text.data(), text.size() + 1);
    }
    for (const auto& [name, words] : channels) {
        h = fnv(h, name.data(), name.size() + 1);
        h = fnv(h, words->data(), words->size() * sizeof(uint32_t));
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

// tinyexr's structures, freed on every path.
struct LoadedExr {
    EXRHeader header;
    EXRImage image;
    bool header_parsed = false, image_loaded = false;
    LoadedExr() {
        InitEXRHeader(&header);
        InitEXRImage(&image);
    }
    ~LoadedExr() {
        if (image_loaded) FreeEXRImage(&image);
        if (header_parsed) FreeEXRHeader(&header);
    }
};

std::string exr_error(const char* err) {
    std::string msg = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    return msg;
}

// Parses "A:B" (two integers), or throws with `what`.
bool parse_range(const std::string& text, long long& a, long long& b) {
    char tail = 0;
    return std::sscanf(text.c_str(), "%lld:%lld%c", &a, &b, &tail) == 2;
}

}  // namespace

std::string PartHeader::pixels_text() const {
    return std::to_string(x0) + ":" + std::to_string(x1) + "," + std::to_string(y0) + ":" +
           std::to_string(y1);
}
std::string PartHeader::samples_text() const {
    return std::to_string(sample_begin) + ":" + std::to_string(sample_end);
}

std::string scene_files_hash(const std::string& scene_file) {
    uint64_t h = 1469598103934665603ull;
    std::vector<std::string> files{scene_file};
    try {
        files = scene_input_files(parse_scene_file(scene_file));
    } catch (const std::exception&) {
        // (the scene was loaded already; this cannot fail but for a race: the file alone names it)
    }
    for (const std::string& f : files) {
        const uint64_t fh = file_hash(f);
        h = fnv(h, &fh, sizeof fh);
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

void write_part(const std::string& path, const PartHeader& h, std::span<const Film> films) {
    const int w = h.width(), ht = h.height();
    const size_t n = static_cast<size_t>(w) * ht;
    if (films.size() != h.films.size())
        throw std::logic_error("write_part: as many films as film names are needed");
    for (const Film& f : films)
        if (f.width() != w || f.height() != ht)
            throw std::logic_error("write_part: a film is not of the crop's size");

    // The merge channels, by name.
    std::map<std::string, std::vector<uint32_t>> words;
    for (size_t f = 0; f < films.size(); ++f) {
        std::vector<std::vector<uint32_t>*> field(kFieldCount);
        for (int k = 0; k < kFieldCount; ++k) {
            std::vector<uint32_t>& v = words[h.films[f] + "." + kFields[k]];
            v.resize(n);
            field[k] = &v;
        }
        uint32_t pixel_words[kFieldCount];
        const std::span<const FilmPixel> pixels = films[f].pixels();
        for (size_t i = 0; i < n; ++i) {
            to_words(pixels[i], pixel_words);
            for (int k = 0; k < kFieldCount; ++k) (*field[k])[i] = pixel_words[k];
        }
    }
    std::map<std::string, const std::vector<uint32_t>*> merge_channels;
    for (const auto& [name, v] : words) merge_channels[name] = &v;
    std::map<std::string, std::string> fields;
    for (auto& [name, text] : header_fields(h))  // (tinyexr reads no empty attribute)
        if (!text.empty()) fields[name] = text;
    const std::string sum = checksum(fields, merge_channels);
    fields["lessons.checksum"] = sum;

    // The mean image, for viewers, as B, G, R (channels are listed in name order).
    const Image mean = films[0].mean();
    std::vector<float> rgb[3];
    for (int c = 0; c < 3; ++c) {
        rgb[c].resize(n);
        for (size_t i = 0; i < n; ++i) rgb[c][i] = mean.pixels[i][c];
    }
    struct Channel {
        std::string name;
        int type;
        unsigned char* data;
    };
    std::vector<Channel> channels;
    const char* colour_names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
        channels.push_back({colour_names[c], TINYEXR_PIXELTYPE_FLOAT,
                            reinterpret_cast<unsigned char*>(rgb[c].data())});
    for (auto& [name, v] : words)
        channels.push_back({name, TINYEXR_PIXELTYPE_UINT, reinterpret_cast<unsigned char*>(v.data())});
    std::sort(channels.begin(), channels.end(),
              [](const Channel& a, const Channel& b) { return a.name < b.name; });

    std::vector<EXRChannelInfo> infos(channels.size());
    std::vector<int> types(channels.size());
    std::vector<unsigned char*> data(channels.size());
    for (size_t c = 0; c < channels.size(); ++c) {
        std::memset(&infos[c], 0, sizeof infos[c]);
        std::strncpy(infos[c].name, channels[c].name.c_str(), 255);
        types[c] = channels[c].type;
        data[c] = channels[c].data;
    }
    std::vector<EXRAttribute> attributes;
    for (auto& [name, text] : fields) {
        EXRAttribute a;
        std::memset(&a, 0, sizeof a);
        std::strncpy(a.name, name.c_str(), 255);
        std::strncpy(a.type, "string", 255);
        a.value = reinterpret_cast<unsigned char*>(text.data());
        a.size = static_cast<int>(text.size());
        attributes.push_back(a);
    }

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = static_cast<int>(channels.size());
    header.channels = infos.data();
    header.pixel_types = types.data();
    header.requested_pixel_types = types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    header.num_custom_attributes = static_cast<int>(attributes.size());
    header.custom_attributes = attributes.data();
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = header.num_channels;
    image.images = data.data();
    image.width = w;
    image.height = ht;

    write_atomically(path, [&](const std::string& tmp) {
        // Check that the file can be created first (as write_exr does).
        if (std::FILE* f = std::fopen(tmp.c_str(), "wb"))
            std::fclose(f);
        else
            throw std::runtime_error(path + ": cannot write EXR: " + std::strerror(errno));
        const char* err = nullptr;
        if (SaveEXRImageToFile(&image, &header, tmp.c_str(), &err) != TINYEXR_SUCCESS)
            throw std::runtime_error(path + ": cannot write EXR: " + exr_error(err));
    });
}

PartFile read_part(const std::string& path, bool with_pixels) {
    check_input_file(path, "part EXR", ~uint64_t{0}, "");
    LoadedExr exr;
    EXRVersion version;
    if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS)
        throw InputError(path, 0, "", "is not an EXR file");
    if (version.multipart || version.non_image || version.tiled)
        throw InputError(path, 0, "", "is not a part written by a lesson (--samples/--pixels)");
    const char* err = nullptr;
    if (ParseEXRHeaderFromFile(&exr.header, &version, path.c_str(), &err) != TINYEXR_SUCCESS)
        throw InputError(path, 0, "", "cannot read the EXR header: " + exr_error(err));
    exr.header_parsed = true;

    std::map<std::string, std::string> fields;
    for (int i = 0; i < exr.header.num_custom_attributes; ++i) {
        const EXRAttribute& a = exr.header.custom_attributes[i];
        if (std::strncmp(a.name, "lessons.", 8) != 0) continue;
        fields[a.name] = std::string(reinterpret_cast<const char*>(a.value), a.size);
    }
    const auto field = [&](const char* name, bool required = true) -> std::string {
        auto it = fields.find(name);
        if (it == fields.end()) {
            if (required)
                throw InputError(path, 0, name,
                                 fields.empty() ? "missing: this EXR is not a part written by a "
                                                  "lesson's --samples or --pixels"
                                                : "missing from the part's header");
            return "";
        }
        return it->second;
    };
    if (field("lessons.format") != kFormat)
        throw InputError(path, 0, "lessons.format",
                         "is '" + field("lessons.format") + "', this merge reads '" + kFormat + "'");
    const auto integer = [&](const char* name) -> long long {
        const std::string text = field(name);
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || errno != 0 || v < 0)
            throw InputError(path, 0, name, "'" + text + "' is not a count");
        return v;
    };

    PartFile part;
    part.path = path;
    PartHeader& h = part.header;
    h.lesson = field("lessons.lesson");
    h.scene = field("lessons.scene");
    h.scene_hash = field("lessons.scene_hash");
    h.options = field("lessons.options", false);
    h.seed = std::strtoull(field("lessons.seed").c_str(), nullptr, 10);
    {
        int iw = 0, ih = 0;
        char tail = 0;
        if (std::sscanf(field("lessons.image").c_str(), "%dx%d%c", &iw, &ih, &tail) != 2 ||
            iw <= 0 || ih <= 0)
            throw InputError(path, 0, "lessons.image", "'" + field("lessons.image") +
                                                           "' is not WIDTHxHEIGHT");
        h.image_width = iw;
        h.image_height = ih;
    }
    {
        long long x0, x1, y0, y1;
        const std::string text = field("lessons.pixels");
        const size_t comma = text.find(',');
        if (comma == std::string::npos || !parse_range(text.substr(0, comma), x0, x1) ||
            !parse_range(text.substr(comma + 1), y0, y1) || x0 < 0 || y0 < 0 || x1 <= x0 ||
            y1 <= y0 || x1 > h.image_width || y1 > h.image_height)
            throw InputError(path, 0, "lessons.pixels",
                             "'" + text + "' is not a crop X0:X1,Y0:Y1 of the " +
                                 field("lessons.image") + " image");
        h.x0 = static_cast<int>(x0);
        h.x1 = static_cast<int>(x1);
        h.y0 = static_cast<int>(y0);
        h.y1 = static_cast<int>(y1);
    }
    {
        long long a, b;
        const std::string text = field("lessons.samples");
        if (!parse_range(text, a, b) || a < 0 || b < a || b > (1 << 24))
            throw InputError(path, 0, "lessons.samples", "'" + text + "' is not a range A:B");
        h.sample_begin = static_cast<int>(a);
        h.sample_end = static_cast<int>(b);
    }
    h.planned_end = static_cast<int>(integer("lessons.planned"));
    if (h.planned_end < h.sample_end)
        throw InputError(path, 0, "lessons.planned", "ends before the samples the part holds");
    h.films = split(field("lessons.films"));
    if (h.films.empty() || h.films[0] != "image")
        throw InputError(path, 0, "lessons.films", "must list 'image' first");
    h.seconds = std::strtod(field("lessons.seconds").c_str(), nullptr);
    h.rays = static_cast<uint64_t>(integer("lessons.rays"));
    h.threads = static_cast<int>(integer("lessons.threads"));
    h.exposure = std::strtof(field("lessons.exposure").c_str(), nullptr);
    h.notes = split(field("lessons.notes", false));
    h.bias = split(field("lessons.bias", false));
    const std::string stored_sum = field("lessons.checksum");

    if (exr.header.data_window.max_x - exr.header.data_window.min_x + 1 != h.width() ||
        exr.header.data_window.max_y - exr.header.data_window.min_y + 1 != h.height())
        throw InputError(path, 0, "lessons.pixels",
                         "the image in the file is not of the crop's size " + h.pixels_text());
    std::map<std::string, int> channel_index;
    for (int c = 0; c < exr.header.num_channels; ++c) {
        channel_index[exr.header.channels[c].name] = c;
        exr.header.requested_pixel_types[c] = exr.header.pixel_types[c];
    }
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            auto it = channel_index.find(name);
            if (it == channel_index.end())
                throw InputError(path, 0, name, "channel missing: the part is incomplete");
            if (exr.header.pixel_types[it->second] != TINYEXR_PIXELTYPE_UINT)
                throw InputError(path, 0, name, "channel is not of 32-bit unsigned integers");
        }
    if (!with_pixels) return part;
    if (LoadEXRImageFromFile(&exr.image, &exr.header, path.c_str(), &err) != TINYEXR_SUCCESS)
        throw InputError(path, 0, "",
                         "cannot read the part's pixels (truncated or damaged?): " +
                             exr_error(err));
    exr.image_loaded = true;
    if (exr.image.images == nullptr || exr.image.width != h.width() ||
        exr.image.height != h.height())
        throw InputError(path, 0, "", "the part's pixels are not scanlines of the crop's size");

    const size_t n = static_cast<size_t>(h.width()) * h.height();
    std::map<std::string, std::vector<uint32_t>> words;
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            const uint32_t* src =
                reinterpret_cast<const uint32_t*>(exr.image.images[channel_index[name]]);
            words[name].assign(src, src + n);
        }
    std::map<std::string, const std::vector<uint32_t>*> merge_channels;
    for (const auto& [name, v] : words) merge_channels[name] = &v;
    fields.erase("lessons.checksum");
    if (checksum(fields, merge_channels) != stored_sum)
        throw InputError(path, 0, "lessons.checksum",
                         "does not match the part's header and pixels: the file is damaged or "
                         "truncated (render the part again)");

    for (const std::string& film : h.films) {
        Film f(h.width(), h.height());
        std::vector<const uint32_t*> src(kFieldCount);
        for (int k = 0; k < kFieldCount; ++k) src[k] = words[film + "." + kFields[k]].data();
        uint32_t pixel_words[kFieldCount];
        const std::span<FilmPixel> pixels = f.pixels();
        for (size_t i = 0; i < n; ++i) {
            for (int k = 0; k < kFieldCount; ++k) pixel_words[k] = src[k][i];
            pixels[i] = from_words(pixel_words);
        }
        part.films.push_back(std::move(f));
    }
    return part;
}

}  // namespace lessons
