// Lesson 6's estimators through the model (PhotonMappingModel, as the render loop runs it):
// photon mapping's fixed radius blurs the light by the kernel, exactly; progressive photon
// mapping's error falls without levelling off; the images do not depend on the threads or on
// how the passes are split into parts; the report and the photons' memory cap
// (docs/accuracy.md, "Density estimation").
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "06_photon_mapping/photon_mapping.h"
#include "06_photon_mapping/radius.h"
#include "image_sources.h"
#include "io/scene_file.h"
#include "render_statistics.h"
#include "test_util.h"

using namespace lessons;
using test::MirroredPointLight;

namespace {

// Photon mapping (or its progressive form) on the mirrored point light: paths of at most three
// segments, so the photons that count (vertex 2 and on, gather.cpp) are exactly those that came
// off the mirror (the floor's photons at vertex 1 are direct light, the light sample's; a
// photon at vertex 3 would make four segments).
PhotonOptions three_segments(PhotonMethod method, float radius, Kernel kernel = Kernel::Constant) {
    PhotonOptions options;
    options.method = method;
    options.radius = radius;
    options.kernel = kernel;
    options.paths.max_depth = 3;
    options.paths.roulette_after = -1;
    return options;
}

}  // namespace

TEST(PhotonMapping, AFixedRadiusConvergesToTheKernelsBlurOfAPointLightsIrradiance) {
    // A point light (I = 1 W/sr) 0.5 m over a diffuse floor (rho = 0.5), under a mirror (R = 0.8)
    // at 0.75 m: the floor gets the light's E_d = I h / (h^2 + d^2)^(3/2) and its image's
    // E_m = R I h' / (h'^2 + d^2)^(3/2), h' = 1 m. Photon mapping (--method pm, paths of at most
    // three segments) takes E_d by a light sample at the camera's first hit x (exact: one point
    // light) and E_m from the photons that came off the mirror; lesson 4 could not find E_m at
    // all (a point light after a mirror). At a fixed radius r = 0.4 m the pixel whose centre sees
    // the light's foot has expectation rho/pi (E_d(0) + (K * E_m)(0)), K * E_m the kernel's
    // average of E_m over the disk (image_sources.h), several percent below E_m(0) where E_m
    // curves most. 1024 passes of 33 x 33 light subpaths, the camera rays through the pixel
    // centres (no jitter), independent samples: the film's variance is that of the passes. For
    // both kernels, a z-test against the blurred value (Sidak over the two), and the unblurred
    // value rejected by many standard errors.
    const MirroredPointLight m;
    const Scene scene = test::point_light_under_a_mirror(m, 33, 0.7f, 46.0f);
    RenderSettings settings = test::quiet_settings(93);
    settings.jitter = false;
    const size_t centre = 16 * 33 + 16;
    const Ray ray = scene.camera.generate_ray(16.5f, 16.5f, 33, 33);
    const auto [x, z] = test::on_the_floor(ray);
    const double d = std::hypot(x, z);
    ASSERT_LT(d, 1e-6);
    const float r = 0.4f;
    const double z_max = test::z_quantile(test::sidak(0.01, 2));
    for (const Kernel kernel : {Kernel::Constant, Kernel::Epanechnikov}) {
        const PhotonMappingModel pm(scene, three_segments(PhotonMethod::PhotonMapping, r, kernel));
        const RenderResult result = render_scene(scene, pm, 1024, settings);
        const double value = result.image.pixels[centre].x;
        const double standard_error = std::sqrt(result.variance.pixels[centre].x);
        const double f = m.rho / kPi;
        const double blurred =
            f * (m.direct(d) + test::kernel_average(kernel, r, x, z, [&](double u, double v) {
                     return m.mirrored(std::hypot(u, v));
                 }));
        const double unblurred = f * (m.direct(d) + m.mirrored(d));
        const double z_blurred = std::fabs(value - blurred) / standard_error;
        const double z_unblurred = std::fabs(value - unblurred) / standard_error;
        std::printf(
            "%-12s: rho/pi (E_d + E_m) %.6f, blurred %.6f, rendered %.6f (standard error "
            "%.6f): z %.2f against the blurred value, %.1f against the unblurred\n",
            kernel_name(kernel), unblurred, blurred, value, standard_error, z_blurred, z_unblurred);
        EXPECT_LT(z_blurred, z_max) << kernel_name(kernel) << ": " << value << " against "
                                    << blurred << " (standard error " << standard_error << ")";
        EXPECT_GT(z_unblurred, 10.0) << kernel_name(kernel) << ": the kernel's blur should be "
                                     << "many standard errors at the light's foot";
    }
}

