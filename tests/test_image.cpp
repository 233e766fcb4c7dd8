// Images: EXR through OpenEXR (every codec, pixel type and layout read; damaged and lying files
// refused; maps in every codec render alike), the sRGB curve, atomic writes; Radiance .hdr input.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "02_whitted/whitted.h"
#include "exr_test_files.h"
#include "farm/part.h"
#include "io/exr_file.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/scene_file.h"
#include "render/film.h"
#include "render/progressive.h"

using namespace lessons;

namespace {
std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("lessons_test_" + name)).string();
}
}  // namespace

TEST(Image, ExrRoundTripIsExactInFloat) {
    Image image(7, 5);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) image.at(x, y) = Color(x * 0.1f, y * 1e3f, 1e-6f * (x + y));
    const std::string path = temp_path("roundtrip.exr");
    write_exr(image, path);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    const Image back = read_exr(path);
    ASSERT_EQ(back.width, 7);
    ASSERT_EQ(back.height, 5);
    for (size_t i = 0; i < image.pixels.size(); ++i) EXPECT_EQ(back.pixels[i], image.pixels[i]);
    std::filesystem::remove(path);
}

namespace {
// The relative error each codec may leave in the values the test files hold (0: lossless).
// PXR24 rounds a float to 24 bits (sign, exponent, 15 bits of mantissa): half a unit of the
// 15th bit, 2^-16 relative; it keeps half and uint exactly. B44 and B44A compress half channels
// only (float and uint are stored as they are): a 4x4 block keeps its largest value and 15
// differences of 6 bits, in the half bits of 8 ln x for a channel that is not perceptually
// linear, so each value is within 1/63 of the block's spread in 8 ln x (0.39 stops of our
// gradient: 2.2), 0.0043 relative in x, plus half's rounding of 8 ln x and of x (2^-10):
// 0.006. DWAA and DWAB quantise each 8x8 block's DCT coefficients of R, G, B and Y (half or
// float) in a perceptual space, at the default level 45; OpenEXR gives no bound per value, only
// "visually lossless": measured on this gradient, 0.87% at most; allowed, 2^-6 (1.6%).
double codec_tolerance(Imf::Compression compression, Imf::PixelType type) {
    switch (compression) {
        case Imf::PXR24_COMPRESSION: return type == Imf::FLOAT ? 0x1p-16 : 0.0;
        case Imf::B44_COMPRESSION:
        case Imf::B44A_COMPRESSION: return type == Imf::HALF ? 0.006 : 0.0;
        case Imf::DWAA_COMPRESSION:
        case Imf::DWAB_COMPRESSION: return type == Imf::UINT ? 0.0 : 0x1p-6;
        default: return 0.0;
    }
}

const Imf::Compression kAllCompressions[] = {
    Imf::NO_COMPRESSION,   Imf::RLE_COMPRESSION,   Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION,
    Imf::PIZ_COMPRESSION,  Imf::PXR24_COMPRESSION, Imf::B44_COMPRESSION,  Imf::B44A_COMPRESSION,
    Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION};
}  // namespace

