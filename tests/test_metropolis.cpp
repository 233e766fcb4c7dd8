// Lesson 7, Metropolis light transport, as a model (chapters/07_metropolis/metropolis.h): the
// furnace in closed form, with b the image's mean; lesson 5's images pixel by pixel (with large
// steps only, and with the defaults); the same bits for any number of threads and for a render
// split into parts (docs/accuracy.md). The chain itself: test_metropolis_chain.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "05_bidirectional/bidirectional.h"
#include "07_metropolis/metropolis.h"
#include "io/scene_file.h"
#include "render/progressive.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

double image_average(const Image& image) {
    double sum = 0.0;
    for (const Color& c : image.pixels) sum += static_cast<double>(luminance(c));
    return sum / static_cast<double>(image.pixels.size());
}

Scene small_scene(const char* name, int width, int height) {
    return load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/" + name, {width, height});
}

}  // namespace

TEST(Metropolis, TheFurnaceIsItsClosedFormAndBIsTheImageMean) {
    // Inside a sphere that emits L_e = 1 and reflects rho = 0.5, every pixel sees L_e / (1 - rho)
    // = 2, and with at most 3 segments L_e (1 - rho^3) / (1 - rho) = 1.75. Each lesson 7 render
    // (8 passes of 16 x 16 pixels) from its own seed is independent of the others: over K = 8
    // seeds, the image mean and the bootstrap's b (the image's mean luminance) against the
    // closed form, by Student's t with 7 degrees (Sidak over the 4 tests).
    const float rho = 0.5f, Le = 1.0f;
    Scene scene = test::furnace(rho, Le);
    scene.width = scene.height = 16;
    const double t_max = test::student_t_quantile(test::sidak(0.01, 4), 7);
    for (const int max_depth : {0, 3}) {
        const double expected =
            max_depth == 0 ? Le / (1.0 - rho) : Le * (1.0 - std::pow(rho, 3.0)) / (1.0 - rho);
        MetropolisOptions options;
        options.max_depth = max_depth;
        std::vector<double> means, bs;
        for (int seed = 0; seed < 8; ++seed) {
            const MetropolisModel model(scene, options);
            const RenderResult r =
                render_scene(scene, model, 8, test::independent_settings(300 + seed));
            EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
            means.push_back(image_average(r.image));
            bs.push_back(model.mean_b());
            // Every state carries light of luminance b / (mutations per pixel): the image's mean
            // luminance is b, up to the floats' sums (a lost splat would show here).
            EXPECT_NEAR(means.back(), bs.back(), 1e-4 * bs.back()) << "seed " << seed;
        }
        const test::MeanAndError m = test::mean_and_error(means), b = test::mean_and_error(bs);
        std::printf("depth %d: image %.5f +- %.5f, b %.5f +- %.5f, expected %.5f\n", max_depth,
                    m.mean, m.standard_error, b.mean, b.standard_error, expected);
        EXPECT_LT(std::fabs(m.mean - expected) / m.standard_error, t_max) << "depth " << max_depth;
        EXPECT_LT(std::fabs(b.mean - expected) / b.standard_error, t_max) << "depth " << max_depth;
    }
}

TEST(Metropolis, ALambertPlaneUnderAUniformSkyIsRhoTimesTheSkyInEveryPixel) {
    // The closed form lesson 3 checks (EveryEstimatorSeesTheUniformSky): a plane of albedo rho
    // under a sky of radiance L, which it sees all of and nothing else, reflects rho L; a flat
    // plane cannot see itself, so every path of two segments or more than one bounce carries
    // nothing, and every pixel of a camera looking down at it is rho L. The light comes from the
    // environment, which lesson 5's strategies reach three ways (a camera path escaping, a light
    // sample, light tracing from the sky). Over K = 8 seeds of 64 passes each, the image mean and
    // every pixel against rho L by Student's t with 7 degrees, Sidak over the pixels.
    const float rho = 0.6f, L = 2.0f;
    Scene scene;
    scene.add_quad(Quad(Vec3(-50, 0, -50), Vec3(0, 0, 100), Vec3(100, 0, 0)),
                   test::add_diffuse(scene, Color(rho)));
    scene.background = Color(L);
    scene.width = scene.height = 8;
    scene.camera = Camera(Vec3(0.3f, 3, 0.2f), Vec3(0, 0, 0), Vec3(0, 0, 1), 40.0f, 1.0f);
    scene.commit();
    const size_t pixels = 64;
    std::vector<std::vector<double>> per_pixel(pixels);
    std::vector<double> means;
    for (int seed = 0; seed < 8; ++seed) {
        const MetropolisModel model(scene, MetropolisOptions{});
        const RenderResult r =
            render_scene(scene, model, 64, test::independent_settings(500 + seed));
        EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
        means.push_back(image_average(r.image));
        for (size_t p = 0; p < pixels; ++p)
            per_pixel[p].push_back(static_cast<double>(luminance(r.image.pixels[p])));
    }
    const double expected = static_cast<double>(rho) * L;
    const test::MeanAndError m = test::mean_and_error(means);
    std::printf("image %.5f +- %.5f, expected %.5f\n", m.mean, m.standard_error, expected);
    EXPECT_LT(std::fabs(m.mean - expected) / m.standard_error,
              test::student_t_quantile(test::sidak(0.01, 2), 7));
    const double t_pixel =
        test::student_t_quantile(test::sidak(0.01, static_cast<int>(pixels)), 7);
    double worst = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
        const test::MeanAndError e = test::mean_and_error(per_pixel[p]);
        worst = std::max(worst, std::fabs(e.mean - expected) / e.standard_error);
    }
    std::printf("worst pixel |t| %.2f, limit %.2f\n", worst, t_pixel);
    EXPECT_LT(worst, t_pixel);
}

