// Parts of a render as EXR files (see part.h).
#include "render/part.h"

#include <tinyexr.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>

#include "io/image.h"
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
        {"lessons.build", h.build},
        {"lessons.cpu", h.cpu},
    };
}


// Over the header's fields and the merge channels (in the order of their names).
std::string checksum(const std::map<std::string, std::string>& fields,
                     const std::map<std::string, std::vector<uint32_t>>& channels) {
    uint64_t h = kFnvStart;
    for (const auto& [name, text] : fields) {
        h = fnv1a(h, name.data(), name.size() + 1);
        h = fnv1a(h, text.data(), text.size() + 1);
    }
    for (const auto& [name, words] : channels) {
        h = fnv1a(h, name.data(), name.size() + 1);
        h = fnv1a(h, words.data(), words.size() * sizeof(uint32_t));
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

std::string exr_error(const char* err) {
    std::string msg = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    return msg;
}

bool parse_range(const std::string& text, long long& a, long long& b) {
    return parse_pair(text, ':', a, b);
}

// ---- Writing ----

// Every film's FilmPixels as 32-bit words, one channel per field, by channel name.
using ChannelWords = std::map<std::string, std::vector<uint32_t>>;

ChannelWords merge_channels(const PartHeader& h, std::span<const Film> films) {
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    ChannelWords words;
    for (size_t f = 0; f < films.size(); ++f) {
        std::vector<std::vector<uint32_t>*> field(kFieldCount);
        for (int k = 0; k < kFieldCount; ++k) {
            field[k] = &words[h.films[f] + "." + kFields[k]];
            field[k]->resize(n);
        }
        uint32_t pixel_words[kFieldCount];
        const std::span<const FilmPixel> pixels = films[f].pixels();
        for (size_t i = 0; i < n; ++i) {
            to_words(pixels[i], pixel_words);
            for (int k = 0; k < kFieldCount; ++k) (*field[k])[i] = pixel_words[k];
        }
    }
    return words;
}

// Writes the mean image (R, G, B floats), the merge channels and the string attributes as a
// ZIP-compressed scanline EXR, atomically; channels in name order, as EXR lists them.
void save_exr(const std::string& path, int width, int height, const Image& mean,
              const ChannelWords& words, const std::map<std::string, std::string>& fields) {
    const size_t n = static_cast<size_t>(width) * height;
    std::vector<float> rgb[3];
    for (int c = 0; c < 3; ++c) {
        rgb[c].resize(n);
        for (size_t i = 0; i < n; ++i) rgb[c][i] = mean.pixels[i][c];
    }
    struct Channel {
        std::string name;
        int type;
        const void* data;
    };
    std::vector<Channel> channels{{"R", TINYEXR_PIXELTYPE_FLOAT, rgb[0].data()},
                                  {"G", TINYEXR_PIXELTYPE_FLOAT, rgb[1].data()},
                                  {"B", TINYEXR_PIXELTYPE_FLOAT, rgb[2].data()}};
    for (const auto& [name, v] : words) channels.push_back({name, TINYEXR_PIXELTYPE_UINT, v.data()});
    std::sort(channels.begin(), channels.end(),
              [](const Channel& a, const Channel& b) { return a.name < b.name; });

    std::vector<EXRChannelInfo> infos(channels.size());
    std::vector<int> types(channels.size());
    std::vector<unsigned char*> data(channels.size());
    for (size_t c = 0; c < channels.size(); ++c) {
        std::memset(&infos[c], 0, sizeof infos[c]);
        std::strncpy(infos[c].name, channels[c].name.c_str(), 255);
        types[c] = channels[c].type;
        // (tinyexr only reads the pixels it is given)
        data[c] = static_cast<unsigned char*>(const_cast<void*>(channels[c].data));
    }
    std::vector<std::string> texts;
    for (const auto& [name, text] : fields) texts.push_back(text);
    std::vector<EXRAttribute> attributes;
    size_t t = 0;
    for (const auto& [name, text] : fields) {
        EXRAttribute a;
        std::memset(&a, 0, sizeof a);
        std::strncpy(a.name, name.c_str(), 255);
        std::strncpy(a.type, "string", 255);
        a.value = reinterpret_cast<unsigned char*>(texts[t].data());
        a.size = static_cast<int>(texts[t].size());
        ++t;
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
    image.width = width;
    image.height = height;
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

// ---- Reading ----

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
    LoadedExr(const LoadedExr&) = delete;
    LoadedExr& operator=(const LoadedExr&) = delete;
};

// Parses the EXR's version and header.
void open_exr(const std::string& path, LoadedExr& exr) {
    EXRVersion version;
    if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS)
        throw InputError(path, 0, "", "is not an EXR file");
    if (version.multipart || version.non_image || version.tiled)
        throw InputError(path, 0, "", "is not a part written by a lesson (--samples/--pixels)");
    check_exr_header(path);  // (what tinyexr would abort on)
    const char* err = nullptr;
    const int status = ParseEXRHeaderFromFile(&exr.header, &version, path.c_str(), &err);
    exr.header_parsed = true;  // (tinyexr fills the header even when it fails: free it)
    if (status != TINYEXR_SUCCESS)
        throw InputError(path, 0, "", "cannot read the EXR header: " + exr_error(err));
}

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

// Every merge channel the header's films need is there, of 32-bit unsigned integers (and every
// channel's type is read as it is stored); the channels' indices by name.
std::map<std::string, int> check_channels(const std::string& path, LoadedExr& exr,
                                          const PartHeader& h) {
    std::map<std::string, int> index;
    for (int c = 0; c < exr.header.num_channels; ++c) {
        index[exr.header.channels[c].name] = c;
        exr.header.requested_pixel_types[c] = exr.header.pixel_types[c];
    }
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            auto it = index.find(name);
            if (it == index.end())
                throw InputError(path, 0, name, "channel missing: the part is incomplete");
            if (exr.header.pixel_types[it->second] != TINYEXR_PIXELTYPE_UINT)
                throw InputError(path, 0, name, "channel is not of 32-bit unsigned integers");
        }
    return index;
}

// The pixels of the merge channels.
ChannelWords load_merge_channels(const std::string& path, LoadedExr& exr, const PartHeader& h,
                                 const std::map<std::string, int>& index) {
    const char* err = nullptr;
    // (When decoding fails, tinyexr 1.0.1 frees the image's channel list but not its channels:
    // they leak, in a merge that then exits: tests/lsan.supp.)
    if (LoadEXRImageFromFile(&exr.image, &exr.header, path.c_str(), &err) != TINYEXR_SUCCESS)
        throw InputError(path, 0, "",
                         "cannot read the part's pixels (truncated or damaged?): " +
                             exr_error(err));
    exr.image_loaded = true;
    if (exr.image.images == nullptr || exr.image.width != h.width() ||
        exr.image.height != h.height())
        throw InputError(path, 0, "", "the part's pixels are not scanlines of the crop's size");
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    ChannelWords words;
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            const unsigned char* src = exr.image.images[index.at(name)];
            if (src == nullptr) throw InputError(path, 0, name, "channel has no pixels");
            std::vector<uint32_t>& v = words[name];
            v.resize(n);
            std::memcpy(v.data(), src, n * sizeof(uint32_t));
        }
    return words;
}

