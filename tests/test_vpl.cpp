// Lesson 6's instant radiosity (--method vpl, chapters/06_photon_mapping/vpl.h): the furnace in
// closed form with and without the cap on G and with its compensation; glossy and metal surfaces
// lit only by virtual lights against lesson 5; the same bits for any number of threads and for a
// render split into parts; the technique images add up to the image (docs/accuracy.md).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "05_bidirectional/bidirectional.h"
#include "06_photon_mapping/photon_mapping.h"
#include "io/scene_file.h"
#include "render/progressive.h"
#include "render_statistics.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

PhotonOptions vpl_options(float clamp, bool compensate, int vpls = 16, int max_depth = 0) {
    PhotonOptions options;
    options.method = PhotonMethod::VirtualLights;
    options.paths.max_depth = max_depth;
    options.vpls = vpls;
    options.vpl_clamp = clamp;
    options.vpl_compensate = compensate;
    return options;
}

// The mean over the image's pixels, of channel x.
double image_average(const Image& image) {
    double sum = 0.0;
    for (const Color& c : image.pixels) sum += c.x;
    return sum / static_cast<double>(image.pixels.size());
}

// The two-sided 0.01 quantile of Student's t with 7 degrees of freedom (8 batch means).
const double kStudentT7 = test::student_t_quantile(0.01, 7);

}  // namespace

TEST(Vpl, TheFurnaceIsItsClosedFormUncappedCappedAndCompensated) {
    // Inside a sphere of radius R = 1 that emits L_e = 1 and reflects rho = 0.5, any two points
    // see each other with G = cos cos / d^2 = 1 / (4 R^2) = 0.25 (each cosine is d / 2R). The
    // virtual lights carry the light reflected at their points, rho L_e / (1 - rho), so:
    //   a cap at or above 0.25 removes nothing:           L_e / (1 - rho)                  = 2
    //   a cap kappa 0.25, kappa = 0.5, keeps kappa of G:  L_e + rho L_e + kappa rho^2 L_e /
    //                                                     (1 - rho)                        = 1.75
    //   that cap compensated:                             L_e / (1 - rho)                  = 2
    // With at most k segments (--max-depth 3 below) every term keeps its paths of up to k
    // segments, and the image is L_e (1 - rho^k) / (1 - rho) with or without the cap
    // compensated. Every pixel sees the same radiance; each pass's virtual lights and camera
    // samples are independent of the others', so each pixel's film variance is that of its mean.
    // A z-test per pixel (Sidak over the 64 pixels of six cases). Inside the furnace a pixel's
    // sample hardly depends on the camera's random numbers (the first hit emits and reflects
    // alike everywhere), so a pass's pixels agree and the 64 tests are nearly one: the
    // correction is conservative.
    const float rho = 0.5f, Le = 1.0f, kappa = 0.5f;
    const Scene scene = test::furnace(rho, Le);
    const double full = Le / (1.0 - rho);
    const double capped = Le + rho * Le + kappa * rho * rho * Le / (1.0 - rho);
    const double three = Le * (1.0 - rho * rho * rho) / (1.0 - rho);
    struct Case {
        float clamp;
        bool compensate;
        double expected;
        int max_depth = 0;
    };
    const Case cases[] = {
        {0.0f, false, full},         {0.25f, false, full},    {kappa * 0.25f, false, capped},
        {kappa * 0.25f, true, full}, {0.0f, false, three, 3}, {kappa * 0.25f, true, three, 3}};
    const double z_max = test::z_quantile(test::sidak(0.01, 6 * 64));
    for (const Case& c : cases) {
        const PhotonMappingModel model(scene, vpl_options(c.clamp, c.compensate, 16, c.max_depth));
        const RenderResult r = render_scene(scene, model, 256, test::independent_settings(41));
        EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
        double worst = 0.0, mean = 0.0;
        for (size_t i = 0; i < r.image.pixels.size(); ++i) {
            const double v = r.image.pixels[i].x, se = std::sqrt(r.variance.pixels[i].x);
            worst = std::max(worst, std::fabs(v - c.expected) / se);
            mean += v / static_cast<double>(r.image.pixels.size());
        }
        std::printf("cap %.4f%s, depth %d: image mean %.5f, expected %.5f, worst pixel z %.2f\n",
                    c.clamp, c.compensate ? " compensated" : "", c.max_depth, mean, c.expected,
                    worst);
        EXPECT_LT(worst, z_max) << "cap " << c.clamp << (c.compensate ? ", compensated" : "")
                                << ": mean " << mean << " against " << c.expected;
    }
}