namespace {

// Least squares slope of log y against log x.
double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double mx = 0.0, my = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
        mx += std::log(x[i]) / x.size();
        my += std::log(y[i]) / y.size();
    }
    double sxy = 0.0, sxx = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
        sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
        sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
    }
    return sxy / sxx;
}

// The two-sided 0.01 quantile of Student's t with 7 degrees of freedom (8 seeds' slopes).
const double kStudentT7 = test::student_t_quantile(0.01, 7);

}  // namespace

TEST(Ppm, TheErrorFallsWithoutLevellingOff) {
    // Progressive photon mapping (Knaus and Zwicker 2011): pass k (k = 1, 2, ...) is photon
    // mapping at radius r_k = r_1 k^((alpha - 1) / 2), and the image averages the passes. On the
    // mirrored point light (33 x 33 pixels, each seen at its centre, whose radiance is known in
    // closed form: rho/pi (E_d + E_m), image_sources.h), the MSE over the image after K passes,
    // K = 4, 16, 64, 256. The kernel's bias of pass k goes as r_k^2 and its variance as
    // 1 / (N r_k^2), so the average's squared bias falls as K^(2 (alpha - 1)) and its variance as
    // K^(-alpha): at alpha = 2/3 both as K^(-2/3), the slope of log MSE against log K. At these K
    // the sums over the passes are not yet their integrals, and at r_1 = 0.4 m the bias is not
    // yet r^2 alone, so the expected slope is computed, not assumed: from the closed form of
    // each pass's bias (the kernel's average of E_m less E_m) and variance (each light subpath
    // leaves at most one photon off the mirror, of power 4 pi I R: a Bernoulli count; pm's
    // variance per pass is (K beta C - C^2) / N, C the kernel's average), giving E[MSE_K].
    // The measured slope (least squares over the four K, per seed; 8 seeds) must be within
    // Student's t (0.01, 7 degrees of freedom) standard errors of that, hence within that plus
    // |expected - (-2/3)| of -min(alpha, 2 (1 - alpha)) = -2/3; so must the last segment's
    // (64 -> 256: no levelling off); the MSE falls at every step; and at 256 passes it is below
    // photon mapping's at the fixed r_1, whose bias stays.
    const MirroredPointLight m;
    const int size = 33;
    const Scene scene = test::point_light_under_a_mirror(m, size, 0.7f, 90.0f);
    const float r1 = 0.4f;
    const std::vector<double> Ks = {4, 16, 64, 256};
    const int seeds = 8, N = size * size;
    RenderSettings settings = test::quiet_settings(0);
    settings.jitter = false;

    // Each pixel's distance from the light's foot and its radiance.
    std::vector<double> distance, truth;
    test::for_each_pixel_center(scene.camera, size, size, [&](int, int, Ray ray) {
        const auto [x, z] = test::on_the_floor(ray);
        distance.push_back(std::hypot(x, z));
        truth.push_back(m.rho / kPi * (m.direct(distance.back()) + m.mirrored(distance.back())));
    });

    // E[MSE_K] from each pass's bias and variance, for radii r_k (k = 1 .. 256).
    const double f = m.rho / kPi, beta = 4.0 * kPi * m.I * m.R;
    auto expected_mse = [&](float alpha) {
        std::map<double, std::pair<double, double>> cache;  // by distance: bias and variance sums
        std::vector<double> mse(Ks.size(), 0.0);
        std::vector<double> bias_sum(distance.size(), 0.0), variance_sum(distance.size(), 0.0);
        for (int k = 1; k <= static_cast<int>(Ks.back()); ++k) {
            const double r = r1 * std::pow(k, (alpha - 1.0) / 2.0);  // Knaus and Zwicker's
            cache.clear();
            for (size_t i = 0; i < distance.size(); ++i) {
                auto [it, fresh] = cache.try_emplace(distance[i]);
                if (fresh) {
                    const double C = test::kernel_average(
                        Kernel::Constant, r, distance[i], 0.0,
                        [&](double u, double v) { return m.mirrored(std::hypot(u, v)); });
                    it->second = {f * (C - m.mirrored(distance[i])),
                                  f * f * (beta / (kPi * r * r) * C - C * C) / N};
                }
                bias_sum[i] += it->second.first;
                variance_sum[i] += it->second.second;
            }
            for (size_t j = 0; j < Ks.size(); ++j) {
                if (k != static_cast<int>(Ks[j])) continue;
                for (size_t i = 0; i < distance.size(); ++i)
                    mse[j] += (std::pow(bias_sum[i] / k, 2) + variance_sum[i] / (k * k)) /
                              distance.size();
            }
        }
        return mse;
    };

    // The measured MSE after each K, per seed.
    auto measured_mse = [&](PhotonMethod method, uint64_t seed) {
        const PhotonMappingModel model(scene, three_segments(method, r1));
        ProgressiveFilms films(scene, model, 0.0f);
        settings.seed = seed;
        std::vector<double> mse;
        for (const double K : Ks) {
            EXPECT_TRUE(films.render_to(static_cast<int>(K), settings));
            const Image image = films.result().image;
            double sum = 0.0;
            for (size_t i = 0; i < truth.size(); ++i)
                sum += std::pow(image.pixels[i].x - truth[i], 2) / truth.size();
            mse.push_back(sum);
        }
        return mse;
    };

    const float alpha =
        PhotonMappingModel(scene, three_segments(PhotonMethod::Progressive, r1)).alpha();
    ASSERT_LT(alpha, 1.0f) << "ppm's radius must shrink";
    const double asymptotic = -std::min(alpha, 2.0f * (1.0f - alpha));
    const std::vector<double> expected = expected_mse(alpha);
    const std::vector<double> expected_pm = expected_mse(1.0f);
    const double expected_slope = log_log_slope(Ks, expected);
    // The setup's own check: at these K the expected slope is already near its limit (so the
    // tolerance below is mostly the measurement's).
    ASSERT_LT(std::fabs(expected_slope - asymptotic), 0.05) << expected_slope;
    const double expected_last = std::log(expected[3] / expected[2]) / std::log(4.0);
    std::vector<double> slopes, lasts, mean_mse(Ks.size(), 0.0), mean_pm(Ks.size(), 0.0);
    for (int seed = 1; seed <= seeds; ++seed) {
        const std::vector<double> ppm = measured_mse(PhotonMethod::Progressive, 100 + seed);
        const std::vector<double> pm = measured_mse(PhotonMethod::PhotonMapping, 100 + seed);
        slopes.push_back(log_log_slope(Ks, ppm));
        lasts.push_back(std::log(ppm[3] / ppm[2]) / std::log(4.0));
        for (size_t j = 0; j < Ks.size(); ++j) {
            mean_mse[j] += ppm[j] / seeds;
            mean_pm[j] += pm[j] / seeds;
        }
    }
    const test::MeanAndError slope = test::mean_and_error(slopes);
    const test::MeanAndError last = test::mean_and_error(lasts);
    for (size_t j = 0; j < Ks.size(); ++j)
        std::printf("K = %3.0f: ppm MSE %.4g (expected %.4g), pm MSE %.4g (expected %.4g)\n", Ks[j],
                    mean_mse[j], expected[j], mean_pm[j], expected_pm[j]);
    std::printf(
        "slope %.3f +- %.3f (expected %.3f, asymptotically %.3f); 64 -> 256: %.3f +- %.3f "
        "(expected %.3f)\n",
        slope.mean, slope.standard_error, expected_slope, asymptotic, last.mean,
        last.standard_error, expected_last);
    EXPECT_NEAR(slope.mean, expected_slope, kStudentT7 * slope.standard_error);
    EXPECT_NEAR(slope.mean, asymptotic,
                std::fabs(expected_slope - asymptotic) + kStudentT7 * slope.standard_error);
    EXPECT_NEAR(last.mean, expected_last, kStudentT7 * last.standard_error);
    for (size_t j = 1; j < Ks.size(); ++j)
        EXPECT_LT(mean_mse[j], mean_mse[j - 1]) << "K = " << Ks[j];
    EXPECT_LT(mean_mse.back(), mean_pm.back()) << "ppm against pm at " << Ks.back() << " passes";
}

