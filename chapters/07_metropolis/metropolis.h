// Lesson 7: Metropolis light transport (Veach and Guibas 1997), in primary sample space (Kelemen
// et al. 2002), over lesson 5's strategies (multiplexed MLT, Hachisuka et al. 2014).
//
// Lessons 4 to 6 draw every path afresh: where almost all light reaches the camera along a few
// narrow families of paths (a room lit through a door left ajar), almost every sample misses
// them, and a sample that finds one is a firefly, forgotten at once. A Markov chain keeps what it
// found: it explores the neighbourhood of a bright path by small changes, and its samples land
// in proportion to the light. The lesson in files:
//   primary_samples.h  the state: the random numbers lesson 5's walks read, mutated lazily;
//   multiplexed.h      the path a state stands for: a length and one of lesson 5's strategies;
//   chain.h            the bootstrap (b and the chains' starts) and the Metropolis chain.
//
// As the render loop runs it (render/render.h): pass k is a round of `chains` chains that
// begin_pass runs whole, after a bootstrap of its own, making `mutations` mutations per pixel
// between them; their splats, summed in chain order, are the pass's image, which sample() reads.
// Each pass is an independent, unbiased estimate of the image, so passes average like any
// lesson's samples, threads and farm parts do not change a bit, and an interrupted render keeps
// its complete passes.
#pragma once

#include <cstdint>
#include <vector>

#include "05_bidirectional/subpaths.h"
#include "07_metropolis/chain.h"
#include "lights/lights.h"
#include "render/model.h"
#include "scene/scene.h"

namespace lessons {

struct MetropolisOptions {
    int max_depth = 0;  // 0: unlimited (lesson 4's safety cut); else segments
    int chains = 16;    // chains per pass
    int mutations = 1;  // mutations per pixel per pass
    float large_step_probability = 0.3f;
    float sigma = 0.01f;  // the small step's standard deviation
    int bootstrap = 0;    // bootstrap paths per pass (0: a quarter of its mutations)
};

class MetropolisModel final : public Model {
public:
    MetropolisModel(const Scene& scene, const MetropolisOptions& options);
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;
    void begin_pass(int k, const RenderSettings& settings) const override;
    uint64_t pass_rays() const override { return rays_; }
    void report(Report& report) const override;

    // For tests: the mean of the bootstrap's b over the passes run.
    double mean_b() const { return passes_ > 0 ? b_sum_ / passes_ : 0.0; }

private:
    ChainValue state_value(PrimarySamples& x) const;
    int64_t pass_mutations() const;
    int bootstrap_count() const;

    LightSampler lights_;
    Bidir b_;  // refers to lights_
    MetropolisOptions options_;
    ChainSettings chain_;
    // The pass's image, and the figures of every pass so far (begin_pass runs with no sample in
    // flight: render/model.h).
    mutable std::vector<Color> image_;
    mutable int pass_index_ = -1;
    mutable uint64_t rays_ = 0;
    mutable int passes_ = 0;
    mutable double b_sum_ = 0.0;
    mutable uint64_t proposed_ = 0, accepted_ = 0, large_proposed_ = 0, large_accepted_ = 0;
    mutable uint64_t non_finite_ = 0;
    mutable size_t most_splat_bytes_ = 0;
};

}  // namespace lessons