namespace {

// A closed box [-1, 1]^3 of grey walls whose lamp, under the ceiling, faces up: the ceiling is
// lit directly and everything else by light that bounced at least once. The camera looks down at
// the floor, half glossy (Blinn-Phong over Lambert), half a GGX metal: what it sees is lit by
// the virtual lights alone (a light sample finds the lamp's back, which emits nothing). The
// walls at x = -1 and x = +1 are glossy and metal too, so that virtual lights lie on them and
// their own BSDFs send the light to the floor (the floor's own lights cannot: G = 0 in a plane).
const char* kIndirectBox = R"(
[image]
width = 16
height = 16
[camera]
position = [0.0, 0.6, -0.6]
look_at = [0.0, -1.0, 0.1]
up = [0, 0, 1]
fov = 50
[materials.wall]
type = "diffuse"
albedo = [0.6, 0.6, 0.6]
[materials.glossy]
type = "glossy"
albedo = [0.3, 0.3, 0.3]
specular = [0.5, 0.5, 0.5]
roughness = 0.3
[materials.metal]
type = "conductor"
specular = [0.9, 0.7, 0.4]
roughness = 0.25
[materials.lamp]
type = "diffuse"
emission = [20, 20, 20]
[[shapes]]  # the floor, glossy half (x < 0), facing up
type = "quad"
material = "glossy"
corner = [-1.0, -1.0, -1.0]
edge_u = [0.0, 0.0, 2.0]
edge_v = [1.0, 0.0, 0.0]
[[shapes]]  # the floor, metal half
type = "quad"
material = "metal"
corner = [0.0, -1.0, -1.0]
edge_u = [0.0, 0.0, 2.0]
edge_v = [1.0, 0.0, 0.0]
[[shapes]]  # the ceiling, facing down
type = "quad"
material = "wall"
corner = [-1.0, 1.0, -1.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 2.0]
[[shapes]]  # the wall at x = -1, glossy
type = "quad"
material = "glossy"
corner = [-1.0, -1.0, -1.0]
edge_u = [0.0, 2.0, 0.0]
edge_v = [0.0, 0.0, 2.0]
[[shapes]]  # the wall at x = +1, metal
type = "quad"
material = "metal"
corner = [1.0, -1.0, -1.0]
edge_u = [0.0, 0.0, 2.0]
edge_v = [0.0, 2.0, 0.0]
[[shapes]]
type = "quad"
material = "wall"
corner = [-1.0, -1.0, 1.0]
edge_u = [0.0, 2.0, 0.0]
edge_v = [2.0, 0.0, 0.0]
[[shapes]]
type = "quad"
material = "wall"
corner = [-1.0, -1.0, -1.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 2.0, 0.0]
[[shapes]]  # the lamp, facing up at the ceiling
type = "quad"
material = "lamp"
corner = [-0.2, 0.8, -0.2]
edge_u = [0.0, 0.0, 0.4]
edge_v = [0.4, 0.0, 0.0]
)";

Scene load_text(const std::string& name, const char* text) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / (name + std::to_string(getpid()) + ".toml");
    std::ofstream(path) << text;
    Scene scene = load_scene(path.string());
    std::filesystem::remove(path);
    return scene;
}

}  // namespace

