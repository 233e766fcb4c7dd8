// A flag that names one of a few choices, bound to the value each name stands for (an enum, a
// bool): for a lesson's flags struct (driver/lesson.h). CLI11 checks that the name given is one
// of them (the studio offers them in this order); the parsed command line keeps the name, so the
// report, a part's header and --help show names, never numbers. The table of names is written
// once, here in the flag, and the model receives the value.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

namespace lessons {

template <class T>
using Choices = std::vector<std::pair<std::string, T>>;

// Declares `flag` on `app`, setting `value` to the choice named; the default is the name of
// `value`'s value when declared.
template <class T>
CLI::Option* add_choice_flag(CLI::App& app, const std::string& flag, T& value,
                             const Choices<T>& choices, const std::string& help) {
    std::vector<std::string> names;
    std::string default_name;
    for (const auto& [name, v] : choices) {
        names.push_back(name);
        if (v == value && default_name.empty()) default_name = name;
    }
    return app
        .add_option_function<std::string>(
            flag,
            [&value, choices](const std::string& given) {
                for (const auto& [name, v] : choices)
                    if (name == given) value = v;
            },
            help)
        ->check(CLI::IsMember(names))
        ->default_str(default_name);
}

// The name of `value` among `choices` (empty if none).
template <class T>
std::string choice_name(const Choices<T>& choices, const T& value) {
    for (const auto& [name, v] : choices)
        if (v == value) return name;
    return "";
}

}  // namespace lessons
