// Speed against error: an unbiased lesson's MSE falls as 1/spp; a local model's does not.
// The reference is the furnace's closed form (radiance 5 everywhere), which no renderer made.
#include <gtest/gtest.h>

#include "01_ray_casting/ray_casting.h"
#include "04_rendering_equation/rendering_equation.h"
#include "driver/app.h"
#include "io/scene_file.h"

using namespace lessons;

namespace {
std::vector<Checkpoint> convergence(const Scene& scene, const Model& model, int spp) {
    Image reference(scene.width, scene.height);
    for (Color& c : reference.pixels) c = Color(5.0f);  // L_e / (1 - rho) = 1 / 0.2
    std::vector<Checkpoint> points;
    ProgressivePlan plan;
    plan.spp = spp;
    plan.reference = &reference;
    plan.on_checkpoint = [&](const Checkpoint& c) { points.push_back(c); };
    RenderSettings settings;
    settings.progress = false;
    settings.seed = 7;
    render_progressive(scene, model, plan, settings, nullptr);
    return points;
}
}  // namespace

TEST(Convergence, PathTracingMseFallsAsOneOverSpp) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/furnace.toml", {48, 48});
    const LightSampler lights(scene);
    const std::vector<Checkpoint> points = convergence(scene, PathTracingModel(scene, {}), 32);
    ASSERT_EQ(points.size(), 6u);  // 1, 2, 4, 8, 16, 32
    // Least-squares slope of log MSE against log spp over the last four doublings (2 .. 32).
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const int n = 5;
    for (int i = 1; i < 6; ++i) {
        const double x = std::log(points[i].spp), y = std::log(points[i].error.mse);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    EXPECT_GT(slope, -1.2);
    EXPECT_LT(slope, -0.8);
    for (size_t i = 1; i < points.size(); ++i) EXPECT_GT(points[i].seconds, points[i - 1].seconds);
}

TEST(Convergence, RayCastingDoesNotConvergeToTheGlobalIllumination) {
    // Ray casting sees the furnace's emission (1) and none of its reflected light (4): its
    // error stays at (5 - 1)^2 = 16 however many samples it takes.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/furnace.toml", {48, 48});
    const std::vector<Checkpoint> points = convergence(scene, RayCastingModel(scene, {}), 16);
    ASSERT_EQ(points.size(), 5u);
    EXPECT_NEAR(points.front().error.mse, 16.0, 1e-3);
    EXPECT_NEAR(points.back().error.mse, 16.0, 1e-3);
}

TEST(Convergence, TimeBudgetRendersWholePassesUntilSpent) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/furnace.toml", {32, 32});
    const LightSampler lights(scene);
    ProgressivePlan plan;
    plan.time_budget = 0.2;
    RenderSettings settings;
    settings.progress = false;
    int spp = 0;
    const RenderResult r =
        render_progressive(scene, PathTracingModel(scene, {}), plan, settings, &spp);
    EXPECT_GE(r.stats.seconds, 0.2);
    EXPECT_GE(spp, 1);
    // Whole passes: the same seed and sample count give the same image as a fixed-spp render.
    ProgressivePlan fixed_plan;
    fixed_plan.spp = spp;
    const RenderResult fixed =
        render_progressive(scene, PathTracingModel(scene, {}), fixed_plan, settings, nullptr);
    for (size_t i = 0; i < r.image.pixels.size(); ++i)
        ASSERT_EQ(r.image.pixels[i], fixed.image.pixels[i]);
}
