// Lesson 6: photons, as a lesson: its flags (the method, the radius and its schedule, the
// kernel, the technique images, the photons' memory, path length), and the model.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "04_rendering_equation/path_length_flags.h"
#include "06_photon_mapping/photon_mapping.h"
#include "driver/choice_flag.h"

namespace lessons {

namespace {

struct PhotonFlags {
    PhotonOptions options;

    void bind(CLI::App& app) {
        add_choice_flag(
            app, "--method", options.method,
            Choices<PhotonMethod>(std::begin(kPhotonMethodNames), std::end(kPhotonMethodNames)),
            "pm (photon mapping, a fixed radius), ppm (progressive: the radius "
            "shrinks every pass), bpt (lesson 5), vcm (vertex connection and "
            "merging: lesson 5's joins and the photons, weighted by MIS), or vpl (instant "
            "radiosity: the light subpaths' vertices as virtual point lights, connected)");
        add_choice_flag(app, "--merging", options.merging,
                        Choices<Merging>(std::begin(kMergingNames), std::end(kMergingNames)),
                        "Where vcm merges: auto (only in a scene with a mirror or smooth glass, "
                        "where a path can need it; elsewhere vcm is bpt, bit for bit), always, "
                        "or never (bpt)");
        add_path_length_flags(app, options.paths.max_depth, options.paths.roulette_after);
        app.add_option("--radius", options.radius,
                       "The photons' radius in the first pass, in scene units (0: two pixel "
                       "footprints at the median distance of what the camera sees)")
            ->check(CLI::NonNegativeNumber)
            ->capture_default_str();
        app.add_option("--alpha", options.alpha,
                       "The radius of pass k is r (k + 1)^((alpha - 1) / 2): 1 keeps it, less "
                       "shrinks it (0: the method's, pm 1, ppm 2/3, vcm 3/4)")
            ->check(CLI::Range(0.0, 1.0))
            ->capture_default_str();
        add_choice_flag(app, "--kernel", options.kernel,
                        Choices<Kernel>(std::begin(kKernelNames), std::end(kKernelNames)),
                        "The photons' weight over the disk: constant or epanechnikov");
        app.add_flag("--techniques", options.technique_layers,
                     "Also write the light of each kind of technique as images, adding up to "
                     "the image: PREFIX_connection, PREFIX_merging and PREFIX_light_tracing "
                     "(bpt, vcm), PREFIX_direct and PREFIX_photons (pm, ppm), PREFIX_direct, "
                     "PREFIX_vpl and PREFIX_compensation (vpl)");
        app.add_option("--vpls", options.vpls,
                       "vpl: light subpaths per pass; their vertices are the pass's virtual "
                       "point lights, each joined to every pixel sample by a shadow ray")
            ->check(CLI::Range(1, 1 << 20))
            ->capture_default_str();
        app.add_option("--vpl-clamp", options.vpl_clamp,
                       "vpl: the cap on each connection's G = cos cos / d^2, in 1 / length^2 (0: "
                       "none, unbiased but blotchy; default: 100 / D^2, D the scene box's "
                       "diagonal)")
            ->check(CLI::NonNegativeNumber);
        app.add_flag("--vpl-compensate", options.vpl_compensate,
                     "vpl: restore the light the cap removes by a BSDF sample (Kollig and Keller "
                     "2004), which makes the image unbiased");
        app.add_option("--max-photon-mb", options.max_photon_mb,
                       "The most memory one pass's light subpaths and photons may take, in MiB")
            ->check(CLI::PositiveNumber)
            ->capture_default_str();
    }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        return std::make_unique<PhotonMappingModel>(scene, options);
    }
};

}  // namespace

Lesson photon_mapping_lesson() {
    return lesson_with_flags<PhotonFlags>(
        "06_photon_mapping",
        "Lesson 6, photons: photon mapping, progressive photon mapping, vertex connection "
        "and merging (lesson 5's joins and the photons, weighted by MIS), and instant radiosity "
        "(virtual point lights, connected instead of merged)",
        16);
}

}  // namespace lessons