namespace {

// The box with a mirror and a glass ball (caustics, chains of delta vertices), small but with
// N = 768 light subpaths per pass: three parts of at least 256 (photons.cpp), so each of three
// threads traces some.
Scene small_cornell_spheres() {
    return load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_spheres.toml", {32, 24});
}

PhotonOptions with_layers(PhotonMethod method) {
    PhotonOptions options;
    options.method = method;
    options.technique_layers = true;
    return options;
}

}  // namespace

TEST(PhotonMapping, IsTheSameForAnyNumberOfThreads) {
    // Each pass's photons are traced in contiguous ranges of subpaths, one per thread, each
    // subpath from its own random numbers (photons.h), and the grid is built by a stable sort
    // (photon_map.h); the pixels' samples and splats are the render loop's (render.h). So the
    // image, its variance and every technique image are the same bits on 1, 2 and 3 threads,
    // for vcm (joins, merges, light tracing), ppm (a radius that changes every pass) and vpl (the
    // pass's virtual lights).
    const Scene scene = small_cornell_spheres();
    for (const PhotonMethod method :
         {PhotonMethod::VertexMerging, PhotonMethod::Progressive, PhotonMethod::VirtualLights}) {
        const PhotonOptions options = with_layers(method);
        std::vector<RenderResult> results;
        for (const int threads : {1, 2, 3})
            results.push_back(render_scene(scene, PhotonMappingModel(scene, options), 4,
                                           test::quiet_settings(94, threads)));
        ASSERT_EQ(results[0].layers.size(), method == PhotonMethod::Progressive ? 2u : 3u);
        EXPECT_GT(test::image_mean(results[0].image, results[0].variance).first, 0.0);
        for (size_t k = 1; k < results.size(); ++k) {
            const char* name = photon_method_name(method);
            EXPECT_TRUE(test::same_bits(results[0].image, results[k].image))
                << name << ", " << k + 1;
            EXPECT_TRUE(test::same_bits(results[0].variance, results[k].variance))
                << name << ", " << k + 1 << " threads";
            for (size_t l = 0; l < results[0].layers.size(); ++l)
                EXPECT_TRUE(test::same_bits(results[0].layers[l], results[k].layers[l]))
                    << name << ", layer " << l << ", " << k + 1 << " threads";
        }
    }
}