TEST(Vpl, GlossyAndMetalLitOnlyByVirtualLightsMatchLessonFive) {
    // Without the cap, instant radiosity is unbiased, and a virtual light evaluates its own BSDF
    // towards the point it lights: on the glossy and the metal floor, lit by nothing else, the
    // image's mean equals lesson 5's. A pass's virtual lights light every pixel, so pixels are
    // not independent: the standard error comes from 8 renders with different seeds (batch
    // means), for both lessons (lesson 5's light tracing splats across pixels too). A t-test
    // with 7 degrees of freedom (the fewer of the two) on the difference's standard error.
    const Scene scene = load_text("vpl_indirect_box", kIndirectBox);
    std::vector<double> vpl, bpt;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        const PhotonMappingModel ir(scene, vpl_options(0.0f, false, 32));
        vpl.push_back(
            image_average(render_scene(scene, ir, 64, test::independent_settings(seed)).image));
        const BidirectionalModel lesson5(scene, BidirOptions{});
        bpt.push_back(image_average(
            render_scene(scene, lesson5, 64, test::independent_settings(100 + seed)).image));
    }
    const auto [m_vpl, se_vpl] = test::mean_and_error(vpl);
    const auto [m_bpt, se_bpt] = test::mean_and_error(bpt);
    const double se = std::sqrt(se_vpl * se_vpl + se_bpt * se_bpt);
    std::printf("vpl %.5f (se %.5f), lesson 5 %.5f (se %.5f)\n", m_vpl, se_vpl, m_bpt, se_bpt);
    ASSERT_GT(m_bpt, 0.0);
    EXPECT_LT(std::fabs(m_vpl - m_bpt), kStudentT7 * se)
        << "vpl " << m_vpl << " against lesson 5 " << m_bpt << " (combined se " << se << ")";
    // The cap removes light here (the default cap acts on connections under 0.35 m): the
    // test can tell a bias apart.
    std::vector<double> capped;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        const PhotonMappingModel ir(scene, vpl_options(-1.0f, false, 32));
        capped.push_back(
            image_average(render_scene(scene, ir, 64, test::independent_settings(seed)).image));
    }
    const auto [m_cap, se_cap] = test::mean_and_error(capped);
    std::printf("vpl with the default cap %.5f (se %.5f)\n", m_cap, se_cap);
    EXPECT_GT(m_bpt - m_cap, kStudentT7 * std::sqrt(se_cap * se_cap + se_bpt * se_bpt));
    EXPECT_LT(m_cap, m_vpl);  // the same seeds: the cap only takes light away
}

TEST(Vpl, ItsTechniqueImagesAddUpToTheImage) {
    // direct (emission and the light sample), vpl (the capped virtual lights) and compensation
    // (what the cap removed, by BSDF samples) add up to the image, and with a cap acting in this
    // small box the last two both carry light. (The same bits for any number of threads and for
    // a render split into parts: PhotonMapping.IsTheSameForAnyNumberOfThreads and
    // PhotonMapping.PassesSplitAcrossPartsMergeIntoTheSingleRun, which run vpl too.)
    const Scene scene = load_text("vpl_indirect_box_layers", kIndirectBox);
    PhotonOptions options = vpl_options(-1.0f, true);
    options.technique_layers = true;
    const RenderResult r =
        render_scene(scene, PhotonMappingModel(scene, options), 4, test::independent_settings(7));
    ASSERT_EQ(r.layers.size(), 3u);
    double worst = 0.0;
    for (size_t i = 0; i < r.image.pixels.size(); ++i) {
        Color sum(0.0f);
        for (const Image& layer : r.layers) sum += layer.pixels[i];
        const Color d = sum - r.image.pixels[i];
        worst = std::max(
            worst, static_cast<double>(std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)})));
    }
    EXPECT_LT(worst, 1e-4 * std::max(1.0, image_average(r.image)));
    EXPECT_GT(image_average(r.layers[1]), 0.0);  // the virtual lights
    EXPECT_GT(image_average(r.layers[2]), 0.0);  // the compensation
}
