// A page's parameters turned into the lesson's own command line (Studio::command_line), checked
// against the studio's scenes, the lesson's flags and the limits, then by the CLI's own parser:
// a request the CLI would refuse is refused with the CLI's message. Also the lessons' flags as
// the page offers them.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <sstream>

#include "io/input_error.h"
#include "studio_internal.h"

namespace lessons::studio {

namespace {

bool truthy(const std::string& v) {
    return v == "1" || v == "true" || v == "on" || v == "yes";
}
bool falsy(const std::string& v) {
    return v.empty() || v == "0" || v == "false" || v == "off";
}

int int_param(const Params& params, const std::string& key, int fallback) {
    const auto it = params.find(key);
    if (it == params.end() || it->second.empty()) return fallback;
    try {
        size_t used = 0;
        const int v = std::stoi(it->second, &used);
        if (used != it->second.size()) throw std::invalid_argument("trailing");
        return v;
    } catch (const std::exception&) {
        throw RequestError(key + ": '" + it->second + "' is not an integer");
    }
}

// The lesson a request names: as registered (to make it) and as the page lists it (its flags).
struct RequestedLesson {
    const RegisteredLesson* registered;
    const LessonInfo* info;
};
RequestedLesson requested_lesson(const Params& params, const std::vector<LessonInfo>& lessons) {
    const auto lesson_it = params.find("lesson");
    if (lesson_it == params.end()) throw RequestError("lesson: missing");
    const RegisteredLesson* registered = find_lesson(lesson_it->second);
    const LessonInfo* info = nullptr;
    for (const LessonInfo& l : lessons)
        if (l.name == lesson_it->second) info = &l;
    if (!registered || !info) {
        std::vector<std::string> names;
        for (const LessonInfo& l : lessons) names.push_back(l.name);
        throw RequestError("lesson: unknown '" + lesson_it->second + "'" +
                           did_you_mean(lesson_it->second, names) + known_names(names));
    }
    return {registered, info};
}

// The scene a request names: one of the studio's, by its id (never a path).
const SceneEntry& requested_scene(const Params& params, const std::vector<SceneEntry>& scenes) {
    const auto scene_it = params.find("scene");
    if (scene_it == params.end()) throw RequestError("scene: missing");
    const SceneEntry* scene = find_scene(scenes, scene_it->second);
    if (!scene)
        throw RequestError("scene: '" + scene_it->second +
                           "' is not one of the studio's scenes (only the .toml files in the "
                           "folders given with --scenes are)");
    return *scene;
}

// The lesson's own option `key`, or null for a common flag; any other key is refused.
const OptionInfo* allowed_option(const std::string& key, const LessonInfo& info) {
    const bool common =
        std::find(common_flags().begin(), common_flags().end(), key) != common_flags().end();
    const OptionInfo* own = nullptr;
    for (const OptionInfo& o : info.options)
        if (o.flag == key) own = &o;
    if (!common && !own)
        throw RequestError("parameter '" + key + "' is not allowed for " + info.name +
                           " (the studio takes scene, lesson, the lesson's own flags and " +
                           "--width, --height, --spp, --seed, --sampler, --clamp, --albedo, " +
                           "--naive, --exposure)");
    return own;
}

// The studio's own limits on the image's sides and the samples per pixel (the CLI checks the
// rest).
void check_limits(const Params& params, const std::string& key, const std::string& value,
                  const Limits& limits) {
    if (key == "--width" || key == "--height") {
        const int side = int_param(params, key, 0);
        if (side < 1 || side > limits.max_side)
            throw RequestError(key + ": " + value + " is outside 1 .. " +
                               std::to_string(limits.max_side) + " (the studio's --max-size)");
    }
    if (key == "--spp") {
        const int spp = int_param(params, key, 0);
        if (spp < 1 || spp > limits.max_spp)
            throw RequestError("--spp: " + value + " is outside 1 .. " +
                               std::to_string(limits.max_spp) + " (the studio's --max-spp)");
    }
}

// One parameter onto the command line: a flag alone when it is on; an option with its value,
// unless the value is empty (the default). Whether an option and its value were appended.
bool append_parameter(std::vector<std::string>& args, const Params& params, const std::string& key,
                      const std::string& value, const LessonInfo& info, const Limits& limits) {
    const OptionInfo* own = allowed_option(key, info);
    if (own && own->is_flag) {
        if (truthy(value))
            args.push_back(key);
        else if (!falsy(value))
            throw RequestError(key + ": a flag is on (1) or off (0), not '" + value + "'");
        return false;
    }
    if (value.empty()) return false;  // the default
    check_limits(params, key, value, limits);
    args.push_back(key);
    args.push_back(value);
    return true;
}

// The same parser as the CLI's: any value it refuses is refused here, with its message.
void parse_as_the_cli(const std::vector<std::string>& args, const RegisteredLesson& registered) {
    const Lesson lesson = registered.make();
    CLI::App app;
    CommonOptions o;
    try {
        parse_lesson_arguments(args, lesson, app, o);
    } catch (const InputError& e) {
        throw RequestError(e.what());
    } catch (const CLI::CallForHelp&) {
        throw RequestError("--help is not a render");
    }
}

}  // namespace

const std::vector<std::string>& common_flags() {
    static const std::vector<std::string> flags{"--width",  "--height",  "--spp",
                                                "--seed",   "--sampler", "--clamp",
                                                "--albedo", "--naive",   "--exposure"};
    return flags;
}

const RegisteredLesson* find_lesson(const std::string& name) {
    for (const RegisteredLesson& l : all_lessons())
        if (l.name == name) return &l;
    return nullptr;
}

const SceneEntry* find_scene(const std::vector<SceneEntry>& scenes, const std::string& id) {
    const SceneEntry* found = nullptr;
    for (const SceneEntry& s : scenes)
        if (s.id == id) found = &s;
    return found;
}

std::vector<OptionInfo> lesson_options(const Lesson& lesson) {
    CLI::App app;
    if (lesson.add_options) lesson.add_options(app);
    std::vector<OptionInfo> options;
    for (const CLI::Option* opt : app.get_options()) {
        const std::string name = opt->get_name();
        if (name.rfind("--", 0) != 0 || name == "--help") continue;
        OptionInfo info;
        info.flag = name;
        info.description = opt->get_description();
        info.is_flag = opt->get_expected_max() == 0;  // takes no value
        info.default_value = opt->get_default_str();
        // CLI11 appends a validator's description to the type name: "TEXT:{a,b,c}" for a set.
        const std::string type = opt->get_type_name();
        const size_t open = type.find('{'), close = type.find('}');
        if (open != std::string::npos && close != std::string::npos && close > open) {
            std::stringstream ss(type.substr(open + 1, close - open - 1));
            for (std::string c; std::getline(ss, c, ',');) info.choices.push_back(c);
        }
        options.push_back(info);
    }
    return options;
}

void load_run(PaneState& state) {
    CLI::App app;
    parse_lesson_arguments(state.args, state.lesson, app, state.options);
    prepare_run(state.options, state.lesson, state.inputs);
}

std::vector<std::string> Studio::command_line(const Params& params) const {
    const RequestedLesson lesson = requested_lesson(params, lessons_);
    const SceneEntry& scene = requested_scene(params, scenes_);
    std::vector<std::string> args{lesson.info->name, "--scene", scene.path};
    bool has_spp = false;
    for (const auto& [key, value] : params) {
        if (key == "lesson" || key == "scene" || key == "pane") continue;
        if (append_parameter(args, params, key, value, *lesson.info, limits_) && key == "--spp")
            has_spp = true;
    }
    if (!has_spp) {
        args.push_back("--spp");
        args.push_back(std::to_string(limits_.max_spp));
    }
    parse_as_the_cli(args, *lesson.registered);
    return args;
}

}  // namespace lessons::studio