TEST(PhotonMapping, PassesSplitAcrossPartsMergeIntoTheSingleRun) {
    // A render split by sample ranges (docs/farm.md): pass k's photons and radius depend on k
    // alone (begin_pass), so a part that renders passes [2, 4) with a model of its own makes the
    // same samples as the single run's passes 2 and 3. The films of [0, 2) and [2, 4), added,
    // hold the single run's sums exactly (film.h) and give its image bit for bit, for vcm, ppm
    // and vpl, with their technique images.
    const Scene scene = small_cornell_spheres();
    const RenderSettings settings = test::quiet_settings(95);
    for (const PhotonMethod method :
         {PhotonMethod::VertexMerging, PhotonMethod::Progressive, PhotonMethod::VirtualLights}) {
        const char* name = photon_method_name(method);
        const PhotonOptions options = with_layers(method);
        const PhotonMappingModel single_model(scene, options);
        ProgressiveFilms single(scene, single_model, 0.0f);
        ASSERT_TRUE(single.render_to(4, settings));

        std::vector<Film> merged;
        for (const int first : {0, 2}) {
            const PhotonMappingModel part_model(scene, options);  // as a part's own run makes
            RenderPart part;
            part.first_sample = first;
            ProgressiveFilms films(scene, part_model, 0.0f, part);
            ASSERT_TRUE(films.render_to(2, settings));
            if (merged.empty()) {
                merged = films.films();
            } else {
                for (size_t f = 0; f < merged.size(); ++f) merged[f].add(films.films()[f]);
            }
        }
        ASSERT_EQ(merged.size(), single.films().size());
        for (size_t f = 0; f < merged.size(); ++f) {
            const std::span<const FilmPixel> a = single.films()[f].pixels();
            const std::span<const FilmPixel> b = merged[f].pixels();
            size_t differ = 0;
            for (size_t i = 0; i < a.size(); ++i)
                differ += a[i].valid != b[i].valid || a[i].sum[0] != b[i].sum[0] ||
                          a[i].sum[1] != b[i].sum[1] || a[i].sum[2] != b[i].sum[2];
            EXPECT_EQ(differ, 0u) << name << ", film " << f << ": pixels whose sums differ";
            EXPECT_TRUE(test::same_bits(single.films()[f].mean(), merged[f].mean()))
                << name << ", film " << f;
        }
    }
}

