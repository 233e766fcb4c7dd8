// Image output: EXR round trip, the sRGB curve, atomic writes; Radiance .hdr input.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "io/image.h"
#include "io/input_error.h"
#include "render/film.h"
#include "render/part.h"

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

// Debian's tinyexr aborts the process on an assert for these headers (found by fuzz_part): they
// must be input errors naming the attribute, in the image reader and the part reader alike,
// while a header that states its scanline type correctly still reads.
TEST(Image, ExrHeadersTinyexrWouldAbortOnAreInputErrors) {
    Image image(3, 2);
    image.at(2, 1) = Color(0.25f, 0.5f, 4.0f);
    const std::string good = temp_path("header_good.exr");
    write_exr(image, good);
    const std::string bytes = read_bytes(good);
    ASSERT_GT(bytes.size(), 8u);
    const std::string magic = bytes.substr(0, 4), scanline = magic + std::string("\2\0\0\0", 4),
                      tiled = magic + std::string("\2\2\0\0", 4);
    // The file with `attribute` put first in its header and the given version bytes; the line
    // offsets after the header (absolute positions in the file) move with it.
    size_t header_end = 8;
    while (bytes.at(header_end) != '\0') {
        header_end = bytes.find('\0', bytes.find('\0', header_end) + 1) + 1;
        uint32_t size = 0;
        std::memcpy(&size, bytes.data() + header_end, 4);
        header_end += 4 + size;
    }
    const size_t table = header_end + 1;
    uint64_t first_chunk = 0;
    std::memcpy(&first_chunk, bytes.data() + table, 8);
    const auto with = [&](const std::string& version, const std::string& attribute) {
        std::string file = version + attribute + bytes.substr(8);
        for (size_t at = table; at < first_chunk; at += 8) {
            uint64_t offset = 0;
            std::memcpy(&offset, bytes.data() + at, 8);
            offset += attribute.size();
            std::memcpy(file.data() + at + attribute.size(), &offset, 8);
        }
        return file;
    };
    const std::string path = temp_path("header_bad.exr");

    write_bytes(path, with(scanline, exr_attribute("type", "string", "scanlineimage")));
    const Image back = read_exr(path);
    ASSERT_EQ(back.width, 3);
    EXPECT_EQ(back.at(2, 1), image.at(2, 1));
    // A chunk count that is the file's (its offset table's length) reads the same image.
    const auto chunk_count = [](uint32_t n) {
        return exr_attribute("chunkCount", "int", std::string(reinterpret_cast<char*>(&n), 4));
    };
    const auto chunks = static_cast<uint32_t>((first_chunk - table) / 8);
    write_bytes(path, with(scanline, chunk_count(chunks)));
    EXPECT_EQ(read_exr(path).at(2, 1), image.at(2, 1));

    std::vector<std::pair<std::string, std::string>> cases = {
        {with(scanline, exr_attribute("type", "string", "bogus")), "type"},
        {with(scanline, exr_attribute("type", "string", "tiledimage")), "type"},
        {with(scanline, exr_attribute("type", "string", "deepscanline")), "type"},
        // Tiled files (tinyexr aborts on a level mode of 3, divides by a tile size of 0).
        {with(tiled, exr_attribute("tiles", "tiledesc", "1234")), ""},
        {with(tiled, exr_attribute("tiles", "tiledesc", std::string(9, '\0')) +
                         exr_attribute("type", "string", "tiledimage")),
         ""},
        // A type before an attribute on which tinyexr's parse stops (codec 9 is unknown).
        {scanline + exr_attribute("type", "string", "tiledimage") +
             exr_attribute("compression", "compression", "\x09"),
         "type"},
        // More line offsets than the file holds: tinyexr would allocate them first.
        {with(scanline, chunk_count(0x7fffffff)), "chunkCount"},
        // Another count: tinyexr reads offsets that are not the table's (a count of 1 for this
        // file's 2 gave garbage for the second line: a wrong image, silently).
        {with(scanline, chunk_count(chunks > 1 ? chunks - 1 : 2)), "chunkCount"},
        {with(scanline, chunk_count(chunks + 1)), "chunkCount"},
        // A damaged header after the type: tinyexr's parse fails there, then converts (and
        // asserts on) what it read.
        {scanline + exr_attribute("type", "string", "bogus") + std::string("x\0y\0\xff\xff", 6),
         "type"},
    };
    // Data windows tinyexr sizes with overflowing int arithmetic, or would allocate for.
    const auto with_window = [&](int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        std::string file = bytes;
        const std::string name("dataWindow\0box2i\0\x10\0\0\0", 21);
        const size_t at = file.find(name);
        EXPECT_NE(at, std::string::npos);
        const int32_t v[4] = {x0, y0, x1, y1};
        std::memcpy(file.data() + at + name.size(), v, 16);
        return file;
    };
    cases.push_back({with_window(0, INT32_MIN, 2, 1), "dataWindow"});      // height wraps
    cases.push_back({with_window(0, 0, 1 << 24, 1), "dataWindow"});        // too wide
    cases.push_back({with_window(0, 0, 999'999, 999'999), "dataWindow"});  // 10^12 pixels
    cases.push_back({with_window(0, 0, -1, 1), "dataWindow"});             // empty
    // Pixels within the bound, but their three channels' samples over it.
    const auto wide = static_cast<int32_t>(2048 * bytes.size());
    cases.push_back({with_window(0, 0, wide - 1, 0), "channels"});
    // Two line offsets to one chunk: tinyexr would leave the other chunk's lines unwritten.
    ASSERT_GE(chunks, 2u);
    std::string twice = bytes;
    std::memcpy(twice.data() + table + 8, bytes.data() + table, 8);
    cases.push_back({twice, ""});
    for (const auto& [file, field] : cases) {
        write_bytes(path, file);
        EXPECT_EQ(error_field([&] { read_exr(path); }), field) << field;
        EXPECT_EQ(error_field([&] { check_exr_header(path); }), field) << field;
    }
    // The part reader checks before tinyexr parses too (the tiled files it refuses itself).
    for (const auto& [file, field] : cases) {
        if (field.empty()) continue;
        write_bytes(path, file);
        EXPECT_EQ(error_field([&] { read_part(path); }), field) << field;
    }
    std::filesystem::remove(path);
    std::filesystem::remove(good);
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
    image.at(1, 1) = Color(0.0f);           // black
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
        const size_t header = data.find("+X " + std::to_string(w) + "\n") + 4 +
                              std::to_string(w).size();
        const std::string cut = temp_path("cut.hdr");
        for (size_t n = 0; n < bytes.size(); ++n) {
            write_bytes(cut, data.substr(0, n));
            const std::string error = read_error(cut);
            ASSERT_NE(error.find(cut + ": "), std::string::npos) << n << " bytes: " << error;
            if (n > header) {
                EXPECT_NE(error.find("(truncated?)"), std::string::npos) << n << " bytes: " << error;
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
        EXPECT_NE(error.find(c.expected), std::string::npos) << "expected: " << c.expected
                                                             << "\ngot: " << error;
    }
    std::filesystem::remove(path);
}