// The films; each pixel checked against what a run can hold, so that sums never overflow.
std::vector<Film> films_from_words(const std::string& path, const PartHeader& h,
                                   const ChannelWords& words) {
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    const uint32_t samples = static_cast<uint32_t>(h.sample_end - h.sample_begin);
    std::vector<Film> films;
    for (const std::string& film : h.films) {
        Film f(h.width(), h.height());
        std::vector<const uint32_t*> src(kFieldCount);
        for (int k = 0; k < kFieldCount; ++k) src[k] = words.at(film + "." + kFields[k]).data();
        uint32_t pixel_words[kFieldCount];
        const std::span<FilmPixel> pixels = f.pixels();
        for (size_t i = 0; i < n; ++i) {
            for (int k = 0; k < kFieldCount; ++k) pixel_words[k] = src[k][i];
            pixels[i] = from_words(pixel_words);
            // Each valid sample's channel is below 2^54, i.e. 2^102 units of 2^-48.
            const FilmPixel& p = pixels[i];
            const __int128 bound = static_cast<__int128>(p.valid) << 102;
            bool sound = p.valid <= samples;
            for (int c = 0; c < 3; ++c) sound = sound && p.sum[c] <= bound && -p.sum[c] <= bound;
            if (!sound)
                throw InputError(path, 0, film + ".valid",
                                 "pixel " + std::to_string(i) + " holds more than its " +
                                     std::to_string(samples) + " samples can: the part is damaged");
        }
        films.push_back(std::move(f));
    }
    return films;
}

}  // namespace

std::string PartHeader::pixels_text() const {
    return std::to_string(x0) + ":" + std::to_string(x1) + "," + std::to_string(y0) + ":" +
           std::to_string(y1);
}
std::string PartHeader::samples_text() const {
    return std::to_string(sample_begin) + ":" + std::to_string(sample_end);
}