TEST(PhotonMapping, PmAndPpmCropsRenderedApartMergeIntoTheSingleRun) {
    // pm and ppm render in passes (each pass has its photons) but splat nothing, so a crop
    // (--pixels) renders its pixels as the whole image does: the same rays, random numbers and
    // photons. Crops rendered apart, each with a model of its own as a part's run makes,
    // added into the whole films give the single run's films bit for bit. vcm splats, so it
    // takes no crop.
    const Scene scene = small_cornell_spheres();
    const RenderSettings settings = test::quiet_settings(96);
    for (const PhotonMethod method : {PhotonMethod::PhotonMapping, PhotonMethod::Progressive}) {
        const char* name = photon_method_name(method);
        const PhotonOptions options = with_layers(method);
        const PhotonMappingModel single_model(scene, options);
        ASSERT_TRUE(single_model.passes);
        ASSERT_FALSE(single_model.splats);
        ProgressiveFilms single(scene, single_model, 0.0f);
        ASSERT_TRUE(single.render_to(3, settings));

        const int w = scene.width, h = scene.height;
        std::vector<Film> merged(single.films().size(), Film(w, h));
        for (const auto& [x0, x1, y0, y1] : std::vector<std::array<int, 4>>{
                 {0, w / 3, 0, h}, {w / 3, w, 0, h / 2}, {w / 3, w, h / 2, h}}) {
            const PhotonMappingModel part_model(scene, options);
            RenderPart part;
            part.x0 = x0, part.x1 = x1, part.y0 = y0, part.y1 = y1;
            ProgressiveFilms crop(scene, part_model, 0.0f, part);
            ASSERT_TRUE(crop.render_to(3, settings));
            for (size_t f = 0; f < merged.size(); ++f)
                merged[f].add_window(crop.films()[f], x0, y0);
        }
        for (size_t f = 0; f < merged.size(); ++f)
            EXPECT_TRUE(test::same_bits(single.films()[f].mean(), merged[f].mean()))
                << name << ", film " << f;
    }
    const PhotonMappingModel vcm(scene, with_layers(PhotonMethod::VertexMerging));
    RenderPart half;
    half.x1 = scene.width / 2, half.y1 = scene.height;
    ProgressiveFilms crop(scene, vcm, 0.0f, half);
    EXPECT_THROW(crop.render_to(1, settings), std::logic_error);
}

