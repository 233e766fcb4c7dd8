// The lesson driver's second step: everything a run renders with, made before any rendering
// (the scene with its --naive methods and --albedo, the reference, the model), so that bad input
// stops the run before it renders (see run.h).
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "driver/run.h"
#include "farm/part.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/scene_file.h"
#include "io/shipped_files.h"

namespace lessons {

namespace {

// Refuses an image whose buffers would not fit in memory, before any work is done.
void check_memory(int width, int height) {
    // The film (FilmPixel, 96 bytes), the mean and variance images and their copies in the
    // result, the PNG bytes: 160 bytes per pixel is a safe upper bound.
    const double bytes_per_pixel = 160.0;
    check_fits_in_memory(
        bytes_per_pixel * width * height,
        std::to_string(width) + "x" + std::to_string(height) + " needs, for the image buffers,",
        "command line", "--width/--height");
}

// Turns on the --naive methods by name (docs/robustness.md); throws InputError for an unknown one.
void apply_naive_methods(const std::vector<std::string>& methods, NaiveMethods& naive) {
    for (const std::string& method : methods) {
        if (method == "quadratic") {
            naive.textbook_quadratic = true;
        } else if (method == "moller-trumbore") {
            naive.moller_trumbore = true;
        } else if (method == "side-by-dot") {
            naive.side_by_dot = true;
        } else if (method == "shading-normals") {
            naive.raw_shading_normals = true;
        } else if (method == "light-cosine") {
            naive.light_abs_cosine = true;
        } else if (method == "adjoint") {
            naive.no_adjoint_correction = true;
        } else if (method.rfind("epsilon=", 0) == 0) {
            char* end = nullptr;
            const float e = std::strtof(method.c_str() + 8, &end);
            if (*end != '\0' || !(e > 0.0f) || !std::isfinite(e))
                throw InputError("command line", 0, "--naive",
                                 "epsilon must be a positive number, got '" + method + "'");
            naive.fixed_epsilon = e;
        } else {
            throw InputError("command line", 0, "--naive",
                             "unknown method '" + method +
                                 "' (known: epsilon=E, quadratic, moller-trumbore, side-by-dot, "
                                 "shading-normals, light-cosine, adjoint)");
        }
    }
}

// The --reference image, which must have the render's size; empty without --reference.
Image read_reference(const CommonOptions& o, const Scene& scene) {
    if (!o.convergence.empty() && o.reference.empty())
        throw InputError("command line", 0, "--convergence",
                         "needs --reference: the error is measured against it");
    if (o.reference.empty()) return {};
    Image reference;
    try {
        reference = read_exr(o.reference);
        for (const std::string& note : reference.notes) std::cerr << "note: " << note << "\n";
    } catch (const std::runtime_error& e) {
        throw InputError("command line", 0, "--reference", e.what());
    }
    if (reference.width != scene.width || reference.height != scene.height)
        throw InputError(o.reference, 0, "--reference",
                         "is " + std::to_string(reference.width) + "x" +
                             std::to_string(reference.height) + ", the render is " +
                             std::to_string(scene.width) + "x" + std::to_string(scene.height) +
                             " (use --width/--height)");
    if (o.part.x1 == 0) return reference;
    // A crop is measured against the same crop of the reference.
    Image crop(o.part.x1 - o.part.x0, o.part.y1 - o.part.y0);
    for (int y = 0; y < crop.height; ++y)
        for (int x = 0; x < crop.width; ++x)
            crop.at(x, y) = reference.at(o.part.x0 + x, o.part.y0 + y);
    return crop;
}

// --pixels must lie in the image (its size is known once the scene is read).
void check_part(const CommonOptions& o, const Scene& scene) {
    if (o.part.x1 == 0) return;
    if (o.part.x1 > scene.width || o.part.y1 > scene.height)
        throw InputError("command line", 0, "--pixels",
                         "'" + o.pixels + "' reaches outside the " + std::to_string(scene.width) +
                             "x" + std::to_string(scene.height) + " image");
}

// --albedo: every diffuse reflectance (of diffuse and glossy materials) becomes grey `rho`.
void apply_albedo(float rho, Scene& scene) {
    if (rho < 0.0f) return;
    for (uint32_t i = 0; i < scene.materials().size(); ++i) {
        Material m = scene.material(i);
        if (!facts_of(m.type).albedo) continue;
        m.albedo = ColorTexture{};
        m.albedo.value = Color(rho);
        scene.replace_material(i, m);
    }
}

}  // namespace

void prepare_run(const CommonOptions& o, const Lesson& lesson, RunInputs& in) {
    in.scene = load_scene(find_scene_file(o.scene), {o.width, o.height, o.limits, o.threads});
    check_memory(in.scene.width, in.scene.height);
    apply_naive_methods(o.naive, in.scene.naive);
    apply_albedo(o.albedo, in.scene);
    check_part(o, in.scene);
    in.reference = read_reference(o, in.scene);
    in.model = lesson.make_model(in.scene);
    in.model->notes.insert(in.model->notes.end(), in.scene.notes.begin(), in.scene.notes.end());
    if (!in.model->renders_media && in.scene.contents().media)
        in.model->biased_because.push_back(
            "the scene's media are ignored: light travels unchanged between surfaces, as in a "
            "vacuum, and the shapes that hold them are seen as their surfaces alone (" +
            in.scene.media_summary() + ")");
    // What a part belongs to, taken now: a scene edited while the part renders is not its scene.
    if (o.is_part()) in.scene_hash = scene_files_hash(in.scene, o.limits);
    if (in.model->splats && o.part.crops(in.scene))
        throw InputError("command line", 0, "--pixels",
                         lesson.name +
                             " splats light onto pixels anywhere in the image, so a "
                             "crop cannot hold its part: split it by --samples only");
    if (!o.variance.empty() && o.sampler != "independent")
        in.model->notes.push_back("--variance: the samples are stratified (--sampler " + o.sampler +
                                  "), so the sample variance / N is not the error of the mean "
                                  "(usually above it, below it for rare events such as a light "
                                  "path few samples take); --sampler independent measures it");
    if (o.albedo >= 0.0f)
        in.model->notes.push_back("--albedo: every diffuse reflectance is grey " +
                                  std::to_string(o.albedo) + " (the scene's own are ignored)");
}

std::vector<std::string> run_bias(const CommonOptions& o, const RunInputs& in) {
    std::vector<std::string> bias = in.model->biased_because;
    if (o.clamp > 0.0f) bias.push_back("--clamp: bright samples are scaled down");
    if (in.scene.naive.any()) bias.push_back("--naive: the naive methods are wrong on purpose");
    bias.insert(bias.end(), in.model->consistent_bias.begin(), in.model->consistent_bias.end());
    return bias;
}

bool run_consistent(const CommonOptions& o, const RunInputs& in) {
    return in.model->biased_because.empty() && !(o.clamp > 0.0f) && !in.scene.naive.any();
}

}  // namespace lessons