std::string scene_files_hash(const Scene& scene, const InputLimits& limits) {
    uint64_t h = kFnvStart;
    for (const std::string& f : scene.input_files) {
        check_input_file(f, "file the scene names", limits.file_bytes(), "--max-file-mb");
        std::ifstream in(f, std::ios::binary);
        if (!in) throw InputError(f, 0, "", "cannot be read (permissions?)");
        const uint64_t fh = file_hash(f);
        h = fnv1a(h, &fh, sizeof fh);
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

std::string this_build() {
    const uint64_t h = file_hash("/proc/self/exe");
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

std::string this_cpu() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            return colon == std::string::npos ? line : line.substr(line.find_first_not_of(" ", colon + 1));
        }
    return "unknown";
}

bool parse_pair(std::string_view text, char separator, long long& a, long long& b) {
    const size_t sep = text.find(separator);
    if (sep == std::string_view::npos) return false;
    const auto number = [](std::string_view t, long long& v) {
        if (t.empty() || t.size() > 18 || t.find_first_not_of("0123456789") != std::string_view::npos)
            return false;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        return r.ec == std::errc() && r.ptr == t.data() + t.size();
    };
    return number(text.substr(0, sep), a) && number(text.substr(sep + 1), b);
}

bool same_header(const PartHeader& a, const PartHeader& b) {
    return header_fields(a) == header_fields(b);
}

void write_part(const std::string& path, const PartHeader& h, std::span<const Film> films) {
    if (films.size() != h.films.size())
        throw std::logic_error("write_part: as many films as film names are needed");
    for (const Film& f : films)
        if (f.width() != h.width() || f.height() != h.height())
            throw std::logic_error("write_part: a film is not of the crop's size");
    const ChannelWords words = merge_channels(h, films);
    std::map<std::string, std::string> fields;
    for (auto& [name, text] : header_fields(h))  // (tinyexr reads no empty attribute)
        if (!text.empty()) fields[name] = text;
    fields["lessons.checksum"] = checksum(fields, words);
    save_exr(path, h.width(), h.height(), films[0].mean(), words, fields);
}

PartFile read_part(const std::string& path, bool with_pixels) {
    check_input_file(path, "part EXR", ~uint64_t{0}, "");
    LoadedExr exr;
    open_exr(path, exr);
    std::map<std::string, std::string> fields;
    for (int i = 0; i < exr.header.num_custom_attributes; ++i) {
        const EXRAttribute& a = exr.header.custom_attributes[i];
        if (std::strncmp(a.name, "lessons.", 8) != 0 || a.value == nullptr || a.size < 0)
            continue;
        fields[a.name] = std::string(reinterpret_cast<const char*>(a.value), a.size);
    }
    PartFile part;
    part.path = path;
    part.header = header_from_fields(path, fields);
    const PartHeader& h = part.header;
    const EXRBox2i& window = exr.header.data_window;
    if (static_cast<int64_t>(window.max_x) - window.min_x + 1 != h.width() ||
        static_cast<int64_t>(window.max_y) - window.min_y + 1 != h.height())
        throw InputError(path, 0, "lessons.pixels",
                         "the image in the file is not of the crop's size " + h.pixels_text());
    const std::map<std::string, int> channel_index = check_channels(path, exr, h);
    if (!with_pixels) return part;
    // A lesson writes ZIP; refusing the other codecs keeps tinyexr's less tried decoders (whose
    // faults are asserts that abort) away from damaged parts.
    const int compression = exr.header.compression_type;
    if (compression != TINYEXR_COMPRESSIONTYPE_ZIP && compression != TINYEXR_COMPRESSIONTYPE_ZIPS &&
        compression != TINYEXR_COMPRESSIONTYPE_NONE)
        throw InputError(path, 0, "compression",
                         "is codec " + std::to_string(compression) +
                             ": a lesson writes parts with ZIP (" +
                             std::to_string(TINYEXR_COMPRESSIONTYPE_ZIP) + ")");

    const ChannelWords words = load_merge_channels(path, exr, h, channel_index);
    const std::string stored_sum = fields.at("lessons.checksum");
    fields.erase("lessons.checksum");
    if (checksum(fields, words) != stored_sum)
        throw InputError(path, 0, "lessons.checksum",
                         "does not match the part's header and pixels: the file is damaged or "
                         "truncated (render the part again)");
    part.films = films_from_words(path, h, words);
    return part;
}

}  // namespace lessons