namespace {

namespace fs = std::filesystem;

struct CommandResult {
    int exit_code;
    std::string output;  // stdout and stderr
};

// Runs a shell command, as the CLI tests do (test_cli.cpp).
CommandResult run(const std::string& command) {
    static int calls = 0;
    const fs::path log = fs::temp_directory_path() / ("lessons_photon_" + std::to_string(getpid()) +
                                                      "_" + std::to_string(++calls) + ".log");
    const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    fs::remove(log);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

std::string read_text(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The value of a field of the report's flat JSON object, as written ("" if it has none).
std::string report_field(const std::string& json, const std::string& key) {
    const std::string name = "\"" + key + "\": ";
    const size_t at = json.find(name);
    if (at == std::string::npos) return "";
    const size_t begin = at + name.size();
    return json.substr(begin, json.find_first_of(",\n}", begin) - begin);
}

double report_number(const std::string& json, const std::string& key) {
    const std::string v = report_field(json, key);
    return v.empty() ? std::nan("") : std::strtod(v.c_str(), nullptr);
}

}  // namespace

TEST(PhotonMapping, ReportsItsRadiusAndPhotonMemoryAndRefusesOverItsCap) {
    // The run's report says the method, the kernel, alpha, the first radius and the one its last
    // pass reached (r_1 K^((alpha - 1) / 2) after K passes: pass_radius of pass K - 1) and the
    // most memory one pass's photons took. ppm with a given radius and alpha; vcm with its
    // defaults (two pixel footprints at the median distance, radius.h; alpha 3/4); bpt makes no
    // photons and says only its method. The flags: a fixed radius (pm) is biased and not
    // consistent; a shrinking one (ppm, vcm where it merges: --merging always on this box of
    // diffuse walls) biased but consistent; bpt here neither. A cap below one pass's photons stops
    // the run before its first pass: exit status 2 (bad input), one line naming --max-photon-mb and
    // the size over it, no image.
    const fs::path dir =
        fs::temp_directory_path() / ("lessons_photon_report_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene_file = std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml";
    const std::string lesson = std::string(LESSONS_BIN_DIR) + "/06_photon_mapping --scene " +
                               scene_file + " --width 16 --height 16 --quiet";
    const int K = 5;
    struct Case {
        const char* method;
        std::string flags;
        double r1, alpha;
        const char *biased, *consistent;
    };
    const Scene scene = load_scene(scene_file, {16, 16});
    const Case cases[] = {
        {"pm", "--radius 0.05", 0.05, 1.0, "true", "false"},
        {"ppm", "--radius 0.05 --alpha 0.5", 0.05, 0.5, "true", "true"},
        {"vcm", "--merging always", default_photon_radius(scene), 0.75, "true", "true"},
        {"bpt", "", 0.0, 0.0, "false", "true"}};
    for (const Case& c : cases) {
        const fs::path report = dir / (std::string(c.method) + ".json");
        const CommandResult r =
            run(lesson + " --spp " + std::to_string(K) + " --method " + c.method + " " + c.flags +
                " --out " + (dir / c.method).string() + " --report " + report.string());
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const std::string json = read_text(report);
        EXPECT_EQ(report_field(json, "method"), "\"" + std::string(c.method) + "\"") << json;
        EXPECT_EQ(report_field(json, "biased"), c.biased) << json;
        EXPECT_EQ(report_field(json, "consistent"), c.consistent) << json;
        if (std::string(c.method) == "bpt") {
            for (const char* field : {"radius_first", "radius_reached", "photon_bytes", "kernel"})
                EXPECT_EQ(report_field(json, field), "") << field << " in\n" << json;
            continue;
        }
        EXPECT_EQ(report_field(json, "kernel"), "\"constant\"") << json;
        EXPECT_NEAR(report_number(json, "alpha"), c.alpha, 1e-7) << json;
        EXPECT_NEAR(report_number(json, "radius_first"), c.r1, 1e-7 * c.r1) << json;
        const double reached = c.r1 * std::pow(static_cast<double>(K), (c.alpha - 1.0) / 2.0);
        EXPECT_NEAR(report_number(json, "radius_reached"), reached, 1e-6 * reached) << json;
        EXPECT_GT(report_number(json, "photon_bytes"), 0.0) << json;
        EXPECT_GT(report_number(json, "photons_per_pass"), 0.0) << json;
    }

    const CommandResult capped =
        run(lesson + " --spp 2 --merging always --max-photon-mb 0.001 --out " +
            (dir / "capped").string());
    EXPECT_EQ(capped.exit_code, 2) << capped.output;
    EXPECT_NE(capped.output.find("06_photon_mapping: error: "), std::string::npos) << capped.output;
    EXPECT_NE(capped.output.find("--max-photon-mb"), std::string::npos) << capped.output;
    const size_t take = capped.output.find(" take ");  // "the photons of pass 0 take X MiB"
    ASSERT_NE(take, std::string::npos) << capped.output;
    EXPECT_GT(std::strtod(capped.output.c_str() + take + 6, nullptr), 0.001) << capped.output;
    EXPECT_FALSE(fs::exists(dir / "capped.exr"));
    fs::remove_all(dir);
}
