// Every lesson of the registry (chapters/lessons.txt), as functions that make them: for front
// ends that offer them all (the studio). Generated into all_lessons.cpp by the build.
#pragma once

#include <string>
#include <vector>

#include "driver/lesson.h"

namespace lessons {

struct RegisteredLesson {
    std::string name;   // the folder and the executable, e.g. "04_rendering_equation"
    std::string label;  // as on the lessons page
    Lesson (*make)();   // a fresh lesson: its flags bound to its own state
};

// In the registry's order.
const std::vector<RegisteredLesson>& all_lessons();

}  // namespace lessons