// Files written by OpenEXR's own API in every compression, pixel type (half, float, uint) and
// layout (scanlines, 8x8 tiles, the first of two parts), with RGB, RGBA and Y channels, a data
// window away from the origin and sizes that are no multiple of a block, a chunk or a tile: each
// reads to the values written, exactly for lossless codecs, within the codec's error for lossy
// ones; Y is grey, alpha is ignored, a multi-part file's other part is named in a note.
TEST(Image, ExrEveryCompressionPixelTypeAndLayoutReadsTheValuesWritten) {
    const std::string path = temp_path("codec.exr");
    int files = 0;
    for (const Imf::Compression compression : kAllCompressions)
        for (const Imf::PixelType type : {Imf::HALF, Imf::FLOAT, Imf::UINT})
            for (const exr_test::Layout layout :
                 {exr_test::Layout::Scanline, exr_test::Layout::Tiled, exr_test::Layout::MultiPart})
                for (const auto& channels : {std::vector<std::string>{"R", "G", "B"},
                                             std::vector<std::string>{"R", "G", "B", "A"},
                                             std::vector<std::string>{"Y"}}) {
                    exr_test::Spec spec;
                    spec.compression = compression;
                    spec.type = type;
                    spec.layout = layout;
                    spec.channels = channels;
                    exr_test::write(path, spec);
                    ++files;
                    const std::string label = compression_name(static_cast<int>(compression)) +
                                              " " + exr_test::type_name(type) + " " +
                                              exr_test::layout_name(layout) + " " +
                                              std::to_string(channels.size()) + " channels";
                    const Image back = read_exr(path);
                    ASSERT_EQ(back.width, spec.width) << label;
                    ASSERT_EQ(back.height, spec.height) << label;
                    const double tolerance = codec_tolerance(compression, type);
                    double worst = 0.0;
                    for (int y = 0; y < spec.height; ++y)
                        for (int x = 0; x < spec.width; ++x)
                            for (int c = 0; c < 3; ++c) {
                                // Y (channel 0) in every channel of a grey file.
                                const float want = exr_test::written_value(
                                    x, y, channels.size() == 1 ? 0 : c, type);
                                const float got = back.at(x, y)[c];
                                if (tolerance == 0.0)
                                    ASSERT_EQ(got, want) << label << " at " << x << ", " << y;
                                worst = std::max(worst, std::abs(double{got} - want) / want);
                            }
                    EXPECT_LE(worst, tolerance) << label;
                    if (layout == exr_test::Layout::MultiPart) {
                        ASSERT_EQ(back.notes.size(), 1u) << label;
                        EXPECT_NE(back.notes[0].find(path + ": a multi-part EXR of 2 parts: only "
                                                            "the first ('beauty') was read"),
                                  std::string::npos)
                            << back.notes[0];
                    } else {
                        EXPECT_TRUE(back.notes.empty()) << label;
                    }
                }
    EXPECT_EQ(files, 270);
    std::filesystem::remove(path);
}

// An environment map in every compression and layout, as half and as float holding the same
// half values, lights a mirror sphere in lesson 2 and is seen around it: the image is the ZIP
// float file's, bit for bit, where the texels read are the same (every lossless codec, and
// PXR24 and B44, which keep these values exactly in float); with a lossy codec each pixel is
// within the codec's relative error of it (a pixel is the map's radiance times the mirror's
// reflectance, the same texels with the same weights: positive, so the relative bound carries).
TEST(Image, ExrEnvironmentMapsInEveryCodecRenderTheZipFloatImage) {
    const auto dir = std::filesystem::temp_directory_path() / "lessons_exr_maps";
    std::filesystem::create_directories(dir);
    const auto render_with = [&](const std::string& map) {
        const std::string text = R"([image]
width = 24
height = 16
[camera]
position = [0, 0.3, -4]
look_at = [0, 0, 0]
fov = 60
[background]
map = ")" + map + R"("
[materials.mirror]
type = "mirror"
reflectance = [0.9, 0.8, 0.7]
[[shapes]]
type = "sphere"
material = "mirror"
center = [0, 0, 0]
radius = 1
)";
        const Scene scene = build_scene(parse_scene_string(text, (dir / "s.toml").string()));
        RenderSettings settings;
        settings.progress = false;
        return render_scene(scene, WhittedModel(scene, WhittedOptions{}), 4, settings).image;
    };
    exr_test::Spec base;
    base.type = Imf::FLOAT;
    base.values_in_half = true;
    const std::string zip_float = (dir / "zip_float.exr").string();
    exr_test::write(zip_float, base);
    const Image reference = render_with(zip_float);
    for (const Imf::Compression compression : kAllCompressions)
        for (const Imf::PixelType type : {Imf::HALF, Imf::FLOAT})
            for (const exr_test::Layout layout :
                 {exr_test::Layout::Scanline, exr_test::Layout::Tiled,
                  exr_test::Layout::MultiPart}) {
                exr_test::Spec spec = base;
                spec.compression = compression;
                spec.type = type;
                spec.layout = layout;
                const std::string label = compression_name(static_cast<int>(compression)) + "_" +
                                          exr_test::type_name(type) + "_" +
                                          exr_test::layout_name(layout);
                const std::string map = (dir / (label + ".exr")).string();
                exr_test::write(map, spec);
                const Image image = render_with(map);
                const bool lossy =
                    compression == Imf::DWAA_COMPRESSION || compression == Imf::DWAB_COMPRESSION ||
                    (type == Imf::HALF &&
                     (compression == Imf::B44_COMPRESSION || compression == Imf::B44A_COMPRESSION));
                const double tolerance = codec_tolerance(compression, type);
                for (size_t i = 0; i < image.pixels.size(); ++i)
                    for (int c = 0; c < 3; ++c) {
                        const float got = image.pixels[i][c], want = reference.pixels[i][c];
                        if (!lossy)
                            ASSERT_EQ(got, want) << label << " pixel " << i;
                        else
                            ASSERT_LE(std::abs(double{got} - want), tolerance * want)
                                << label << " pixel " << i;
                    }
            }
    std::filesystem::remove_all(dir);
}

