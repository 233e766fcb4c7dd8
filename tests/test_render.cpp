// The render loop: the image does not depend on the number of threads or on how the samples
// are split into passes.
#include <gtest/gtest.h>

#include "01_ray_casting/ray_casting.h"
#include "driver/app.h"
#include "io/scene_file.h"
#include "render/render.h"
#include "test_util.h"

using namespace lessons;

namespace {
Image render_with(const Scene& scene, int threads, const std::vector<int>& pass_ends) {
    Film film(scene.width, scene.height);
    // A model that uses the random numbers, so that seeding matters.
    const test::FunctionModel radiance([&scene](const Ray& ray, Rng& rng) {
        return ray_cast(scene, ray, {}) * (0.5f + rng.uniform());
    });
    RenderSettings settings;
    settings.threads = threads;
    settings.seed = 1234;
    settings.progress = false;
    int begin = 0;
    for (int end : pass_ends) {
        test::render_film(scene.camera, film, settings, radiance, begin, end);
        begin = end;
    }
    return film.mean();
}
}  // namespace

TEST(Render, SameSeedGivesTheSameImageForOneTwoAndThreeThreads) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {96, 80});
    const Image one = render_with(scene, 1, {4});
    const Image two = render_with(scene, 2, {4});
    const Image three = render_with(scene, 3, {4});
    const Image passes = render_with(scene, 2, {1, 2, 3, 4});
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    int nonzero = 0;
    for (size_t i = 0; i < one.pixels.size(); ++i) {
        ASSERT_EQ(one.pixels[i], two.pixels[i]) << "pixel " << i;
        ASSERT_EQ(one.pixels[i], three.pixels[i]) << "pixel " << i;
        ASSERT_EQ(one.pixels[i], passes.pixels[i]) << "pixel " << i;
        nonzero += one.pixels[i].x > 0.0f;
    }
    EXPECT_GT(nonzero, 1000);
}

TEST(Render, DifferentSeedsGiveDifferentNoise) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {32, 32});
    Film a(32, 32), b(32, 32);
    const test::FunctionModel noise([](const Ray&, Rng& rng) { return Color(rng.uniform()); });
    RenderSettings s;
    s.progress = false;
    test::render_film(scene.camera, a, s, noise, 0, 1);
    s.seed = 1;
    test::render_film(scene.camera, b, s, noise, 0, 1);
    EXPECT_NE(a.mean().pixels[0], b.mean().pixels[0]);
}

TEST(Render, CountsTheRaysItTraces) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/whitted_1979.toml", {40, 30});
    const auto model = RayCastingModel(scene, {});
    RenderSettings s;
    s.progress = false;
    const RenderResult r = render_scene(scene, model, 2, s);
    // Every sample traces one camera ray; hits also trace one shadow ray to the point light.
    EXPECT_GE(r.stats.rays, 40u * 30u * 2u);
    EXPECT_LE(r.stats.rays, 40u * 30u * 2u * 2u);
    EXPECT_EQ(r.nan_pixels, 0);
    EXPECT_EQ(r.inf_pixels, 0);
}

TEST(Render, PassByPassAndPixelByPixelGiveTheSameImageAndASplatNeedsPasses) {
    // The loop's two orders add the same samples (each from Rng(seed, pixel, k)) to exact,
    // order-free sums: a model that says `passes` gets the image it gets pixel by pixel, crop
    // or not. A model that splats without passes, or a model that splats into a crop, is a
    // programming error the loop refuses.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {40, 30});
    test::FunctionModel model([&scene](const Ray& ray, Rng& rng) {
        return ray_cast(scene, ray, {}) * (0.5f + rng.uniform());
    });
    const RenderSettings settings = test::quiet_settings(77, 2);
    Film by_pixel(40, 30), by_pass(40, 30), crop(20, 10);
    test::render_film(scene.camera, by_pixel, settings, model, 0, 3);
    model.passes = true;
    test::render_film(scene.camera, by_pass, settings, model, 0, 3);
    RenderSettings cropped = settings;
    cropped.image_width = 40;
    cropped.image_height = 30;
    cropped.crop_x = 10;
    cropped.crop_y = 5;
    test::render_film(scene.camera, crop, cropped, model, 0, 3);
    const Image a = by_pixel.mean(), b = by_pass.mean(), c = crop.mean();
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_EQ(a.pixels[i], b.pixels[i]) << i;
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x)
            ASSERT_EQ(c.pixels[y * 20 + x], a.pixels[(y + 5) * 40 + x + 10]) << x << ", " << y;

    model.splats = true;
    model.passes = false;
    EXPECT_THROW(test::render_film(scene.camera, by_pixel, settings, model, 3, 4),
                 std::logic_error);
    model.passes = true;
    EXPECT_THROW(test::render_film(scene.camera, crop, cropped, model, 3, 4), std::logic_error);
}

namespace {
// A model whose sample is the index of the pixel it is told (its place in the whole image).
class PixelIndexModel final : public Model {
public:
    Color sample(const Ray&, Rng&, uint32_t pixel, std::span<Color>,
                 std::vector<Splat>&) const override {
        return Color(static_cast<float>(pixel));
    }
};
}  // namespace

TEST(Render, AModelIsToldEachPixelsIndexInTheWholeImageInACrop) {
    // Pixel by pixel and pass by pass, a crop's pixel (x, y) is pixel (crop_x + x, crop_y + y)
    // of the whole image: its random numbers' key, and the index sample() is told (lesson 6's
    // vcm takes the pass's light subpath of that index).
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {40, 30});
    for (const bool passes : {false, true}) {
        PixelIndexModel model;
        model.passes = passes;
        RenderSettings cropped = test::quiet_settings(5, 2);
        cropped.image_width = 40;
        cropped.image_height = 30;
        cropped.crop_x = 7;
        cropped.crop_y = 11;
        Film crop(13, 9);
        test::render_film(scene.camera, crop, cropped, model, 0, 1);
        const Image c = crop.mean();
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < 13; ++x)
                ASSERT_EQ(c.pixels[y * 13 + x].x, static_cast<float>((y + 11) * 40 + x + 7))
                    << x << ", " << y << (passes ? " (pass by pass)" : "");
    }
}
