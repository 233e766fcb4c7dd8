// The lessons registry, chapters/lessons.txt, as the tests read it: every lesson's executable,
// its label and the flag variants that the scene tests also run.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace lessons::test {

struct RegisteredLesson {
    std::string name;                   // the folder and the executable
    std::string label;                  // as on the lessons page
    std::vector<std::string> variants;  // extra flag sets, e.g. "--plain"
};

inline std::string trimmed(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

inline std::vector<RegisteredLesson> registered_lessons() {
    std::ifstream in(std::string(LESSONS_SOURCE_DIR) + "/chapters/lessons.txt");
    std::vector<RegisteredLesson> lessons;
    for (std::string line; std::getline(in, line);) {
        if (trimmed(line).empty() || trimmed(line)[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream ss(line);
        for (std::string f; std::getline(ss, f, '|');) fields.push_back(trimmed(f));
        RegisteredLesson l;
        l.name = fields.at(0);
        l.label = fields.size() > 1 ? fields[1] : "";
        if (fields.size() > 2) {
            std::stringstream vs(fields[2]);
            for (std::string v; std::getline(vs, v, '&');)
                if (!trimmed(v).empty()) l.variants.push_back(trimmed(v));
        }
        lessons.push_back(l);
    }
    return lessons;
}

inline std::vector<std::string> registered_lesson_names() {
    std::vector<std::string> names;
    for (const RegisteredLesson& l : registered_lessons()) names.push_back(l.name);
    return names;
}

}  // namespace lessons::test
