// The lesson driver's last step, private to driver/: what a run wrote, from what it rendered.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "driver/run.h"
#include "render/metrics.h"

namespace lessons {

// What a run rendered: the result, the samples per pixel it took, and the error checkpoints
// (with --reference).
struct RunResult {
    RenderResult render;
    int spp_taken = 0;
    std::vector<Checkpoint> checkpoints;  // with --reference
};

// The EXR and PNG of the image and of every layer, the variance and the convergence CSV; a part
// writes its part EXR and the PNG of what it holds.
void write_images(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                  const RunResult& run);
// The JSON report (--report), with the error against the reference if measured and each layer's
// share of the image.
void write_run_report(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                      const RunResult& run, const std::optional<ErrorMetrics>& error,
                      const std::vector<std::string>& shares);
double mrays_per_second(const RenderStats& s);

}  // namespace lessons
