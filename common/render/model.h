// A lesson's illumination model, as the render loop sees it: one interface, whatever the model.
// A lesson makes one for a scene (its constructor reads the scene and says what it ignores);
// the render loop (render/render.h) asks it for samples; the driver prints and reports what it
// says of itself. Nothing here knows the command line: a lesson's flags are its front end's
// (driver/lesson.h).
//
// The render loop asks two facts of a model, apart:
//   passes  it renders pass by pass: sample index k of every pixel before index k + 1, with
//           begin_pass(k) before each pass (lesson 6 traces the pass's photons there);
//   splats  its samples also add light to other pixels (lessons 5 and 6's light tracing); such
//           a model renders in passes too, so that a pass's splats land in a fixed order, and
//           takes no crop (a splat lands anywhere).
// A model that does neither (lessons 1 to 4) is rendered pixel by pixel, all its samples at once.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "io/report.h"
#include "render/settings.h"
#include "sampling/rng.h"

namespace lessons {

// Light that a sample adds to some pixel of the image, as its share of film `film`.
struct Splat {
    uint32_t
        pixel;  // row-major index in the film (the whole image: a model that splats takes no crop)
    uint32_t film;  // 0: the image; 1 + k: layer k
    Color value;
};

class Model {
public:
    Model() = default;
    // A model may refer to its own members (lesson 5's subpaths to its light sampler), so it
    // stays where it is made.
    Model(const Model&) = delete;
    Model& operator=(const Model&) = delete;
    virtual ~Model() = default;

    // One sample of the radiance arriving at the camera along the primary ray `ray` through
    // pixel `pixel` (its row-major index in the whole image), with its random numbers from
    // `rng`. A model with layers (layer_names) also adds each layer's share of the sample into
    // `layers` (as many entries as names, zeroed before each call; empty when the model has
    // none); a model that splats appends the light it adds to other pixels to `splats`, and any
    // other leaves it alone. A model rendered in passes may give each pixel something of the
    // pass's own (lesson 6's vcm: the pass's light subpath of the pixel's index).
    virtual Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                         std::vector<Splat>& splats) const = 0;

    // Whether the model renders pass by pass (see above).
    bool passes = false;
    // Whether sample() splats; a model that splats also sets `passes`.
    bool splats = false;
    // Whether the model renders participating media (common/media/). One that does not, in a
    // scene that has them, is biased, and says so: the driver adds that to biased_because.
    bool renders_media = false;
    // Called before the samples of index k of every pixel, with no sample in flight, for a
    // model rendered in passes: a model that prepares something per pass (lesson 6 traces its
    // photons) does it here, on settings.threads threads, and keeps it for sample() (so state it
    // changes here is `mutable`: it is a cache of the pass, never read across passes). Throws
    // InputError if the pass cannot be made (lesson 6: over its memory cap).
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
    // Why the model's expected image after any finite number of samples differs from the
    // rendering equation's, where it still converges to it (biased but consistent: ppm's and
    // vcm's shrinking radius), with how the bias shrinks. Printed, and in the report's "bias";
    // "biased" is then true and "consistent" stays true.
    std::vector<std::string> consistent_bias;
};

}  // namespace lessons
