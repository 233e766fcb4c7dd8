// Every shipped scene through every lesson: no NaN and no infinite sample, ever.
#include <gtest/gtest.h>

#include <filesystem>

#include "app.h"
#include "bidirectional.h"
#include "ray_casting.h"
#include "reflection_equation.h"
#include "rendering_equation.h"
#include "scene_file.h"
#include "whitted.h"

using namespace lessons;

TEST(AllScenes, EveryLessonRendersEverySceneWithoutNaNOrInf) {
    int scenes = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(
             std::string(LESSONS_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".toml") continue;
        ++scenes;
        const Scene scene = load_scene(entry.path().string(), {40, 30});
        const LightSampler lights(scene);
        BidirOptions light_tracing;
        light_tracing.light_tracing = true;
        const std::vector<std::pair<std::string, Model>> models = {
            {"01", make_ray_casting_model(scene, {scene.background})},
            {"02", make_whitted_model(scene, {})},
            {"03 mis", make_reflection_model(scene, lights, {})},
            {"03 uniform",
             make_reflection_model(scene, lights, {Estimator::Uniform, MisHeuristic::Power})},
            {"04", make_path_tracing_model(scene, lights, {})},
            {"04 plain", make_path_tracing_model(scene, lights, {false, 0, 3, 0})},
            {"05", make_bidirectional_model(scene, lights, {})},
            {"05 light tracing", make_bidirectional_model(scene, lights, light_tracing)},
        };
        for (const auto& [name, model] : models) {
            RenderSettings settings;
            settings.progress = false;
            const RenderResult r = render_scene(scene, model, 4, settings);
            EXPECT_EQ(r.nan_samples, 0u) << name << " on " << entry.path().filename();
            EXPECT_EQ(r.inf_samples, 0u) << name << " on " << entry.path().filename();
            EXPECT_EQ(r.nan_pixels + r.inf_pixels, 0) << name << " on " << entry.path().filename();
        }
    }
    EXPECT_GE(scenes, 7);
}