namespace {
// One EXR header attribute's bytes: name, type, little-endian size, value.
std::string exr_attribute(const std::string& name, const std::string& type,
                          const std::string& value) {
    std::string a = name + '\0' + type + '\0';
    const uint32_t n = static_cast<uint32_t>(value.size());
    for (int i = 0; i < 4; ++i) a.push_back(static_cast<char>((n >> (8 * i)) & 0xff));
    return a + value;
}
std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}
// The field of the InputError `read` throws, or "(none)" / "(other)".
template <class Read>
std::string error_field(Read&& read) {
    try {
        read();
    } catch (const InputError& e) {
        return e.field();
    } catch (const std::exception&) {
        return "(other)";
    }
    return "(none)";
}
}  // namespace

// The offsets of an EXR file's header end and line offset table (single part).
struct ExrTable {
    size_t table = 0;          // the first offset's position (after the header's final NUL)
    uint64_t first_chunk = 0;  // where the first chunk starts
};
ExrTable exr_table(const std::string& bytes) {
    size_t header_end = 8;
    while (bytes.at(header_end) != '\0') {
        header_end = bytes.find('\0', bytes.find('\0', header_end) + 1) + 1;
        uint32_t size = 0;
        std::memcpy(&size, bytes.data() + header_end, 4);
        header_end += 4 + size;
    }
    ExrTable t;
    t.table = header_end + 1;
    std::memcpy(&t.first_chunk, bytes.data() + t.table, 8);
    return t;
}

