// Lesson 7: Metropolis light transport, as the render loop runs it (see metropolis.h).
#include "07_metropolis/metropolis.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "04_rendering_equation/rendering_equation.h"
#include "05_bidirectional/bidirectional.h"
#include "07_metropolis/multiplexed.h"
#include "accel/parallel.h"
#include "io/input_error.h"
#include "io/report.h"

namespace lessons {

namespace {

// Where the numbers of pass k come from: its bootstrap's paths and its chains, apart from each
// other and from every pixel sample of the lessons before (which use the pixel's index).
constexpr uint64_t kBootstrapStreams = 0xb0075ULL << 40;
constexpr uint64_t kChainStreams = 0xc4a1ULL << 40;
// The most memory one pass's splats may take.
constexpr double kMostSplatBytes = 4096.0 * 1048576.0;

}  // namespace

MetropolisModel::MetropolisModel(const Scene& scene, const MetropolisOptions& options)
    : lights_(scene),
      b_{scene, lights_, scene.camera, scene.width, scene.height},
      options_(options) {
    passes = true;  // a pass is a round of chains that begin_pass runs whole
    chain_.sigma = options.sigma;
    chain_.large_step_probability = options.large_step_probability;
    chain_.streams = kStreams;
    char steps[96];
    std::snprintf(steps, sizeof steps, "large steps %.4g, small steps sigma %.4g",
                  static_cast<double>(options.large_step_probability),
                  static_cast<double>(options.sigma));
    notes.push_back("estimator: Metropolis light transport in primary sample space, " +
                    std::to_string(options.chains) + " chains per pass making " +
                    std::to_string(options.mutations) +
                    " mutation(s) per pixel between them, each state one of lesson 5's "
                    "strategies (s, t) with its MIS weight (multiplexed MLT); " +
                    std::string(steps));
    notes.push_back(
        "what MLT trades: a chain's samples are correlated (noise comes in blotches and streaks, "
        "not grain), the pixels are not estimated independently, and effort goes where the light "
        "is, so dark pixels get few samples; each pass's scale b comes from a bootstrap of " +
        std::to_string(bootstrap_count()) + " independent paths");
    if (options.max_depth > 0)
        biased_because.push_back("paths end after " + std::to_string(options.max_depth) +
                                 " segments: later bounces are missing");
    else
        notes.push_back(
            "no depth limit: a state's path length k is drawn with probability "
            "1 / (k (k + 1)), up to a safety cut at " +
            std::to_string(kLongestPath) + " segments");
    // Lesson 5's strategies miss what lesson 5 misses.
    if (std::optional<std::string> missing = strategies_miss(scene.contents()))
        biased_because.push_back(*missing);
    // Two splats a mutation, kept until the pass's chains are summed in order.
    const double splat_bytes = 2.0 * sizeof(ChainSplat) * static_cast<double>(pass_mutations());
    if (splat_bytes > kMostSplatBytes)
        throw InputError("command line", 0, "--mutations",
                         "a pass of " + std::to_string(pass_mutations()) + " mutations keeps " +
                             std::to_string(static_cast<int64_t>(splat_bytes / 1048576.0)) +
                             " MiB of splats, over the cap of " +
                             std::to_string(static_cast<int64_t>(kMostSplatBytes / 1048576.0)) +
                             " MiB (fewer --mutations per pass, or a smaller image)");
    if (lights_.empty()) notes.push_back("the scene has no lights: only emission is visible");
}

ChainValue MetropolisModel::state_value(PrimarySamples& x) const {
    const PathContribution p = multiplexed_path(b_, x, longest_path(options_.max_depth));
    return {p.value, p.pixel};
}

int64_t MetropolisModel::pass_mutations() const {
    return static_cast<int64_t>(b_.width) * b_.height * options_.mutations;
}

int MetropolisModel::bootstrap_count() const {
    if (options_.bootstrap > 0) return options_.bootstrap;
    return static_cast<int>(std::clamp<int64_t>(pass_mutations() / 4, 256, 1 << 24));
}

void MetropolisModel::begin_pass(int k, const RenderSettings& settings) const {
    const ChainTarget target = [this](PrimarySamples& x) { return state_value(x); };
    const Bootstrap boot =
        bootstrap(target, bootstrap_count(), settings.seed,
                  kBootstrapStreams + static_cast<uint64_t>(k), chain_, settings.threads);
    rays_ += boot.rays;
    non_finite_ += boot.non_finite;
    const int64_t mutations = pass_mutations();
    const int chains = options_.chains;
    std::vector<ChainRun> runs(static_cast<size_t>(chains));
    std::atomic<int> next{0};
    parallel_parts(static_cast<size_t>(chains), settings.threads, 1, [&](size_t, size_t, int) {
        for (int j = next++; j < chains; j = next++) {
            const int64_t length = mutations / chains + (j < mutations % chains ? 1 : 0);
            runs[static_cast<size_t>(j)] = run_chain(
                target, boot, kChainStreams + static_cast<uint64_t>(k), static_cast<uint64_t>(j),
                length, chain_, ChainStart::Resampled, settings.stop);
        }
    });
    // An interrupted pass is dropped whole by the render loop: its figures are not the run's.
    if (settings.stop && settings.stop->load()) return;
    // The pass's image: b / (mutations per pixel) times the splats, in chain order.
    image_.assign(static_cast<size_t>(b_.width) * b_.height, Color(0.0f));
    const double scale =
        boot.b * static_cast<double>(image_.size()) / static_cast<double>(mutations);
    size_t splat_bytes = 0;
    for (const ChainRun& run : runs) {
        for (const ChainSplat& s : run.splats)
            image_[s.pixel] += s.value * static_cast<float>(scale);
        splat_bytes += run.splats.capacity() * sizeof(ChainSplat);
        rays_ += run.rays;
        proposed_ += run.proposed;
        accepted_ += run.accepted;
        large_proposed_ += run.large_proposed;
        large_accepted_ += run.large_accepted;
        non_finite_ += run.non_finite;
    }
    most_splat_bytes_ = std::max(most_splat_bytes_, splat_bytes);
    pass_index_ = k;
    b_sum_ += boot.b;
    ++passes_;
}

Color MetropolisModel::sample(const Ray&, Rng&, uint32_t pixel, std::span<Color>,
                              std::vector<Splat>&) const {
    if (pass_index_ < 0)
        throw std::logic_error("lesson 7 samples pass by pass, after begin_pass ran the chains");
    return image_[pixel];
}

void MetropolisModel::report(Report& report) const {
    report.set("b", mean_b());
    report.set("chains_per_pass", options_.chains);
    report.set("mutations_per_pixel_per_pass", options_.mutations);
    report.set("bootstrap_paths_per_pass", bootstrap_count());
    report.set("large_step_probability", static_cast<double>(options_.large_step_probability));
    report.set("sigma", static_cast<double>(options_.sigma));
    report.set("proposals", proposed_);
    report.set(
        "acceptance_rate",
        proposed_ > 0 ? static_cast<double>(accepted_) / static_cast<double>(proposed_) : 0.0);
    report.set("large_step_share",
               proposed_ > 0 ? static_cast<double>(large_proposed_) / static_cast<double>(proposed_)
                             : 0.0);
    report.set("large_step_acceptance",
               large_proposed_ > 0
                   ? static_cast<double>(large_accepted_) / static_cast<double>(large_proposed_)
                   : 0.0);
    report.set("non_finite_paths", non_finite_);
    report.set("chain_splat_bytes", static_cast<uint64_t>(most_splat_bytes_));
}

}  // namespace lessons
