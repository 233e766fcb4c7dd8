// A lesson's illumination model, as the render loop sees it: one interface, whatever the model.
// A lesson makes one for a scene (its constructor reads the scene and says what it ignores);
// the render loop asks it for samples; the driver prints and reports what it says of itself.
// Nothing here knows the command line: a lesson's flags are its front end's (render/lesson.h).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "io/report.h"
#include "render/render.h"
#include "sampling/rng.h"

namespace lessons {

class Model {
public:
    Model() = default;
    // A model may refer to its own members (lesson 5's subpaths to its light sampler), so it
    // stays where it is made.
    Model(const Model&) = delete;
    Model& operator=(const Model&) = delete;
    virtual ~Model() = default;

    // One sample of the radiance arriving at the camera along the primary ray `ray`, with its
    // random numbers from `rng`. A model with layers (layer_names) also adds each layer's share
    // of the sample into `layers` (as many entries as names, zeroed before each call; empty
    // when the model has none); a splatting model appends the light it adds to other pixels to
    // `splats` (a model that does not splat leaves it alone).
    virtual Color sample(const Ray& ray, Rng& rng, std::span<Color> layers,
                         std::vector<Splat>& splats) const = 0;

    // A splatting model's sample in a pass, as the pass-by-pass loop asks for it: sample() (by
    // default), told the row-major index of the pixel whose sample it is, for a model that gives
    // each pixel something of the pass's own (lesson 6's vcm: the pass's light subpath of that
    // index). Every pixel of the image has one sample in each pass.
    virtual Color sample_in_pass(const Ray& ray, Rng& rng, uint32_t /*pixel*/,
                                 std::span<Color> layers, std::vector<Splat>& splats) const {
        return sample(ray, rng, layers, splats);
    }

    // Whether sample() splats: then the render loop goes one pass per sample index, so that the
    // splats of a pass land in a fixed order (render_splatting, render/render.h).
    bool splats = false;
    // Called by the pass-by-pass loop (a model that splats) before the samples of index k of
    // every pixel, with no sample in flight: a model that prepares something per pass (lesson 6
    // traces its photons) does it here, on settings.threads threads, and keeps it for sample()
    // (so state it changes here is `mutable`: it is a cache of the pass, never read across
    // passes). Throws InputError if the pass cannot be made (lesson 6: over its memory cap).
    virtual void begin_pass(int /*sample_index*/, const RenderSettings& /*settings*/) const {}
    // Rays traced by begin_pass so far, for the render's ray count.
    virtual uint64_t pass_rays() const { return 0; }
    // Figures of the run for its report beyond the driver's own (lesson 6: the radius reached,
    // the photons' memory), written after the render.
    virtual void report(Report& /*report*/) const {}
    // The layers the model splits its radiance into (e.g. light by number of bounces), each
    // written as an image <out>_<name> with its share of the total printed; they add up to the
    // image unless a note says otherwise.
    std::vector<std::string> layer_names;
    // One line per thing the model approximates or ignores in this scene, printed before the
    // render and stored in the report.
    std::vector<std::string> notes;
    // Why the model's answer differs from the rendering equation's in this scene, however many
    // samples it takes (its bias); empty when it converges to the true image. Printed, and in
    // the report as "biased" and "bias".
    std::vector<std::string> biased_because;
};

}  // namespace lessons
