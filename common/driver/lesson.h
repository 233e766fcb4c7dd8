// A lesson as its front ends run it (the command line: driver/app.h; the studio): its name, its
// flags, and the model it makes for a scene. A lesson declares its flags once, in one struct of
// its own (chapters/NN_*/lesson.cpp), next to their help text: the struct's bind() hands each
// flag to CLI11 bound to a member, and its make_model() makes the model from their values. The
// command line, the studio and the report (driver/run.h's image_options) all read that one
// parser. The models themselves know nothing of flags (render/model.h).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "render/model.h"
#include "scene/scene.h"

namespace CLI {
class App;
}

namespace lessons {

struct Lesson {
    std::string name;         // e.g. "01_ray_casting": the executable and the report's "chapter"
    std::string description;  // first line of --help
    int default_spp = 1;
    std::function<void(CLI::App&)> add_options;  // declares the lesson's own flags
    // Makes the model for a scene from the flags' values; throws InputError if the scene cannot
    // be shown or the flags do not go together. The model refers to the scene, which must
    // outlive it.
    std::function<std::unique_ptr<Model>(const Scene&)> make_model;
};

// A lesson whose flags are the struct `Flags`, which has
//   void bind(CLI::App& app);                                  // declares every flag
//   std::unique_ptr<Model> make_model(const Scene&) const;     // the model for their values
// Each Lesson made holds a Flags of its own, shared by its two functions.
template <class Flags>
Lesson lesson_with_flags(std::string name, std::string description, int default_spp) {
    auto flags = std::make_shared<Flags>();
    Lesson lesson;
    lesson.name = std::move(name);
    lesson.description = std::move(description);
    lesson.default_spp = default_spp;
    lesson.add_options = [flags](CLI::App& app) { flags->bind(app); };
    lesson.make_model = [flags](const Scene& scene) { return flags->make_model(scene); };
    return lesson;
}

}  // namespace lessons
