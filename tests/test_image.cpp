// Image output: EXR round trip, the sRGB curve, atomic writes.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/image.h"
#include "render/film.h"

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