// Damaged and lying headers are input errors naming the file and, for what the header check
// measures, the attribute, before OpenEXR allocates for them; every prefix of a good file, in
// scanlines, tiles, a lossy codec and a multi-part file, is an input error naming the file.
TEST(Image, DamagedAndLyingExrFilesAreInputErrors) {
    Image image(3, 40);
    image.at(2, 1) = Color(0.25f, 0.5f, 4.0f);
    const std::string good = temp_path("header_good.exr");
    write_exr(image, good);
    const std::string bytes = read_bytes(good);
    const ExrTable t = exr_table(bytes);
    const std::string magic = bytes.substr(0, 4), scanline = magic + std::string("\2\0\0\0", 4);
    // The file with `attribute` put first (or last) in its header; the line offsets move with it.
    const auto with = [&](const std::string& attribute, bool last = false) {
        const size_t at = last ? t.table - 1 : 8;
        std::string file = scanline + bytes.substr(8, at - 8) + attribute + bytes.substr(at);
        for (size_t at = t.table; at < t.first_chunk; at += 8) {
            uint64_t offset = 0;
            std::memcpy(&offset, bytes.data() + at, 8);
            offset += attribute.size();
            std::memcpy(file.data() + at + attribute.size(), &offset, 8);
        }
        return file;
    };
    const std::string path = temp_path("header_bad.exr");
    const auto chunk_count = [](uint32_t n) {
        return exr_attribute("chunkCount", "int", std::string(reinterpret_cast<char*>(&n), 4));
    };
    const auto chunks = static_cast<uint32_t>((t.first_chunk - t.table) / 8);
    ASSERT_EQ(chunks, 3u);  // 40 lines of ZIP: 16 a chunk
    // A chunk count that is the data window's reads the same image.
    write_bytes(path, with(chunk_count(chunks)));
    EXPECT_EQ(read_exr(path).at(2, 1), image.at(2, 1));

    // A data window given twice: OpenEXRCore, which the check reads with, keeps the first, and
    // the C++ library, which decodes, the last (and would allocate for it).
    const auto window = [](int32_t x1, int32_t y1) {
        const int32_t v[4] = {0, 0, x1, y1};
        return exr_attribute("dataWindow", "box2i",
                             std::string(reinterpret_cast<const char*>(v), 16));
    };
    std::vector<std::pair<std::string, std::string>> cases = {
        {with(chunk_count(0x7fffffff)), "chunkCount"},
        {with(chunk_count(chunks - 1)), "chunkCount"},
        {with(window(99'999, 39), true), "dataWindow"},
    };
    // Data windows that lie about the file's size.
    const auto with_window = [&](int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        std::string file = bytes;
        const std::string name("dataWindow\0box2i\0\x10\0\0\0", 21);
        const size_t at = file.find(name);
        EXPECT_NE(at, std::string::npos);
        const int32_t v[4] = {x0, y0, x1, y1};
        std::memcpy(file.data() + at + name.size(), v, 16);
        return file;
    };
    cases.push_back({with_window(0, 0, 99'999, 99'999), "dataWindow"});  // 10^10 pixels
    cases.push_back({with_window(0, 0, 39'999, 39'999), "channels"});    // 1.6 10^9 pixels
    // Pixels within 2^31, but their three channels' samples over what the file can encode.
    const auto wide = static_cast<int32_t>(kMaxSamplesPerByte * bytes.size() / 3 / 16 + 1);
    cases.push_back({with_window(0, 0, wide - 1, 0), "channels"});
    for (const auto& [file, field] : cases) {
        write_bytes(path, file);
        EXPECT_EQ(error_field([&] { read_exr(path); }), field) << field;
        EXPECT_EQ(error_field([&] { check_exr_header(path); }), field) << field;
        // The part reader checks the header first too.
        EXPECT_EQ(error_field([&] { read_part(path); }), field) << field;
    }
    // What OpenEXR's parser refuses (an empty or wrapping window, a window too wide for it):
    // input errors naming the file.
    for (const std::string& file : {with_window(0, 0, -1, 1), with_window(0, INT32_MIN, 2, 1),
                                    with_window(0, 0, 1 << 24, 1)}) {
        write_bytes(path, file);
        try {
            read_exr(path);
            ADD_FAILURE() << "read a damaged file";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        }
    }
    // What OpenEXR reads right, unlike tinyexr before it: a type it does not know in a file whose
    // version says scanlines, and two line offsets to one chunk (OpenEXR finds that the table is
    // not in order and rebuilds it from the chunks themselves).
    std::string twice = bytes;
    std::memcpy(twice.data() + t.table + 8, bytes.data() + t.table, 8);
    for (const std::string& file : {with(exr_attribute("type", "string", "bogus")), twice}) {
        write_bytes(path, file);
        EXPECT_EQ(read_exr(path).pixels, image.pixels);
    }
    // Cuts of good files, each layout.
    std::vector<std::string> goods{good};
    for (const auto& [compression, layout] :
         {std::pair{Imf::PIZ_COMPRESSION, exr_test::Layout::Tiled},
          std::pair{Imf::DWAB_COMPRESSION, exr_test::Layout::Scanline},
          std::pair{Imf::ZIP_COMPRESSION, exr_test::Layout::MultiPart}}) {
        exr_test::Spec spec;
        spec.compression = compression;
        spec.layout = layout;
        spec.type = Imf::HALF;
        goods.push_back(temp_path(std::string("prefix_") + exr_test::layout_name(layout) + ".exr"));
        exr_test::write(goods.back(), spec);
    }
    // (A multi-part file cut in its second part still holds the whole first part, and reads.)
    for (const std::string& file : goods) {
        const std::string whole = read_bytes(file);
        const Image all = read_exr(file);
        // Every cut in the headers and offset tables, then every 7th byte of the chunks.
        const size_t chunks_from = exr_table(whole).first_chunk;
        for (size_t n = 0; n < whole.size(); n += n < chunks_from ? 1 : 7) {
            write_bytes(path, whole.substr(0, n));
            try {
                const Image cut = read_exr(path);
                EXPECT_TRUE(file.find("multi-part") != std::string::npos &&
                            cut.pixels == all.pixels)
                    << file << " cut to " << n << " bytes read";
            } catch (const InputError& e) {
                ASSERT_NE(std::string(e.what()).find(path + ": "), std::string::npos)
                    << n << " bytes: " << e.what();
            }
        }
        std::filesystem::remove(file);
    }
    std::filesystem::remove(path);
}

// The bound of kMaxSamplesPerByte holds for the densest files OpenEXR writes: constant images,
// wide enough that the chunks' own bytes hardly count, in the codec that packs most (DWAB, then
// DWAA and ZIP), each of which still reads.
TEST(Image, ExrSizeBoundHoldsForTheDensestFiles) {
    for (const auto compression :
         {Imf::DWAB_COMPRESSION, Imf::DWAA_COMPRESSION, Imf::ZIP_COMPRESSION}) {
        for (const auto& channels :
             {std::vector<std::string>{"Y"}, std::vector<std::string>{"R", "G", "B"}}) {
            const int w = 8192, h = 256;
            const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(w - 1, h - 1));
            Imf::Header header(w, h);
            header.compression() = compression;
            std::vector<half> constant(static_cast<size_t>(w) * h, half(0.5f));
            Imf::FrameBuffer frame;
            for (const std::string& c : channels) {
                header.channels().insert(c, Imf::Channel(Imf::HALF));
                frame.insert(c, Imf::Slice::Make(Imf::HALF, constant.data(), window));
            }
            const std::string path = temp_path("densest.exr");
            {
                Imf::OutputFile file(path.c_str(), header);
                file.setFrameBuffer(frame);
                file.writePixels(h);
            }
            const auto bytes = static_cast<int64_t>(std::filesystem::file_size(path));
            const int64_t samples = int64_t{w} * h * static_cast<int64_t>(channels.size());
            EXPECT_LT(samples, kMaxSamplesPerByte * bytes)
                << compression_name(static_cast<int>(compression)) << ": " << samples / bytes
                << " samples per byte";
            const Image back = read_exr(path);  // (DWA's error: within 2^-6, as above)
            EXPECT_NEAR(back.at(w - 1, h - 1).x, 0.5f, 0.5f * 0x1p-6f);
            std::filesystem::remove(path);
        }
    }
}

TEST(Image, SrgbCurveMatchesTheStandard) {
    EXPECT_FLOAT_EQ(srgb_encode(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgb_encode(1.0f), 1.0f);
    EXPECT_NEAR(srgb_encode(0.0031308f), 0.04045f, 1e-5f);  // the two pieces meet here
    EXPECT_NEAR(srgb_encode(0.18f), 0.4614f, 1e-4f);        // middle grey
}

TEST(Image, PngIsWrittenAndUnreadableExrIsAClearError) {
    Image image(4, 4);
    image.at(1, 1) = Color(kInfinity, -1.0f, 0.5f);  // saturates, clamps, does not crash
    const std::string png = temp_path("out.png");
    write_png(image, png, 1.0f);
    EXPECT_GT(std::filesystem::file_size(png), 0u);
    std::filesystem::remove(png);
    try {
        read_exr(temp_path("does_not_exist.exr"));
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("does_not_exist.exr"), std::string::npos);
    }
}

TEST(Image, WritingIntoAMissingFolderFailsWithoutLeavingATemporary) {
    Image image(2, 2);
    const std::string path = temp_path("no_such_dir/x.exr");
    EXPECT_THROW(write_exr(image, path), std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(Film, MeanVarianceAndNonFiniteSamplesAreCountedNotAveraged) {
    Film film(2, 1);
    for (float v : {1.0f, 2.0f, 3.0f, 4.0f}) film.add_sample(0, Color(v));
    film.add_sample(0, Color(std::nanf(""), 0, 0));
    film.add_sample(1, Color(kInfinity));
    film.add_sample(1, Color(5.0f));
    const Image mean = film.mean();
    EXPECT_FLOAT_EQ(mean.pixels[0].x, 2.5f);
    EXPECT_FLOAT_EQ(mean.pixels[1].y, 5.0f);
    // Sample variance of {1,2,3,4} is 5/3; of the mean of 4 samples, 5/12.
    EXPECT_FLOAT_EQ(film.variance_of_mean().pixels[0].z, 5.0f / 12.0f);
    EXPECT_EQ(film.nan_samples(), 1u);
    EXPECT_EQ(film.inf_samples(), 1u);
    EXPECT_EQ(film.nan_pixels(), 1);
    EXPECT_EQ(film.inf_pixels(), 1);
}

// Radiance .hdr (RGBE) files (io/image_hdr.cpp), written here by stb_image_write.
namespace {

std::string write_hdr_file(const std::string& name, const Image& image) {
    const std::string path = temp_path(name);
    EXPECT_TRUE(stbi_write_hdr(path.c_str(), image.width, image.height, 3,
                               reinterpret_cast<const float*>(image.pixels.data())));
    return path;
}

Image varied_image(int w, int h) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            image.at(x, y) = Color(0.37f * x + 0.01f, 0.5f + 0.11f * y, 0.013f * (x + y)) *
                             std::pow(10.0f, static_cast<float>(y % 5) - 2.0f);
    image.at(1, 1) = Color(0.0f);            // black
    image.at(2, 1) = Color(3e4f, 2e-3f, 0);  // a sun with a dim channel
    return image;
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The InputError read_image throws for `path`, or "" if it read the file.
std::string read_error(const std::string& path) {
    try {
        read_image(path);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// RGBE keeps 8 bits of mantissa per channel with a shared exponent e, 2^(e-1) <= the largest
// channel < 2^e: each channel within one unit, 2^(e-8), of the value written (less than 2^-7 of
// the largest channel; stb_image_write truncates, so never above it). Both of stb_image's
// layouts: run-length scanlines (width 8 to 32767) and flat pixels (here width 5). Linear: no
// curve is applied.
TEST(HdrImage, ReadsTheSameTexelsAsAnExrWithinRgbePrecision) {
    for (const auto& [w, h] : {std::pair{24, 6}, std::pair{5, 3}}) {
        const Image image = varied_image(w, h);
        const std::string hdr = write_hdr_file("varied_" + std::to_string(w) + ".hdr", image);
        const std::string exr = temp_path("varied_" + std::to_string(w) + ".exr");
        write_exr(image, exr);
        const Image from_hdr = read_image(hdr), from_exr = read_image(exr);
        ASSERT_EQ(from_hdr.width, w);
        ASSERT_EQ(from_hdr.height, h);
        const Image linear = read_linear_image(hdr);
        for (size_t i = 0; i < image.pixels.size(); ++i) {
            EXPECT_EQ(linear.pixels[i], from_hdr.pixels[i]);
            const Color& want = from_exr.pixels[i];
            const float largest = max_component(want);
            if (largest == 0.0f) {
                EXPECT_EQ(from_hdr.pixels[i], Color(0.0f)) << "texel " << i;
                continue;
            }
            int e = 0;
            std::frexp(largest, &e);
            const float unit = std::ldexp(1.0f, e - 8);
            EXPECT_LE(unit, largest * 0x1p-7f);
            for (int c = 0; c < 3; ++c) {
                EXPECT_GE(from_hdr.pixels[i][c], 0.0f);
                EXPECT_LE(from_hdr.pixels[i][c], want[c]) << "texel " << i << " channel " << c;
                EXPECT_LT(want[c] - from_hdr.pixels[i][c], unit)
                    << "texel " << i << " channel " << c;
            }
        }
        std::filesystem::remove(hdr);
        std::filesystem::remove(exr);
    }
}

// What stb_image 2.27 would misread (zeros past the end of a truncated file, a run of length 0
// read for ever, an allocation for any size the header claims) is an InputError naming the
// file, before stb_image decodes: every prefix of a good file, in both layouts, and damaged
// headers.
TEST(HdrImage, DamagedFilesAreInputErrorsNamingTheFile) {
    for (const int w : {24, 5}) {
        const std::string good = write_hdr_file("good.hdr", varied_image(w, 6));
        const std::vector<unsigned char> bytes = file_bytes(good);
        const std::string data(bytes.begin(), bytes.end());
        const size_t header =
            data.find("+X " + std::to_string(w) + "\n") + 4 + std::to_string(w).size();
        const std::string cut = temp_path("cut.hdr");
        for (size_t n = 0; n < bytes.size(); ++n) {
            write_bytes(cut, data.substr(0, n));
            const std::string error = read_error(cut);
            ASSERT_NE(error.find(cut + ": "), std::string::npos) << n << " bytes: " << error;
            if (n > header) {
                EXPECT_NE(error.find("(truncated?)"), std::string::npos)
                    << n << " bytes: " << error;
            }
        }
        EXPECT_EQ(read_error(good), "");
        std::filesystem::remove(cut);
        std::filesystem::remove(good);
    }
    using namespace std::string_literals;  // (strings with NUL bytes)
    const std::string head = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
    struct Case {
        std::string bytes, expected;
    };
    const std::vector<Case> cases = {
        {head + "-Y 30000 +X 30000\n" + std::string(100, '\x01'),
         "its size 30000 x 30000 is more pixels than a file of 153 bytes can encode"},
        {head + "-Y 1 +X 16\n\x02\x02\x00\x10\x00"s, "has a run-length code that does not fit it"},
        {head + "-Y 1 +X 16\n\x02\x02\x00\x10\x90\x05\x85"s, "cut short"},
        {head + "-Y 2 +X 16\n\x02\x02\x00\x11"s, "gives a width other than the header's"},
        {head + "+Y 1 +X 4\n" + std::string(16, '\x01'), "'-Y HEIGHT +X WIDTH'"},
        {head + "-Y 0 +X 4\n", "holds no pixels"},
        {"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 4\n" + std::string(16, '\x01'),
         "no FORMAT=32-bit_rle_rgbe"},
        {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", "header is cut short"},
        {"\x89PNG\r\n\x1a\n" + std::string(40, '\0'), "not a Radiance HDR (RGBE) file"},
    };
    const std::string path = temp_path("damaged.hdr");
    for (const Case& c : cases) {
        write_bytes(path, c.bytes);
        const std::string error = read_error(path);
        EXPECT_NE(error.find(path + ": "), std::string::npos) << error;
        EXPECT_NE(error.find(c.expected), std::string::npos)
            << "expected: " << c.expected << "\ngot: " << error;
    }
    std::filesystem::remove(path);
}
