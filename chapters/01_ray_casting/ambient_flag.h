// The --ambient flag of the local models (lessons 1 and 2): L_a, the constant radiance that
// stands in for indirect light at diffuse hits. One grey value or R G B; by default the scene's
// background radiance (an environment map's mean).
#pragma once

#include <vector>

#include "geometry/math.h"
#include "scene/scene.h"

namespace CLI {
class App;
}

namespace lessons {

struct AmbientFlag {
    std::vector<float> values;  // as given: none, one grey value, or R G B
    void bind(CLI::App& app);
    // L_a for this scene; throws InputError for two values.
    Color radiance(const Scene& scene) const;
};

}  // namespace lessons