namespace {

// Per pixel, K independent lesson 7 renders against one long lesson 5 render: the difference of
// means over its standard error (lesson 7's across the K seeds, lesson 5's from its film), each
// channel; returns the largest |t| and the image means.
struct PixelAgreement {
    double worst_t = 0.0, mean7 = 0.0, mean5 = 0.0, se7 = 0.0;
    size_t worst_pixel = 0;
};
PixelAgreement against_lesson_five(const Scene& scene, const MetropolisOptions& options, int K,
                                   int passes, const RenderResult& five) {
    const size_t n = five.image.pixels.size();
    std::vector<std::vector<double>> runs(n * 3);
    std::vector<double> means;
    for (int seed = 0; seed < K; ++seed) {
        const MetropolisModel model(scene, options);
        const RenderResult r =
            render_scene(scene, model, passes, test::independent_settings(700 + seed));
        EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) runs[3 * i + c].push_back(r.image.pixels[i][c]);
        means.push_back(image_average(r.image));
    }
    PixelAgreement a;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            const test::MeanAndError m = test::mean_and_error(runs[3 * i + c]);
            const double se5 = std::sqrt(static_cast<double>(five.variance.pixels[i][c]));
            const double se = std::sqrt(m.standard_error * m.standard_error + se5 * se5);
            const double d = m.mean - static_cast<double>(five.image.pixels[i][c]);
            if (se == 0.0) {
                EXPECT_EQ(d, 0.0) << "pixel " << i;
            }
            if (se > 0.0 && std::fabs(d) / se > a.worst_t) {
                a.worst_t = std::fabs(d) / se;
                a.worst_pixel = i;
            }
        }
    const test::MeanAndError m = test::mean_and_error(means);
    a.mean7 = m.mean;
    a.se7 = m.standard_error;
    a.mean5 = image_average(five.image);
    return a;
}

}  // namespace

TEST(Metropolis, AgreesWithLessonFivePixelByPixelOnTheCornellBox) {
    // The Cornell box at 16 x 16: lesson 5 at 8,192 spp; lesson 7 over K = 16 seeds of 256
    // passes (a pass's image is far from normal in a dim pixel, which a chain visits in a few
    // clumps or not at all; the mean of 256 independent passes is close to normal), with large
    // steps only (every state an independent path: lesson 5's strategies
    // drawn one at a time) and with the defaults (mostly small steps). Each pixel and channel's
    // difference over its standard error within Student's t with 15 degrees at 0.01, Sidak over
    // every pixel and channel; the image means agree too.
    const Scene scene = small_scene("cornell_box.toml", 16, 16);
    const BidirectionalModel five_model(scene, BidirOptions{});
    const RenderResult five = render_scene(scene, five_model, 8192, test::independent_settings(77));
    const int K = 16;
    const double t_max = test::student_t_quantile(
        test::sidak(0.01, static_cast<int>(3 * five.image.pixels.size())), K - 1);
    for (const float large : {1.0f, 0.3f}) {
        MetropolisOptions options;
        options.large_step_probability = large;
        const PixelAgreement a = against_lesson_five(scene, options, K, 256, five);
        std::printf(
            "large steps %.1f: worst pixel t %.2f (limit %.2f); image mean %.5f +- %.5f "
            "against lesson 5's %.5f\n",
            large, a.worst_t, t_max, a.mean7, a.se7, a.mean5);
        EXPECT_LT(a.worst_t, t_max)
            << "large-step probability " << large << ", pixel " << a.worst_pixel;
        EXPECT_LT(std::fabs(a.mean7 - a.mean5) / a.se7, test::student_t_quantile(0.01, K - 1));
    }
}

TEST(Metropolis, IsTheSameForAnyNumberOfThreadsAndForPartsMerged) {
    // The chains of a pass are fixed in number and each draws from (seed, pass, chain); their
    // splats are summed in chain order. So 1, 2 and 3 threads give the same bits, and a render
    // split into passes [0, 2) and [2, 4), each with a model of its own, merges into the single
    // run's films exactly.
    const Scene scene = small_scene("cornell_spheres.toml", 32, 24);
    const MetropolisOptions options;
    std::vector<RenderResult> results;
    for (const int threads : {1, 2, 3})
        results.push_back(render_scene(scene, MetropolisModel(scene, options), 4,
                                       test::independent_settings(5, threads)));
    EXPECT_GT(image_average(results[0].image), 0.0);
    for (size_t k = 1; k < results.size(); ++k) {
        EXPECT_TRUE(test::same_bits(results[0].image, results[k].image)) << k + 1 << " threads";
        EXPECT_TRUE(test::same_bits(results[0].variance, results[k].variance))
            << k + 1 << " threads";
    }
    const RenderSettings settings = test::independent_settings(5);
    const MetropolisModel single_model(scene, options);
    ProgressiveFilms single(scene, single_model, 0.0f);
    ASSERT_TRUE(single.render_to(4, settings));
    std::vector<Film> merged;
    for (const int first : {0, 2}) {
        const MetropolisModel part_model(scene, options);
        RenderPart part;
        part.first_sample = first;
        ProgressiveFilms films(scene, part_model, 0.0f, part);
        ASSERT_TRUE(films.render_to(2, settings));
        if (merged.empty())
            merged = films.films();
        else
            merged[0].add(films.films()[0]);
    }
    EXPECT_TRUE(test::same_bits(single.films()[0].mean(), merged[0].mean()));
    EXPECT_TRUE(test::same_bits(single.films()[0].mean(), results[0].image));
}
